// Origami hinges, one colour per dispatch, and the tracking of their
// continuous fold angle after each substep (lib/hinge.wgsl).

@group(1) @binding(0) var<storage, read_write> hinges: array<Hinge>;
@group(1) @binding(1) var<storage, read_write> hinge_lambda: array<f32>;

@compute @workgroup_size(256)
fn solve(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let j = range_item(gid, groups);
    if j != NONE {
        solve_hinge(j);
    }
}

@compute @workgroup_size(256)
fn track(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    // The range is every hinge (first 0).
    let j = range_item(gid, groups);
    if j != NONE {
        track_hinge(j);
    }
}
