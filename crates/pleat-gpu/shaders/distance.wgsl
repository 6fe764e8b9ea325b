// Distance constraints, one colour per dispatch (crate::constraint::distance):
// the compliant projection with its strain limit, and the strain limit alone.

struct Distance {
    a: u32,
    b: u32,
    rest_length: f32,
    compliance: f32,
    slot: u32,
    // Largest change of length (m); f32::MAX for no limit.
    max_stretch: f32,
}

@group(1) @binding(0) var<storage, read_write> items: array<Distance>;
@group(1) @binding(1) var<storage, read_write> lambda: array<f32>;
@group(1) @binding(4) var<uniform> range: Range;

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
    var e: Edge;
    e.ok = false;
    let k = flat_index(gid, groups);
    if k >= range.count {
        return e;
    }
    e.j = range.first + k;
    let c = items[e.j];
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
    let alpha = alpha_of(c.compliance, c.slot);
    let dlambda = (-e.c - alpha * lambda[e.j]) / (w + alpha);
    lambda[e.j] += dlambda;
    move_by(c.a, e.n * (e.wa * dlambda));
    move_by(c.b, e.n * (-e.wb * dlambda));
    // The projection moved the ends along n: C is now c + w dlambda.
    clamp_stretch(e, e.c + w * dlambda);
}

@compute @workgroup_size(256)
fn limit(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let e = edge(gid, groups);
    if e.ok {
        clamp_stretch(e, e.c);
    }
}
