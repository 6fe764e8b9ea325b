// Colliders, the ground and the sky: matte Blinn-Phong, checked in the
// collider's own frame (so a turning body is seen to turn), a mirror that
// reflects the environment cube map, a checkered ground that receives the
// shadows, and the cube map itself behind everything.

struct MeshIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
    // The point in the collider's frame, in checks.
    @location(3) body: vec3<f32>,
    // 0 matte, 1 mirror, 2 ground, 3 patterned.
    @location(4) kind: u32,
};

struct MeshOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec3<f32>,
    @location(3) @interpolate(flat) kind: u32,
    @location(4) body: vec3<f32>,
};

const KIND_MIRROR: u32 = 1u;
const KIND_GROUND: u32 = 2u;
const KIND_PATTERNED: u32 = 3u;

@vertex
fn vs_main(in: MeshIn) -> MeshOut {
    var out: MeshOut;
    out.clip = globals.view_proj * vec4<f32>(in.position, 1.0);
    out.world = in.position;
    out.normal = in.normal;
    out.color = in.color.rgb;
    out.kind = in.kind;
    out.body = in.body;
    return out;
}

@vertex
fn vs_shadow(in: MeshIn) -> @builtin(position) vec4<f32> {
    return globals.light_view_proj * vec4<f32>(in.position, 1.0);
}

@fragment
fn fs_main(in: MeshOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    var n = normalize(in.normal);
    if (!front) {
        n = -n;
    }
    var color: vec3<f32>;
    if (in.kind == KIND_MIRROR) {
        let v = normalize(globals.camera_position.xyz - in.world);
        let reflected = textureSampleLevel(environment, environment_sampler, reflect(-v, n), 0.0).rgb;
        let h = normalize(globals.light_direction.xyz + v);
        let highlight = pow(max(dot(n, h), 0.0), 200.0) * shadow_factor(in.world, n);
        color = reflected * in.color + highlight * globals.light_color.rgb;
    } else if (in.kind == KIND_GROUND) {
        let cell = floor(in.world.xz * 4.0);
        let checker = select(0.62, 0.7, (i32(cell.x) + i32(cell.y)) % 2 == 0);
        color = blinn_phong(in.color * checker, n, in.world);
    } else if (in.kind == KIND_PATTERNED) {
        // 3D checks in the body frame: light and dark cells alternate.
        let cell = vec3<i32>(floor(in.body));
        let dark = ((cell.x + cell.y + cell.z) & 1) == 1;
        color = blinn_phong(in.color * select(1.0, 0.55, dark), n, in.world);
    } else {
        color = blinn_phong(in.color, n, in.world);
    }
    return vec4<f32>(color, 1.0);
}

struct SkyOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) ndc: vec2<f32>,
};

// One triangle over the whole screen, at the far plane.
@vertex
fn vs_sky(@builtin(vertex_index) i: u32) -> SkyOut {
    let ndc = vec2<f32>(f32(i32(i & 1u) * 4 - 1), f32(i32(i >> 1u) * 4 - 1));
    var out: SkyOut;
    out.clip = vec4<f32>(ndc, 1.0, 1.0);
    out.ndc = ndc;
    return out;
}

@fragment
fn fs_sky(in: SkyOut) -> @location(0) vec4<f32> {
    let far = globals.inv_view_proj * vec4<f32>(in.ndc, 1.0, 1.0);
    let direction = far.xyz / far.w - globals.camera_position.xyz;
    return vec4<f32>(textureSampleLevel(environment, environment_sampler, direction, 0.0).rgb, 1.0);
}
