// Self-contacts' shared layout and geometry (contact_grid.wgsl finds the
// candidate pairs, self_contact.wgsl solves them).
//
// candidates: a header, then the pairs found at the last build, two words
// each: a particle, then a triangle or, with PARTICLE_PAIR set, a
// particle; or, with EDGE_PAIR set in the first, two edges.
// rest: [0, N) rest positions with the cloth's index in w, [N, 2N) the
// positions at the last build with how far each vertex's owned triangles
// reached from it then in w (contact_grid.wgsl's `owned_span`), [2N, 3N)
// the vertices' edge summaries at that build (`edge_summary`).

// Header words of `candidates`: the pairs found at the last build;
// nonzero while no particle has moved half the margin since that build
// (2 once its overflow is counted);
// then counters the host reads back and clears: the candidates solved
// and the contacts that acted, summed over substeps, the builds, and the
// most pairs a build found that did not all fit (0: none overflowed);
// then the least and the greatest displacement since the build along each
// axis (as keys ordered as the floats are); then the margin's state
// (contact_dispatch.wgsl's `choose_margin`): the builds of the frame so
// far, the frames since the margin was dropped plus one (0 while it is in
// use), the frames since it was last tried again plus one (0: never), and
// the frames to go without it before the next try (0: the first wait).
const FOUND: u32 = 0u;
const FRESH: u32 = 1u;
const SOLVED: u32 = 2u;
const ACTED: u32 = 3u;
const BUILDS: u32 = 4u;
const OVERFLOWED: u32 = 5u;
const LEAST: u32 = 6u;
const GREATEST: u32 = 9u;
const FRAME_BUILDS: u32 = 12u;
const DROPPED: u32 = 13u;
const SINCE_TRY: u32 = 14u;
const WAIT: u32 = 15u;
const HEADER: u32 = 16u;
// A candidate's second word names a particle, not a triangle.
const PARTICLE_PAIR: u32 = 0x80000000u;
// A candidate's first word names an edge, and its second word another.
const EDGE_PAIR: u32 = 0x80000000u;

fn triangle(k: u32) -> vec3<u32> {
    return vec3<u32>(topology[3u * k], topology[3u * k + 1u], topology[3u * k + 2u]);
}

// topology holds, after the triangles and the triangles each vertex owns,
// each particle's edges in compressed rows (starts, then edge indices),
// then each edge's two ends and the vertices opposite it in its
// triangles (NO_VERTEX where it has one).
fn incident_starts() -> u32 {
    return 4u * params.triangle_count + params.particle_count + 1u;
}

fn incident_list() -> u32 {
    return incident_starts() + params.particle_count + 1u;
}

const NO_VERTEX: u32 = 0xffffffffu;

// Edge e's ends, then the vertices opposite it.
fn edge_wings(e: u32) -> vec4<u32> {
    let k = incident_list() + topology[incident_starts() + params.particle_count] + 4u * e;
    return vec4<u32>(topology[k], topology[k + 1u], topology[k + 2u], topology[k + 3u]);
}

fn edge(e: u32) -> vec2<u32> {
    return edge_wings(e).xy;
}

// Parameters (s along p0 p1, u along q0 q1) of the closest points of two
// segments (Ericson 2005, 5.1.9), as the CPU backend's
// `ccd::segment_closest_params`.
fn segment_closest(p0: vec3<f32>, p1: vec3<f32>, q0: vec3<f32>, q1: vec3<f32>) -> vec2<f32> {
    let d1 = p1 - p0;
    let d2 = q1 - q0;
    let r = p0 - q0;
    let a = dot(d1, d1);
    let e = dot(d2, d2);
    let f = dot(d2, r);
    if a <= 1.1920929e-7 && e <= 1.1920929e-7 {
        return vec2<f32>(0.0);
    }
    if a <= 1.1920929e-7 {
        return vec2<f32>(0.0, clamp(f / e, 0.0, 1.0));
    }
    let c = dot(d1, r);
    if e <= 1.1920929e-7 {
        return vec2<f32>(clamp(-c / a, 0.0, 1.0), 0.0);
    }
    let b = dot(d1, d2);
    let denom = a * e - b * b;
    var s = 0.0;
    if denom > 0.0 {
        s = clamp((b * f - c * e) / denom, 0.0, 1.0);
    }
    var u = (b * s + f) / e;
    if u < 0.0 {
        u = 0.0;
        s = clamp(-c / a, 0.0, 1.0);
    } else if u > 1.0 {
        u = 1.0;
        s = clamp((b - c) / a, 0.0, 1.0);
    }
    return vec2<f32>(s, u);
}

// Closest point on triangle abc to p, as barycentric weights (Ericson 2005).
fn closest_barycentric(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 { return vec3<f32>(1.0, 0.0, 0.0); }
    let bp = p - b;
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 { return vec3<f32>(0.0, 1.0, 0.0); }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return vec3<f32>(1.0 - v, v, 0.0);
    }
    let cp = p - c;
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 { return vec3<f32>(0.0, 0.0, 1.0); }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return vec3<f32>(1.0 - w, 0.0, w);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return vec3<f32>(0.0, 1.0 - w, w);
    }
    let denom = 1.0 / (va + vb + vc);
    let v = vb * denom;
    let w = vc * denom;
    return vec3<f32>(1.0 - v - w, v, w);
}

// Cosine of 15 degrees: an edge whose triangles lie within it of each
// other is flat, and two flat edges whose normals do (either way up) lie
// in parallel layers, which the vertex-triangle contacts keep apart both
// ways: they are no candidate (as on the CPU backend).
const PARALLEL: f32 = 0.9659258;

// The unit normal of edge `e` (ends, then wings) if it is flat, else zero.
fn flat_normal(e: vec4<u32>) -> vec3<f32> {
    if e.z == NO_VERTEX || e.w == NO_VERTEX {
        return vec3<f32>(0.0);
    }
    let a = position(e.x);
    let along = position(e.y) - a;
    let n = normalize(cross(along, position(e.z) - a));
    let m = normalize(cross(position(e.w) - a, along));
    return select(vec3<f32>(0.0), n, dot(n, m) > PARALLEL);
}
