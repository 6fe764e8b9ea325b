// Distance constraints, one colour per dispatch (crate::constraint::distance).

struct Distance {
    a: u32,
    b: u32,
    rest_length: f32,
    compliance: f32,
    slot: u32,
}

@group(1) @binding(0) var<storage, read_write> items: array<Distance>;
@group(1) @binding(1) var<storage, read_write> lambda: array<f32>;
@group(1) @binding(4) var<uniform> range: Range;

@compute @workgroup_size(256)
fn solve(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k >= range.count {
        return;
    }
    let j = range.first + k;
    let c = items[j];
    let wa = inv_mass(c.a);
    let wb = inv_mass(c.b);
    let w = wa + wb;
    if w == 0.0 {
        return;
    }
    let d = position(c.a) - position(c.b);
    let len = length(d);
    if !(len > 1.1920929e-7 * max(c.rest_length, 1e-6)) {
        return;
    }
    let n = d / len;
    let alpha = alpha_of(c.compliance, c.slot);
    let dlambda = (-(len - c.rest_length) - alpha * lambda[j]) / (w + alpha);
    lambda[j] += dlambda;
    move_by(c.a, n * (wa * dlambda));
    move_by(c.b, n * (-wb * dlambda));
}
