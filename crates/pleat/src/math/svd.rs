//! The singular value
//! decomposition of a 3x3 matrix (cyclic Jacobi eigenvalue sweeps on `AᵀA`,
//! in f64) and the rotation of its polar decomposition with reflections
//! removed, as shape matching needs (Müller et al. 2005).

use glam::{DMat3, DVec3, Mat3};

/// Jacobi sweeps before giving up (a 3x3 matrix converges in about five).
const MAX_SWEEPS: usize = 24;

/// `a = u * diag(sigma) * vᵀ`, singular values descending, `u` and `v` orthogonal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Svd3 {
    /// Left singular vectors, as columns.
    pub u: DMat3,
    /// Singular values, descending and non-negative.
    pub sigma: DVec3,
    /// Right singular vectors, as columns.
    pub v: DMat3,
}

/// The singular value decomposition of `a`. Singular vectors of zero
/// singular values are completed to an orthonormal basis with `det(u) = +1`.
pub fn svd3(a: DMat3) -> Svd3 {
    let (eigenvalues, eigenvectors) = symmetric_eigen((a.transpose() * a).to_cols_array_2d());
    let mut order = [0, 1, 2];
    order.sort_by(|&i, &j| eigenvalues[j].total_cmp(&eigenvalues[i]));
    let v = DMat3::from_cols_array_2d(&order.map(|k| eigenvectors[k]));
    let sigma = DVec3::from_array(order.map(|k| eigenvalues[k].max(0.0).sqrt()));
    Svd3 {
        u: left_vectors(a, v, sigma),
        sigma,
        v,
    }
}

/// The columns `a v_i / sigma_i`, orthonormalised; completed where a singular value vanishes.
fn left_vectors(a: DMat3, v: DMat3, sigma: DVec3) -> DMat3 {
    let tiny = 1e-12 * sigma.x.max(f64::MIN_POSITIVE);
    let u0 = if sigma.x > 0.0 {
        (a * v.x_axis).normalize_or(DVec3::X)
    } else {
        DVec3::X
    };
    let u1 = if sigma.y > tiny {
        let w = a * v.y_axis;
        (w - u0 * u0.dot(w)).normalize_or(u0.any_orthonormal_vector())
    } else {
        u0.any_orthonormal_vector()
    };
    let normal = u0.cross(u1);
    let u2 = if sigma.z > tiny && (a * v.z_axis).dot(normal) < 0.0 {
        -normal
    } else {
        normal
    };
    DMat3::from_cols(u0, u1, u2)
}

/// Eigenvalues and unit eigenvectors of a symmetric matrix (columns `m[c][r]`).
fn symmetric_eigen(mut m: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let scale: f64 = m.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
    for _ in 0..MAX_SWEEPS {
        let off = m[0][1].abs() + m[0][2].abs() + m[1][2].abs();
        // Also stops on NaN input.
        if off.partial_cmp(&(1e-15 * scale)) != Some(std::cmp::Ordering::Greater) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            jacobi_rotate(&mut m, &mut v, p, q);
        }
    }
    ([m[0][0], m[1][1], m[2][2]], v)
}

/// One Jacobi rotation `m = Jᵀ m J`, `v = v J` that zeroes `m[p][q]`.
fn jacobi_rotate(m: &mut [[f64; 3]; 3], v: &mut [[f64; 3]; 3], p: usize, q: usize) {
    let apq = m[p][q];
    if apq == 0.0 {
        return;
    }
    let theta = (m[q][q] - m[p][p]) / (2.0 * apq);
    let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
    let c = 1.0 / (t * t + 1.0).sqrt();
    let s = t * c;
    // m is symmetric, so columns and rows are interchangeable: rotate both.
    for row in m.iter_mut() {
        let (mkp, mkq) = (row[p], row[q]);
        row[p] = c * mkp - s * mkq;
        row[q] = s * mkp + c * mkq;
    }
    rotate_pair(m, p, q, c, s);
    // Eigenvectors are the columns of v (v[c] is column c).
    rotate_pair(v, p, q, c, s);
}

/// `(a[p], a[q]) = (c a[p] - s a[q], s a[p] + c a[q])`.
fn rotate_pair(a: &mut [[f64; 3]; 3], p: usize, q: usize, c: f64, s: f64) {
    let (ap, aq) = (a[p], a[q]);
    for k in 0..3 {
        a[p][k] = c * ap[k] - s * aq[k];
        a[q][k] = s * ap[k] + c * aq[k];
    }
}

/// The rotation `R` of the polar decomposition `a = R S`: `U Vᵀ`, with the
/// column of `U` of the smallest singular value negated if that would be a
/// reflection (`det < 0`), so that `R` is always a proper rotation.
pub fn polar_rotation(a: Mat3) -> Mat3 {
    let Svd3 { mut u, v, .. } = svd3(a.as_dmat3());
    if (u * v.transpose()).determinant() < 0.0 {
        u.z_axis = -u.z_axis;
    }
    (u * v.transpose()).as_mat3()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Quat, Vec3};

    fn samples() -> Vec<DMat3> {
        let mut out = vec![
            DMat3::IDENTITY,
            DMat3::ZERO,
            DMat3::from_diagonal(DVec3::new(3.0, 3.0, 1.0)),
            DMat3::from_cols(DVec3::X, DVec3::Y, DVec3::ZERO),
            DMat3::from_cols(
                DVec3::new(1.0, 2.0, 0.0),
                DVec3::new(2.0, 4.0, 0.0),
                DVec3::ZERO,
            ),
        ];
        let mut seed = 7u32;
        let mut next = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            (seed >> 8) as f64 / (1u32 << 24) as f64 * 2.0 - 1.0
        };
        for _ in 0..200 {
            out.push(DMat3::from_cols_array(&[(); 9].map(|_| next())));
        }
        out
    }

    #[test]
    fn svd_reconstructs_with_orthonormal_factors() {
        for a in samples() {
            let s = svd3(a);
            let back = s.u * DMat3::from_diagonal(s.sigma) * s.v.transpose();
            assert!(back.abs_diff_eq(a, 1e-9), "{a} vs {back}");
            assert!((s.u.transpose() * s.u).abs_diff_eq(DMat3::IDENTITY, 1e-9));
            assert!((s.v.transpose() * s.v).abs_diff_eq(DMat3::IDENTITY, 1e-9));
            assert!(s.sigma.x >= s.sigma.y && s.sigma.y >= s.sigma.z && s.sigma.z >= 0.0);
        }
    }

    #[test]
    fn polar_rotation_is_proper_and_recovers_rotations() {
        let q = Quat::from_axis_angle(Vec3::new(1.0, 2.0, -0.5).normalize(), 2.0);
        let r = Mat3::from_quat(q);
        let stretch = Mat3::from_diagonal(Vec3::new(1.5, 0.7, 1.1));
        assert!(polar_rotation(r * stretch).abs_diff_eq(r, 1e-5));
        for a in samples() {
            let r = polar_rotation(a.as_mat3());
            assert!((r.determinant() - 1.0).abs() < 1e-5, "{a}");
        }
    }

    #[test]
    fn reflection_becomes_the_nearest_rotation() {
        // A mirror in z: the nearest rotation flips the smallest direction instead.
        let mirror = Mat3::from_diagonal(Vec3::new(2.0, 1.0, -0.5));
        let r = polar_rotation(mirror);
        assert!(r.abs_diff_eq(Mat3::IDENTITY, 1e-6), "{r}");
    }
}
