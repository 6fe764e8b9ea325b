// Soft attachments: a particle pulled towards its scripted target with a
// compliance (crate::constraint::attachment). Targets hold, per substep, the
// hard pins' targets then the soft attachments'.

@group(1) @binding(0) var<storage, read_write> items: array<Attachment>;
@group(1) @binding(1) var<storage, read_write> lambda: array<f32>;
@group(1) @binding(2) var<storage, read_write> targets: array<vec4<f32>>;

@compute @workgroup_size(256)
fn solve(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let j = range_item(gid, groups);
    if j == NONE { return; }
    let a = items[j];
    let w = inv_mass(a.particle);
    let d = position(a.particle) - targets[params.substep * params.pin_count + a.slot].xyz;
    let c = length(d);
    if w == 0.0 || c <= 1.1920929e-7 {
        return;
    }
    let dlambda = lagrange_update(c, w, a.compliance * params.inv_dt2, lambda[j]);
    lambda[j] += dlambda;
    move_by(a.particle, d / c * (w * dlambda));
}
