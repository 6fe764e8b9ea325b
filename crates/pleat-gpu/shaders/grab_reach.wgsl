// Long-range attachments to the grabbed particle
// (pleat::solver::grab_reach): every dynamic particle of its cloth pulled
// back within its reach of it; over every particle, after the grab.

// Rest position (xyz) and reach factor (w; 0: the cloth keeps no length).
@group(1) @binding(0) var<storage, read_write> rest: array<vec4<f32>>;
// Each particle's cloth: its stretch compliance slot, and 1 where a strain
// limit holds the reach whatever the compliance.
@group(1) @binding(1) var<storage, read_write> cloth: array<vec2<u32>>;

@compute @workgroup_size(256)
fn reach(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let i = range_item(gid, groups);
    let g = params.grab_particle;
    if i == NONE || g >= params.particle_count {
        return;
    }
    let held = rest[g];
    let c = cloth[g];
    let compliant = c.y == 0u && compliances[c.x / 4u][c.x % 4u] != 0.0;
    if held.w == 0.0 || compliant || any(cloth[i] != c) || inv_mass(i) == 0.0 {
        return;
    }
    let r = rest[i];
    let limit = r.w * distance(r.xyz, held.xyz);
    let at = position(g);
    let d = position(i) - at;
    let len = length(d);
    if len > limit {
        pos[i] = vec4<f32>(at + d * (limit / len), pos[i].w);
    }
}
