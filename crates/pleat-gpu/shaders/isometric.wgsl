// Isometric bending (Bergou et al. 2006), one colour per dispatch
// (crate::constraint::isometric_bending).

@group(1) @binding(0) var<storage, read_write> items: array<Isometric>;
@group(1) @binding(1) var<storage, read_write> lambda: array<f32>;

@compute @workgroup_size(256)
fn solve(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let j = range_item(gid, groups);
    if j == NONE { return; }
    let c = items[j];
    let p0 = position(c.v[0]);
    let b = (position(c.v[1]) - p0) * c.k[1] + (position(c.v[2]) - p0) * c.k[2] + (position(c.v[3]) - p0) * c.k[3];
    let value = length(b);
    if !(value > 1e-6) {
        return;
    }
    let dir = b / value;
    let w = array<f32, 4>(inv_mass(c.v[0]), inv_mass(c.v[1]), inv_mass(c.v[2]), inv_mass(c.v[3]));
    let norm = w[0] * c.k[0] * c.k[0] + w[1] * c.k[1] * c.k[1] + w[2] * c.k[2] * c.k[2] + w[3] * c.k[3] * c.k[3];
    let dlambda = lagrange_update(value, norm, alpha_of(c.compliance, c.slot), lambda[j]);
    if dlambda == 0.0 {
        return;
    }
    lambda[j] += dlambda;
    for (var q = 0u; q < 4u; q++) {
        if w[q] > 0.0 {
            move_by(c.v[q], dir * (w[q] * c.k[q] * dlambda));
        }
    }
}
