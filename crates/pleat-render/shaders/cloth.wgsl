// The cloth: positions straight from a storage buffer (array<vec4<f32>>,
// xyz = position), smooth normals and edge strain from normals.wgsl,
// displacement from the height map in the vertex stage, bump mapping,
// two-sided Blinn-Phong with a texture, and the strain colour map.

@group(1) @binding(0) var<storage, read> positions: array<vec4<f32>>;
// xyz: unit normal, w: largest edge strain at the vertex.
@group(1) @binding(1) var<storage, read> normals: array<vec4<f32>>;
@group(1) @binding(2) var<storage, read> uvs: array<vec2<f32>>;
@group(1) @binding(3) var albedo: texture_2d<f32>;
@group(1) @binding(4) var height_map: texture_2d<f32>;
@group(1) @binding(5) var material_sampler: sampler;

// globals.mode.y: shade with the facet normal instead of the smooth one.
const FLAT_FACETS: u32 = 1u;

struct ClothOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) strain: f32,
};

// The position of particle `i` moved along its normal by the height map.
fn displaced(i: u32) -> vec3<f32> {
    let h = textureSampleLevel(height_map, material_sampler, uvs[i], 0.0).r;
    return positions[i].xyz + normals[i].xyz * (h - 0.5) * globals.material.y;
}

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> ClothOut {
    var out: ClothOut;
    let world = displaced(i);
    out.clip = globals.view_proj * vec4<f32>(world, 1.0);
    out.world = world;
    out.normal = normals[i].xyz;
    out.uv = uvs[i];
    out.strain = normals[i].w;
    return out;
}

@vertex
fn vs_shadow(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return globals.light_view_proj * vec4<f32>(displaced(i), 1.0);
}

@fragment
fn fs_main(in: ClothOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    // Derivatives first, in uniform control flow.
    let texel = textureSample(albedo, material_sampler, in.uv).rgb;
    let h = textureSample(height_map, material_sampler, in.uv).r;
    let dhdx = dpdx(h);
    let dhdy = dpdy(h);
    let dpx = dpdx(in.world);
    let dpy = dpdy(in.world);

    var n = normalize(in.normal);
    if (!front) {
        n = -n;
    }
    let face = cross(dpx, dpy);
    if (globals.mode.y == FLAT_FACETS && dot(face, face) > 0.0) {
        // Paper: flat facets and sharp creases, lit on the side seen.
        let to_eye = globals.camera_position.xyz - in.world;
        n = normalize(face) * sign(dot(face, to_eye));
    }
    // Bump mapping without tangents (Mikkelsen 2010, "Bump Mapping Unparametrized Surfaces on the GPU").
    let r1 = cross(dpy, n);
    let r2 = cross(n, dpx);
    let det = dot(dpx, r1);
    let surface_gradient = sign(det) * (dhdx * r1 + dhdy * r2);
    let view = globals.mode.x;
    let bump = globals.material.x;
    if (view == VIEW_SHADED && bump > 0.0 && abs(det) > 1e-20) {
        n = normalize(abs(det) * n - bump * surface_gradient);
    }

    var base: vec3<f32>;
    if (view == VIEW_SHADED) {
        base = select(globals.back_color.rgb, globals.front_color.rgb, front) * texel;
    } else if (view == VIEW_STRAIN) {
        base = strain_color(in.strain / globals.material.z);
    } else {
        // Wireframe and constraint views: a pale surface under the lines.
        base = vec3<f32>(0.8, 0.8, 0.78);
    }
    return vec4<f32>(blinn_phong(base, n, in.world), 1.0);
}
