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
// Pairs of one cloth closer at rest than the exclusion radius (the CPU
// backend's: the thickness for cloth, twice it for paper) never collide:
// the cloth's stretch and bending keep them apart. A vertex and a triangle
// closer at rest than FACING thicknesses collide only while the vertex
// lies over the triangle, not beside it (OVER): where the cloth has folded
// back on itself within a few edges. Flat cloth thus gives no candidates,
// since the margin keeps thickness + margin below FACING thicknesses, and
// a cloth crumpled as tightly as its thickness still meets itself two
// edges along.
// Triangles are found through their vertices: a triangle within reach of
// a particle has every vertex within the cell size of it, so the particles
// of the 27 cells around it farther than that are skipped, and a triangle
// is taken through its vertex of lowest index, which owns it: once, with
// no test. A vertex closer at rest than the exclusion radius rules out
// itself and every triangle it owns at once, and so does one farther than
// its owned triangles' span (`owned_span`, noted by `scatter` with the
// positions at the build) plus the reach.
// Edge pairs (paper's, in `find_edges`: kernel_buffers.rs lists only
// paper's edges) are found through their nearest ends: edges within reach of
// each other have a pair of ends within half of each edge plus the reach,
// so each particle takes the edges at it against those at each neighbour
// of higher index, keeping a pair only where these two particles are its
// nearest pair of ends: once, with no test. `scatter` notes each
// vertex's longest edge and, if it is flat, its normal at the build,
// which bound the search: a neighbour farther than half of both longest
// edges plus the reach, or flat in a layer parallel to the particle's,
// has no edge pair with it.

// grid: [0, B) bucket counts, then their exclusive prefix (bucket starts);
// [B, 2B) fill counters; [2B, 2B + N) particles sorted by bucket;
// [2B + N, ...) workgroup sums of the prefix scan.
@group(1) @binding(0) var<storage, read_write> grid: array<atomic<u32>>;
// topology: triangles (3 per triangle), then the triangles each vertex
// owns (those whose lowest vertex it is) in compressed rows: starts
// (N + 1), then triangle indices; then the edges at each vertex, likewise,
// and the edges' ends (lib/contact.wgsl's `edge`).
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
// noted as at the build, and its edge summary where the rest buffer has
// room for them (a model with edge pairs).
@compute @workgroup_size(256)
fn scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = flat_index(gid, groups);
    if i < params.particle_count {
        let b = bucket(cell_of(position(i), cell_size()));
        let slot = atomicLoad(&grid[b]) + atomicAdd(&grid[params.contact_buckets + b], 1u);
        atomicStore(&grid[2u * params.contact_buckets + slot], i);
        rest[params.particle_count + i] = vec4<f32>(position(i), owned_span(i));
        if arrayLength(&rest) >= 3u * params.particle_count {
            rest[2u * params.particle_count + i] = edge_summary(i);
        }
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

// Whether particles i and j of one cloth lie closer at rest than `radius`.
fn rest_near(i: vec4<f32>, j: u32, radius: f32) -> bool {
    let r = rest[j];
    let d = r.xyz - i.xyz;
    return r.w == i.w && dot(d, d) < radius * radius;
}

// Thicknesses within which, at rest, a vertex collides with a triangle of
// its cloth only where it lies over it, and a particle pair never does.
const FACING: f32 = 2.0;
// Sine of the least angle between a vertex's offset from a triangle and
// the triangle's plane at which the vertex lies over it (30 degrees).
const OVER: f32 = 0.5;

fn facing_radius() -> f32 {
    return max(FACING * params.contact_thickness, params.contact_exclusion);
}

// Whether offset `d` from a triangle of normal `n` (any length) leaves its
// plane at OVER or steeper.
fn over(d: vec3<f32>, n: vec3<f32>) -> bool {
    return dot(d, n) * dot(d, n) >= OVER * OVER * dot(d, d) * dot(n, n);
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
// exclusion radius, or than the facing radius with i beside it.
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
    if dot(d, d) >= reach * reach {
        return;
    }
    if rest[v.x].w == home.w {
        let apart = rest_distance_to_triangle(home, v);
        if apart < params.contact_exclusion || (apart < facing_radius() && !over(d, cross(b - a, c - a))) {
            return;
        }
    }
    push(i, t);
}

// Whether the ends u and v, `d` apart squared, come before i and j (i < j),
// `own` apart squared: nearer, or as near with lower indices.
fn precedes(d: f32, u: u32, v: u32, own: f32, i: u32, j: u32) -> bool {
    let lo = min(u, v);
    return d < own || (d == own && (lo < i || (lo == i && max(u, v) < j)));
}

fn distance2(p: vec3<f32>, q: vec3<f32>) -> f32 {
    return dot(p - q, p - q);
}

// Cosine of 5 degrees: a vertex whose edges are flat with normals within
// it of the first edge's is flat, and two flat vertices whose normals lie
// within it of each other have every pair of their edges within 15
// degrees: parallel, no candidate.
const VERTEX_PARALLEL: f32 = 0.9961947;

// What the edge search needs of vertex i at a build: its unit normal if
// it is flat (VERTEX_PARALLEL), else zero, and the length of its longest
// edge.
fn edge_summary(i: u32) -> vec4<f32> {
    let starts = incident_starts();
    let list = incident_list();
    var first = vec3<f32>(0.0);
    var flat = true;
    var longest = 0.0;
    for (var x = topology[starts + i]; x < topology[starts + i + 1u]; x++) {
        let e = edge_wings(topology[list + x]);
        let n = flat_normal(e);
        if x == topology[starts + i] {
            first = n;
        }
        flat = flat && any(n != vec3<f32>(0.0)) && abs(dot(n, first)) > VERTEX_PARALLEL;
        longest = max(longest, distance(position(e.x), position(e.y)));
    }
    return vec4<f32>(select(vec3<f32>(0.0), first, flat), longest);
}

// Takes the pairs of an edge at particle i and one at its neighbour j
// (i < j) that lie within `reach`, whose nearest ends i and j are, that do
// not lie in parallel layers and that are not of one cloth and closer at
// rest than the exclusion radius.
fn consider_edges(i: u32, j: u32, home: vec4<f32>, reach: f32) {
    // Edges within reach whose nearest ends are i and j have those ends
    // within half of each edge plus the reach of each other.
    let si = rest[2u * params.particle_count + i];
    let sj = rest[2u * params.particle_count + j];
    let pi = position(i);
    let pj = position(j);
    let own = distance2(pi, pj);
    let apart = 0.5 * (si.w + sj.w) + reach;
    if own > apart * apart || abs(dot(si.xyz, sj.xyz)) > VERTEX_PARALLEL {
        return;
    }
    let starts = incident_starts();
    let list = incident_list();
    for (var x = topology[starts + i]; x < topology[starts + i + 1u]; x++) {
        let ea = topology[list + x];
        let a = edge(ea);
        let ka = select(a.x, a.y, a.x == i);
        let pa = position(ka);
        // Ends nearer than i and j, for every edge at j.
        if ka == j || precedes(distance2(pa, pj), ka, j, own, i, j) {
            continue;
        }
        for (var y = topology[starts + j]; y < topology[starts + j + 1u]; y++) {
            let eb = topology[list + y];
            let b = edge(eb);
            let kb = select(b.x, b.y, b.x == j);
            if kb == i || kb == ka {
                continue;
            }
            let pb = position(kb);
            if precedes(distance2(pi, pb), i, kb, own, i, j) || precedes(distance2(pa, pb), ka, kb, own, i, j) {
                continue;
            }
            let st = segment_closest(pi, pa, pj, pb);
            if distance2(mix(pi, pa, st.x), mix(pj, pb, st.y)) >= reach * reach
                || abs(dot(flat_normal(edge_wings(ea)), flat_normal(edge_wings(eb)))) > PARALLEL {
                continue;
            }
            if rest[kb].w == home.w {
                let r = segment_closest(home.xyz, rest[ka].xyz, rest[j].xyz, rest[kb].xyz);
                let gap = mix(home.xyz, rest[ka].xyz, r.x) - mix(rest[j].xyz, rest[kb].xyz, r.y);
                if dot(gap, gap) < params.contact_exclusion * params.contact_exclusion {
                    continue;
                }
            }
            push(ea | EDGE_PAIR, eb);
        }
    }
}

// The slots in the sorted particles of the bucket of cell `near`.
fn cell_slots(near: vec3<i32>) -> vec2<u32> {
    let b = bucket(near);
    let first = atomicLoad(&grid[b]);
    return vec2<u32>(first, first + atomicLoad(&grid[params.contact_buckets + b]));
}

// Whether particle j, at `d` from the searching particle (of rest position
// and cloth `home`), is its neighbour: in cell `near` itself (not only in
// its bucket), within the cell size, and not closer at rest than the
// exclusion radius.
fn neighbour(j: u32, d: vec3<f32>, near: vec3<i32>, size: f32, home: vec4<f32>) -> bool {
    return all(cell_of(position(j), size) == near) && dot(d, d) <= size * size && !rest_near(home, j, params.contact_exclusion);
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
                let slots = cell_slots(near);
                for (var s = slots.x; s < slots.y; s++) {
                    let j = atomicLoad(&grid[sorted + s]);
                    let d = position(j) - p;
                    if !neighbour(j, d, near, size, home) {
                        continue;
                    }
                    if j > i && dot(d, d) < reach * reach && !rest_near(home, j, facing_radius()) {
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

// Particle i's edge pairs: those of the edges at it and at each neighbour
// of higher index (consider_edges), less the rest-near ones. A kernel of
// its own, run after `find` where the model has edges listed (paper's,
// kernel_buffers.rs): the edge search inlined into `find`, though never
// entered for cloth, doubled that kernel's time on lavapipe.
@compute @workgroup_size(256)
fn find_edges(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k >= params.particle_count {
        return;
    }
    let sorted = 2u * params.contact_buckets;
    let i = atomicLoad(&grid[sorted + k]);
    if topology[incident_starts() + i] == topology[incident_starts() + i + 1u] {
        return;
    }
    let p = position(i);
    let home = rest[i];
    let size = cell_size();
    let cell = cell_of(p, size);
    let reach = params.contact_thickness + margin();
    for (var dz = -1; dz <= 1; dz++) {
        for (var dy = -1; dy <= 1; dy++) {
            for (var dx = -1; dx <= 1; dx++) {
                let near = cell + vec3<i32>(dx, dy, dz);
                let slots = cell_slots(near);
                for (var s = slots.x; s < slots.y; s++) {
                    let j = atomicLoad(&grid[sorted + s]);
                    if j > i && neighbour(j, position(j) - p, near, size, home) {
                        consider_edges(i, j, home, reach);
                    }
                }
            }
        }
    }
}
