//! Natural cubic spline through samples: C², so a velocity splined this
//! way has a continuous acceleration and splined angles a continuous rate.

use super::smooth::SignalValue;

/// Interpolating cubic spline with natural end conditions (zero second
/// derivative at both ends). Knots must be strictly increasing (the caller
/// checks).
#[derive(Debug, Clone)]
pub struct CubicSpline {
    knots: Vec<f64>,
    values: Vec<f64>,
    /// Second derivative at each knot.
    curvature: Vec<f64>,
}

impl CubicSpline {
    /// Spline through `(knots[i], values[i])`; needs at least two knots.
    /// Solves the tridiagonal system for the knot second derivatives by the
    /// Thomas algorithm (diagonally dominant, so stable without pivoting).
    pub fn new(knots: Vec<f64>, values: Vec<f64>) -> Self {
        assert!(knots.len() >= 2 && knots.len() == values.len());
        let n = knots.len();
        let mut curvature = vec![0.0; n];
        if n > 2 {
            // Interior equations i = 1..n−2:
            // h₀ M_{i−1} + 2(h₀ + h₁) M_i + h₁ M_{i+1} = 6 (Δ₁/h₁ − Δ₀/h₀).
            let m = n - 2;
            let mut diag = vec![0.0; m];
            let mut upper = vec![0.0; m];
            let mut rhs = vec![0.0; m];
            for i in 1..n - 1 {
                let h0 = knots[i] - knots[i - 1];
                let h1 = knots[i + 1] - knots[i];
                let j = i - 1;
                let lower = h0;
                diag[j] = 2.0 * (h0 + h1);
                upper[j] = h1;
                rhs[j] =
                    6.0 * ((values[i + 1] - values[i]) / h1 - (values[i] - values[i - 1]) / h0);
                if j > 0 {
                    let w = lower / diag[j - 1];
                    diag[j] -= w * upper[j - 1];
                    rhs[j] -= w * rhs[j - 1];
                }
            }
            curvature[m] = rhs[m - 1] / diag[m - 1];
            for j in (0..m - 1).rev() {
                curvature[j + 1] = (rhs[j] - upper[j] * curvature[j + 2]) / diag[j];
            }
        }
        Self {
            knots,
            values,
            curvature,
        }
    }

    /// Value and first two derivatives at `t` (clamped to the knot range).
    #[cfg(test)]
    pub fn at(&self, t: f64) -> SignalValue {
        self.value_in(self.interval(t), t)
    }

    /// Value and first two derivatives at `t` (clamped to the knot range),
    /// for times visited in non-decreasing order: `hint`
    /// starts at 0 and is kept between calls; the interval is found by
    /// scanning forward from it (bitwise the same values).
    pub fn at_from(&self, t: f64, hint: &mut usize) -> SignalValue {
        let n = self.knots.len();
        let mut i = *hint;
        if i > n - 2 || (i > 0 && self.knots[i] > t) {
            i = self.interval(t);
        } else {
            while i < n - 2 && self.knots[i + 1] <= t {
                i += 1;
            }
        }
        *hint = i;
        self.value_in(i, t)
    }

    /// Index of the knot interval holding `t` (the first or last for times
    /// outside the knots).
    fn interval(&self, t: f64) -> usize {
        self.knots
            .partition_point(|&k| k <= t)
            .saturating_sub(1)
            .min(self.knots.len() - 2)
    }

    fn value_in(&self, i: usize, t: f64) -> SignalValue {
        let (t0, t1) = (self.knots[i], self.knots[i + 1]);
        let h = t1 - t0;
        let t = t.clamp(t0, t1);
        let (a, b) = ((t1 - t) / h, (t - t0) / h);
        let (m0, m1) = (self.curvature[i], self.curvature[i + 1]);
        let (y0, y1) = (self.values[i], self.values[i + 1]);
        SignalValue {
            value: a * y0 + b * y1 + ((a * a * a - a) * m0 + (b * b * b - b) * m1) * h * h / 6.0,
            rate: (y1 - y0) / h - (3.0 * a * a - 1.0) * h * m0 / 6.0
                + (3.0 * b * b - 1.0) * h * m1 / 6.0,
            accel: a * m0 + b * m1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reproduces_a_cubic_away_from_the_ends_and_is_c2() {
        // A natural spline is exact for a straight line and close to a
        // smooth function; check interpolation, derivatives and continuity.
        let knots: Vec<f64> = (0..41)
            .map(|k| k as f64 * 0.25 + 0.01 * (k % 3) as f64)
            .collect();
        let values: Vec<f64> = knots.iter().map(|t| 3.0 - 2.0 * t).collect();
        let s = CubicSpline::new(knots.clone(), values);
        for t in [0.0, 0.3, 5.55, 10.0] {
            let v = s.at(t);
            assert!((v.value - (3.0 - 2.0 * t)).abs() < 1e-12);
            assert!((v.rate + 2.0).abs() < 1e-12 && v.accel.abs() < 1e-12);
        }
        let values: Vec<f64> = knots.iter().map(|t| t.sin()).collect();
        let s = CubicSpline::new(knots.clone(), values);
        for &k in &knots[1..knots.len() - 1] {
            assert!((s.at(k).value - k.sin()).abs() < 1e-15);
            let (a, b) = (s.at(k - 1e-9), s.at(k + 1e-9));
            assert!((a.rate - b.rate).abs() < 1e-7 && (a.accel - b.accel).abs() < 1e-6);
        }
        let mut hint = 0;
        for t in [-1.0, 0.0, 0.25, 0.3, 0.3, 5.55, 9.9, 10.0, 12.0, 3.0, 3.5] {
            assert_eq!(s.at_from(t, &mut hint), s.at(t), "{t}");
        }
        let v = s.at(4.1);
        assert!((v.value - 4.1_f64.sin()).abs() < 1e-4);
        assert!((v.rate - 4.1_f64.cos()).abs() < 1e-3);
    }
}
