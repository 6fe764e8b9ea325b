// Distance constraints, one colour per dispatch (crate::constraint::distance):
// the compliant projection with its strain limit, and the strain limit alone;
// then the strain limits' further sweeps (crate::solver::xpbd), which one
// workgroup runs over every colour while an edge is still far beyond its
// limit, so that the dispatch stops itself.

@group(1) @binding(0) var<storage, read_write> items: array<Distance>;
@group(1) @binding(1) var<storage, read_write> lambda: array<f32>;
// The further sweeps' colours: each colour's slice of `items`.
@group(1) @binding(2) var<storage, read_write> colours: array<Range>;
// Whether the last sweep found an edge beyond STRAIN_LIMIT_SLACK times its
// limit (1) or not (0); the further sweeps clear it.
@group(1) @binding(3) var<storage, read_write> beyond: array<atomic<u32>>;

// Sweeps of the strain limits a substep: the first STRAIN_LIMIT_SWEEPS,
// then more while the last found an edge beyond STRAIN_LIMIT_SLACK times
// its limit, up to MAX_STRAIN_LIMIT_SWEEPS in all (crate::solver::xpbd).
const STRAIN_LIMIT_SWEEPS: u32 = 2u;
const MAX_STRAIN_LIMIT_SWEEPS: u32 = 384u;
const STRAIN_LIMIT_SLACK: f32 = 1.8;
// Most sweeps of the held limits when a fold comes to rest.
const FOLD_HOLD_SWEEPS: u32 = 500u;

// The edge of this invocation's constraint: its index, inverse masses,
// `C` and direction from b to a; `ok` is false where it cannot move.
struct Edge {
    ok: bool,
    j: u32,
    wa: f32,
    wb: f32,
    c: f32,
    n: vec3<f32>,
}

fn edge(gid: vec3<u32>, groups: vec3<u32>) -> Edge {
    let j = range_item(gid, groups);
    if j == NONE {
        var none: Edge;
        none.ok = false;
        return none;
    }
    return edge_at(j);
}

// The edge of constraint j.
fn edge_at(j: u32) -> Edge {
    var e: Edge;
    e.ok = false;
    e.j = j;
    let c = items[j];
    e.wa = inv_mass(c.a);
    e.wb = inv_mass(c.b);
    if e.wa + e.wb == 0.0 {
        return e;
    }
    let d = position(c.a) - position(c.b);
    let len = length(d);
    if !(len > 1.1920929e-7 * max(c.rest_length, 1e-6)) {
        return e;
    }
    e.n = d / len;
    e.c = len - c.rest_length;
    e.ok = true;
    return e;
}

// Moves the ends along n so that C = `c` comes back within the limit.
fn clamp_stretch(e: Edge, c: f32) {
    let item = items[e.j];
    let excess = c - clamp(c, -item.max_stretch, item.max_stretch);
    if excess != 0.0 {
        let s = excess / (e.wa + e.wb);
        move_by(item.a, e.n * (-e.wa * s));
        move_by(item.b, e.n * (e.wb * s));
    }
}

@compute @workgroup_size(256)
fn solve(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let e = edge(gid, groups);
    if !e.ok {
        return;
    }
    let c = items[e.j];
    let w = e.wa + e.wb;
    let dlambda = lagrange_update(e.c, w, alpha_of(c.compliance, c.slot), lambda[e.j]);
    lambda[e.j] += dlambda;
    move_by(c.a, e.n * (e.wa * dlambda));
    move_by(c.b, e.n * (-e.wb * dlambda));
    // The projection moved the ends along n: C is now c + w dlambda.
    clamp_stretch(e, e.c + w * dlambda);
}

// Whether the edge is beyond `slack` times its limit, stretched or
// compressed (the sign of crate::constraint::distance's project_limit).
fn is_beyond(e: Edge, slack: f32) -> bool {
    return abs(e.c) > slack * items[e.j].max_stretch;
}

@compute @workgroup_size(256)
fn limit(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let e = edge(gid, groups);
    if e.ok {
        clamp_stretch(e, e.c);
    }
}

// The last of the first sweeps: the strain limit alone, noting in `beyond`
// whether an edge was beyond the slack before its projection.
@compute @workgroup_size(256)
fn limit_measured(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let e = edge(gid, groups);
    if e.ok {
        if is_beyond(e, STRAIN_LIMIT_SLACK) {
            atomicStore(&beyond[0], 1u);
        }
        clamp_stretch(e, e.c);
    }
}

var<workgroup> beyond_in_sweep: atomic<u32>;
var<workgroup> sweep_again: u32;

// Sweeps `first` to `last` (exclusive) of the strain limits at `slack`, in
// one workgroup: a sweep over every colour, a storage barrier between
// colours, while the sweep before found an edge beyond the slack
// (`sweep_again`, which the caller sets for the first).
fn sweep_while_beyond(t: u32, slack: f32, first: u32, last: u32) {
    for (var sweep = first; sweep < last; sweep++) {
        if workgroupUniformLoad(&sweep_again) == 0u {
            break;
        }
        if t == 0u {
            atomicStore(&beyond_in_sweep, 0u);
        }
        workgroupBarrier();
        for (var c = 0u; c < arrayLength(&colours); c++) {
            let r = colours[c];
            for (var k = t; k < r.count; k += WORKGROUP) {
                let e = edge_at(r.first + k);
                if e.ok {
                    if is_beyond(e, slack) {
                        atomicStore(&beyond_in_sweep, 1u);
                    }
                    clamp_stretch(e, e.c);
                }
            }
            storageBarrier();
        }
        workgroupBarrier();
        if t == 0u {
            sweep_again = atomicLoad(&beyond_in_sweep);
        }
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
    sweep_while_beyond(t, STRAIN_LIMIT_SLACK, STRAIN_LIMIT_SWEEPS, MAX_STRAIN_LIMIT_SWEEPS);
}

// The held limits met over the positions alone when a fold comes to rest
// (crate::solver::xpbd's meet_held_limits): sweeps until no edge is beyond
// its limit, up to FOLD_HOLD_SWEEPS.
@compute @workgroup_size(256)
fn limit_held(@builtin(local_invocation_index) t: u32) {
    if t == 0u {
        sweep_again = 1u;
    }
    sweep_while_beyond(t, 1.0, 0u, FOLD_HOLD_SWEEPS);
}
