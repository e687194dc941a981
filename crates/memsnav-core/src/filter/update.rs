//! Sequential scalar measurement update in Joseph form with a chi-square
//! innovation gate (Groves eq. 3.58 with the rank-one structure of a scalar
//! measurement; Bar-Shalom et al. 2001 §5.4 for the gate and NIS).

use nalgebra::{SMatrix, SVector};

use super::measurement::{ScalarMeasurement, ScalarStep, SparseRow};

/// What happened to one scalar measurement.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ScalarOutcome {
    /// Innovation ν = y − h x (prediction minus measurement, corrected by the
    /// error state accumulated so far), in the measurement's unit.
    pub innovation: f64,
    /// Its predicted variance s = h P hᵀ + r.
    pub innovation_variance: f64,
    /// Normalised innovation squared ν²/s (chi-square(1) when consistent).
    pub nis: f64,
    /// Whether the measurement was applied (false: gated out or not finite).
    pub accepted: bool,
}

/// x ← x + k ν, P ← (I − k h) P (I − k h)ᵀ + k r kᵀ with k = P hᵀ / s, written
/// as three rank-one corrections (A = P − k uᵀ; P⁺ = A − (A hᵀ) kᵀ + r k kᵀ),
/// then symmetrised. Skipped when the NIS exceeds `gate` or a value is not finite.
pub(super) fn scalar_joseph<const N: usize>(
    x: &mut SVector<f64, N>,
    p: &mut SMatrix<f64, N, N>,
    h: &SparseRow,
    y: f64,
    r: f64,
    gate: f64,
) -> ScalarOutcome {
    let innovation = y - h.dot(x);
    let u = h.times(p);
    let s = h.dot(&u) + r;
    let nis = innovation * innovation / s;
    let accepted = innovation.is_finite() && s.is_finite() && s > 0.0 && nis <= gate;
    if accepted {
        let k = u / s;
        x.axpy(innovation, &k, 1.0);
        // A = (I − k h) P = P − k uᵀ.
        super::add_outer(p, -1.0, &k, &u);
        // A hᵀ, then P⁺ = A (I − k h)ᵀ + r k kᵀ.
        let w = h.times_transposed(p);
        super::add_outer(p, -1.0, &w, &k);
        super::add_outer(p, r, &k, &k);
        // Symmetrised through the fixed-size columns (no index checks):
        // P_ij (column j, row i) and P_ji for i < j.
        let columns = &mut p.data.0;
        for j in 1..N {
            let (left, right) = columns.split_at_mut(j);
            let column_j = &mut right[0];
            for (column_i, pij) in left.iter_mut().zip(column_j.iter_mut()) {
                let m = 0.5 * (*pij + column_i[j]);
                *pij = m;
                column_i[j] = m;
            }
        }
    }
    ScalarOutcome {
        innovation,
        innovation_variance: s,
        nis,
        accepted,
    }
}

/// What the test of a batch of measurements found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BatchOutcome {
    /// Normalised innovation squared of the batch, νᵀ S⁻¹ ν.
    pub nis: f64,
    /// Its degrees of freedom (the number of measurements tested).
    pub dof: usize,
    /// Whether the batch passed the test and was applied.
    pub accepted: bool,
}

/// Applies `measurements` (those with `active[i]`) one after the other to
/// x and P, ungated, writing each one's outcome, and returns the summed
/// NIS. For measurements with independent noise the sequential
/// innovations are the batch innovation vector whitened by the Cholesky
/// factor of its covariance S = HPHᵀ + R (each is the part of its
/// measurement the earlier ones do not predict), so the sum of their NIS
/// is the batch νᵀ S⁻¹ ν: a chi-square with as many degrees of freedom as
/// measurements (Bar-Shalom et al. 2001 §5.4; Groves §3.4.1).
/// When `gains` is given, each applied measurement's gain k = P hᵀ / s
/// (before it) is pushed there with its innovation, for a smoother.
pub(super) fn sequential<const N: usize>(
    x: &mut SVector<f64, N>,
    p: &mut SMatrix<f64, N, N>,
    measurements: &[ScalarMeasurement],
    active: &[bool],
    outcomes: &mut [ScalarOutcome],
    mut gains: Option<&mut Vec<ScalarStep<N>>>,
) -> f64 {
    let mut nis = 0.0;
    for ((m, &on), out) in measurements.iter().zip(active).zip(outcomes.iter_mut()) {
        if on {
            if let Some(g) = gains.as_deref_mut() {
                let u = m.h.times(p);
                let s = m.h.dot(&u) + m.variance;
                g.push(ScalarStep {
                    measurement: *m,
                    innovation: m.y - m.h.dot(x),
                    innovation_variance: s,
                    gain: u / s,
                });
            }
            *out = scalar_joseph(x, p, &m.h, m.y, m.variance, f64::INFINITY);
            nis += out.nis;
        }
    }
    nis
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The rank-one Joseph update equals the textbook dense Kalman update.
    #[test]
    fn matches_dense_kalman_update() {
        let a = SMatrix::<f64, 17, 17>::from_fn(|i, j| ((i * 5 + j * 3) % 7) as f64 / 7.0 - 0.3);
        let p0 = a * a.transpose() + SMatrix::identity();
        let x0 = SVector::<f64, 17>::from_fn(|i, _| 0.01 * i as f64);
        let h = SparseRow::new(&[(6, 0.3), (7, -0.5), (8, 0.81), (15, 1.0)]);
        let hd = h.to_dense::<17>();
        let (y, r) = (2.5, 4.0);
        let s = (hd.transpose() * p0 * hd)[0] + r;
        let k = p0 * hd / s;
        let nu = y - hd.dot(&x0);
        let x_ref = x0 + k * nu;
        let i_kh = SMatrix::<f64, 17, 17>::identity() - k * hd.transpose();
        let p_ref = i_kh * p0 * i_kh.transpose() + k * r * k.transpose();
        let (mut x, mut p) = (x0, p0);
        let out = scalar_joseph(&mut x, &mut p, &h, y, r, f64::INFINITY);
        assert!(out.accepted);
        assert!((out.nis - nu * nu / s).abs() < 1e-12);
        assert!((x - x_ref).abs().max() < 1e-12);
        assert!((p - p_ref).abs().max() < 1e-12);
        assert!((p - (p0 - p0 * hd * hd.transpose() * p0 / s)).abs().max() < 1e-12);
    }

    /// The summed sequential NIS is the batch νᵀ S⁻¹ ν, and the final state
    /// and covariance are those of the batch update.
    #[test]
    fn sequential_nis_is_the_batch_nis() {
        let a = SMatrix::<f64, 17, 17>::from_fn(|i, j| ((i * 3 + j * 7) % 5) as f64 / 5.0 - 0.4);
        let p0 = a * a.transpose() + SMatrix::identity();
        let x0 = SVector::<f64, 17>::from_fn(|i, _| 0.02 * i as f64 - 0.1);
        let rows = [
            SparseRow::new(&[(6, 0.6), (7, -0.8), (15, 1.0), (0, 0.2)]),
            SparseRow::new(&[(6, -0.1), (8, 0.99), (15, 1.0)]),
            SparseRow::new(&[(3, 0.5), (4, 0.5), (16, 1.0)]),
        ];
        let ms: Vec<ScalarMeasurement> = rows
            .iter()
            .enumerate()
            .map(|(i, h)| ScalarMeasurement {
                h: *h,
                y: 1.5 - i as f64,
                variance: 0.5 + i as f64,
            })
            .collect();
        let h = nalgebra::SMatrix::<f64, 3, 17>::from_fn(|i, j| rows[i].to_dense::<17>()[j]);
        let r = nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::new(0.5, 1.5, 2.5));
        let nu = nalgebra::Vector3::from_fn(|i, _| ms[i].y) - h * x0;
        let s = h * p0 * h.transpose() + r;
        let k = p0 * h.transpose() * s.try_inverse().unwrap();
        let batch_nis = (nu.transpose() * s.try_inverse().unwrap() * nu)[0];
        let (mut x, mut p) = (x0, p0);
        let mut out = [ScalarOutcome {
            innovation: 0.0,
            innovation_variance: 0.0,
            nis: 0.0,
            accepted: false,
        }; 3];
        let nis = sequential(&mut x, &mut p, &ms, &[true; 3], &mut out, None);
        assert!(
            (nis - batch_nis).abs() < 1e-10 * batch_nis,
            "{nis} vs {batch_nis}"
        );
        assert!((x - (x0 + k * nu)).abs().max() < 1e-12);
        assert!((p - (p0 - k * h * p0)).abs().max() < 1e-12);
        // An inactive measurement is skipped entirely.
        let (mut x2, mut p2) = (x0, p0);
        let nis2 = sequential(&mut x2, &mut p2, &ms, &[true, false, true], &mut out, None);
        let (mut x3, mut p3) = (x0, p0);
        let nis3 = sequential(
            &mut x3,
            &mut p3,
            &[ms[0], ms[2]],
            &[true; 2],
            &mut out[..2],
            None,
        );
        assert_eq!((nis2, x2, p2), (nis3, x3, p3));
    }

    #[test]
    fn gate_and_non_finite_values_leave_the_filter_untouched() {
        let p0 = SMatrix::<f64, 17, 17>::identity() * 4.0;
        let h = SparseRow::new(&[(6, 1.0), (15, 1.0)]);
        for y in [100.0, f64::NAN, f64::INFINITY, 1e9] {
            let (mut x, mut p) = (SVector::<f64, 17>::zeros(), p0);
            let out = scalar_joseph(&mut x, &mut p, &h, y, 9.0, 10.83);
            assert!(!out.accepted, "{y}");
            assert_eq!(p, p0);
            assert_eq!(x, SVector::<f64, 17>::zeros());
        }
        let (mut x, mut p) = (SVector::<f64, 17>::zeros(), p0);
        assert!(scalar_joseph(&mut x, &mut p, &h, 5.0, 9.0, 10.83).accepted);
    }
}
