// Self-contacts' corrections (self_contact.wgsl solves the candidates of
// the last build with them, persistent.wgsl a small sheet's contact
// pairs): each contact's corrections summed per particle in `accum` in
// fixed point with integer atomics, then averaged by `apply_correction`.

const FIXED: f32 = 16777216.0;

fn add_correction(i: u32, dx: vec3<f32>) {
    let q = vec3<i32>(round(dx * FIXED));
    atomicAdd(&accum[4u * i], q.x);
    atomicAdd(&accum[4u * i + 1u], q.y);
    atomicAdd(&accum[4u * i + 2u], q.z);
    atomicAdd(&accum[4u * i + 3u], 1);
}

// Whether a collider held particle i in the substep before (collide.wgsl
// notes it in the velocity's w).
fn held(i: u32) -> bool {
    return vel[i].w != 0.0;
}

// The inverse masses `w` of a contact's particles (the first side's where
// `first`, their shares of the contact point `share`), none on a side
// whose every particle that shares in the point a collider held (`side_held`),
// where the other side can move: the collider stands behind them, so the
// other side gives way (crate::collide::ContactMasses::of). A cloth lying
// on the floor is thus not pushed into it by one landing on it, for the
// floor to lift it back up through the cloth above.
fn contact_masses(w: vec4<f32>, first: vec4<bool>, held: vec2<bool>, share: vec4<f32>) -> vec4<f32> {
    let zeroed = select(w, vec4<f32>(0.0), select(vec4<bool>(held.y), vec4<bool>(held.x), first));
    return select(w, zeroed, dot(zeroed, share * share) > 0.0);
}

// Whether every particle of a side (held where `held`) that shares in the
// contact point (`share` above zero) was held.
fn side_held(held: vec3<bool>, share: vec3<f32>) -> bool {
    return all(held | !(share > vec3<f32>(0.0)));
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
    let m = contact_masses(
        vec4<f32>(inv_mass(i), inv_mass(j), 0.0, 0.0),
        vec4<bool>(true, false, false, false),
        vec2<bool>(held(i), held(j)),
        vec4<f32>(1.0, 1.0, 0.0, 0.0),
    );
    let wi = m.x;
    let wj = m.y;
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

// Keeps particle i at the thickness from triangle t on the side it was on
// at the substep's start, with friction on their relative motion; whether
// it acted. A particle farther than the thickness from the triangle acts
// only where its path went through the face of a steady triangle in the
// substep (`crossed_face`; the CPU backend finds every crossing by
// continuous detection).
fn triangle_contact(i: u32, t: vec3<u32>) -> bool {
    let h = params.contact_thickness;
    let p = position(i);
    let a = position(t.x);
    let b = position(t.y);
    let c = position(t.z);
    var bary = closest_barycentric(p, a, b, c);
    let beyond = distance(p, bary.x * a + bary.y * b + bary.z * c) - h;
    if beyond >= 0.0 && !may_have_crossed(i, t, beyond) {
        return false;
    }
    let normal = cross(b - a, c - a);
    let area2 = length(normal);
    if area2 <= 0.0 {
        return false;
    }
    let pa = prev[t.x].xyz;
    let prev_normal = cross(prev[t.y].xyz - pa, prev[t.z].xyz - pa);
    let start_height = dot(prev[i].xyz - pa, prev_normal) / max(length(prev_normal), 1e-30);
    let n = normal / area2 * select(-1.0, 1.0, start_height >= 0.0);
    if beyond >= 0.0 {
        let normals = array<vec3<f32>, 2>(normal / area2, prev_normal);
        bary = crossed_face(i, t, normals, vec2<f32>(abs(start_height), dot(p - a, n)));
        if bary.x < 0.0 {
            return false;
        }
    }
    let q = bary.x * a + bary.y * b + bary.z * c;
    let gap = dot(p - q, n) - h;
    if gap >= 0.0 {
        return false;
    }
    let w = contact_masses(
        vec4<f32>(inv_mass(i), inv_mass(t.x), inv_mass(t.y), inv_mass(t.z)),
        vec4<bool>(true, false, false, false),
        vec2<bool>(held(i), side_held(vec3<bool>(held(t.x), held(t.y), held(t.z)), bary)),
        vec4<f32>(1.0, bary),
    );
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

// Whether particle i, `beyond` farther than the thickness from triangle t
// now, moved far enough from it in the substep to have crossed it: from
// where it crossed, within the thickness of the face, it has moved at
// least `beyond` from the triangle's nearest point, which moved no more
// than the triangle's corners.
fn may_have_crossed(i: u32, t: vec3<u32>, beyond: f32) -> bool {
    let corners = max(distance(position(t.x), prev[t.x].xyz), max(distance(position(t.y), prev[t.y].xyz), distance(position(t.z), prev[t.z].xyz)));
    return distance(position(i), prev[i].xyz) + corners > beyond;
}

// Cosine of 5 degrees: a triangle that turned less in a substep is steady.
const STEADY: f32 = 0.9961947;
// How near its face, in thicknesses, a particle crossing a triangle's
// plane went through the face (on it, but for the round-off of taking the
// height as linear in time): one passing by an edge has not.
const ON_FACE: f32 = 0.05;

// Where particle i's path over the substep went through the face of
// triangle t, both taken as moving linearly, if the triangle is steady
// (its unit normal now and its normal at the start, `normals`, within
// STEADY), so that i's height over its plane (`heights`: at the start and
// now, positive on the side i started on) is all but linear in time: the
// barycentric coordinates of the triangle's point i met when that height
// changed sign, where i lay within the thickness of the face then; else a
// negative x.
fn crossed_face(i: u32, t: vec3<u32>, normals: array<vec3<f32>, 2>, heights: vec2<f32>) -> vec3<f32> {
    let steady = dot(normals[0], normals[1]) >= STEADY * length(normals[1]);
    if !steady || !(heights.y < 0.0) {
        return vec3<f32>(-1.0);
    }
    let s = heights.x / (heights.x - heights.y);
    let p = mix(prev[i].xyz, position(i), s);
    let a = mix(prev[t.x].xyz, position(t.x), s);
    let b = mix(prev[t.y].xyz, position(t.y), s);
    let c = mix(prev[t.z].xyz, position(t.z), s);
    let w = closest_barycentric(p, a, b, c);
    if distance(p, w.x * a + w.y * b + w.z * c) >= ON_FACE * params.contact_thickness {
        return vec3<f32>(-1.0);
    }
    return w;
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
    let held_a = side_held(vec3<bool>(held(a.x), held(a.y), true), vec3<f32>(weights.xy, 0.0));
    let held_b = side_held(vec3<bool>(held(b.x), held(b.y), true), vec3<f32>(weights.zw, 0.0));
    let masses = contact_masses(
        vec4<f32>(inv_mass(a.x), inv_mass(a.y), inv_mass(b.x), inv_mass(b.y)),
        vec4<bool>(true, true, false, false),
        vec2<bool>(held_a, held_b),
        weights,
    );
    let w = masses * weights;
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

// Moves particle i by the average of the corrections summed for it, and
// clears them.
fn apply_correction(i: u32) {
    let n = atomicExchange(&accum[4u * i + 3u], 0);
    let sum = vec3<f32>(
        f32(atomicExchange(&accum[4u * i], 0)),
        f32(atomicExchange(&accum[4u * i + 1u], 0)),
        f32(atomicExchange(&accum[4u * i + 2u], 0)),
    );
    if n > 0 && inv_mass(i) > 0.0 {
        move_by(i, sum / (FIXED * f32(n)));
    }
}
