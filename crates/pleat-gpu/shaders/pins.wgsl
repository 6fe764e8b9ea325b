// Hard pins: kinematic particles put on their targets at the end of the
// substep (crate::solver::position_based::HardPins). Targets hold, per
// substep, the hard pins' targets then the soft attachments'.

@group(1) @binding(0) var<storage, read_write> pins: array<u32>;
@group(1) @binding(2) var<storage, read_write> targets: array<vec4<f32>>;

@compute @workgroup_size(256)
fn place_pins(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let k = flat_index(gid, groups);
    if k >= range.count {
        return;
    }
    let i = pins[k];
    pos[i] = vec4<f32>(targets[params.substep * params.pin_count + k].xyz, pos[i].w);
}
