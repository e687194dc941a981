//! The gyroscope's offsets from the rests: in every pose the body does not
//! turn, so the mean nominal reading is s̄_k = c₀ + C Γ̄_k (eq. 3 with Ω = 0:
//! c₀ = −A b, C = −A K), linear in [1, Γ̄_k]. One row per gyro axis, solved
//! by QR over the pose means ([`Regression`]), each row with
//! its own residual variance. Columns of Γ held by the determinable rule
//! drop out (C's column zero).

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::rotation::Offsets;
use crate::calibration::least_squares::Regression;
use crate::calibration::GYROSCOPE_AXES;
use crate::Result;

/// Coefficients [c₀ (3), C row-major (9)] with their covariance (12 × 12).
pub struct RestFit {
    /// The fitted c₀ and C.
    pub offsets: Offsets,
    /// Their covariance (12 × 12), in coefficient order.
    pub covariance: DMatrix<f64>,
    /// Residual std per gyro axis, √(RSS / dof), nominal units.
    pub residual_std: Vector3<f64>,
    /// Sum of squared residuals per gyro axis, (nominal units)².
    pub rss: Vector3<f64>,
    /// Pose means in the fit (residuals per axis).
    pub poses: usize,
    /// Condition number of the column-scaled design matrix.
    pub condition_number: f64,
    /// The column of [1, Γ^u, Γ^v, Γ^w] that dominates the weakest direction.
    pub weakest_column: usize,
}

/// Index of c₀_i and C_il in the coefficient vector.
pub fn c0_index(i: usize) -> usize {
    i
}

/// Index of C_il (row i, column l) in the coefficient vector.
pub fn c_index(i: usize, l: usize) -> usize {
    3 + 3 * i + l
}

/// The offsets of a coefficient vector [c₀ (3), C row-major (9)].
pub fn offsets_from(c: &DVector<f64>) -> Offsets {
    Offsets {
        c0: Vector3::new(c[0], c[1], c[2]),
        c: Matrix3::from_row_slice(&c.as_slice()[3..12]),
    }
}

/// The coefficient vector [c₀ (3), C row-major (9)] of the offsets.
pub fn offsets_to(o: &Offsets) -> DVector<f64> {
    let mut v = DVector::zeros(12);
    v.rows_mut(0, 3).copy_from(&o.c0);
    for i in 0..3 {
        for l in 0..3 {
            v[c_index(i, l)] = o.c[(i, l)];
        }
    }
    v
}

/// Fits c₀ and the columns `free_columns` (of Γ: 0, 1, 2) of C to the
/// pose means `gyro_means` (nominal units) and `specific_force_means` (SI).
pub fn fit(
    gyro_means: &[Vector3<f64>],
    specific_force_means: &[Vector3<f64>],
    free_columns: &[usize],
) -> Result<RestFit> {
    let n = gyro_means.len();
    let p = 1 + free_columns.len();
    let g = DMatrix::from_fn(n, p, |k, c| {
        if c == 0 {
            1.0
        } else {
            specific_force_means[k][free_columns[c - 1]]
        }
    });
    let regression = Regression::new(g, n);
    let mut offsets = Offsets {
        c0: Vector3::zeros(),
        c: Matrix3::zeros(),
    };
    let mut covariance = DMatrix::zeros(12, 12);
    let mut residual_std = Vector3::zeros();
    let mut rss = Vector3::zeros();
    for (i, axis) in GYROSCOPE_AXES.iter().enumerate() {
        let y = DVector::from_iterator(n, gyro_means.iter().map(|s| s[i]));
        let solution = regression.solve(&y, None, axis)?;
        let index = |c: usize| {
            if c == 0 {
                c0_index(i)
            } else {
                c_index(i, free_columns[c - 1])
            }
        };
        offsets.c0[i] = solution.coefficients[0];
        for (c, &l) in free_columns.iter().enumerate() {
            offsets.c[(i, l)] = solution.coefficients[1 + c];
        }
        for a in 0..p {
            for b in 0..p {
                covariance[(index(a), index(b))] = solution.covariance[(a, b)];
            }
        }
        residual_std[i] = solution.residual_std;
        rss[i] = solution.residual_std.powi(2) * (n - p) as f64;
    }
    let weakest = regression.weakest_column(0);
    Ok(RestFit {
        offsets,
        covariance,
        residual_std,
        rss,
        poses: n,
        condition_number: regression.condition_number,
        weakest_column: if weakest == 0 {
            0
        } else {
            1 + free_columns[weakest - 1]
        },
    })
}

/// Inverse Fisher information (12 × 12, the layout of [`RestFit`]) of the
/// rest fit for white gyro noise of variance `white[i]` per sample on axis
/// i: per row, (Gᵀ W G)⁻¹ with W = diag(n_k / σ_i²), `counts` the samples of
/// each pose.
pub fn bound(
    specific_force_means: &[Vector3<f64>],
    counts: &[f64],
    free_columns: &[usize],
    white: &Vector3<f64>,
) -> DMatrix<f64> {
    let p = 1 + free_columns.len();
    let mut gram = DMatrix::zeros(p, p);
    for (f, n) in specific_force_means.iter().zip(counts) {
        let row = DVector::from_iterator(
            p,
            std::iter::once(1.0).chain(free_columns.iter().map(|&l| f[l])),
        );
        gram += &row * row.transpose() * *n;
    }
    let unit = gram.try_inverse().unwrap_or_else(|| DMatrix::zeros(p, p));
    let mut out = DMatrix::zeros(12, 12);
    for i in 0..3 {
        let index = |c: usize| {
            if c == 0 {
                c0_index(i)
            } else {
                c_index(i, free_columns[c - 1])
            }
        };
        for a in 0..p {
            for b in 0..p {
                out[(index(a), index(b))] = unit[(a, b)] * white[i];
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_offsets_are_recovered_and_held_columns_stay_zero() {
        let c0 = Vector3::new(0.01, -0.02, 0.005);
        let c = Matrix3::from_fn(|i, j| 1e-4 * (1.0 + i as f64 - 2.0 * j as f64));
        let f: Vec<Vector3<f64>> = (0..12)
            .map(|k| {
                let a = k as f64;
                Vector3::new(a.sin(), (1.3 * a).cos(), (0.7 * a).sin() - 0.2) * 9.8
            })
            .collect();
        let s: Vec<Vector3<f64>> = f.iter().map(|f| c0 + c * f).collect();
        let all = fit(&s, &f, &[0, 1, 2]).unwrap();
        assert!((all.offsets.c0 - c0).amax() < 1e-14);
        assert!((all.offsets.c - c).amax() < 1e-15);
        let bias_only = fit(&s, &f, &[]).unwrap();
        assert_eq!(bias_only.offsets.c, Matrix3::zeros());
        assert_eq!(bias_only.covariance[(c_index(1, 2), c_index(1, 2))], 0.0);
        assert!(bias_only.covariance[(c0_index(1), c0_index(1))] > 0.0);
    }
}
