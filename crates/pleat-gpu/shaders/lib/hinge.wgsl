// Origami hinges (crate::constraint::hinge), on an index: the projection
// and the tracking of the continuous fold angle after each substep. The
// target goes from the start angle to the full (end) angle as the fold
// progress (a uniform) goes from 0 to 1 (a fold's step, or the whole fold
// from flat, start 0: crate::fold_steps); driven
// creases are stiffening springs while the fold is held, flat hinges
// linear. The includer binds `hinges` and `hinge_lambda`.

const MAX_TRACKED_ANGLE: f32 = 1.25 * PI;
const STIFFENING_ANGLE: f32 = PI / 2.0;

// A driven crease's stiffening spring (crate::constraint::hinge::stiffened_error):
// the constraint for the error e in x, its slope in y.
fn stiffened_error(e: f32) -> vec2<f32> {
    let s = STIFFENING_ANGLE;
    let k = 1.0 / (s * s);
    let a = abs(e);
    var cs: vec2<f32>;
    if a <= s {
        cs = vec2<f32>(a + a * a * a * k / 3.0, 1.0 + a * a * k);
    } else if a <= 2.0 * s {
        let r = 2.0 * s - a;
        cs = vec2<f32>(a + s / 3.0 + (s * s * s - r * r * r) * k / 3.0, 1.0 + r * r * k);
    } else {
        cs = vec2<f32>(a + 2.0 * s / 3.0, 1.0);
    }
    if e < 0.0 {
        cs.x = -cs.x;
    }
    return cs;
}

// The branch phi + 2 pi k nearest the tracked angle.
fn unwrap_angle(tracked: f32, phi: f32) -> f32 {
    var r = (phi - tracked + PI) % TAU;
    if r < 0.0 {
        r += TAU;
    }
    return tracked + r - PI;
}

// The projection of hinge j.
fn solve_hinge(j: u32) {
    let h = hinges[j];
    let d = dihedral_of(h.v);
    if !d.ok {
        return;
    }
    let target_angle = clamp(
        h.start_angle + params.progress * (h.full_angle - h.start_angle),
        -params.max_fold_angle,
        params.max_fold_angle,
    );
    let error = unwrap_angle(h.angle, d.phi) - target_angle;
    let driven = h.full_angle != 0.0 || h.start_angle != 0.0;
    if !driven || params.fold_held == 0u {
        hinge_lambda[j] = project_four(h.v, alpha_of(h.compliance, h.slot), error, d, hinge_lambda[j]);
        return;
    }
    let s = stiffened_error(error);
    var ds = d;
    ds.g0 *= s.y;
    ds.g1 *= s.y;
    ds.g2 *= s.y;
    ds.g3 *= s.y;
    hinge_lambda[j] = project_four(h.v, alpha_of(h.compliance, h.slot), s.x, ds, hinge_lambda[j]);
}

// Hinge j's tracked angle moved to the branch of its angle now.
fn track_hinge(j: u32) {
    let h = hinges[j];
    let d = dihedral_of(h.v);
    if d.ok {
        hinges[j].angle = clamp(unwrap_angle(h.angle, d.phi), -MAX_TRACKED_ANGLE, MAX_TRACKED_ANGLE);
    }
}
