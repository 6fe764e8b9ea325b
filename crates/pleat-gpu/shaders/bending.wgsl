// Dihedral bending, one colour per dispatch (crate::constraint::bending).

@group(1) @binding(0) var<storage, read_write> items: array<Bending>;
@group(1) @binding(1) var<storage, read_write> lambda: array<f32>;

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
    let j = range_item(gid, groups);
    if j == NONE { return; }
    let c = items[j];
    let d = dihedral_of(c.v);
    if !d.ok {
        return;
    }
    lambda[j] = project_four(c.v, alpha_of(c.compliance, c.slot), wrap_angle(d.phi - c.rest_angle), d, lambda[j]);
}
