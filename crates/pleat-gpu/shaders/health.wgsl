// The health of the state after a frame (crate::stability): non-finite
// positions and velocities, kinetic and potential energy, the fastest
// particle and the largest length over tear length of a paper edge (a
// cloth's tear is found when its state is read back). Reduced per workgroup,
// then over the workgroups by one workgroup in a fixed order, so every run
// sums the same way.

@group(1) @binding(0) var<storage, read_write> rest: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> tear_edges: array<TearEdge>;
@group(1) @binding(2) var<storage, read_write> partials: array<Summary>;
@group(1) @binding(3) var<storage, read_write> result: array<Summary>;
// count: the number of tear edges.

var<workgroup> scratch: array<Summary, 256>;

fn empty() -> Summary {
    return Summary(0u, NONE, NONE, -1.0, 0.0, 0.0, 0.0, 0u);
}

fn merge(a: Summary, b: Summary) -> Summary {
    var r = a;
    r.non_finite = a.non_finite + b.non_finite;
    r.first_bad = min(a.first_bad, b.first_bad);
    if b.speed2 > a.speed2 {
        r.fastest = b.fastest;
        r.speed2 = b.speed2;
    }
    r.kinetic = a.kinetic + b.kinetic;
    r.potential = a.potential + b.potential;
    r.tear = max(a.tear, b.tear);
    return r;
}

// Finite by the bits (NaN and infinities have every exponent bit set), so
// no compiler assumption about NaN can hide one.
fn finite(v: vec3<f32>) -> bool {
    let exponent = bitcast<vec3<u32>>(v) & vec3<u32>(0x7f800000u);
    return all(exponent != vec3<u32>(0x7f800000u));
}

// Particle k's part, and tear edge k's length over its tear length.
fn measure(k: u32) -> Summary {
    var s = empty();
    if k < params.particle_count {
        let x = pos[k];
        let v = vel[k].xyz;
        if !finite(x.xyz) || !finite(v) {
            s.non_finite = 1u;
            s.first_bad = k;
        } else {
            s.fastest = k;
            s.speed2 = dot(v, v);
            if x.w > 0.0 {
                s.kinetic = 0.5 * dot(v, v) / x.w;
                s.potential = -dot(params.gravity, x.xyz - rest[k].xyz) / x.w;
            }
        }
    }
    if k < range.count {
        let e = tear_edges[k];
        s.tear = length(pos[e.a].xyz - pos[e.b].xyz) / e.tear_length;
    }
    return s;
}

// The merge of every invocation's `s` in the workgroup (a tree in a fixed order).
fn reduce_workgroup(local: u32, s: Summary) -> Summary {
    scratch[local] = s;
    workgroupBarrier();
    for (var stride = WORKGROUP / 2u; stride > 0u; stride = stride / 2u) {
        if local < stride {
            scratch[local] = merge(scratch[local], scratch[local + stride]);
        }
        workgroupBarrier();
    }
    return scratch[0];
}

@compute @workgroup_size(256)
fn reduce_blocks(at: Invocation) {
    let total = reduce_workgroup(at.lid.x, measure(flat_index(at.gid, at.groups)));
    if at.lid.x == 0u {
        partials[block_index(at)] = total;
    }
}

@compute @workgroup_size(256)
fn reduce_sums(@builtin(local_invocation_id) lid: vec3<u32>) {
    let blocks = (max(params.particle_count, range.count) + WORKGROUP - 1u) / WORKGROUP;
    var s = empty();
    for (var b = lid.x; b < blocks; b = b + WORKGROUP) {
        s = merge(s, partials[b]);
    }
    let total = reduce_workgroup(lid.x, s);
    if lid.x == 0u {
        result[0] = total;
    }
}
