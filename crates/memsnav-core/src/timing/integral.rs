//! Exact means of a piecewise-linear series (samples joined by straight
//! lines) under a box or a triangle, from its first and second integrals.
//! The lag searches compare GNSS differences, which are such means of the
//! true motion, with the same means of the other series.

/// A sampled series and its running first and second integrals.
pub(super) struct Integrals<'a> {
    time: &'a [f64],
    value: Vec<f64>,
    first: Vec<f64>,
    second: Vec<f64>,
}

impl<'a> Integrals<'a> {
    /// `value` at strictly increasing `time` (at least two samples).
    pub fn new(time: &'a [f64], value: Vec<f64>) -> Self {
        let n = time.len();
        let (mut first, mut second) = (vec![0.0; n], vec![0.0; n]);
        for i in 1..n {
            let dt = time[i] - time[i - 1];
            first[i] = first[i - 1] + 0.5 * (value[i - 1] + value[i]) * dt;
            // ∫ of the piecewise-quadratic first integral: the trapezoid
            // plus its exact correction.
            second[i] = second[i - 1]
                + 0.5 * (first[i - 1] + first[i]) * dt
                + (value[i - 1] - value[i]) * dt * dt / 12.0;
        }
        Self {
            time,
            value,
            first,
            second,
        }
    }

    /// The sample interval holding `t` (the first or last one outside the
    /// span), its start and the time into it.
    fn locate(&self, t: f64) -> (usize, f64, f64) {
        let i = self
            .time
            .partition_point(|&x| x <= t)
            .clamp(1, self.time.len() - 1)
            - 1;
        (i, self.time[i + 1] - self.time[i], t - self.time[i])
    }

    fn first_at(&self, t: f64) -> f64 {
        let (i, dt, s) = self.locate(t);
        let (x0, x1) = (self.value[i], self.value[i + 1]);
        self.first[i] + x0 * s + (x1 - x0) * s * s / (2.0 * dt)
    }

    fn second_at(&self, t: f64) -> f64 {
        let (i, dt, s) = self.locate(t);
        let (x0, x1) = (self.value[i], self.value[i + 1]);
        self.second[i] + self.first[i] * s + x0 * s * s / 2.0 + (x1 - x0) * s * s * s / (6.0 * dt)
    }

    /// Mean over [`start`, `end`].
    pub fn box_mean(&self, start: f64, end: f64) -> f64 {
        (self.first_at(end) - self.first_at(start)) / (end - start)
    }

    /// Mean under a triangle of half-width `h` centred on `t` (unit area):
    /// the second difference of the second integral.
    pub fn triangle_mean(&self, t: f64, h: f64) -> f64 {
        (self.second_at(t + h) - 2.0 * self.second_at(t) + self.second_at(t - h)) / (h * h)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn means_are_exact_for_linear_pieces() {
        let time: Vec<f64> = (0..101).map(|k| k as f64 * 0.01).collect();
        // x = 2 + 3 t: every symmetric mean is the value at its centre.
        let x = Integrals::new(&time, time.iter().map(|t| 2.0 + 3.0 * t).collect());
        for &c in &[0.3, 0.5, 0.677] {
            assert!((x.triangle_mean(c, 0.25) - (2.0 + 3.0 * c)).abs() < 1e-10);
            assert!((x.box_mean(c - 0.123, c + 0.123) - (2.0 + 3.0 * c)).abs() < 1e-10);
        }
        // A kink at 0.5 (x = |t − 0.5|): the box mean over [0.4, 0.7] is
        // (0.1² + 0.2²) / 2 / 0.3.
        let x = Integrals::new(&time, time.iter().map(|t| (t - 0.5f64).abs()).collect());
        assert!((x.box_mean(0.4, 0.7) - 0.025 / 0.3).abs() < 1e-12);
    }
}
