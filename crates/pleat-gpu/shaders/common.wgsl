// Shared by every kernel, after structs.wgsl and the state's bindings
// (state.wgsl, or a persistent kernel's own): constants and helpers.
// Positions carry the inverse mass in w (zero for pinned particles).

const WORKGROUP: u32 = 256u;
const PI: f32 = 3.14159265358979;
const TAU: f32 = 6.28318530717959;
// The largest magnitude taken as finite: just under f32::MAX, which naga
// writes back out as a decimal that WebGPU (Tint) refuses as out of range.
const MAX_FINITE: f32 = 3.4e38;
// No index.
const NONE: u32 = 0xffffffffu;

// The builtins of a compute invocation, as one entry-point parameter.
struct Invocation {
    @builtin(global_invocation_id) gid: vec3<u32>,
    @builtin(local_invocation_id) lid: vec3<u32>,
    @builtin(workgroup_id) wid: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
}

// Flat invocation index of a dispatch that may spread over two dimensions.
fn flat_index(gid: vec3<u32>, groups: vec3<u32>) -> u32 {
    return gid.x + gid.y * groups.x * WORKGROUP;
}

// Flat index of an invocation's workgroup (a block of a reduction).
fn block_index(at: Invocation) -> u32 {
    return at.wid.x + at.wid.y * at.groups.x;
}

fn position(i: u32) -> vec3<f32> {
    return pos[i].xyz;
}

fn inv_mass(i: u32) -> f32 {
    return pos[i].w;
}

// alpha~ = compliance * table[slot] / dt^2, rounded as the CPU does.
fn alpha_of(compliance: f32, slot: u32) -> f32 {
    return compliance * (params.inv_dt2 * compliances[slot / 4u][slot % 4u]);
}

fn move_by(i: u32, dx: vec3<f32>) {
    pos[i] = vec4<f32>(pos[i].xyz + dx, pos[i].w);
}

// atan2 to within 2e-6 rad: the polynomial of crate::constraint::bending::fast_atan2.
fn fast_atan2(y: f32, x: f32) -> f32 {
    let ax = abs(x);
    let ay = abs(y);
    let num = select(ay, ax, ay > ax);
    let den = select(ax, ay, ay > ax);
    if den == 0.0 {
        return 0.0;
    }
    let t = num / den;
    let t2 = t * t;
    var poly = -0.0117212;
    poly = poly * t2 + 0.05265332;
    poly = poly * t2 - 0.11643287;
    poly = poly * t2 + 0.19354346;
    poly = poly * t2 - 0.33262347;
    poly = poly * t2 + 0.99997726;
    var a = t * poly;
    if ay > ax {
        a = 1.5707963267948966 - a;
    }
    if x < 0.0 {
        a = PI - a;
    }
    return select(a, -a, y < 0.0 || (y == 0.0 && bitcast<u32>(y) != 0u));
}

// The signed fold angle of a triangle pair (shared edge p0 p1, wings p2 p3)
// and its gradient (crate::constraint::bending::dihedral_angle_simd);
// ok is false for a degenerate pair.
struct Dihedral {
    phi: f32,
    ok: bool,
    g0: vec3<f32>,
    g1: vec3<f32>,
    g2: vec3<f32>,
    g3: vec3<f32>,
}

fn dihedral_angle(p0: vec3<f32>, p1: vec3<f32>, p2: vec3<f32>, p3: vec3<f32>) -> Dihedral {
    var r: Dihedral;
    r.ok = false;
    let e = p1 - p0;
    let len2 = dot(e, e);
    let na = cross(e, p2 - p0);
    let nb = cross(p3 - p0, e);
    let a2 = dot(na, na);
    let b2 = dot(nb, nb);
    let tiny = 1e-12 * len2 * len2;
    if len2 <= 1.17549435e-38 || a2 <= tiny || b2 <= tiny {
        return r;
    }
    let len = sqrt(len2);
    r.phi = fast_atan2(dot(cross(nb, na), e) / len, dot(na, nb));
    r.g2 = na * (len / a2);
    r.g3 = nb * (len / b2);
    let s2 = dot(p2 - p0, e) / len2;
    let s3 = dot(p3 - p0, e) / len2;
    r.g0 = -(1.0 - s2) * r.g2 - (1.0 - s3) * r.g3;
    r.g1 = -s2 * r.g2 - s3 * r.g3;
    r.ok = true;
    return r;
}

// The XPBD multiplier update (crate::constraint::xpbd::lagrange_update):
// dlambda = (-c - alpha~ lambda) / (sum w |grad C|^2 + alpha~) for a
// constraint of value c, weighted gradient norm sum w |grad C|^2 and alpha~;
// the caller adds it to lambda and moves the particles by it. Zero where the
// denominator is not positive (nothing can move): a step of zero moves
// nothing and leaves lambda as it was.
fn lagrange_update(c: f32, weighted_gradient_norm: f32, alpha_tilde: f32, lambda: f32) -> f32 {
    let denominator = weighted_gradient_norm + alpha_tilde;
    if denominator <= 1.17549435e-38 {
        return 0.0;
    }
    return (-c - alpha_tilde * lambda) / denominator;
}

// The dihedral angle of four particles (see dihedral_angle).
fn dihedral_of(v: array<u32, 4>) -> Dihedral {
    return dihedral_angle(position(v[0]), position(v[1]), position(v[2]), position(v[3]));
}

// XPBD update of a constraint on four particles with value c, gradient d
// and alpha~ (crate::constraint::bending::project_four); returns the new multiplier.
fn project_four(v: array<u32, 4>, alpha: f32, c: f32, d: Dihedral, lambda: f32) -> f32 {
    let w0 = inv_mass(v[0]);
    let w1 = inv_mass(v[1]);
    let w2 = inv_mass(v[2]);
    let w3 = inv_mass(v[3]);
    let norm = w0 * dot(d.g0, d.g0) + w1 * dot(d.g1, d.g1) + w2 * dot(d.g2, d.g2) + w3 * dot(d.g3, d.g3);
    let dlambda = lagrange_update(c, norm, alpha, lambda);
    if dlambda == 0.0 {
        return lambda;
    }
    if w0 > 0.0 { move_by(v[0], d.g0 * (w0 * dlambda)); }
    if w1 > 0.0 { move_by(v[1], d.g1 * (w1 * dlambda)); }
    if w2 > 0.0 { move_by(v[2], d.g2 * (w2 * dlambda)); }
    if w3 > 0.0 { move_by(v[3], d.g3 * (w3 * dlambda)); }
    return lambda + dlambda;
}
