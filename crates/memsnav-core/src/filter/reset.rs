//! Resets of part of the error state: what a filter does when a state is
//! set anew from outside (a position reset to a GNSS fix, a heading from
//! the GNSS course, a receiver clock jump) or when its covariance has to
//! be opened after measurements kept failing their test.
//!
//! A reset replaces some states by new values independent of everything
//! the filter knew: their error is the new value's error, uncorrelated
//! with the other states, so their rows and columns of P are cleared and
//! the new covariance is put on the block (the treatment of ArduPilot
//! EKF3's `ResetPosition` and PX4 EKF2's `resetHorizontalPositionTo`; in
//! general form, Simon, *Optimal State Estimation*, 2006, §7.5 on
//! "resetting" a filter).

use nalgebra::{Matrix3, SMatrix, Vector3};

use super::smoother::ResetStep;
use super::ErrorStateKf;

impl<const N: usize> ErrorStateKf<N> {
    /// States `first..first + K` become new values with error covariance
    /// `covariance`, independent of the rest: their error estimate is zero,
    /// their rows and columns of P are zero but for the block.
    pub fn reset_block<const K: usize>(&mut self, first: usize, covariance: &SMatrix<f64, K, K>) {
        for i in first..first + K {
            self.x.0[i] = 0.0;
            self.p.row_mut(i).fill(0.0);
            self.p.column_mut(i).fill(0.0);
        }
        let sym = 0.5 * (covariance + covariance.transpose());
        self.p.fixed_view_mut::<K, K>(first, first).copy_from(&sym);
        const {
            assert!(
                K <= 3,
                "the smoother records resets of at most three states"
            )
        };
        let mut block = [0.0; 9];
        for a in 0..K {
            for b in 0..K {
                block[a + 3 * b] = sym[(a, b)];
            }
        }
        self.record_reset(ResetStep::Block {
            first,
            len: K,
            covariance: block,
        });
    }

    /// The component along the unit vector `direction` of the three states
    /// at `first` becomes a new value of variance `variance`, independent of
    /// the rest (e.g. the heading about the local vertical after an
    /// alignment to the GNSS course): with T = I − d dᵀ on that block,
    /// x ← T x and P ← T P Tᵀ + variance · d dᵀ.
    pub fn reset_component(&mut self, first: usize, direction: &Vector3<f64>, variance: f64) {
        let d = direction.normalize();
        let t = nalgebra::Matrix3::identity() - d * d.transpose();
        let xb = t * self.x.0.fixed_rows::<3>(first);
        self.x.0.fixed_rows_mut::<3>(first).copy_from(&xb);
        let rows = t * self.p.fixed_rows::<3>(first);
        self.p.fixed_rows_mut::<3>(first).copy_from(&rows);
        let cols = self.p.fixed_columns::<3>(first) * t;
        self.p.fixed_columns_mut::<3>(first).copy_from(&cols);
        let block = self.p.fixed_view::<3, 3>(first, first) + variance * d * d.transpose();
        self.p
            .fixed_view_mut::<3, 3>(first, first)
            .copy_from(&block);
        // The smoother must see it: without it the backward pass carries
        // information through the reset and the smoothed covariance before
        // it turns negative.
        self.record_reset(ResetStep::Component {
            first,
            direction: d,
            variance,
        });
    }

    /// A change of variables that moves states `target..target + 3` by
    /// `m` times states `source..source + 3` (x ← T x, T = I + E with E
    /// the block m at (target, source); P ← T P Tᵀ), e.g. the IMU
    /// position when the heading it was derived with is replaced and the
    /// antenna it was measured at stays. Nothing is learnt or forgotten:
    /// the smoother carries information through it with Tᵀ.
    pub fn shear(&mut self, target: usize, source: usize, m: &Matrix3<f64>) {
        let moved = m * self.x.0.fixed_rows::<3>(source);
        let mut xt = self.x.0.fixed_rows_mut::<3>(target);
        xt += moved;
        // T P: rows of the target gain m times the rows of the source;
        // then (T P) Tᵀ: its columns likewise.
        let rows = m * self.p.fixed_rows::<3>(source);
        let mut pt = self.p.fixed_rows_mut::<3>(target);
        pt += rows;
        let cols = self.p.fixed_columns::<3>(source) * m.transpose();
        let mut pc = self.p.fixed_columns_mut::<3>(target);
        pc += cols;
        self.record_reset(ResetStep::Shear {
            target,
            source,
            matrix: *m,
        });
    }

    /// Multiplies the whole covariance by `factor` ≥ 1: the fading-memory
    /// remedy for a model that has proved too optimistic (Simon, *Optimal
    /// State Estimation*, 2006, §7.4: the old information is weighed less,
    /// every correlation kept). The error estimate is unchanged.
    pub fn fade(&mut self, factor: f64) {
        let factor = factor.max(1.0);
        self.p *= factor;
        self.record_reset(ResetStep::Fade { factor });
    }

    /// Multiplies the variances of `states` by `factor` ≥ 1, their
    /// covariances with the other states by √factor (rows and columns
    /// scaled: P stays positive definite and the correlations are kept).
    pub fn inflate(&mut self, states: &[usize], factor: f64) {
        let s = factor.max(1.0).sqrt();
        for &i in states {
            self.p.row_mut(i).scale_mut(s);
            self.p.column_mut(i).scale_mut(s);
        }
        let mut recorded = [0; 8];
        let count = states.len().min(8);
        recorded[..count].copy_from_slice(&states[..count]);
        self.record_reset(ResetStep::Inflate {
            states: recorded,
            count,
            factor,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;

    fn kf() -> ErrorStateKf<17> {
        let a = SMatrix::<f64, 17, 17>::from_fn(|i, j| ((i * 5 + j * 3) % 7) as f64 / 7.0 - 0.3);
        ErrorStateKf::new(a * a.transpose() + SMatrix::identity()).unwrap()
    }

    #[test]
    fn a_reset_block_is_independent_of_the_rest() {
        let mut f = kf();
        let before = f.p;
        let cov = Matrix3::new(4.0, 1.0, 0.0, 1.0, 3.0, 0.5, 0.0, 0.5, 2.0);
        f.reset_block::<3>(6, &cov);
        for i in 0..17 {
            for j in 0..17 {
                let expected = match ((6..9).contains(&i), (6..9).contains(&j)) {
                    (true, true) => cov[(i - 6, j - 6)],
                    (false, false) => before[(i, j)],
                    _ => 0.0,
                };
                assert_eq!(f.p[(i, j)], expected, "({i}, {j})");
            }
        }
        assert!(f.check_health(0.0).is_ok());
    }

    /// T P Tᵀ + σ² d dᵀ against the dense product, and the variance along d
    /// is σ² afterwards.
    #[test]
    fn a_component_reset_matches_the_dense_projection() {
        let mut f = kf();
        f.x.0[0] = 0.3;
        f.x.0[2] = -0.2;
        let before = f.clone();
        let d = Vector3::new(0.3, -0.5, 0.8).normalize();
        f.reset_component(0, &d, 0.01);
        let mut t = SMatrix::<f64, 17, 17>::identity();
        t.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(Matrix3::identity() - d * d.transpose()));
        let mut dd = SMatrix::<f64, 17, 17>::zeros();
        dd.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(0.01 * d * d.transpose()));
        let dense = t * before.p * t.transpose() + dd;
        assert!((f.p - dense).abs().max() < 1e-12);
        assert!((f.x.0 - t * before.x.0).abs().max() < 1e-15);
        let along = (d.transpose() * f.p.fixed_view::<3, 3>(0, 0) * d)[0];
        assert!((along - 0.01).abs() < 1e-12);
        assert!(f.check_health(0.0).is_ok());
    }

    #[test]
    fn fading_scales_the_whole_covariance() {
        let mut f = kf();
        let before = f.p;
        f.fade(10.0);
        assert!((f.p - 10.0 * before).abs().max() < 1e-12);
        f.fade(0.5); // never shrinks
        assert!((f.p - 10.0 * before).abs().max() < 1e-12);
        assert!(f.check_health(0.0).is_ok());
    }

    #[test]
    fn inflation_scales_variances_and_keeps_correlations() {
        let mut f = kf();
        let before = f.p;
        f.inflate(&[6, 7, 8], 9.0);
        assert!((f.p[(6, 6)] - 9.0 * before[(6, 6)]).abs() < 1e-12);
        assert!((f.p[(6, 7)] - 9.0 * before[(6, 7)]).abs() < 1e-12);
        assert!((f.p[(6, 0)] - 3.0 * before[(6, 0)]).abs() < 1e-12);
        assert_eq!(f.p[(0, 1)], before[(0, 1)]);
        assert!(f.check_health(0.0).is_ok());
    }

    /// The shear against the dense T x and T P Tᵀ.
    #[test]
    fn a_shear_is_the_dense_change_of_variables() {
        let mut f = kf();
        f.x.0[3] = 0.4;
        f.x.0[14] = -0.2;
        let before = f.clone();
        let m = Matrix3::new(0.1, -0.2, 0.3, 0.0, 0.5, -0.1, 0.2, 0.1, -0.4);
        f.shear(6, 12, &m);
        let mut t = SMatrix::<f64, 17, 17>::identity();
        t.fixed_view_mut::<3, 3>(6, 12).copy_from(&m);
        assert!((f.x.0 - t * before.x.0).norm() < 1e-15);
        assert!((f.p - t * before.p * t.transpose()).norm() < 1e-12);
        assert!(f.check_health(0.0).is_ok());
    }
}
