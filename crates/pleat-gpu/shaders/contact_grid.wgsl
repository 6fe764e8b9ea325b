// Self-contacts' broad phase: the candidate pairs, found at a build and
// kept while no particle has moved more than half the margin since, so
// that a pair left out (farther apart than thickness + margin at the
// build) cannot have come within the thickness: the substeps between
// builds only solve the kept pairs (self_contact.wgsl).
//
// A pair's distance changes by no more than the two particles'
// displacements differ, so what counts is each displacement less one
// shared by all (any, here the middle of their range along each axis):
// a falling or carried cloth keeps its candidates. Each substep `bound`
// takes that range and `check` notes whether a particle has moved more
// than half the margin from its middle; the build's kernels then run on
// workgroup counts that contact_dispatch.wgsl wrote, zero when none has:
// a hash grid of the particles (count, multi-workgroup exclusive prefix
// sum, scatter) and `find`.
//
// Pairs of one cloth closer at rest than the exclusion radius (twice the
// thickness) never collide: the cloth's stretch and bending keep them
// apart. Flat cloth thus gives no candidates, since the margin keeps
// thickness + margin below that radius.
// Triangles are found through their vertices: a triangle within reach of
// a particle has every vertex within the cell size of it, so the particles
// of the 27 cells around it farther than that are skipped, and a triangle
// is taken through its vertex of lowest index, which owns it: once, with
// no test. A vertex closer at rest than the exclusion radius rules out
// itself and every triangle it owns at once, and so does one farther than
// its owned triangles' span (`owned_span`, noted by `scatter` with the
// positions at the build) plus the reach.

// grid: [0, B) bucket counts, then their exclusive prefix (bucket starts);
// [B, 2B) fill counters; [2B, 2B + N) particles sorted by bucket;
// [2B + N, ...) workgroup sums of the prefix scan.
@group(1) @binding(0) var<storage, read_write> grid: array<atomic<u32>>;
// topology: triangles (3 per triangle), then the triangles each vertex
// owns (those whose lowest vertex it is) in compressed rows: starts
// (N + 1), then triangle indices.
@group(1) @binding(1) var<storage, read_write> topology: array<u32>;
@group(1) @binding(2) var<storage, read_write> rest: array<vec4<f32>>;
@group(1) @binding(3) var<storage, read_write> candidates: array<atomic<u32>>;

const SCAN: u32 = 256u;

var<workgroup> scan_scratch: array<u32, 256>;

// The margin in use: none while dropped (contact_dispatch.wgsl's
// `choose_margin`); the hash grid's cells shrink with it.
fn margin() -> f32 {
    return select(params.contact_margin, 0.0, atomicLoad(&candidates[DROPPED]) != 0u);
}

fn cell_size() -> f32 {
    return params.contact_cell - params.contact_margin + margin();
}

fn cell_of(p: vec3<f32>, size: f32) -> vec3<i32> {
    return vec3<i32>(floor(p / size));
}

fn bucket(c: vec3<i32>) -> u32 {
    let h = (bitcast<u32>(c.x) * 73856093u) ^ (bitcast<u32>(c.y) * 19349663u) ^ (bitcast<u32>(c.z) * 83492791u);
    return h & (params.contact_buckets - 1u);
}

fn sums_base() -> u32 {
    return 2u * params.contact_buckets + params.particle_count;
}

// A key of x ordered as the floats are.
fn ordered(x: f32) -> u32 {
    let bits = bitcast<u32>(x);
    return select(bits | 0x80000000u, ~bits, (bits & 0x80000000u) != 0u);
}

fn from_ordered(key: u32) -> f32 {
    return bitcast<f32>(select(~key, key & 0x7fffffffu, (key & 0x80000000u) != 0u));
}

fn moved(i: u32) -> vec3<f32> {
    return position(i) - rest[params.particle_count + i].xyz;
}

// The workgroup's range of displacements.
var<workgroup> least: array<atomic<u32>, 3>;
var<workgroup> greatest: array<atomic<u32>, 3>;

// Widens the range of the displacements since the last build by the
// workgroup's particles': over the workgroup first, so that the shared
// range takes one update a workgroup.
@compute @workgroup_size(256)
fn bound(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    if lid < 3u {
        atomicStore(&least[lid], 0xffffffffu);
    }
    workgroupBarrier();
    let i = flat_index(gid, groups);
    if i < params.particle_count {
        let d = moved(i);
        for (var axis = 0u; axis < 3u; axis++) {
            atomicMin(&least[axis], ordered(d[axis]));
            atomicMax(&greatest[axis], ordered(d[axis]));
        }
    }
    workgroupBarrier();
    if lid < 3u {
        atomicMin(&candidates[LEAST + lid], atomicLoad(&least[lid]));
        atomicMax(&candidates[GREATEST + lid], atomicLoad(&greatest[lid]));
    }
}

// Notes whether particle i has moved more than half the margin from the
// middle of the displacements since the last build.
@compute @workgroup_size(256)
fn check(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i >= params.particle_count {
        return;
    }
    var middle = vec3<f32>(0.0);
    for (var axis = 0u; axis < 3u; axis++) {
        let low = from_ordered(atomicLoad(&candidates[LEAST + axis]));
        let high = from_ordered(atomicLoad(&candidates[GREATEST + axis]));
        middle[axis] = 0.5 * low + 0.5 * high;
    }
    let off = moved(i) - middle;
    let half = 0.5 * margin();
    // Not `<=`: a position that is NaN moves on too.
    if !(dot(off, off) <= half * half) {
        atomicStore(&candidates[FRESH], 0u);
    }
}

@compute @workgroup_size(256)
fn clear(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k < 2u * params.contact_buckets {
        atomicStore(&grid[k], 0u);
    }
}

@compute @workgroup_size(256)
fn count(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i < params.particle_count {
        atomicAdd(&grid[bucket(cell_of(position(i), cell_size()))], 1u);
    }
}

// The prefix sum of the bucket counts runs without workgroup barriers
// where it can (a CPU adapter pays for each): each invocation sums a block
// of SCAN counts in turn, then one workgroup scans the blocks' totals.

// Exclusive prefix of one block of SCAN counts, and the block's total.
@compute @workgroup_size(256)
fn scan_blocks(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let block = flat_index(gid, groups);
    if block >= params.contact_buckets / SCAN {
        return;
    }
    var total = 0u;
    for (var k = block * SCAN; k < (block + 1u) * SCAN; k++) {
        let own = atomicLoad(&grid[k]);
        atomicStore(&grid[k], total);
        total += own;
    }
    atomicStore(&grid[sums_base() + block], total);
}

// Exclusive prefix of the blocks' totals, in one workgroup: each
// invocation's run of totals in turn, then the runs' sums across the
// workgroup.
@compute @workgroup_size(256)
fn scan_sums(@builtin(local_invocation_index) lid: u32) {
    let blocks = params.contact_buckets / SCAN;
    let run = (blocks + SCAN - 1u) / SCAN;
    let first = min(lid * run, blocks);
    let last = min(first + run, blocks);
    var total = 0u;
    for (var b = first; b < last; b++) {
        let s = atomicLoad(&grid[sums_base() + b]);
        atomicStore(&grid[sums_base() + b], total);
        total += s;
    }
    scan_scratch[lid] = total;
    workgroupBarrier();
    for (var offset = 1u; offset < SCAN; offset *= 2u) {
        var add = 0u;
        if lid >= offset {
            add = scan_scratch[lid - offset];
        }
        workgroupBarrier();
        scan_scratch[lid] += add;
        workgroupBarrier();
    }
    let before = scan_scratch[lid] - total;
    for (var b = first; b < last; b++) {
        atomicAdd(&grid[sums_base() + b], before);
    }
}

@compute @workgroup_size(256)
fn scan_add(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k < params.contact_buckets {
        atomicAdd(&grid[k], atomicLoad(&grid[sums_base() + k / SCAN]));
    }
}

// Particle i into its bucket; its position and its owned triangles' span
// noted as at the build.
@compute @workgroup_size(256)
fn scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i < params.particle_count {
        let b = bucket(cell_of(position(i), cell_size()));
        let slot = atomicLoad(&grid[b]) + atomicAdd(&grid[params.contact_buckets + b], 1u);
        atomicStore(&grid[2u * params.contact_buckets + slot], i);
        rest[params.particle_count + i] = vec4<f32>(position(i), owned_span(i));
    }
}

// How far the triangles vertex i owns reach from it: the longest of their
// edges at i (0 if it owns none).
fn owned_span(i: u32) -> f32 {
    let owned_start = 3u * params.triangle_count;
    let owned = owned_start + params.particle_count + 1u;
    let p = position(i);
    var span = 0.0;
    for (var a = topology[owned_start + i]; a < topology[owned_start + i + 1u]; a++) {
        let v = triangle(topology[owned + a]);
        span = max(span, max(distance(position(v.x), p), max(distance(position(v.y), p), distance(position(v.z), p))));
    }
    return span;
}

// Whether particles i and j of one cloth lie closer at rest than the
// exclusion radius.
fn rest_near(i: vec4<f32>, j: u32) -> bool {
    let r = rest[j];
    let d = r.xyz - i.xyz;
    return r.w == i.w && dot(d, d) < params.contact_exclusion * params.contact_exclusion;
}

fn push(i: u32, other: u32) {
    let k = atomicAdd(&candidates[FOUND], 1u);
    if k < params.contact_capacity {
        atomicStore(&candidates[HEADER + 2u * k], i);
        atomicStore(&candidates[HEADER + 2u * k + 1u], other);
    }
}

// Rest distance from particle i (at `home`) to triangle v.
fn rest_distance_to_triangle(home: vec4<f32>, v: vec3<u32>) -> f32 {
    let a = rest[v.x].xyz;
    let b = rest[v.y].xyz;
    let c = rest[v.z].xyz;
    let w = closest_barycentric(home.xyz, a, b, c);
    return distance(home.xyz, w.x * a + w.y * b + w.z * c);
}

// Takes triangle t as particle i's candidate if it lies within thickness +
// margin of i, unless it is of i's cloth and closer to i at rest than the
// exclusion radius.
fn consider_triangle(i: u32, home: vec4<f32>, t: u32, reach: f32) {
    let v = triangle(t);
    if i == v.x || i == v.y || i == v.z {
        return;
    }
    let p = position(i);
    let a = position(v.x);
    let b = position(v.y);
    let c = position(v.z);
    let w = closest_barycentric(p, a, b, c);
    let d = p - (w.x * a + w.y * b + w.z * c);
    if dot(d, d) < reach * reach && (rest[v.x].w != home.w || rest_distance_to_triangle(home, v) >= params.contact_exclusion) {
        push(i, t);
    }
}

// Particle i's candidates: the particles (of higher index: each pair once)
// and triangles within thickness + margin of it, less the rest-near ones.
@compute @workgroup_size(256)
fn find(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k >= params.particle_count {
        return;
    }
    // Particles in bucket order: neighbouring invocations walk the same
    // cells, so they run the same loops over the same memory.
    let sorted = 2u * params.contact_buckets;
    let i = atomicLoad(&grid[sorted + k]);
    let p = position(i);
    let home = rest[i];
    let size = cell_size();
    let cell = cell_of(p, size);
    let reach = params.contact_thickness + margin();
    let owned_start = 3u * params.triangle_count;
    let owned = owned_start + params.particle_count + 1u;
    for (var dz = -1; dz <= 1; dz++) {
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                let near = cell + vec3<i32>(dx, dy, dz);
                let b = bucket(near);
                let first = atomicLoad(&grid[b]);
                let last = first + atomicLoad(&grid[params.contact_buckets + b]);
                for (var s = first; s < last; s++) {
                    let j = atomicLoad(&grid[sorted + s]);
                    let d = position(j) - p;
                    if any(cell_of(position(j), size) != near) || dot(d, d) > size * size || rest_near(home, j) {
                        continue;
                    }
                    if j > i && dot(d, d) < reach * reach {
                        push(i, j | PARTICLE_PAIR);
                    }
                    // Every point of j's triangles lies within their span
                    // of j.
                    let span = rest[params.particle_count + j].w + reach;
                    if dot(d, d) >= span * span {
                        continue;
                    }
                    for (var a = topology[owned_start + j]; a < topology[owned_start + j + 1u]; a++) {
                        consider_triangle(i, home, topology[owned + a], reach);
                    }
                }
            }
        }
    }
}
