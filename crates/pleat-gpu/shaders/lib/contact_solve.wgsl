// Self-contacts' corrections (self_contact.wgsl solves the candidates of
// the last build with them, persistent.wgsl a small sheet's contact
// pairs), summed per particle in fixed point with integer atomics, in one
// of two ways:
//
// - paper's, as the CPU backend gathers them: a Jacobi iteration
//   evaluates every contact twice from the same positions, first counting
//   per particle the contacts that move it (`count_contact`), then summing
//   each contact's corrections scaled by the relaxation over the count of
//   its busiest particle (`scaled_contact`); `apply_correction` moves each
//   particle by its sum. One scale per contact keeps its corrections equal
//   and opposite, so the contacts keep the total momentum (averaged per
//   particle, a vertex in one contact would take the whole push of a
//   triangle in many, and jammed paper would never come to rest).
// - cloth's: each contact's corrections summed with a count per particle
//   (`sum_contact`), each particle moved by their average
//   (`apply_average`, Macklin et al. 2014). A cloth lying on a collider
//   under another takes its share of each push and the collider pushes it
//   back; scaled per contact, the lower cloth's many contacts would slow
//   the upper one's until it sank through (the CPU backend gives the
//   particles a collider holds no share instead, which the GPU has not).

const FIXED: f32 = 16777216.0;

// Jacobi over-relaxation of the scaled corrections (the CPU backend's
// `RELAXATION`).
const RELAXATION: f32 = 1.5;

// The corrections of the contact being evaluated, of up to four
// particles: `add_correction` lists them, `count_contact` or
// `scaled_contact` takes them (callers clear `touches` first).
var<private> touched: array<u32, 4>;
var<private> moves: array<vec3<f32>, 4>;
var<private> touches: u32;

fn add_correction(i: u32, dx: vec3<f32>) {
    touched[touches] = i;
    moves[touches] = dx;
    touches += 1u;
}

// Cloth's: the contact's corrections summed, each particle's contacts
// counted.
fn sum_contact() {
    for (var k = 0u; k < touches; k++) {
        let i = touched[k];
        let q = vec3<i32>(round(moves[k] * FIXED));
        atomicAdd(&accum[4u * i], q.x);
        atomicAdd(&accum[4u * i + 1u], q.y);
        atomicAdd(&accum[4u * i + 2u], q.z);
        atomicAdd(&accum[4u * i + 3u], 1);
    }
}

// Paper's first pass of an iteration: the contact counted for each particle it
// moves.
fn count_contact() {
    for (var k = 0u; k < touches; k++) {
        if any(moves[k] != vec3<f32>(0.0)) {
            atomicAdd(&accum[4u * touched[k] + 3u], 1);
        }
    }
}

// Paper's second: the contact's corrections, scaled by the relaxation over the
// count of its busiest particle, summed per particle.
fn scaled_contact() {
    var most = 1;
    for (var k = 0u; k < touches; k++) {
        most = max(most, atomicLoad(&accum[4u * touched[k] + 3u]));
    }
    let scale = RELAXATION / f32(most);
    for (var k = 0u; k < touches; k++) {
        let i = touched[k];
        let q = vec3<i32>(round(moves[k] * (scale * FIXED)));
        atomicAdd(&accum[4u * i], q.x);
        atomicAdd(&accum[4u * i + 1u], q.y);
        atomicAdd(&accum[4u * i + 2u], q.z);
    }
}

// The tangential part of the relative motion `relative` over the substep
// that Coulomb friction removes at penetration depth `depth`: all of it
// when it is within the static cone, else `kinetic * depth` of it.
fn friction(relative: vec3<f32>, n: vec3<f32>, depth: f32) -> vec3<f32> {
    let tangential = relative - n * dot(relative, n);
    let slide = length(tangential);
    if slide < params.contact_static * depth {
        return tangential;
    }
    if slide > 0.0 {
        return tangential * min(params.contact_kinetic * depth / slide, 1.0);
    }
    return vec3<f32>(0.0);
}

// Keeps particles i and j at the thickness from each other; whether it
// acted.
fn particle_contact(i: u32, j: u32) -> bool {
    let h = params.contact_thickness;
    let d = position(i) - position(j);
    let len = length(d);
    let wi = inv_mass(i);
    let wj = inv_mass(j);
    if len >= h || len <= 0.0 || wi + wj == 0.0 {
        return false;
    }
    let n = d / len;
    let s = (h - len) / (wi + wj);
    let f = friction((position(i) - prev[i].xyz) - (position(j) - prev[j].xyz), n, h - len) / (wi + wj);
    add_correction(i, n * (s * wi) - f * wi);
    add_correction(j, f * wj - n * (s * wj));
    return true;
}

// Keeps particle i at the thickness from triangle t on the side it was on,
// with friction on their relative motion; whether it acted.
fn triangle_contact(i: u32, t: vec3<u32>) -> bool {
    let h = params.contact_thickness;
    let p = position(i);
    let a = position(t.x);
    let b = position(t.y);
    let c = position(t.z);
    let bary = closest_barycentric(p, a, b, c);
    let q = bary.x * a + bary.y * b + bary.z * c;
    if distance(p, q) >= h {
        return false;
    }
    let normal = cross(b - a, c - a);
    let area2 = length(normal);
    if area2 <= 0.0 {
        return false;
    }
    let pa = prev[t.x].xyz;
    let prev_normal = cross(prev[t.y].xyz - pa, prev[t.z].xyz - pa);
    let side = select(-1.0, 1.0, dot(prev[i].xyz - pa, prev_normal) >= 0.0);
    let n = normal / area2 * side;
    let gap = dot(p - q, n) - h;
    if gap >= 0.0 {
        return false;
    }
    let w = vec4<f32>(inv_mass(i), inv_mass(t.x), inv_mass(t.y), inv_mass(t.z));
    let denom = w.x + dot(bary * bary, w.yzw);
    if denom <= 0.0 {
        return false;
    }
    let s = -gap / denom;
    let motion = (p - prev[i].xyz) - (bary.x * (a - prev[t.x].xyz) + bary.y * (b - prev[t.y].xyz) + bary.z * (c - prev[t.z].xyz));
    // The friction impulse shares the normal one's weights.
    let f = friction(motion, n, -gap) / denom;
    add_correction(i, n * (s * w.x) - f * w.x);
    add_correction(t.x, (n * (-s) + f) * (bary.x * w.y));
    add_correction(t.y, (n * (-s) + f) * (bary.y * w.z));
    add_correction(t.z, (n * (-s) + f) * (bary.z * w.w));
    return true;
}

// Keeps edges a and b at the thickness from each other at their closest
// points, on the side they were on at the substep's start, with friction
// on the points' relative motion; whether it acted. Edges found on the
// other side than they started, while they lay within two thicknesses
// then, crossed: they are pulled back along their separation at the
// start (the CPU backend finds the crossing by continuous detection).
fn edge_contact(a: vec2<u32>, b: vec2<u32>) -> bool {
    let h = params.contact_thickness;
    let a0 = position(a.x);
    let a1 = position(a.y);
    let b0 = position(b.x);
    let b1 = position(b.y);
    let st = segment_closest(a0, a1, b0, b1);
    let weights = vec4<f32>(1.0 - st.x, st.x, 1.0 - st.y, st.y);
    let diff = mix(a0, a1, st.x) - mix(b0, b1, st.y);
    let before = mix(prev[a.x].xyz, prev[a.y].xyz, st.x) - mix(prev[b.x].xyz, prev[b.y].xyz, st.y);
    let dist = length(diff);
    var n = diff / dist;
    var height = dist;
    if dot(diff, before) <= 0.0 && dot(before, before) < 4.0 * h * h {
        let gone = length(before);
        if gone <= 0.0 {
            return false;
        }
        n = before / gone;
        height = dot(diff, n);
    }
    // Not `height >= h`: edges that meet at a point (n is NaN) are left.
    if !(height < h) || any(n != n) {
        return false;
    }
    let w = vec4<f32>(inv_mass(a.x), inv_mass(a.y), inv_mass(b.x), inv_mass(b.y)) * weights;
    let denom = dot(w, weights);
    if denom <= 0.0 {
        return false;
    }
    let s = (h - height) / denom;
    let f = friction(diff - before, n, h - height) / denom;
    let push = n * s - f;
    add_correction(a.x, push * w.x);
    add_correction(a.y, push * w.y);
    add_correction(b.x, -push * w.z);
    add_correction(b.y, -push * w.w);
    return true;
}

// Particle i's summed corrections in fixed point (xyz) and count (w),
// cleared.
fn take_sums(i: u32) -> vec4<f32> {
    let n = atomicExchange(&accum[4u * i + 3u], 0);
    return vec4<f32>(
        f32(atomicExchange(&accum[4u * i], 0)),
        f32(atomicExchange(&accum[4u * i + 1u], 0)),
        f32(atomicExchange(&accum[4u * i + 2u], 0)),
        f32(n),
    );
}

// Moves particle i by the average of its contacts' corrections (cloth's),
// and clears them.
fn apply_average(i: u32) {
    let sums = take_sums(i);
    if sums.w > 0.0 && inv_mass(i) > 0.0 {
        move_by(i, sums.xyz / (FIXED * sums.w));
    }
}

// Moves particle i by the sum of its contacts' scaled corrections
// (paper's), and clears them and its count.
fn apply_correction(i: u32) {
    let sums = take_sums(i);
    if sums.w > 0.0 && inv_mass(i) > 0.0 {
        move_by(i, sums.xyz / FIXED);
    }
}
