// Dihedral bending, one colour per dispatch (crate::constraint::bending).

struct Bending {
    v: array<u32, 4>,
    rest_angle: f32,
    compliance: f32,
    slot: u32,
}

@group(1) @binding(0) var<storage, read_write> items: array<Bending>;
@group(1) @binding(1) var<storage, read_write> lambda: array<f32>;
@group(1) @binding(4) var<uniform> range: Range;

// An angle difference in (-2 pi, 2 pi] brought into (-pi, pi].
fn wrap_angle(a: f32) -> f32 {
    if a > PI {
        return a - TAU;
    }
    if a <= -PI {
        return a + TAU;
    }
    return a;
}

@compute @workgroup_size(256)
fn solve(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k >= range.count {
        return;
    }
    let j = range.first + k;
    let c = items[j];
    let d = dihedral_angle(position(c.v[0]), position(c.v[1]), position(c.v[2]), position(c.v[3]));
    if !d.ok {
        return;
    }
    lambda[j] = project_four(c.v, alpha_of(c.compliance, c.slot), wrap_angle(d.phi - c.rest_angle), d, lambda[j]);
}
