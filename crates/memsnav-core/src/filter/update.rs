//! Sequential scalar measurement update in Joseph form with a chi-square
//! innovation gate (Groves eq. 3.58 with the rank-one structure of a scalar
//! measurement; Bar-Shalom et al. 2001 §5.4 for the gate and NIS).

use nalgebra::{SMatrix, SVector};

/// A measurement row h with at most four non-zero entries (a pseudorange
/// touches position and clock offset; a range rate velocity and drift; a
/// position fix one position state).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SparseRow {
    index: [usize; 4],
    value: [f64; 4],
    len: usize,
}

impl SparseRow {
    /// A row from (index, value) pairs (at most four).
    pub fn new(entries: &[(usize, f64)]) -> Self {
        assert!(entries.len() <= 4, "a SparseRow holds at most four entries");
        let mut row = Self {
            index: [0; 4],
            value: [0.0; 4],
            len: entries.len(),
        };
        for (k, (i, v)) in entries.iter().enumerate() {
            row.index[k] = *i;
            row.value[k] = *v;
        }
        row
    }

    /// h · x.
    pub fn dot<const N: usize>(&self, x: &SVector<f64, N>) -> f64 {
        (0..self.len)
            .map(|k| self.value[k] * x[self.index[k]])
            .sum()
    }

    /// P hᵀ.
    pub fn times<const N: usize>(&self, p: &SMatrix<f64, N, N>) -> SVector<f64, N> {
        let mut u = SVector::<f64, N>::zeros();
        for k in 0..self.len {
            u.axpy(self.value[k], &p.column(self.index[k]), 1.0);
        }
        u
    }

    /// The dense row.
    pub fn to_dense<const N: usize>(&self) -> SVector<f64, N> {
        let mut h = SVector::zeros();
        for k in 0..self.len {
            h[self.index[k]] += self.value[k];
        }
        h
    }
}

/// What happened to one scalar measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
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
        p.ger(-1.0, &k, &u, 1.0);
        // A hᵀ, then P⁺ = A (I − k h)ᵀ + r k kᵀ.
        let w = h.times(&p.transpose());
        p.ger(-1.0, &w, &k, 1.0);
        p.ger(r, &k, &k, 1.0);
        for i in 0..N {
            for j in (i + 1)..N {
                let m = 0.5 * (p[(i, j)] + p[(j, i)]);
                p[(i, j)] = m;
                p[(j, i)] = m;
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
