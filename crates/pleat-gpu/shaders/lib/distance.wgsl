// Distance constraints (crate::constraint::distance), on an index: the
// compliant projection with its strain limit, the strain limit alone, and
// the strain limits' sweeps that one workgroup runs over every colour
// while an edge is still far beyond its limit (crate::solver::xpbd).
// The includer binds `distances` and `distance_lambda`, and gives the
// colours of the distances through `distance_colour_count` and
// `distance_colour`.

// Sweeps of the strain limits a substep: the first STRAIN_LIMIT_SWEEPS,
// then more while the last found an edge beyond STRAIN_LIMIT_SLACK times
// its limit, up to MAX_STRAIN_LIMIT_SWEEPS in all (crate::solver::xpbd).
const STRAIN_LIMIT_SWEEPS: u32 = 2u;
const MAX_STRAIN_LIMIT_SWEEPS: u32 = 384u;
const STRAIN_LIMIT_SLACK: f32 = 1.8;
// Most sweeps of the held limits when a fold comes to rest.
const FOLD_HOLD_SWEEPS: u32 = 500u;
// Sweeps of a round of them, where self-contacts check each round
// (crate::kernels::HOLD_ROUND_SWEEPS).
const HOLD_ROUND_SWEEPS: u32 = 1u;

// The edge of a constraint: its index, inverse masses, `C` and direction
// from b to a; `ok` is false where it cannot move.
struct Edge {
    ok: bool,
    j: u32,
    wa: f32,
    wb: f32,
    c: f32,
    n: vec3<f32>,
}

// The edge of constraint j.
fn edge_at(j: u32) -> Edge {
    var e: Edge;
    e.ok = false;
    e.j = j;
    let c = distances[j];
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
    let item = distances[e.j];
    let excess = c - clamp(c, -item.max_stretch, item.max_stretch);
    if excess != 0.0 {
        let s = excess / (e.wa + e.wb);
        move_by(item.a, e.n * (-e.wa * s));
        move_by(item.b, e.n * (e.wb * s));
    }
}

// The compliant projection of constraint j, then its strain limit.
fn solve_distance(j: u32) {
    let e = edge_at(j);
    if !e.ok {
        return;
    }
    let c = distances[j];
    let w = e.wa + e.wb;
    let dlambda = lagrange_update(e.c, w, alpha_of(c.compliance, c.slot), distance_lambda[j]);
    distance_lambda[j] += dlambda;
    move_by(c.a, e.n * (e.wa * dlambda));
    move_by(c.b, e.n * (-e.wb * dlambda));
    // The projection moved the ends along n: C is now c + w dlambda.
    clamp_stretch(e, e.c + w * dlambda);
}

// Whether the edge is beyond `slack` times its limit, stretched or
// compressed (the sign of crate::constraint::distance's project_limit).
fn is_beyond(e: Edge, slack: f32) -> bool {
    return abs(e.c) > slack * distances[e.j].max_stretch;
}

// The strain limit alone of constraint j; whether it was beyond `slack`
// times its limit before.
fn limit_distance(j: u32, slack: f32) -> bool {
    let e = edge_at(j);
    if !e.ok {
        return false;
    }
    let beyond = is_beyond(e, slack);
    clamp_stretch(e, e.c);
    return beyond;
}

var<workgroup> beyond_in_sweep: atomic<u32>;
var<workgroup> sweep_again: u32;

// Sweeps `first` to `last` (exclusive) of the strain limits at `slack`, in
// one workgroup of `threads` invocations (t is this one's index): a sweep
// over every colour, a `colour_barrier` between colours; from sweep
// `forced` on, only while the sweep before found an edge beyond the slack
// (`sweep_again`, which the caller sets before the first).
fn sweep_while_beyond(t: u32, threads: u32, slack: f32, first: u32, forced: u32, last: u32) {
    for (var sweep = first; sweep < last; sweep++) {
        let again = workgroupUniformLoad(&sweep_again);
        if sweep >= forced && again == 0u {
            break;
        }
        if t == 0u {
            atomicStore(&beyond_in_sweep, 0u);
        }
        workgroupBarrier();
        for (var c = 0u; c < distance_colour_count(); c++) {
            let r = distance_colour(c);
            for (var k = t; k < r.count; k += threads) {
                if limit_distance(r.first + k, slack) {
                    atomicStore(&beyond_in_sweep, 1u);
                }
            }
            colour_barrier();
        }
        workgroupBarrier();
        if t == 0u {
            sweep_again = atomicLoad(&beyond_in_sweep);
        }
    }
}

// Every strain-limit sweep of a substep in one workgroup, as
// crate::solver::xpbd's sweep_strain_limits: `sweeps` of them, then more
// while the last found an edge beyond STRAIN_LIMIT_SLACK times its limit,
// up to MAX_STRAIN_LIMIT_SWEEPS in all.
fn sweep_strain_limits_in_workgroup(t: u32, threads: u32, sweeps: u32) {
    if t == 0u {
        sweep_again = 1u;
    }
    sweep_while_beyond(t, threads, STRAIN_LIMIT_SLACK, 0u, sweeps, MAX_STRAIN_LIMIT_SWEEPS);
}
