// Angular momentum kept through a substep's own constraints
// (lib/momentum.wgsl): for one free cloth (the range), the sums per
// workgroup, then over the workgroups by one workgroup in a fixed order,
// and the turn applied.

// What the last turn could not move each particle by (round-off).
@group(1) @binding(0) var<storage, read_write> left: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> partials: array<Sums>;
// The turn's rotation vector, then the centre it turns about.
@group(1) @binding(2) var<storage, read_write> turn: array<vec4<f32>>;
// first, count: the cloth's particles.

var<workgroup> scratch: array<vec4<f32>, 256>;

// Particle first + k's share, none past the range.
fn measure(k: u32) -> Sums {
    if k >= range.count {
        return zero_sums();
    }
    return measure_particle(range.first + k);
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
    if i != NONE {
        apply_turn(i, turn[0].xyz, turn[1].xyz);
    }
}
