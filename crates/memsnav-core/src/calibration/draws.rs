//! Calibrations drawn from their uncertainty: parameter vectors from the
//! Gaussian N(θ̂, Σ) of a calibration's estimate and covariance, to carry
//! the calibration's uncertainty into what is done with it (the drive
//! calibration navigates its drive with each draw).
//!
//! A draw is θ̂ + F z, z ~ N(0, I) and F Fᵀ = Σ. Σ is singular where a
//! parameter was held (a zero row) and spans many orders of magnitude
//! (biases against nonlinearities), so F is not a Cholesky factor but
//! comes from the eigendecomposition of the correlation matrix,
//! Σ = S R S with S = diag(√Σ_ii) and R = V Λ Vᵀ: F = S V Λ^½, which
//! needs no positive definiteness and keeps the small variances' relative
//! accuracy. Only the parameters of non-zero variance are factored, so a
//! held one stays at its estimate exactly. Eigenvalues down to −10⁻⁸ λ_max
//! are rounding and count as zero; below that Σ is refused.
//!
//! Draw i of a set depends only on (seed, i): it reads its z from
//! [`crate::random::stream`]`(seed, i)` alone, so it is the same whatever
//! the number of draws and in whatever order they are made.

use nalgebra::{DMatrix, SMatrix, SVector, SymmetricEigen};
use rand_distr::{Distribution, StandardNormal};

use super::layout::{ACCELEROMETER_PARAMETERS, GYROSCOPE_PARAMETERS};
use crate::random::{self, Rng};
use crate::{validate, Error, Result};

/// Eigenvalues of the correlation matrix above −`ROUNDING` × the largest
/// are rounding (module docs).
const ROUNDING: f64 = 1e-8;

/// A Gaussian over a parameter vector, factored once for its draws.
#[derive(Debug, Clone, PartialEq)]
pub struct ParameterDistribution<const P: usize> {
    mean: SVector<f64, P>,
    factor: SMatrix<f64, P, P>,
}

impl<const P: usize> ParameterDistribution<P> {
    /// N(`mean`, `covariance`); errors name `argument` (the covariance's
    /// name; its mean is `argument` with `_covariance` read as `_mean`) when
    /// a value is not finite, a variance is negative or the covariance is
    /// not positive semi-definite. Only the lower triangle of the
    /// covariance is read.
    pub fn new(
        argument: &str,
        mean: &SVector<f64, P>,
        covariance: &SMatrix<f64, P, P>,
    ) -> Result<Self> {
        validate::finite_scalars(&argument.replace("covariance", "mean"), mean.as_slice())?;
        validate::finite_array(argument, covariance.as_slice(), &[P, P])?;
        if let Some(i) = (0..P).find(|&i| covariance[(i, i)] < 0.0) {
            return Err(Error::invalid(
                argument,
                format!("variance {i} is negative ({:e})", covariance[(i, i)]),
            ));
        }
        // Held parameters (zero variance) stay at the mean exactly: only
        // the others are factored.
        let free: Vec<usize> = (0..P).filter(|&i| covariance[(i, i)] > 0.0).collect();
        let lower = |i: usize, j: usize| covariance[(i.max(j), i.min(j))];
        for i in (0..P).filter(|i| !free.contains(i)) {
            if let Some(j) = (0..P).find(|&j| lower(i, j) != 0.0) {
                return Err(Error::invalid(
                    argument,
                    format!(
                        "not positive semi-definite: variance {i} is zero but its covariance \
                         with {j} is {:e}",
                        lower(i, j)
                    ),
                ));
            }
        }
        let scale: Vec<f64> = free.iter().map(|&i| covariance[(i, i)].sqrt()).collect();
        // Factored once, dynamically sized (nalgebra's fixed-size
        // eigendecomposition needs a typenum size); the draws are fixed-size.
        let correlation = DMatrix::<f64>::from_fn(free.len(), free.len(), |a, b| {
            lower(free[a], free[b]) / (scale[a] * scale[b])
        });
        let eigen = SymmetricEigen::new(correlation);
        let largest = eigen.eigenvalues.max();
        if let Some(k) = eigen
            .eigenvalues
            .iter()
            .position(|&l| l < -ROUNDING * largest.max(0.0))
        {
            return Err(Error::invalid(
                argument,
                format!(
                    "not positive semi-definite: its correlation matrix has eigenvalue {:e} \
                     (largest {largest:e})",
                    eigen.eigenvalues[k]
                ),
            ));
        }
        let mut factor = SMatrix::<f64, P, P>::zeros();
        for (a, &i) in free.iter().enumerate() {
            for (b, l) in eigen.eigenvalues.iter().enumerate() {
                factor[(i, b)] = scale[a] * eigen.eigenvectors[(a, b)] * l.max(0.0).sqrt();
            }
        }
        Ok(Self {
            mean: *mean,
            factor,
        })
    }

    /// One draw θ̂ + F z, z the next P standard normals of `rng`.
    pub fn draw(&self, rng: &mut Rng) -> SVector<f64, P> {
        let z = SVector::<f64, P>::from_fn(|_, _| StandardNormal.sample(rng));
        self.mean + self.factor * z
    }
}

/// An accelerometer and a gyroscope calibration drawn together.
pub struct ImuDraws {
    /// The accelerometer's parameter distribution.
    pub accelerometer: ParameterDistribution<ACCELEROMETER_PARAMETERS>,
    /// The gyroscope's parameter distribution.
    pub gyroscope: ParameterDistribution<GYROSCOPE_PARAMETERS>,
}

impl ImuDraws {
    /// Draw `i` of the set seeded by `seed`: the accelerometer's parameters,
    /// then the gyroscope's, from stream (seed, i) alone (module docs).
    pub fn draw(
        &self,
        seed: u64,
        i: u64,
    ) -> (
        SVector<f64, ACCELEROMETER_PARAMETERS>,
        SVector<f64, GYROSCOPE_PARAMETERS>,
    ) {
        let mut rng = random::stream(seed, i);
        let accelerometer = self.accelerometer.draw(&mut rng);
        (accelerometer, self.gyroscope.draw(&mut rng))
    }

    /// Draws 0..`draws` of the set seeded by `seed`, row-major: the
    /// accelerometer's (draws × 15) and the gyroscope's (draws × 21)
    /// parameters. A set too large to hold is refused naming `draws`.
    pub fn draw_set(&self, seed: u64, draws: usize) -> Result<(Vec<f64>, Vec<f64>)> {
        crate::limits::output_size(
            "draws",
            draws as f64 * GYROSCOPE_PARAMETERS as f64,
            "the gyroscope draws",
        )?;
        let mut a = Vec::with_capacity(draws * ACCELEROMETER_PARAMETERS);
        let mut g = Vec::with_capacity(draws * GYROSCOPE_PARAMETERS);
        for i in 0..draws {
            let (da, dg) = self.draw(seed, i as u64);
            a.extend_from_slice(da.as_slice());
            g.extend_from_slice(dg.as_slice());
        }
        Ok((a, g))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix4, Vector4};

    /// A covariance of three parameters with strong correlation and
    /// variances six orders apart, and a held (zero-variance) one at index 1.
    fn covariance() -> SMatrix<f64, 4, 4> {
        let s = Vector4::new(1e-2, 0.0, 1e-5, 3e-4);
        let r = Matrix4::new(
            1.0, 0.0, 0.8, -0.3, //
            0.0, 0.0, 0.0, 0.0, //
            0.8, 0.0, 1.0, 0.1, //
            -0.3, 0.0, 0.1, 1.0,
        );
        Matrix4::from_fn(|i, j| s[i] * r[(i, j)] * s[j])
    }

    /// Sample mean and covariance (about the given mean) of many draws
    /// against the given ones, within their sampling error: the mean's
    /// standard error is σ/√n, that of a covariance entry
    /// √((Σ_ii Σ_jj + Σ_ij²)/n) (Gaussian fourth moments); checked at 5
    /// standard errors. The held parameter never moves.
    #[test]
    fn draws_have_the_given_mean_and_covariance() {
        let mean = Vector4::new(0.1, 0.7, -2e-4, 5e-3);
        let c = covariance();
        let d = ParameterDistribution::new("covariance", &mean, &c).unwrap();
        let n = 40_000;
        let draws: Vec<_> = (0..n).map(|i| d.draw(&mut random::stream(9, i))).collect();
        assert!(draws.iter().all(|x| x[1] == 0.7));
        let nf = n as f64;
        let m = draws.iter().map(|x| x - mean).sum::<Vector4<f64>>() / nf + mean;
        for i in 0..4 {
            let se = (c[(i, i)] / nf).sqrt();
            assert!(
                (m[i] - mean[i]).abs() <= 5.0 * se,
                "mean {i}: {} vs {}",
                m[i],
                mean[i]
            );
        }
        let s = draws
            .iter()
            .map(|x| (x - mean) * (x - mean).transpose())
            .sum::<Matrix4<f64>>()
            / nf;
        for i in 0..4 {
            for j in 0..4 {
                let se = ((c[(i, i)] * c[(j, j)] + c[(i, j)].powi(2)) / nf).sqrt();
                assert!(
                    (s[(i, j)] - c[(i, j)]).abs() <= 5.0 * se,
                    "({i}, {j}): {} vs {}",
                    s[(i, j)],
                    c[(i, j)]
                );
            }
        }
    }

    /// Draw i is a function of (seed, i): the same in a set of 3 and of 50,
    /// made forwards or backwards; other seeds or indices differ.
    #[test]
    fn draw_i_depends_only_on_seed_and_i() {
        let accel = ParameterDistribution::new(
            "accelerometer_covariance",
            &SVector::zeros(),
            &SMatrix::identity(),
        )
        .unwrap();
        let gyro = ParameterDistribution::new(
            "gyroscope_covariance",
            &SVector::zeros(),
            &(SMatrix::identity() * 1e-6),
        )
        .unwrap();
        let set = ImuDraws {
            accelerometer: accel,
            gyroscope: gyro,
        };
        let few: Vec<_> = (0..3).map(|i| set.draw(5, i)).collect();
        let many: Vec<_> = (0..50).rev().map(|i| set.draw(5, i)).collect();
        for i in 0..3 {
            assert_eq!(few[i], many[49 - i]);
        }
        assert_ne!(set.draw(5, 0).0, set.draw(5, 1).0);
        assert_ne!(set.draw(5, 0).0, set.draw(6, 0).0);
        // Accelerometer and gyroscope take different numbers of one stream.
        let (a, g) = set.draw(5, 2);
        assert!((0..15).all(|k| (g[k] * 1e3 - a[k]).abs() > 1e-9));
    }

    #[test]
    fn an_indefinite_or_invalid_covariance_is_refused() {
        let mean = SVector::<f64, 2>::zeros();
        let bad = SMatrix::<f64, 2, 2>::new(1.0, 2.0, 2.0, 1.0);
        let e = ParameterDistribution::new("gyroscope_covariance", &mean, &bad).unwrap_err();
        assert!(e.to_string().contains("gyroscope_covariance"), "{e}");
        assert!(e.to_string().contains("semi-definite"), "{e}");
        let zero_variance = SMatrix::<f64, 2, 2>::new(0.0, 0.1, 0.1, 1.0);
        let e = ParameterDistribution::new("c", &mean, &zero_variance).unwrap_err();
        assert!(e.to_string().contains("variance 0 is zero"), "{e}");
        let negative = SMatrix::<f64, 2, 2>::new(-1.0, 0.0, 0.0, 1.0);
        let e = ParameterDistribution::new("c", &mean, &negative).unwrap_err();
        assert!(e.to_string().contains("negative"), "{e}");
        let nan_mean = SVector::<f64, 2>::new(f64::NAN, 0.0);
        let e = ParameterDistribution::new("gyroscope_covariance", &nan_mean, &SMatrix::identity())
            .unwrap_err();
        assert!(e.to_string().contains("gyroscope_mean"), "{e}");
    }
}
