// Self-collision and cloth-cloth contact: a hash grid of the particles
// built every substep (count, multi-workgroup exclusive prefix sum,
// scatter), then particle-particle and vertex-triangle proximity contacts
// within the contact thickness, rest-mesh neighbours excluded, solved as
// Jacobi: each contact's corrections summed per particle in fixed point
// with integer atomics (WGSL has no float atomics; integer sums do not
// depend on the order, so two runs are bit-identical), then averaged.
//
// Triangles are found through their vertices: a triangle within the
// thickness of a particle has every vertex within reach of it (the cell
// size: an edge stretched by half plus the thickness), so the particles of
// the 27 cells around it farther than that are skipped, and a triangle is
// taken through its vertex of lowest index, which owns it: once, with no
// test. Each test rejects on the current positions first; the rest-mesh
// exclusion, which needs a closest point on the rest triangle, runs only
// for the few pairs that are in contact.

// grid: [0, B) bucket counts, then their exclusive prefix (bucket starts);
// [B, 2B) fill counters; [2B, 2B + N) particles sorted by bucket;
// [2B + N, ...) workgroup sums of the prefix scan.
@group(1) @binding(0) var<storage, read_write> grid: array<atomic<u32>>;
// topology: triangles (3 per triangle), then the triangles each vertex
// owns (those whose lowest vertex it is) in compressed rows: starts
// (N + 1), then triangle indices.
@group(1) @binding(1) var<storage, read_write> topology: array<u32>;
@group(1) @binding(2) var<storage, read_write> rest: array<vec4<f32>>;
// Per particle: correction x, y, z in fixed point, and the contact count.
@group(1) @binding(3) var<storage, read_write> accum: array<atomic<i32>>;

const FIXED: f32 = 16777216.0;
const SCAN: u32 = 256u;

var<workgroup> scan_scratch: array<u32, 256>;

fn cell_of(p: vec3<f32>) -> vec3<i32> {
    return vec3<i32>(floor(p / params.contact_cell));
}

fn bucket(c: vec3<i32>) -> u32 {
    let h = (bitcast<u32>(c.x) * 73856093u) ^ (bitcast<u32>(c.y) * 19349663u) ^ (bitcast<u32>(c.z) * 83492791u);
    return h & (params.contact_buckets - 1u);
}

fn sums_base() -> u32 {
    return 2u * params.contact_buckets + params.particle_count;
}

@compute @workgroup_size(256)
fn clear(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k < 2u * params.contact_buckets {
        atomicStore(&grid[k], 0u);
    }
    if k < 4u * params.particle_count {
        atomicStore(&accum[k], 0);
    }
}

@compute @workgroup_size(256)
fn count(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i < params.particle_count {
        atomicAdd(&grid[bucket(cell_of(position(i)))], 1u);
    }
}

// Exclusive prefix of each block of 256 counts, and the block's total.
@compute @workgroup_size(256)
fn scan_blocks(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>) {
    let k = wid.x * SCAN + lid.x;
    let own = atomicLoad(&grid[k]);
    scan_scratch[lid.x] = own;
    workgroupBarrier();
    for (var offset = 1u; offset < SCAN; offset *= 2u) {
        var add = 0u;
        if lid.x >= offset {
            add = scan_scratch[lid.x - offset];
        }
        workgroupBarrier();
        scan_scratch[lid.x] += add;
        workgroupBarrier();
    }
    atomicStore(&grid[k], scan_scratch[lid.x] - own);
    if lid.x == SCAN - 1u {
        atomicStore(&grid[sums_base() + wid.x], scan_scratch[lid.x]);
    }
}

// Exclusive prefix of the block totals (one invocation: a few thousand at most).
@compute @workgroup_size(1)
fn scan_sums() {
    var total = 0u;
    for (var b = 0u; b < params.contact_buckets / SCAN; b++) {
        let s = atomicLoad(&grid[sums_base() + b]);
        atomicStore(&grid[sums_base() + b], total);
        total += s;
    }
}

@compute @workgroup_size(256)
fn scan_add(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k < params.contact_buckets {
        atomicAdd(&grid[k], atomicLoad(&grid[sums_base() + k / SCAN]));
    }
}

@compute @workgroup_size(256)
fn scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i < params.particle_count {
        let b = bucket(cell_of(position(i)));
        let slot = atomicLoad(&grid[b]) + atomicAdd(&grid[params.contact_buckets + b], 1u);
        atomicStore(&grid[2u * params.contact_buckets + slot], i);
    }
}

fn add_correction(i: u32, dx: vec3<f32>) {
    let q = vec3<i32>(round(dx * FIXED));
    atomicAdd(&accum[4u * i], q.x);
    atomicAdd(&accum[4u * i + 1u], q.y);
    atomicAdd(&accum[4u * i + 2u], q.z);
    atomicAdd(&accum[4u * i + 3u], 1);
}

// Whether particle j is within reach of p (the cell size).
fn within_reach(j: u32, p: vec3<f32>) -> bool {
    let d = position(j) - p;
    return dot(d, d) <= params.contact_cell * params.contact_cell;
}

// Closest point on triangle abc to p, as barycentric weights (Ericson 2005).
fn closest_barycentric(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 { return vec3<f32>(1.0, 0.0, 0.0); }
    let bp = p - b;
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 { return vec3<f32>(0.0, 1.0, 0.0); }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return vec3<f32>(1.0 - v, v, 0.0);
    }
    let cp = p - c;
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 { return vec3<f32>(0.0, 0.0, 1.0); }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return vec3<f32>(1.0 - w, 0.0, w);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return vec3<f32>(0.0, 1.0 - w, w);
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    return vec3<f32>(1.0 - v - w, v, w);
}

fn rest_distance_to_triangle(i: u32, t: vec3<u32>) -> f32 {
    let p = rest[i].xyz;
    let a = rest[t.x].xyz;
    let b = rest[t.y].xyz;
    let c = rest[t.z].xyz;
    let w = closest_barycentric(p, a, b, c);
    return distance(p, w.x * a + w.y * b + w.z * c);
}

// Keeps particle i at the thickness from particle j (j > i: each pair once).
fn particle_contact(i: u32, j: u32) {
    let h = params.contact_thickness;
    if j <= i {
        return;
    }
    let d = position(i) - position(j);
    let len = length(d);
    let wi = inv_mass(i);
    let wj = inv_mass(j);
    if len >= h || len <= 0.0 || wi + wj == 0.0 || distance(rest[i].xyz, rest[j].xyz) < 2.0 * h {
        return;
    }
    let n = d / len;
    let s = (h - len) / (wi + wj);
    let f = friction((position(i) - prev[i].xyz) - (position(j) - prev[j].xyz), n, h - len) / (wi + wj);
    add_correction(i, n * (s * wi) - f * wi);
    add_correction(j, f * wj - n * (s * wj));
}

// The tangential part of the relative motion `relative` over the substep
// that Coulomb friction removes at penetration depth `depth`: all of it
// when it is within the static cone, else `kinetic * depth` of it.
fn friction(relative: vec3<f32>, n: vec3<f32>, depth: f32) -> vec3<f32> {
    let tangential = relative - n * dot(relative, n);
    let slide = length(tangential);
    if slide < params.contact_static * depth {
        return tangential;
    }
    if slide > 0.0 {
        return tangential * min(params.contact_kinetic * depth / slide, 1.0);
    }
    return vec3<f32>(0.0);
}

// Keeps particle i at the thickness from triangle t on the side it was on,
// with friction on their relative motion.
fn triangle_contact(i: u32, t: vec3<u32>) {
    let h = params.contact_thickness;
    if i == t.x || i == t.y || i == t.z {
        return;
    }
    let p = position(i);
    let a = position(t.x);
    let b = position(t.y);
    let c = position(t.z);
    let bary = closest_barycentric(p, a, b, c);
    let q = bary.x * a + bary.y * b + bary.z * c;
    if distance(p, q) >= h || rest_distance_to_triangle(i, t) < 2.0 * h {
        return;
    }
    let normal = cross(b - a, c - a);
    let area2 = length(normal);
    if area2 <= 0.0 {
        return;
    }
    let pa = prev[t.x].xyz;
    let prev_normal = cross(prev[t.y].xyz - pa, prev[t.z].xyz - pa);
    let side = select(-1.0, 1.0, dot(prev[i].xyz - pa, prev_normal) >= 0.0);
    let n = normal / area2 * side;
    let gap = dot(p - q, n) - h;
    if gap >= 0.0 {
        return;
    }
    let w = vec4<f32>(inv_mass(i), inv_mass(t.x), inv_mass(t.y), inv_mass(t.z));
    let denom = w.x + dot(bary * bary, w.yzw);
    if denom <= 0.0 {
        return;
    }
    let s = -gap / denom;
    let motion = (p - prev[i].xyz) - (bary.x * (a - prev[t.x].xyz) + bary.y * (b - prev[t.y].xyz) + bary.z * (c - prev[t.z].xyz));
    // The friction impulse shares the normal one's weights.
    let f = friction(motion, n, -gap) / denom;
    add_correction(i, n * (s * w.x) - f * w.x);
    add_correction(t.x, (n * (-s) + f) * (bary.x * w.y));
    add_correction(t.y, (n * (-s) + f) * (bary.y * w.z));
    add_correction(t.z, (n * (-s) + f) * (bary.z * w.w));
}

fn triangle(k: u32) -> vec3<u32> {
    return vec3<u32>(topology[3u * k], topology[3u * k + 1u], topology[3u * k + 2u]);
}

@compute @workgroup_size(256)
fn contacts(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k >= params.particle_count {
        return;
    }
    // Particles in bucket order: neighbouring invocations walk the same
    // cells, so they run the same loops over the same memory.
    let sorted = 2u * params.contact_buckets;
    let i = atomicLoad(&grid[sorted + k]);
    let p = position(i);
    let home = cell_of(p);
    let owned_start = 3u * params.triangle_count;
    let owned = owned_start + params.particle_count + 1u;
    for (var dz = -1; dz <= 1; dz++) {
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                let cell = home + vec3<i32>(dx, dy, dz);
                let b = bucket(cell);
                let first = atomicLoad(&grid[b]);
                let last = first + atomicLoad(&grid[params.contact_buckets + b]);
                for (var s = first; s < last; s++) {
                    let j = atomicLoad(&grid[sorted + s]);
                    if any(cell_of(position(j)) != cell) || !within_reach(j, p) {
                        continue;
                    }
                    particle_contact(i, j);
                    for (var a = topology[owned_start + j]; a < topology[owned_start + j + 1u]; a++) {
                        triangle_contact(i, triangle(topology[owned + a]));
                    }
                }
            }
        }
    }
}

@compute @workgroup_size(256)
fn apply(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i >= params.particle_count {
        return;
    }
    let n = atomicLoad(&accum[4u * i + 3u]);
    if n > 0 && inv_mass(i) > 0.0 {
        let sum = vec3<f32>(
            f32(atomicLoad(&accum[4u * i])),
            f32(atomicLoad(&accum[4u * i + 1u])),
            f32(atomicLoad(&accum[4u * i + 2u])),
        );
        move_by(i, sum / (FIXED * f32(n)));
    }
}
