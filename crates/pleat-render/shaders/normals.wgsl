// Smooth vertex normals and edge strain, one invocation per particle: the
// area-weighted sum of the incident triangles' normals, and the largest
// |length / rest length - 1| of the edges at the particle. Reads positions
// as array<vec4<f32>> (xyz = position, w = inverse mass, unused), so it
// runs on the GPU backend's own buffer with no readback.

struct Counts {
    // x: particles.
    counts: vec4<u32>,
};

@group(0) @binding(0) var<uniform> params: Counts;
@group(0) @binding(1) var<storage, read> positions: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read> rest: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read> triangles: array<u32>;
// Triangles around particle i: incidence[incidence_start[i]..incidence_start[i + 1]].
@group(0) @binding(4) var<storage, read> incidence_start: array<u32>;
@group(0) @binding(5) var<storage, read> incidence: array<u32>;
@group(0) @binding(6) var<storage, read_write> normals: array<vec4<f32>>;

fn edge_strain(a: u32, b: u32) -> f32 {
    let rest_length = distance(rest[a].xyz, rest[b].xyz);
    if (rest_length <= 0.0) {
        return 0.0;
    }
    return abs(distance(positions[a].xyz, positions[b].xyz) / rest_length - 1.0);
}

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= params.counts.x) {
        return;
    }
    var sum = vec3<f32>(0.0);
    var strain = 0.0;
    for (var k = incidence_start[i]; k < incidence_start[i + 1u]; k++) {
        let t = incidence[k] * 3u;
        let a = triangles[t];
        let b = triangles[t + 1u];
        let c = triangles[t + 2u];
        let pa = positions[a].xyz;
        sum += cross(positions[b].xyz - pa, positions[c].xyz - pa);
        // The two edges of the triangle that meet at particle i.
        var others = vec2<u32>(b, c);
        if (i == b) {
            others = vec2<u32>(c, a);
        } else if (i == c) {
            others = vec2<u32>(a, b);
        }
        strain = max(strain, max(edge_strain(i, others.x), edge_strain(i, others.y)));
    }
    let len = length(sum);
    var n = vec3<f32>(0.0, 1.0, 0.0);
    if (len > 0.0) {
        n = sum / len;
    }
    normals[i] = vec4<f32>(n, strain);
}
