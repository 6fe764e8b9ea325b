// Long-range attachments: a particle no farther from its pin than at rest
// (crate::constraint::tether). Tethers of one colour move distinct particles.

struct Tether {
    particle: u32,
    pin: u32,
    max_length: f32,
}

@group(1) @binding(0) var<storage, read_write> items: array<Tether>;
@group(1) @binding(4) var<uniform> range: Range;

@compute @workgroup_size(256)
fn solve(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k >= range.count {
        return;
    }
    let c = items[range.first + k];
    if inv_mass(c.particle) == 0.0 {
        return;
    }
    let d = position(c.particle) - position(c.pin);
    let len = length(d);
    if len > c.max_length {
        move_by(c.particle, d * ((c.max_length - len) / len));
    }
}
