// Shared by cloth.wgsl, lines.wgsl and meshes.wgsl (prepended to each):
// the per-frame uniforms, the shadow map and the environment cube map, and
// Blinn-Phong lighting with shadows.

struct Globals {
    view_proj: mat4x4<f32>,
    light_view_proj: mat4x4<f32>,
    inv_view_proj: mat4x4<f32>,
    camera_position: vec4<f32>,
    // xyz: unit vector from the surface towards the light.
    light_direction: vec4<f32>,
    // rgb: colour times intensity of the light.
    light_color: vec4<f32>,
    front_color: vec4<f32>,
    back_color: vec4<f32>,
    // x: bump height (m), y: displacement (m), z: strain at the red end of the colour map, w: shininess.
    material: vec4<f32>,
    // x: shadow map texel size, y: depth offset of lines (clip space), z: specular strength.
    misc: vec4<f32>,
    // x: view (0 shaded, 1 wireframe, 2 constraints, 3 strain), y: 1 for flat facets (paper).
    mode: vec4<u32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;
@group(0) @binding(1) var shadow_map: texture_depth_2d;
@group(0) @binding(2) var shadow_sampler: sampler_comparison;
@group(0) @binding(3) var environment: texture_cube<f32>;
@group(0) @binding(4) var environment_sampler: sampler;

const VIEW_SHADED: u32 = 0u;
const VIEW_STRAIN: u32 = 3u;

// Fraction of light reaching `world` (1 lit, 0 in shadow): 3 x 3 percentage-closer filtering.
fn shadow_factor(world: vec3<f32>, normal: vec3<f32>) -> f32 {
    let clip = globals.light_view_proj * vec4<f32>(world + normal * 0.004, 1.0);
    let ndc = clip.xyz / clip.w;
    let uv = vec2<f32>(ndc.x * 0.5 + 0.5, 0.5 - ndc.y * 0.5);
    if (any(uv < vec2<f32>(0.0)) || any(uv > vec2<f32>(1.0)) || ndc.z > 1.0) {
        return 1.0;
    }
    let texel = globals.misc.x;
    var lit = 0.0;
    for (var y = -1; y <= 1; y++) {
        for (var x = -1; x <= 1; x++) {
            let offset = vec2<f32>(f32(x), f32(y)) * texel;
            lit += textureSampleCompareLevel(shadow_map, shadow_sampler, uv + offset, ndc.z - 0.0015);
        }
    }
    return lit / 9.0;
}

// Light from the sky and the ground: a hemisphere blend on the normal.
fn ambient(normal: vec3<f32>) -> vec3<f32> {
    let sky = vec3<f32>(0.55, 0.62, 0.75);
    let ground = vec3<f32>(0.35, 0.32, 0.3);
    return mix(ground, sky, normal.y * 0.5 + 0.5) * 0.45;
}

// Blinn-Phong: ambient, Lambert diffuse and a specular lobe on the half vector.
fn blinn_phong(base: vec3<f32>, normal: vec3<f32>, world: vec3<f32>) -> vec3<f32> {
    let l = globals.light_direction.xyz;
    let v = normalize(globals.camera_position.xyz - world);
    let h = normalize(l + v);
    let shadow = shadow_factor(world, normal);
    let diffuse = max(dot(normal, l), 0.0);
    let specular = select(0.0, pow(max(dot(normal, h), 0.0), globals.material.w), diffuse > 0.0)
        * globals.misc.z;
    let light = globals.light_color.rgb * shadow;
    return base * (ambient(normal) + diffuse * light) + specular * light;
}

// The strain colour map: blue (0) through cyan, green and yellow to red (1).
fn strain_color(t: f32) -> vec3<f32> {
    let x = clamp(t, 0.0, 1.0) * 4.0;
    let r = clamp(x - 2.0, 0.0, 1.0);
    let g = clamp(x, 0.0, 1.0) - clamp(x - 3.0, 0.0, 1.0);
    let b = 1.0 - clamp(x - 1.0, 0.0, 1.0);
    return vec3<f32>(r, g, b);
}
