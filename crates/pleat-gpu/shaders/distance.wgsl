// Distance constraints, one colour per dispatch (lib/distance.wgsl): the
// compliant projection with its strain limit, and the strain limit alone;
// then the strain limits' further sweeps, in one workgroup that stops
// itself, the held limits met in one, and, for small sheets, every sweep of
// a substep in one.

@group(1) @binding(0) var<storage, read_write> distances: array<Distance>;
@group(1) @binding(1) var<storage, read_write> distance_lambda: array<f32>;
// The further sweeps' colours: each colour's slice of `distances`.
@group(1) @binding(2) var<storage, read_write> colours: array<Range>;
// Whether the last sweep found an edge beyond STRAIN_LIMIT_SLACK times its
// limit (1) or not (0); the further sweeps clear it.
@group(1) @binding(3) var<storage, read_write> beyond: array<atomic<u32>>;

fn distance_colour_count() -> u32 {
    return arrayLength(&colours);
}

fn distance_colour(c: u32) -> Range {
    return colours[c];
}

@compute @workgroup_size(256)
fn solve(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let j = range_item(gid, groups);
    if j != NONE {
        solve_distance(j);
    }
}

@compute @workgroup_size(256)
fn limit(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let j = range_item(gid, groups);
    if j != NONE {
        limit_distance(j, 1.0);
    }
}

// The last of the first sweeps: the strain limit alone, noting in `beyond`
// whether an edge was beyond the slack before its projection.
@compute @workgroup_size(256)
fn limit_measured(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let j = range_item(gid, groups);
    if j != NONE && limit_distance(j, STRAIN_LIMIT_SLACK) {
        atomicStore(&beyond[0], 1u);
    }
}

// The further sweeps of a substep, in one dispatch that stops itself:
// while the sweep before found an edge beyond the slack, up to
// MAX_STRAIN_LIMIT_SWEEPS in all. Clears `beyond`.
@compute @workgroup_size(256)
fn limit_further(@builtin(local_invocation_index) t: u32) {
    if t == 0u {
        sweep_again = atomicExchange(&beyond[0], 0u);
    }
    sweep_while_beyond(t, WORKGROUP, STRAIN_LIMIT_SLACK, STRAIN_LIMIT_SWEEPS, STRAIN_LIMIT_SWEEPS, MAX_STRAIN_LIMIT_SWEEPS);
}

// Every sweep of a substep in one dispatch of one workgroup, for sheets
// small enough that a workgroup walks each colour in a few rounds: no
// dispatch per colour and sweep.
@compute @workgroup_size(256)
fn limit_alone(@builtin(local_invocation_index) t: u32) {
    sweep_strain_limits_in_workgroup(t, WORKGROUP, STRAIN_LIMIT_SWEEPS);
}

// The held limits met over the positions alone when a fold comes to rest
// (crate::solver::xpbd's meet_held_limits): sweeps until no edge is beyond
// its limit, up to FOLD_HOLD_SWEEPS.
@compute @workgroup_size(256)
fn limit_held(@builtin(local_invocation_index) t: u32) {
    if t == 0u {
        sweep_again = 1u;
    }
    sweep_while_beyond(t, WORKGROUP, 1.0, 0u, 0u, FOLD_HOLD_SWEEPS);
}

// One round of them where the paper has self-contacts: up to
// HOLD_ROUND_SWEEPS sweeps while an edge is beyond its limit (one once
// none is), each round's motion then checked by the contacts (record.rs),
// as crate::solver::xpbd's rounds.
@compute @workgroup_size(256)
fn limit_held_round(@builtin(local_invocation_index) t: u32) {
    if t == 0u {
        sweep_again = 1u;
    }
    sweep_while_beyond(t, WORKGROUP, 1.0, 0u, 0u, HOLD_ROUND_SWEEPS);
}
