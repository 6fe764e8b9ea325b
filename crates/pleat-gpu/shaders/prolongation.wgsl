// The hierarchy's prolongation (pleat::solver::hierarchy): the positions
// noted when the hierarchy begins, then, after each level is solved, each
// particle of the level below that it does not hold moved by the weighted
// mean of what its parents (particles of the level, which this dispatch
// does not move) moved since.

@group(1) @binding(0) var<storage, read_write> items: array<Prolongation>;
@group(1) @binding(1) var<storage, read_write> start: array<vec4<f32>>;

// Over every particle (the range is all of them).
@compute @workgroup_size(256)
fn snapshot(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = range_item(gid, groups);
    if i == NONE { return; }
    start[i] = pos[i];
}

@compute @workgroup_size(256)
fn prolongate(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let j = range_item(gid, groups);
    if j == NONE { return; }
    let p = items[j];
    var moved = vec3<f32>(0.0);
    for (var k = 0u; k < 4u; k++) {
        let c = p.parents[k];
        moved += p.weights[k] * (position(c) - start[c].xyz);
    }
    move_by(p.particle, moved);
}
