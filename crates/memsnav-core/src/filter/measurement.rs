//! A Kalman filter's scalar measurement: its sparse row h, the measurement
//! y = h·x + v with its noise variance, and the record of one applied
//! update that the smoother replays (the scalar Joseph update of
//! [`super::update`] writes it, the smoother of [`super::smoother`] reads it).

use nalgebra::{SMatrix, SVector};

/// Most non-zero entries a measurement row has: a pseudorange rate at an
/// antenna away from the IMU touches velocity, attitude and gyro bias
/// (through the lever arm), position (the line of sight turning with it),
/// the clock drift (13), with a time offset the accelerometer bias (16)
/// and, with the installation states, the lever arm and the time offset
/// (20).
pub const MAX_ROW_ENTRIES: usize = 20;

/// A measurement row h with at most [`MAX_ROW_ENTRIES`] non-zero entries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SparseRow {
    index: [usize; MAX_ROW_ENTRIES],
    value: [f64; MAX_ROW_ENTRIES],
    len: usize,
}

impl Default for SparseRow {
    fn default() -> Self {
        Self::new(&[])
    }
}

impl SparseRow {
    /// A row from (index, value) pairs (at most [`MAX_ROW_ENTRIES`]).
    pub fn new(entries: &[(usize, f64)]) -> Self {
        let mut row = Self {
            index: [0; MAX_ROW_ENTRIES],
            value: [0.0; MAX_ROW_ENTRIES],
            len: 0,
        };
        for &(i, v) in entries {
            row.push(i, v);
        }
        row
    }

    /// Adds `value` at state `index` (summed with an entry already there).
    pub fn push(&mut self, index: usize, value: f64) {
        if let Some(k) = self.index[..self.len].iter().position(|&i| i == index) {
            self.value[k] += value;
            return;
        }
        assert!(
            self.len < MAX_ROW_ENTRIES,
            "a SparseRow holds at most {MAX_ROW_ENTRIES} entries"
        );
        self.index[self.len] = index;
        self.value[self.len] = value;
        self.len += 1;
    }

    /// `a` times this row plus `b` times `other`.
    pub fn combine(&self, a: f64, other: &SparseRow, b: f64) -> Self {
        let mut row = Self::default();
        for k in 0..self.len {
            row.push(self.index[k], a * self.value[k]);
        }
        for k in 0..other.len {
            row.push(other.index[k], b * other.value[k]);
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

    /// (h M)ᵀ = Mᵀ hᵀ: Σ h_k × row k of M, accumulated in the order of
    /// [`Self::times`] of Mᵀ (the same result, without forming Mᵀ).
    pub fn times_transposed<const N: usize>(&self, m: &SMatrix<f64, N, N>) -> SVector<f64, N> {
        let mut w = [0.0; N];
        let columns = &m.data.0;
        for k in 0..self.len {
            let (a, row) = (self.value[k], self.index[k]);
            for (i, wi) in w.iter_mut().enumerate() {
                *wi += a * columns[i][row];
            }
        }
        SVector::from(w)
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

/// One scalar measurement y = h·x + v, var(v) = `variance`, with `y`
/// prediction minus measurement (the convention of
/// [`super::ErrorState`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ScalarMeasurement {
    /// The measurement row.
    pub h: SparseRow,
    /// Prediction minus measurement.
    pub y: f64,
    /// Measurement-noise variance.
    pub variance: f64,
}

/// An applied scalar measurement as the smoother needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScalarStep<const N: usize> {
    /// Its row, prediction minus measurement and noise variance.
    pub measurement: ScalarMeasurement,
    /// Innovation ν = y − h x⁻.
    pub innovation: f64,
    /// Its variance s = h P⁻ hᵀ + r.
    pub innovation_variance: f64,
    /// Gain k = P⁻ hᵀ / s.
    pub gain: SVector<f64, N>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// h Mᵀ without the transpose is bitwise the product with it.
    #[test]
    fn times_transposed_is_times_of_the_transpose() {
        let m = SMatrix::<f64, 17, 17>::from_fn(|i, j| ((i * 7 + j * 11) % 13) as f64 / 3.0 - 1.7);
        let h = SparseRow::new(&[(6, 0.3), (0, -0.5), (8, 0.81), (15, 1.0 / 3.0)]);
        assert_eq!(h.times_transposed(&m), h.times(&m.transpose()));
    }

    #[test]
    fn rows_merge_repeated_states() {
        let a = SparseRow::new(&[(6, 1.0), (0, 2.0)]);
        let b = SparseRow::new(&[(6, 3.0), (15, 1.0)]);
        let c = a.combine(2.0, &b, -1.0);
        let d = c.to_dense::<17>();
        assert_eq!((d[6], d[0], d[15]), (-1.0, 4.0, -1.0));
        assert_eq!(c.len, 3);
    }
}
