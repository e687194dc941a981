//! The gyroscope from the rotations between poses (Tedaldi et al. 2014
//! §III-C, in the model of method §2).
//!
//! In the nominal reading s (the gyro output scaled by its nominal scale),
//! eq. 3 reads s = A(Ω − b − KΓ), so Ω = T(s − c₀ − CΓ) with T = A⁻¹,
//! c₀ = −A b and C = −A K. The offsets c₀ + CΓ come from the rests
//! ([`super::rests`]); T (9 entries, row-major) is fitted here.
//!
//! Between pose k and pose k+1 the body turns by R = ∏ exp([θ_j×]) over the
//! sample intervals j of the motion, with θ_j = α_j + (1/12) α_{j−1} × α_j
//! (coning, Savage 1998 eq. 7.1.1.1-11) and α_j = T(Δs_j − c₀ Δt_j − C ΔΓ_j)
//! from the increments Δs_j = ∫s dt and ΔΓ_j = ∫Γ dt of the interval
//! (fourth-order, [`crate::ins::increments_from_samples`]). The direction of
//! gravity measured by the calibrated accelerometer, u_k in pose k, must be
//! carried into u_{k+1} = Rᵀ u_k; the residual is Rᵀu_k − u_{k+1} on two
//! axes orthogonal to u_{k+1} (its two degrees of freedom), in radians.
//!
//! The Earth's rotation (≤ 7.3e-5 rad/s, 0.004° over a 3 s turn) is
//! neglected, as in Tedaldi et al.; at rest its projection joins the
//! offsets (its vertical part looks like a g-sensitivity of Ω_ie sin φ / g
//! ≈ 5e-6 (rad/s)/(m/s²) on the diagonal).

use nalgebra::{DMatrix, DVector, Matrix3, UnitQuaternion, Vector2, Vector3};

use super::solver::{central_jacobian, Residuals};

/// The data of one motion between two poses.
#[derive(Debug, Clone)]
pub struct Segment {
    /// Pose indices (k, k + 1).
    pub from: usize,
    /// Increments of the interval: (Δs, ΔΓ, Δt).
    pub increments: Vec<(Vector3<f64>, Vector3<f64>, f64)>,
    /// Unit gravity direction (specific force at rest) in the first pose.
    pub up_from: Vector3<f64>,
    /// The same in the second pose.
    pub up_to: Vector3<f64>,
}

/// The gyro offset model s_rest = c₀ + CΓ in nominal reading units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Offsets {
    /// The constant offset c₀.
    pub c0: Vector3<f64>,
    /// The gravity-dependent offset C.
    pub c: Matrix3<f64>,
}

impl Segment {
    /// R (body at the end → body at the start) for T and the offsets.
    pub fn rotation(&self, t: &Matrix3<f64>, offsets: &Offsets) -> UnitQuaternion<f64> {
        let mut q = UnitQuaternion::identity();
        let mut previous = Vector3::zeros();
        for (ds, dg, dt) in &self.increments {
            let alpha = t * (ds - offsets.c0 * *dt - offsets.c * dg);
            let theta = alpha + previous.cross(&alpha) / 12.0;
            q *= UnitQuaternion::from_scaled_axis(theta);
            previous = alpha;
        }
        q
    }

    /// Rᵀu_k on two axes orthogonal to u_{k+1} (radians to first order).
    pub fn residual(&self, t: &Matrix3<f64>, offsets: &Offsets) -> Vector2<f64> {
        let carried = self
            .rotation(t, offsets)
            .inverse_transform_vector(&self.up_from);
        let e1 = self.up_to.cross(&Vector3::x());
        let e1 = if e1.norm() > 0.1 {
            e1.normalize()
        } else {
            self.up_to.cross(&Vector3::y()).normalize()
        };
        let e2 = self.up_to.cross(&e1);
        Vector2::new(e1.dot(&carried), e2.dot(&carried))
    }

    /// Angle between Rᵀu_k and u_{k+1}, rad.
    pub fn angle_error(&self, t: &Matrix3<f64>, offsets: &Offsets) -> f64 {
        let carried = self
            .rotation(t, offsets)
            .inverse_transform_vector(&self.up_from);
        carried
            .cross(&self.up_to)
            .norm()
            .atan2(carried.dot(&self.up_to))
    }
}

/// T as a row-major 9-vector and back.
pub fn t_from_vector(x: &DVector<f64>) -> Matrix3<f64> {
    Matrix3::from_row_slice(x.as_slice())
}

/// T as a row-major 9-vector (the inverse of [`t_from_vector`]).
pub fn t_to_vector(t: &Matrix3<f64>) -> DVector<f64> {
    DVector::from_row_slice(t.transpose().as_slice())
}

/// The rotation problem over T for fixed offsets and segments.
pub struct Rotations<'a> {
    /// The turns between poses.
    pub segments: &'a [Segment],
    /// The gyro offsets subtracted from each increment.
    pub offsets: Offsets,
}

impl Rotations<'_> {
    /// Central-difference step of each entry of T.
    pub fn steps(x: &DVector<f64>) -> Vec<f64> {
        vec![1e-6 * x.amax().max(f64::MIN_POSITIVE); 9]
    }

    /// Σ ‖residual‖² for T = m·T₀ over a log grid of m (10⁻⁶…10⁶, 20 per
    /// decade): the best m·T₀, a start from which the solver cannot fall
    /// into a turn wrapped by a whole revolution.
    pub fn scan(&self, t0: &Matrix3<f64>) -> Matrix3<f64> {
        let mut best = (f64::INFINITY, *t0);
        for k in -120..=120 {
            let t = t0 * 10f64.powf(k as f64 / 20.0);
            let cost: f64 = self
                .segments
                .iter()
                .map(|s| s.residual(&t, &self.offsets).norm_squared())
                .sum();
            if cost < best.0 {
                best = (cost, t);
            }
        }
        best.1
    }
}

impl Residuals for Rotations<'_> {
    fn residuals(&self, x: &DVector<f64>) -> Option<DVector<f64>> {
        let t = t_from_vector(x);
        let mut out = DVector::zeros(2 * self.segments.len());
        for (k, s) in self.segments.iter().enumerate() {
            out.rows_mut(2 * k, 2)
                .copy_from(&s.residual(&t, &self.offsets));
        }
        Some(out)
    }

    fn jacobian(&self, x: &DVector<f64>) -> Option<DMatrix<f64>> {
        central_jacobian(|x| self.residuals(x), x, &Self::steps(x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A constant rate about z for 1 s in 100 steps: a turn of 1 rad.
    #[test]
    fn a_known_turn_carries_gravity_and_a_wrong_scale_is_seen() {
        let rate = Vector3::new(0.0, 0.0, 1.0);
        let segment = Segment {
            from: 0,
            increments: vec![(rate * 0.01, Vector3::zeros(), 0.01); 100],
            up_from: Vector3::new(1.0, 0.0, 0.0),
            up_to: Vector3::new(1f64.cos(), -(1f64.sin()), 0.0),
        };
        let offsets = Offsets {
            c0: Vector3::zeros(),
            c: Matrix3::zeros(),
        };
        let identity = Matrix3::identity();
        assert!(segment.residual(&identity, &offsets).amax() < 1e-12);
        assert!(segment.angle_error(&identity, &offsets) < 1e-12);
        // A 10 % scale error on z turns 0.1 rad too far.
        let wrong = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 1.1));
        assert!((segment.angle_error(&wrong, &offsets) - 0.1).abs() < 1e-12);
        // A bias in the readings of 0.05 rad/s on z, removed by c₀.
        let biased = Segment {
            increments: vec![
                (
                    (rate + Vector3::new(0.0, 0.0, 0.05)) * 0.01,
                    Vector3::zeros(),
                    0.01
                );
                100
            ],
            ..segment.clone()
        };
        let with_c0 = Offsets {
            c0: Vector3::new(0.0, 0.0, 0.05),
            ..offsets
        };
        assert!(biased.angle_error(&identity, &with_c0) < 1e-12);
        let problem = Rotations {
            segments: std::slice::from_ref(&segment),
            offsets,
        };
        assert!((problem.scan(&(identity * 3e-3)) - identity).amax() < 0.07);
    }
}
