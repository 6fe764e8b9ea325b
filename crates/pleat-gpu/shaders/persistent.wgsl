// A persistent kernel: one workgroup runs every substep of a frame of a
// small sheet, colour after colour with a barrier between them, in one
// dispatch (crate::backend::persistent). It runs what the per-colour
// kernels run for paper, in the same order: the prediction, the hinges
// and distances by colour, the strain limits' sweeps, each free cloth's
// turn, the hinges' tracking and the velocity update; with thickness
// (`frame_with_contacts`), the sheet's self-contacts before the velocity
// update, over every pair of particles, of a vertex and a triangle or of
// two edges that the rest mesh does not keep apart (listed by the host),
// each tried only where the two features' boxes over the substep come
// within the thickness, in the Jacobi iterations of self_contact.wgsl.
// The pairs within the thickness plus a margin are kept over substeps
// and dispatches while no particle has moved half the margin (as
// contact_grid.wgsl keeps its candidates).
//
// The positions live in workgroup memory for the dispatch: read from
// `pos_buffer` at its start, written back at its end. Every constraint
// reads and writes them, and a GPU serves workgroup memory in a few
// cycles where a storage buffer that other invocations write between
// colours is served from its L2 cache.

@group(0) @binding(0) var<storage, read_write> pos_buffer: array<vec4<f32>>;
@group(0) @binding(1) var<storage, read_write> prev: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> vel: array<vec4<f32>>;
// Every substep's parameters, 256 bytes apart as the dispatched kernels
// read them.
@group(0) @binding(3) var<uniform> substeps: array<ParamsSlot, MAX_SUBSTEPS>;
@group(0) @binding(4) var<uniform> compliances: array<vec4<f32>, 256>;
@group(1) @binding(0) var<storage, read_write> distances: array<Distance>;
@group(1) @binding(1) var<storage, read_write> distance_lambda: array<f32>;
@group(1) @binding(2) var<storage, read_write> hinges: array<Hinge>;
@group(1) @binding(3) var<storage, read_write> hinge_lambda: array<f32>;
@group(1) @binding(5) var<storage, read_write> left: array<vec4<f32>>;
@group(1) @binding(6) var<uniform> program: Program;
// This dispatch's first substep and how many a dispatch runs (a frame is
// split where a CPU adapter would cut a long one short).
@group(1) @binding(7) var<uniform> chunk: vec4<u32>;
// The self-contacts' topology (lib/contact.wgsl), then the pairs (two
// words each, as self_contact.wgsl's candidates), then the frame's counts.
@group(2) @binding(0) var<storage, read_write> topology: array<u32>;

// Per particle: the contacts' correction x, y, z in fixed point and the
// count of those that move it (lib/contact_solve.wgsl), for up to
// MAX_CONTACT_PARTICLES.
var<workgroup> accum: array<atomic<i32>, 2048>;
// The contacts that acted in the frame's last iterations.
var<workgroup> contacts_acted: atomic<u32>;
// The kept pairs (`keep_pairs`), whether a particle moved beyond half the
// margin since their build, and whether this substep builds them.
var<workgroup> kept: atomic<u32>;
var<workgroup> moved: atomic<u32>;
var<workgroup> rebuilding: u32;
// The pairs solved in the frame so far (alike in every invocation), and
// the builds (counted by the first).
var<private> solved: u32;
var<private> builds: u32;

// The substep this invocation runs.
var<private> params: Params;

// The sheet's positions and inverse masses for the dispatch (its
// PARTICLES particles, set by the host): the `pos` that common.wgsl and
// the libraries read and write.
override PARTICLES: u32;
var<workgroup> pos: array<vec4<f32>, PARTICLES>;

// Orders the positions' writes before other invocations read them
// (between colours).
fn colour_barrier() {
    workgroupBarrier();
}

// Orders every write, the positions' and the storage buffers' (the
// multipliers, the hinges' tracked angles, the previous positions).
fn full_barrier() {
    workgroupBarrier();
    storageBarrier();
}

// The dispatch's first act: the positions into workgroup memory.
fn load_positions(t: u32) {
    for (var i = t; i < PARTICLES; i += THREADS) {
        pos[i] = pos_buffer[i];
    }
    workgroupBarrier();
}

// The dispatch's last act: the positions back into their buffer.
fn store_positions(t: u32) {
    workgroupBarrier();
    for (var i = t; i < PARTICLES; i += THREADS) {
        pos_buffer[i] = pos[i];
    }
}

// Most substeps a frame of this kernel has: a 64 KiB uniform.
const MAX_SUBSTEPS: u32 = 256u;

struct ParamsSlot {
    p: Params,
    pad: array<vec4<u32>, 6>,
}

// Invocations of the workgroup, set by the host (crate::backend::persistent).
override THREADS: u32 = 64u;
// Invocations that sum a free cloth's shares, each over every SUMMING-th
// particle; one then sums theirs in order.
override SUMMING: u32 = min(THREADS, 64u);

// Per summing invocation, its sums.
var<workgroup> partial_sums: array<Sums, SUMMING>;
// The turn of the cloth being kept: its rotation vector, then its centre.
var<workgroup> kept_turn: array<vec4<f32>, 2>;

fn distance_colour_count() -> u32 {
    return program.distance_colours;
}

fn distance_colour(c: u32) -> Range {
    let s = program.slices[program.hinge_colours + c];
    return Range(s.x, s.y);
}

fn hinge_colour(c: u32) -> Range {
    let s = program.slices[c];
    return Range(s.x, s.y);
}

fn free_part(k: u32) -> Range {
    let s = program.slices[program.hinge_colours + program.distance_colours + k];
    return Range(s.x, s.y);
}

// Turns the free cloth `part` back by the angle its substep turned it
// without cause: SUMMING invocations sum its particles' shares, one sums
// theirs in a fixed order and finds the turn, all apply it.
fn keep_momentum(t: u32, part: Range) {
    if t < SUMMING {
        var s = zero_sums();
        for (var k = t; k < part.count; k += SUMMING) {
            s = add_sums(s, measure_particle(part.first + k));
        }
        partial_sums[t] = s;
    }
    workgroupBarrier();
    if t == 0u {
        var total = zero_sums();
        for (var k = 0u; k < SUMMING; k++) {
            total = add_sums(total, partial_sums[k]);
        }
        kept_turn[0] = vec4<f32>(spurious_turn(total), 0.0);
        kept_turn[1] = vec4<f32>(total.mx.xyz / total.mx.w, 0.0);
    }
    workgroupBarrier();
    let theta = kept_turn[0].xyz;
    let centre = kept_turn[1].xyz;
    for (var k = t; k < part.count; k += THREADS) {
        apply_turn(part.first + k, theta, centre);
    }
    full_barrier();
}

// The strain limits after the iterations, as the dispatched kernels run
// them.
fn sweep_strain_limits(t: u32) {
    if program.strain_limit_sweeps == 0u {
        return;
    }
    sweep_strain_limits_in_workgroup(t, THREADS, program.strain_limit_sweeps);
}

// One substep up to the self-contacts: the prediction with the
// multipliers cleared, the iterations, the strain limits, the free
// cloths' turns and the tracking.
fn substep(t: u32) {
    for (var i = t; i < params.particle_count; i += THREADS) {
        predict_particle(i);
    }
    for (var j = t; j < program.distance_count; j += THREADS) {
        distance_lambda[j] = 0.0;
    }
    for (var j = t; j < program.hinge_count; j += THREADS) {
        hinge_lambda[j] = 0.0;
    }
    full_barrier();
    for (var iteration = 0u; iteration < program.iterations; iteration++) {
        for (var c = 0u; c < program.hinge_colours; c++) {
            let r = hinge_colour(c);
            for (var k = t; k < r.count; k += THREADS) {
                solve_hinge(r.first + k);
            }
            colour_barrier();
        }
        for (var c = 0u; c < program.distance_colours; c++) {
            let r = distance_colour(c);
            for (var k = t; k < r.count; k += THREADS) {
                solve_distance(r.first + k);
            }
            colour_barrier();
        }
    }
    sweep_strain_limits(t);
    for (var k = 0u; k < program.free_parts; k++) {
        keep_momentum(t, free_part(k));
    }
    for (var j = t; j < program.hinge_count; j += THREADS) {
        track_hinge(j);
    }
}

// The velocity update that ends a substep.
fn finish_substep(t: u32) {
    for (var i = t; i < params.particle_count; i += THREADS) {
        update_velocity(i);
    }
    full_barrier();
}

// The box of particle i over the substep (its start and now).
fn swept(i: u32) -> array<vec3<f32>, 2> {
    let p = position(i);
    let q = prev[i].xyz;
    return array<vec3<f32>, 2>(min(p, q), max(p, q));
}

fn merged(a: array<vec3<f32>, 2>, b: array<vec3<f32>, 2>) -> array<vec3<f32>, 2> {
    return array<vec3<f32>, 2>(min(a[0], b[0]), max(a[1], b[1]));
}

// Whether two boxes come within `reach` of each other.
fn boxes_near(a: array<vec3<f32>, 2>, b: array<vec3<f32>, 2>, reach: f32) -> bool {
    return all(a[0] <= b[1] + reach) && all(b[0] <= a[1] + reach);
}

// Pair k's two features' boxes over the substep (as at a build, where
// the substep's start is its end).
fn pair_boxes(k: u32) -> array<array<vec3<f32>, 2>, 2> {
    let first = topology[program.contact_pairs_start + 2u * k];
    let second = topology[program.contact_pairs_start + 2u * k + 1u];
    if (first & EDGE_PAIR) != 0u {
        let a = edge(first & ~EDGE_PAIR);
        let b = edge(second);
        return array<array<vec3<f32>, 2>, 2>(merged(swept(a.x), swept(a.y)), merged(swept(b.x), swept(b.y)));
    }
    if (second & PARTICLE_PAIR) != 0u {
        return array<array<vec3<f32>, 2>, 2>(swept(first), swept(second & ~PARTICLE_PAIR));
    }
    let v = triangle(second);
    return array<array<vec3<f32>, 2>, 2>(swept(first), merged(merged(swept(v.x), swept(v.y)), swept(v.z)));
}

// Pair k's contact, where the features' boxes over the substep come
// within the thickness (nothing farther can touch or have crossed);
// whether it acted.
fn pair_contact(k: u32) -> bool {
    let boxes = pair_boxes(k);
    if !boxes_near(boxes[0], boxes[1], params.contact_thickness) {
        return false;
    }
    let first = topology[program.contact_pairs_start + 2u * k];
    let second = topology[program.contact_pairs_start + 2u * k + 1u];
    if (first & EDGE_PAIR) != 0u {
        return edge_contact(edge(first & ~EDGE_PAIR), edge(second));
    }
    if (second & PARTICLE_PAIR) != 0u {
        return particle_contact(first, second & ~PARTICLE_PAIR);
    }
    return triangle_contact(first, triangle(second));
}

// Whether pair k is of two edges flat in parallel layers, which the
// vertex-triangle contacts keep apart both ways: no pair to keep (as at a
// build of contact_grid.wgsl).
fn parallel_edges(k: u32) -> bool {
    let first = topology[program.contact_pairs_start + 2u * k];
    if (first & EDGE_PAIR) == 0u {
        return false;
    }
    let second = topology[program.contact_pairs_start + 2u * k + 1u];
    return abs(dot(flat_normal(edge_wings(first & ~EDGE_PAIR)), flat_normal(edge_wings(second)))) > PARALLEL;
}

// The frame's three counts in `topology` are followed by the last build's
// kept pairs plus one (zero before the first) and the reach they were kept
// within, so that a dispatch goes on with the pairs the one before kept;
// then the kept pairs, then the positions at that build, three words a
// particle.
fn kept_state() -> u32 {
    return program.contact_counts + 3u;
}

fn kept_start() -> u32 {
    return kept_state() + 2u;
}

fn build_start() -> u32 {
    return kept_start() + program.contact_pairs;
}

fn build_position(i: u32) -> vec3<f32> {
    let k = build_start() + 3u * i;
    return bitcast<vec3<f32>>(vec3<u32>(topology[k], topology[k + 1u], topology[k + 2u]));
}

// Keeps the pairs whose features lie within the thickness plus the margin
// (a build), where none are kept yet, the reach changed or some particle
// moved more than half the margin since the last build: a pair left out
// cannot have come within the thickness, nor crossed, since. Kept pairs
// are listed in no fixed order; their corrections' sums do not depend on
// it.
fn keep_pairs(t: u32) {
    let half = 0.5 * params.contact_margin;
    let reach = params.contact_thickness + params.contact_margin;
    let state = kept_state();
    if t == 0u && (topology[state] == 0u || bitcast<f32>(topology[state + 1u]) != reach) {
        atomicStore(&moved, 1u);
    }
    for (var i = t; i < params.particle_count; i += THREADS) {
        let d = position(i) - build_position(i);
        if dot(d, d) > half * half {
            atomicStore(&moved, 1u);
        }
    }
    workgroupBarrier();
    if t == 0u {
        rebuilding = atomicLoad(&moved);
        atomicStore(&moved, 0u);
        if rebuilding != 0u {
            atomicStore(&kept, 0u);
            builds += 1u;
        }
    }
    // Every invocation meets every barrier: the build's loops alone are
    // conditional.
    let build = workgroupUniformLoad(&rebuilding) != 0u;
    for (var k = t; build && k < program.contact_pairs; k += THREADS) {
        let boxes = pair_boxes(k);
        if boxes_near(boxes[0], boxes[1], reach) && !parallel_edges(k) {
            topology[kept_start() + atomicAdd(&kept, 1u)] = k;
        }
    }
    for (var i = t; build && i < params.particle_count; i += THREADS) {
        let k = build_start() + 3u * i;
        let p = bitcast<vec3<u32>>(position(i));
        topology[k] = p.x;
        topology[k + 1u] = p.y;
        topology[k + 2u] = p.z;
    }
    workgroupBarrier();
    if build && t == 0u {
        topology[state] = atomicLoad(&kept) + 1u;
        topology[state + 1u] = bitcast<u32>(reach);
    }
    storageBarrier();
}

// The pairs the last dispatch kept, as the dispatch starts.
fn load_kept(t: u32) {
    if t == 0u && topology[kept_state()] != 0u {
        atomicStore(&kept, topology[kept_state()] - 1u);
    }
}

// The substep's self-contacts: the kept pairs in Jacobi iterations, each
// evaluated twice (counted per particle, then scaled and summed:
// lib/contact_solve.wgsl), the corrections applied once all are summed;
// the last iteration's acting contacts counted.
fn self_contacts(t: u32) {
    keep_pairs(t);
    let count = atomicLoad(&kept);
    let last = program.contact_iterations - 1u;
    for (var iteration = 0u; iteration <= last; iteration++) {
        for (var j = t; j < count; j += THREADS) {
            touches = 0u;
            if pair_contact(topology[kept_start() + j]) {
                count_contact();
            }
        }
        workgroupBarrier();
        for (var j = t; j < count; j += THREADS) {
            touches = 0u;
            if pair_contact(topology[kept_start() + j]) {
                scaled_contact();
                if iteration == last {
                    atomicAdd(&contacts_acted, 1u);
                }
            }
        }
        workgroupBarrier();
        for (var i = t; i < params.particle_count; i += THREADS) {
            apply_correction(i);
        }
        colour_barrier();
    }
    solved += count;
}

@compute @workgroup_size(THREADS)
fn frame(@builtin(local_invocation_index) t: u32) {
    load_positions(t);
    for (var s = chunk.x; s < min(chunk.x + chunk.y, program.substeps); s++) {
        params = substeps[s].p;
        substep(t);
        finish_substep(t);
    }
    store_positions(t);
}

// A frame with self-contacts; the pairs solved, the contacts that acted
// and the builds are added to the counts in `topology` at
// `contact_counts` (read back and cleared by the host's health check),
// then the kept pairs and their build's positions.
@compute @workgroup_size(THREADS)
fn frame_with_contacts(@builtin(local_invocation_index) t: u32) {
    load_kept(t);
    load_positions(t);
    for (var s = chunk.x; s < min(chunk.x + chunk.y, program.substeps); s++) {
        params = substeps[s].p;
        substep(t);
        full_barrier();
        self_contacts(t);
        finish_substep(t);
    }
    store_positions(t);
    workgroupBarrier();
    if t == 0u {
        topology[program.contact_counts] += solved;
        topology[program.contact_counts + 1u] += atomicLoad(&contacts_acted);
        topology[program.contact_counts + 2u] += builds;
    }
}
