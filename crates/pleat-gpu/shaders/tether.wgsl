// Long-range attachments: a particle no farther from its pin than at rest
// (crate::constraint::tether). Tethers of one colour move distinct particles.

@group(1) @binding(0) var<storage, read_write> items: array<Tether>;

@compute @workgroup_size(256)
fn solve(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let j = range_item(gid, groups);
    if j == NONE { return; }
    let c = items[j];
    if inv_mass(c.particle) == 0.0 {
        return;
    }
    let d = position(c.particle) - position(c.pin);
    let len = length(d);
    if len > c.max_length {
        move_by(c.particle, d * ((c.max_length - len) / len));
    }
}
