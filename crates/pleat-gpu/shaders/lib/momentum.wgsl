// Angular momentum kept through a substep's own constraints
// (crate::solver::momentum), on a particle: its share of the mass-weighted
// sums of how far the projection moved a free cloth's particles from the
// exact prediction x_prev + dt v, the smallest rigid turn about the centre
// of mass that takes their angular impulse back, and that turn applied.
// The includer binds `left`, what the last turn could not move each
// particle by (round-off).

// Mass-weighted sums over the cloth, with m the mass, p the position
// before the substep, x the position now and d how far x is from the
// prediction, less what the last turn left.
struct Sums {
    // sum m x, and sum m in w.
    mx: vec4<f32>,
    mp: vec4<f32>,
    // sum m p x d
    mpd: vec4<f32>,
    md: vec4<f32>,
    // sum m x p^T, by columns.
    mxp0: vec4<f32>,
    mxp1: vec4<f32>,
    mxp2: vec4<f32>,
}

// Turns smaller than this (radians) are the sums' round-off, and skipped
// (crate::solver::momentum::SMALLEST_TURN).
const SMALLEST_TURN: f32 = 1e-9;

fn zero_sums() -> Sums {
    let z = vec4<f32>(0.0);
    return Sums(z, z, z, z, z, z, z);
}

fn add_sums(a: Sums, b: Sums) -> Sums {
    return Sums(a.mx + b.mx, a.mp + b.mp, a.mpd + b.mpd, a.md + b.md,
                a.mxp0 + b.mxp0, a.mxp1 + b.mxp1, a.mxp2 + b.mxp2);
}

// Particle i's share.
fn measure_particle(i: u32) -> Sums {
    var s = zero_sums();
    let m = 1.0 / pos[i].w;
    let x = pos[i].xyz;
    let p = prev[i].xyz;
    let d = (x - p) - vel[i].xyz * params.dt - left[i].xyz;
    s.mx = vec4<f32>(x * m, m);
    s.mp = vec4<f32>(p * m, 0.0);
    s.mpd = vec4<f32>(cross(p, d) * m, 0.0);
    s.md = vec4<f32>(d * m, 0.0);
    s.mxp0 = vec4<f32>(x * (m * p.x), 0.0);
    s.mxp1 = vec4<f32>(x * (m * p.y), 0.0);
    s.mxp2 = vec4<f32>(x * (m * p.z), 0.0);
    return s;
}

// The rotation vector theta with sum m p x (theta x r) = -sum m p x d, p
// and r about their centres of mass; zero where the cloth lies on a line.
fn spurious_turn(s: Sums) -> vec3<f32> {
    let mass = s.mx.w;
    let c = s.mx.xyz / mass;
    let cp = s.mp.xyz / mass;
    let impulse = s.mpd.xyz - cross(cp, s.md.xyz);
    // sum m r p^T, and the map theta -> (p . r) theta - r (p . theta).
    let rp = mat3x3<f32>(s.mxp0.xyz - c * (mass * cp.x),
                         s.mxp1.xyz - c * (mass * cp.y),
                         s.mxp2.xyz - c * (mass * cp.z));
    let trace = rp[0].x + rp[1].y + rp[2].z;
    let map = mat3x3<f32>(vec3<f32>(trace, 0.0, 0.0), vec3<f32>(0.0, trace, 0.0),
                          vec3<f32>(0.0, 0.0, trace)) - rp;
    let scale = map[0].x + map[1].y + map[2].z;
    let det = determinant(map);
    if !(abs(det) > 1e-9 * scale * scale * scale) {
        return vec3<f32>(0.0);
    }
    // The inverse's rows are the cross products of the columns over det.
    let inverse = transpose(mat3x3<f32>(cross(map[1], map[2]), cross(map[2], map[0]),
                                        cross(map[0], map[1]))) * (1.0 / det);
    let turn = -(inverse * impulse);
    return select(vec3<f32>(0.0), turn, length(turn) > SMALLEST_TURN);
}

// Particle i turned by theta about `centre`.
fn apply_turn(i: u32, theta: vec3<f32>, centre: vec3<f32>) {
    let x = pos[i].xyz;
    let step = cross(theta, x - centre);
    let moved = x + step;
    // step - (moved - x) is the round-off of the sum, exactly; a compiler
    // free to reassociate (Mesa's is) makes it zero unless `moved` passes
    // through an operation it cannot see through.
    let kept = bitcast<vec3<f32>>(bitcast<vec3<u32>>(moved) ^ vec3<u32>(params.opaque_zero));
    left[i] = vec4<f32>(step - (kept - x), 0.0);
    pos[i] = vec4<f32>(moved, pos[i].w);
}
