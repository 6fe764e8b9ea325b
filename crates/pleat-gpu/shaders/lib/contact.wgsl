// Self-contacts' shared layout and geometry (contact_grid.wgsl finds the
// candidate pairs, self_contact.wgsl solves them).
//
// candidates: a header, then the pairs found at the last build, two words
// each: a particle, then a triangle or, with PARTICLE_PAIR set, a particle.
// rest: [0, N) rest positions with the cloth's index in w, [N, 2N) the
// positions at the last build.

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
// the frames to go without it before the next try (0: the first wait);
// then the least and the greatest displacement of this substep along each
// axis (from `prev`, the substep's start), the least as the complement of
// its key so that zero (as the buffer starts, and as it is emptied after
// each build) is an empty range.
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
const STEP_LEAST: u32 = 16u;
const STEP_GREATEST: u32 = 19u;
const HEADER: u32 = 22u;
// A candidate's second word names a particle, not a triangle.
const PARTICLE_PAIR: u32 = 0x80000000u;

fn triangle(k: u32) -> vec3<u32> {
    return vec3<u32>(topology[3u * k], topology[3u * k + 1u], topology[3u * k + 2u]);
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

// Slack on the barycentric weights of a crossing point (the CPU backend's
// INSIDE_TOLERANCE).
const CROSSING_SLACK: f32 = 1e-3;
// Bisection steps that find when a vertex crossed a triangle's plane (to
// 1.5e-5 of the substep).
const CROSSING_STEPS: u32 = 16u;

// Particle k a fraction `s` of the way through the substep, moving
// linearly from its start (`prev`).
fn swept(k: u32, s: f32) -> vec3<f32> {
    return mix(prev[k].xyz, position(k), s);
}

// The triple product (b - a) x (c - a) . (p - a) of vertex i and triangle
// v a fraction `s` of the way through the substep: zero where the vertex
// lies in the triangle's plane.
fn coplanarity(i: u32, v: vec3<u32>, s: f32) -> f32 {
    let a = swept(v.x, s);
    return dot(cross(swept(v.y, s) - a, swept(v.z, s) - a), swept(i, s) - a);
}

// Continuous detection (the CPU backend's collide/ccd.rs, in f32): where
// vertex i passed through triangle v during the substep, as the
// triangle's barycentric weights of the crossing point (xyz) and w = 1; w
// = 0 where it did not. The vertex ends on the other side of the moving
// triangle's plane than it started; bisection finds a moment it lay in
// the plane, and the vertex must lie inside the triangle then. A vertex
// that crosses and crosses back within one substep ends on its side and
// is not reported.
fn crossing(i: u32, v: vec3<u32>) -> vec4<f32> {
    let start = coplanarity(i, v, 0.0);
    let end = coplanarity(i, v, 1.0);
    if start == 0.0 || end == 0.0 || (start > 0.0) == (end > 0.0) {
        return vec4<f32>(0.0);
    }
    var before = 0.0;
    var after = 1.0;
    for (var k = 0u; k < CROSSING_STEPS; k++) {
        let middle = 0.5 * (before + after);
        if (coplanarity(i, v, middle) > 0.0) == (start > 0.0) {
            before = middle;
        } else {
            after = middle;
        }
    }
    let a = swept(v.x, after);
    let ab = swept(v.y, after) - a;
    let ac = swept(v.z, after) - a;
    let ap = swept(i, after) - a;
    let n = cross(ab, ac);
    let area = dot(n, n);
    if area <= 0.0 {
        return vec4<f32>(0.0);
    }
    let wb = dot(cross(ap, ac), n) / area;
    let wc = dot(cross(ab, ap), n) / area;
    let w = vec3<f32>(1.0 - wb - wc, wb, wc);
    if any(w < vec3<f32>(-CROSSING_SLACK)) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(w, 1.0);
}
