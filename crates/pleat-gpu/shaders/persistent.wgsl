// A persistent kernel: one workgroup runs every substep of a frame of a
// small sheet, colour after colour with a barrier between them, in one
// dispatch (crate::backend::persistent). It runs what the per-colour
// kernels run for paper, in the same order: the prediction, the hinges
// and distances by colour, the strain limits' sweeps, each free cloth's
// turn, the hinges' tracking and the velocity update.

@group(0) @binding(0) var<storage, read_write> pos: array<vec4<f32>>;
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

// The substep this invocation runs.
var<private> params: Params;

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
var<workgroup> partial_sums: array<Sums, 64>;
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
    storageBarrier();
}

// The strain limits after the iterations, as the dispatched kernels run
// them.
fn sweep_strain_limits(t: u32) {
    if program.strain_limit_sweeps == 0u {
        return;
    }
    sweep_strain_limits_in_workgroup(t, THREADS, program.strain_limit_sweeps);
}

// One substep: the prediction with the multipliers cleared, the
// iterations, the strain limits, the free cloths' turns, the tracking and
// the velocity update.
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
    storageBarrier();
    for (var iteration = 0u; iteration < program.iterations; iteration++) {
        for (var c = 0u; c < program.hinge_colours; c++) {
            let r = hinge_colour(c);
            for (var k = t; k < r.count; k += THREADS) {
                solve_hinge(r.first + k);
            }
            storageBarrier();
        }
        for (var c = 0u; c < program.distance_colours; c++) {
            let r = distance_colour(c);
            for (var k = t; k < r.count; k += THREADS) {
                solve_distance(r.first + k);
            }
            storageBarrier();
        }
    }
    sweep_strain_limits(t);
    for (var k = 0u; k < program.free_parts; k++) {
        keep_momentum(t, free_part(k));
    }
    for (var j = t; j < program.hinge_count; j += THREADS) {
        track_hinge(j);
    }
    for (var i = t; i < params.particle_count; i += THREADS) {
        update_velocity(i);
    }
    storageBarrier();
}

@compute @workgroup_size(THREADS)
fn frame(@builtin(local_invocation_index) t: u32) {
    for (var s = 0u; s < program.substeps; s++) {
        params = substeps[s].p;
        substep(t);
    }
}
