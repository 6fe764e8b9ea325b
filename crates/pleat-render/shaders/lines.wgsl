// Lines between particles (mesh edges, constraints), read from the same
// position buffer as the cloth; one instance per line.

@group(1) @binding(0) var<storage, read> positions: array<vec4<f32>>;

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec3<f32>,
};

@vertex
fn vs_main(
    @builtin(vertex_index) corner: u32,
    @location(0) ends: vec2<u32>,
    @location(1) color: vec4<f32>,
) -> LineOut {
    var out: LineOut;
    let p = positions[select(ends.x, ends.y, corner == 1u)].xyz;
    var clip = globals.view_proj * vec4<f32>(p, 1.0);
    // Drawn just in front of the surface they lie on.
    clip.z -= globals.misc.y * clip.w;
    out.clip = clip;
    out.color = color.rgb;
    return out;
}

@fragment
fn fs_main(in: LineOut) -> @location(0) vec4<f32> {
    return vec4<f32>(in.color, 1.0);
}
