// Soft attachments: a particle pulled towards its scripted target with a
// compliance (crate::constraint::attachment). Targets hold, per substep, the
// hard pins' targets then the soft attachments'.

struct Attachment {
    particle: u32,
    compliance: f32,
    // Index among the pins' targets of a substep.
    slot: u32,
    pad: u32,
}

@group(1) @binding(0) var<storage, read_write> items: array<Attachment>;
@group(1) @binding(1) var<storage, read_write> lambda: array<f32>;
@group(1) @binding(2) var<storage, read_write> targets: array<vec4<f32>>;
@group(1) @binding(4) var<uniform> range: Range;

@compute @workgroup_size(256)
fn solve(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k >= range.count {
        return;
    }
    let j = range.first + k;
    let a = items[j];
    let w = inv_mass(a.particle);
    let d = position(a.particle) - targets[params.substep * params.pin_count + a.slot].xyz;
    let c = length(d);
    if w == 0.0 || c <= 1.1920929e-7 {
        return;
    }
    let alpha = a.compliance * params.inv_dt2;
    let dlambda = (-c - alpha * lambda[j]) / (w + alpha);
    lambda[j] += dlambda;
    move_by(a.particle, d / c * (w * dlambda));
}
