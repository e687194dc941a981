//! Rotation helpers on nalgebra types: skew matrices, Euler angles, rotation
//! vectors, and re-orthonormalisation. Euler angles are the aerospace
//! z-y-x sequence (yaw ψ, pitch θ, roll φ) from the reference frame to body.

use nalgebra::{Matrix3, Rotation3, Vector3};

/// An angle wrapped into (−π, π], rad: the difference of two headings or
/// courses as the shorter turn between them.
pub fn wrap_angle_rad(angle_rad: f64) -> f64 {
    let d = angle_rad.rem_euclid(std::f64::consts::TAU);
    if d > std::f64::consts::PI {
        d - std::f64::consts::TAU
    } else {
        d
    }
}

/// Skew-symmetric matrix [v×] with [v×] w = v × w.
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// Body-to-reference rotation C_b^n from roll, pitch, yaw (Groves eq. 2.22, transposed).
pub fn euler_to_dcm(roll_rad: f64, pitch_rad: f64, yaw_rad: f64) -> Matrix3<f64> {
    Rotation3::from_euler_angles(roll_rad, pitch_rad, yaw_rad).into_inner()
}

/// Roll, pitch, yaw of a body-to-reference rotation C_b^n (Groves eq. 2.23).
pub fn dcm_to_euler(c_b_n: &Matrix3<f64>) -> Vector3<f64> {
    let roll = c_b_n[(2, 1)].atan2(c_b_n[(2, 2)]);
    let pitch = -c_b_n[(2, 0)].clamp(-1.0, 1.0).asin();
    let yaw = c_b_n[(1, 0)].atan2(c_b_n[(0, 0)]);
    Vector3::new(roll, pitch, yaw)
}

/// Rotation matrix of a rotation vector θ (axis × angle) by Rodrigues'
/// rotation formula C = I + a [θ×] + b [θ×]² with a = sin|θ|/|θ| and
/// b = (1 − cos|θ|)/|θ|², written out with [θ×]² = θθᵀ − |θ|² I.
///
/// An IMU interval turns by far less than 0.1 rad; below that (|θ|² < 10⁻²)
/// a and b come from their Taylor series in |θ|² to the fourth power, whose
/// truncation (|θ|¹⁰/11! and |θ|¹⁰/12!, < 3·10⁻¹⁸ there) is below the
/// rounding of the closed form: the same matrix to rounding, without the
/// square root, sine and cosine the closed form costs every step.
pub fn rotation_vector_to_dcm(rotation_vector: &Vector3<f64>) -> Matrix3<f64> {
    let t = rotation_vector.norm_squared();
    let (a, b) = if t < 1e-2 {
        (
            1.0 - t / 6.0 * (1.0 - t / 20.0 * (1.0 - t / 42.0 * (1.0 - t / 72.0))),
            0.5 * (1.0 - t / 12.0 * (1.0 - t / 30.0 * (1.0 - t / 56.0 * (1.0 - t / 90.0)))),
        )
    } else {
        let angle = t.sqrt();
        let (s, c) = angle.sin_cos();
        (s / angle, (1.0 - c) / t)
    };
    let (x, y, z) = (rotation_vector.x, rotation_vector.y, rotation_vector.z);
    let d = 1.0 - b * t;
    Matrix3::new(
        d + b * x * x,
        b * x * y - a * z,
        b * x * z + a * y,
        b * x * y + a * z,
        d + b * y * y,
        b * y * z - a * x,
        b * x * z - a * y,
        b * y * z + a * x,
        d + b * z * z,
    )
}

/// Rotation vector of a rotation matrix (inverse of [`rotation_vector_to_dcm`]).
pub fn dcm_to_rotation_vector(c: &Matrix3<f64>) -> Vector3<f64> {
    Rotation3::from_matrix_unchecked(*c).scaled_axis()
}

/// The nearest rotation matrix in the Frobenius norm: the orthogonal factor
/// U Vᵀ of the SVD C = U Σ Vᵀ (polar decomposition; Higham, *Functions of
/// Matrices*, §8.1), with the sign fixed so the determinant is +1. Removes the
/// slow loss of orthogonality of an integrated attitude, whatever the
/// rotation's angle.
pub fn orthonormalize(c: &Matrix3<f64>) -> Matrix3<f64> {
    let svd = c.svd(true, true);
    let (mut u, v_t) = (svd.u.expect("requested"), svd.v_t.expect("requested"));
    if (u * v_t).determinant() < 0.0 {
        u.column_mut(2).neg_mut();
    }
    u * v_t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_round_trip_and_axes() {
        let (r, p, y) = (0.1, -0.2, 2.5);
        let c = euler_to_dcm(r, p, y);
        let e = dcm_to_euler(&c);
        assert!((e - Vector3::new(r, p, y)).norm() < 1e-14);
        // A pure yaw of 90° turns body x (forward) into reference y (east).
        let c = euler_to_dcm(0.0, 0.0, std::f64::consts::FRAC_PI_2);
        assert!((c * Vector3::x() - Vector3::y()).norm() < 1e-15);
    }

    /// Both branches of Rodrigues' formula against nalgebra's axis-angle
    /// rotation, from a micro-radian to π, around the series' threshold too.
    #[test]
    fn rotation_vector_matches_axis_angle() {
        let axis = Vector3::new(0.48, -0.6, 0.64);
        for angle in [0.0, 1e-6, 1e-3, 0.01, 0.0999, 0.1, 0.1001, 0.5, 2.0, 3.1] {
            let v = axis * angle;
            let expected = Rotation3::new(v).into_inner();
            let c = rotation_vector_to_dcm(&v);
            assert!(
                (c - expected).abs().max() < 4e-16,
                "angle {angle}: {c} vs {expected}"
            );
        }
    }

    #[test]
    fn rotation_vector_round_trip_and_skew() {
        let v = Vector3::new(0.3, -0.1, 0.7);
        assert!((dcm_to_rotation_vector(&rotation_vector_to_dcm(&v)) - v).norm() < 1e-14);
        let w = Vector3::new(-2.0, 0.5, 1.0);
        assert!((skew(&v) * w - v.cross(&w)).norm() < 1e-15);
        let noisy = rotation_vector_to_dcm(&v) + Matrix3::from_element(1e-7);
        let fixed = orthonormalize(&noisy);
        assert!(
            (fixed.transpose() * fixed - Matrix3::identity())
                .abs()
                .max()
                < 1e-14
        );
    }
}
