// Angular momentum kept through a substep's own constraints
// (crate::solver::momentum): for one free cloth (the range), the angular
// impulse of how far the projection moved its particles from the exact
// prediction x_prev + dt v is summed per workgroup, then over the
// workgroups by one workgroup in a fixed order, and taken back by the
// smallest rigid turn about the centre of mass.

// Mass-weighted sums over the cloth, with m the mass, p the position
// before the substep, x the position now and d how far x is from the
// prediction, less what the last turn left.
struct Sums {
    // sum m x, and sum m in w.
    mx: vec4<f32>,
    mp: vec4<f32>,
    // sum m p x d
    mpd: vec4<f32>,
    md: vec4<f32>,
    // sum m x p^T, by columns.
    mxp0: vec4<f32>,
    mxp1: vec4<f32>,
    mxp2: vec4<f32>,
}

// What the last turn could not move each particle by (round-off).
@group(1) @binding(0) var<storage, read_write> left: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> partials: array<Sums>;
// The turn's rotation vector, then the centre it turns about.
@group(1) @binding(2) var<storage, read_write> turn: array<vec4<f32>>;
// first, count: the cloth's particles.

var<workgroup> scratch: array<vec4<f32>, 256>;

// Turns smaller than this (radians) are the sums' round-off, and skipped
// (crate::solver::momentum::SMALLEST_TURN).
const SMALLEST_TURN: f32 = 1e-9;

fn zero_sums() -> Sums {
    let z = vec4<f32>(0.0);
    return Sums(z, z, z, z, z, z, z);
}

fn add_sums(a: Sums, b: Sums) -> Sums {
    return Sums(a.mx + b.mx, a.mp + b.mp, a.mpd + b.mpd, a.md + b.md,
                a.mxp0 + b.mxp0, a.mxp1 + b.mxp1, a.mxp2 + b.mxp2);
}

// Particle first + k's share.
fn measure(k: u32) -> Sums {
    var s = zero_sums();
    if k >= range.count {
        return s;
    }
    let i = range.first + k;
    let m = 1.0 / pos[i].w;
    let x = pos[i].xyz;
    let p = prev[i].xyz;
    let d = (x - p) - vel[i].xyz * params.dt - left[i].xyz;
    s.mx = vec4<f32>(x * m, m);
    s.mp = vec4<f32>(p * m, 0.0);
    s.mpd = vec4<f32>(cross(p, d) * m, 0.0);
    s.md = vec4<f32>(d * m, 0.0);
    s.mxp0 = vec4<f32>(x * (m * p.x), 0.0);
    s.mxp1 = vec4<f32>(x * (m * p.y), 0.0);
    s.mxp2 = vec4<f32>(x * (m * p.z), 0.0);
    return s;
}

// The sum of every invocation's `v` in the workgroup (a tree in a fixed order).
fn reduce_field(local: u32, v: vec4<f32>) -> vec4<f32> {
    workgroupBarrier();
    scratch[local] = v;
    workgroupBarrier();
    for (var stride = WORKGROUP / 2u; stride > 0u; stride = stride / 2u) {
        if local < stride {
            scratch[local] = scratch[local] + scratch[local + stride];
        }
        workgroupBarrier();
    }
    return scratch[0];
}

fn reduce_workgroup(local: u32, s: Sums) -> Sums {
    return Sums(
        reduce_field(local, s.mx),
        reduce_field(local, s.mp),
        reduce_field(local, s.mpd),
        reduce_field(local, s.md),
        reduce_field(local, s.mxp0),
        reduce_field(local, s.mxp1),
        reduce_field(local, s.mxp2),
    );
}

@compute @workgroup_size(256)
fn sum_blocks(at: Invocation) {
    let total = reduce_workgroup(at.lid.x, measure(flat_index(at.gid, at.groups)));
    if at.lid.x == 0u {
        partials[block_index(at)] = total;
    }
}

// The rotation vector theta with sum m p x (theta x r) = -sum m p x d, p
// and r about their centres of mass; zero where the cloth lies on a line.
fn spurious_turn(s: Sums) -> vec3<f32> {
    let mass = s.mx.w;
    let c = s.mx.xyz / mass;
    let cp = s.mp.xyz / mass;
    let impulse = s.mpd.xyz - cross(cp, s.md.xyz);
    // sum m r p^T, and the map theta -> (p . r) theta - r (p . theta).
    let rp = mat3x3<f32>(s.mxp0.xyz - c * (mass * cp.x),
                         s.mxp1.xyz - c * (mass * cp.y),
                         s.mxp2.xyz - c * (mass * cp.z));
    let trace = rp[0].x + rp[1].y + rp[2].z;
    let map = mat3x3<f32>(vec3<f32>(trace, 0.0, 0.0), vec3<f32>(0.0, trace, 0.0),
                          vec3<f32>(0.0, 0.0, trace)) - rp;
    let scale = map[0].x + map[1].y + map[2].z;
    let det = determinant(map);
    if !(abs(det) > 1e-9 * scale * scale * scale) {
        return vec3<f32>(0.0);
    }
    // The inverse's rows are the cross products of the columns over det.
    let inverse = transpose(mat3x3<f32>(cross(map[1], map[2]), cross(map[2], map[0]),
                                        cross(map[0], map[1]))) * (1.0 / det);
    let turn = -(inverse * impulse);
    return select(vec3<f32>(0.0), turn, length(turn) > SMALLEST_TURN);
}

@compute @workgroup_size(256)
fn solve(@builtin(local_invocation_id) lid: vec3<u32>) {
    let blocks = (range.count + WORKGROUP - 1u) / WORKGROUP;
    var s = zero_sums();
    for (var b = lid.x; b < blocks; b = b + WORKGROUP) {
        s = add_sums(s, partials[b]);
    }
    let total = reduce_workgroup(lid.x, s);
    if lid.x == 0u {
        turn[0] = vec4<f32>(spurious_turn(total), 0.0);
        turn[1] = vec4<f32>(total.mx.xyz / total.mx.w, 0.0);
    }
}

@compute @workgroup_size(256)
fn apply(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = range_item(gid, groups);
    if i == NONE { return; }
    let x = pos[i].xyz;
    let step = cross(turn[0].xyz, x - turn[1].xyz);
    let moved = x + step;
    // step - (moved - x) is the round-off of the sum, exactly; a compiler
    // free to reassociate (Mesa's is) makes it zero unless `moved` passes
    // through an operation it cannot see through.
    let kept = bitcast<vec3<f32>>(bitcast<vec3<u32>>(moved) ^ vec3<u32>(params.opaque_zero));
    left[i] = vec4<f32>(step - (kept - x), 0.0);
    pos[i] = vec4<f32>(moved, pos[i].w);
}
