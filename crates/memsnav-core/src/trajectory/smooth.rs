//! Piecewise signals joined by quintic smoothsteps: C² everywhere, with the
//! value, its first two derivatives and its integral in closed form.
//!
//! A vehicle's speed, yaw rate and path angle are built from such pieces,
//! so the acceleration and the angular rate derived from them are
//! continuous, and the heading (the integral of the yaw rate) is exact.

/// Quintic smoothstep S(τ) = 10τ³ − 15τ⁴ + 6τ⁵ on [0, 1]: S(0) = 0,
/// S(1) = 1, with S' and S'' zero at both ends, so joined pieces are C².
fn smoothstep(tau: f64) -> [f64; 3] {
    let t2 = tau * tau;
    let value = smoothstep_value(tau);
    let rate = 30.0 * t2 * (1.0 - tau) * (1.0 - tau);
    let accel = 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau);
    [value, rate, accel]
}

/// S(τ) alone.
#[inline]
fn smoothstep_value(tau: f64) -> f64 {
    let t2 = tau * tau;
    t2 * tau * (10.0 + tau * (-15.0 + 6.0 * tau))
}

/// ∫₀^τ S(u) du = τ⁴ (5/2 − 3τ + τ²).
fn smoothstep_integral(tau: f64) -> f64 {
    let t2 = tau * tau;
    t2 * t2 * (2.5 + tau * (-3.0 + tau))
}

/// Peak of S'(τ) (at τ = ½): a change Δ over a duration T has a peak rate
/// of 1.875 Δ / T.
pub const SMOOTHSTEP_PEAK_RATE: f64 = 1.875;

#[derive(Debug, Clone, Copy)]
struct Piece {
    start_s: f64,
    duration_s: f64,
    from: f64,
    to: f64,
    /// ∫ of the signal from time 0 to `start_s`.
    integral_before: f64,
}

impl Piece {
    fn end_s(&self) -> f64 {
        self.start_s + self.duration_s
    }

    fn integral_over(&self, elapsed_s: f64) -> f64 {
        self.integral_at_tau((elapsed_s / self.duration_s).clamp(0.0, 1.0))
    }

    /// The piece's normalised time τ ∈ [0, 1] at `t_s`.
    #[inline]
    fn tau(&self, t_s: f64) -> f64 {
        ((t_s - self.start_s) / self.duration_s).clamp(0.0, 1.0)
    }

    /// ∫ of the piece from its start to normalised time `tau`.
    #[inline]
    fn integral_at_tau(&self, tau: f64) -> f64 {
        self.duration_s * (self.from * tau + (self.to - self.from) * smoothstep_integral(tau))
    }
}

/// A signal of time made of holds and smoothstep ramps laid end to end
/// from t = 0. Before 0 it keeps its initial value, after its last piece
/// its final value.
#[derive(Debug, Clone)]
pub struct SmoothSignal {
    initial: f64,
    pieces: Vec<Piece>,
}

/// Value, first and second time derivatives of a signal at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SignalValue {
    /// The value.
    pub value: f64,
    /// Its first time derivative, per s.
    pub rate: f64,
    /// Its second time derivative, per s².
    pub accel: f64,
}

impl SmoothSignal {
    /// A signal at `initial` with no pieces yet.
    pub fn new(initial: f64) -> Self {
        Self {
            initial,
            pieces: Vec::new(),
        }
    }

    /// The time at which the last piece ends, s.
    pub fn end_s(&self) -> f64 {
        self.pieces.last().map_or(0.0, Piece::end_s)
    }

    /// The value after the last piece.
    pub fn final_value(&self) -> f64 {
        self.pieces.last().map_or(self.initial, |p| p.to)
    }

    /// Keeps the current value for `duration_s` (ignored if not positive).
    pub fn hold(&mut self, duration_s: f64) {
        let v = self.final_value();
        self.ramp_to(duration_s, v);
    }

    /// Moves from the current value to `target` along a smoothstep lasting
    /// `duration_s` (ignored if not positive).
    pub fn ramp_to(&mut self, duration_s: f64, target: f64) {
        if duration_s <= 0.0 {
            return;
        }
        let (start_s, from, integral_before) = match self.pieces.last() {
            None => (0.0, self.initial, 0.0),
            Some(p) => (
                p.end_s(),
                p.to,
                p.integral_before + p.integral_over(p.duration_s),
            ),
        };
        self.pieces.push(Piece {
            start_s,
            duration_s,
            from,
            to: target,
            integral_before,
        });
    }

    /// Index of the piece holding `t`, or None before 0 / after the end.
    fn piece_at(&self, t_s: f64) -> Option<&Piece> {
        if t_s < 0.0 {
            return None;
        }
        let k = self.pieces.partition_point(|p| p.end_s() <= t_s);
        self.pieces.get(k)
    }

    /// The piece holding `t_s` found by scanning forward from `*hint` (the
    /// index found for an earlier, not later, time; 0 to start), which is
    /// updated: O(1) per call over non-decreasing times. The same piece as
    /// [`Self::piece_at`]; a time before the hint's falls back to the search.
    fn piece_from(&self, t_s: f64, hint: &mut usize) -> Option<&Piece> {
        if t_s < 0.0 {
            return None;
        }
        let mut k = *hint;
        if k > self.pieces.len() || (k > 0 && self.pieces[k - 1].end_s() > t_s) {
            k = self.pieces.partition_point(|p| p.end_s() <= t_s);
        } else {
            while k < self.pieces.len() && self.pieces[k].end_s() <= t_s {
                k += 1;
            }
        }
        *hint = k;
        self.pieces.get(k)
    }

    /// Value and derivatives at `t_s`.
    pub fn at(&self, t_s: f64) -> SignalValue {
        self.value_in(self.piece_at(t_s), t_s)
    }

    /// [`Self::at`] for times visited in non-decreasing order: `hint`
    /// starts at 0 and is kept between calls (bitwise the same values).
    pub fn at_from(&self, t_s: f64, hint: &mut usize) -> SignalValue {
        self.value_in(self.piece_from(t_s, hint), t_s)
    }

    /// [`Self::at`] and [`Self::integral`] at one time from one lookup, for
    /// times visited in non-decreasing order (as [`Self::at_from`]); τ is
    /// computed once for both (the same arithmetic).
    pub fn at_and_integral_from(&self, t_s: f64, hint: &mut usize) -> (SignalValue, f64) {
        let piece = self.piece_from(t_s, hint);
        match piece {
            Some(p) if t_s > 0.0 => {
                let tau = p.tau(t_s);
                (
                    Self::value_at_tau(p, tau),
                    p.integral_before + p.integral_at_tau(tau),
                )
            }
            _ => (self.value_in(piece, t_s), self.integral_in(piece, t_s)),
        }
    }

    /// `at_from(t_s, hint).value` alone (bitwise), for the position
    /// integration's requests, which need no derivatives.
    pub fn value_from(&self, t_s: f64, hint: &mut usize) -> f64 {
        match self.piece_from(t_s, hint) {
            Some(p) => p.from + (p.to - p.from) * smoothstep_value(p.tau(t_s)),
            None => self.outside(t_s),
        }
    }

    /// `at_and_integral_from(t_s, hint).1` alone (bitwise).
    pub fn integral_from(&self, t_s: f64, hint: &mut usize) -> f64 {
        let piece = self.piece_from(t_s, hint);
        self.integral_in(piece, t_s)
    }

    fn value_in(&self, piece: Option<&Piece>, t_s: f64) -> SignalValue {
        match piece {
            Some(p) => Self::value_at_tau(p, p.tau(t_s)),
            None => SignalValue {
                value: self.outside(t_s),
                rate: 0.0,
                accel: 0.0,
            },
        }
    }

    /// The value before 0 or after the last piece.
    fn outside(&self, t_s: f64) -> f64 {
        if t_s < 0.0 {
            self.initial
        } else {
            self.final_value()
        }
    }

    #[inline]
    fn value_at_tau(p: &Piece, tau: f64) -> SignalValue {
        let [s, ds, dds] = smoothstep(tau);
        let delta = p.to - p.from;
        SignalValue {
            value: p.from + delta * s,
            rate: delta * ds / p.duration_s,
            accel: delta * dds / (p.duration_s * p.duration_s),
        }
    }

    /// ∫₀^t of the signal, exact.
    pub fn integral(&self, t_s: f64) -> f64 {
        self.integral_in(self.piece_at(t_s), t_s)
    }

    fn integral_in(&self, piece: Option<&Piece>, t_s: f64) -> f64 {
        if t_s <= 0.0 {
            return self.initial * t_s;
        }
        match piece {
            Some(p) => p.integral_before + p.integral_over(t_s - p.start_s),
            None => {
                let total = self
                    .pieces
                    .last()
                    .map_or(0.0, |p| p.integral_before + p.integral_over(p.duration_s));
                total + self.final_value() * (t_s - self.end_s())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signal() -> SmoothSignal {
        let mut s = SmoothSignal::new(2.0);
        s.hold(3.0);
        s.ramp_to(4.0, -1.0);
        s.ramp_to(2.5, 5.0);
        s.hold(1.0);
        s
    }

    #[test]
    fn derivatives_and_integral_match_finite_differences() {
        let s = signal();
        let h = 1e-4;
        for k in 0..200 {
            let t = -0.5137 + k as f64 * 0.06; // off the joins, where ȧ has a kink
            let v = s.at(t);
            let rate_fd = (s.at(t + h).value - s.at(t - h).value) / (2.0 * h);
            let accel_fd = (s.at(t + h).rate - s.at(t - h).rate) / (2.0 * h);
            let integral_fd = (s.integral(t + h) - s.integral(t - h)) / (2.0 * h);
            assert!((v.rate - rate_fd).abs() < 1e-6, "{t}");
            assert!((v.accel - accel_fd).abs() < 1e-5, "{t}");
            assert!((v.value - integral_fd).abs() < 1e-7, "{t}");
        }
    }

    #[test]
    fn cursor_lookups_equal_the_search() {
        let s = signal();
        let mut hint = 0;
        // Non-decreasing times (with repeats and joins), then a step back.
        let times = [
            -1.0, 0.0, 0.0, 1.0, 3.0, 3.0, 5.2, 7.0, 9.49, 9.5, 11.0, 30.0, 4.0, 6.0,
        ];
        for t in times {
            let (v, integral) = s.at_and_integral_from(t, &mut hint);
            assert_eq!(v, s.at(t), "{t}");
            assert_eq!(integral.to_bits(), s.integral(t).to_bits(), "{t}");
            let mut other = hint;
            assert_eq!(s.at_from(t, &mut other), s.at(t), "{t}");
            let mut other = hint;
            assert_eq!(s.value_from(t, &mut other).to_bits(), v.value.to_bits());
            let mut other = hint;
            assert_eq!(s.integral_from(t, &mut other).to_bits(), integral.to_bits());
        }
    }

    #[test]
    fn continuous_at_joins_with_known_integral() {
        let s = signal();
        for t in [3.0, 7.0, 9.5] {
            let (a, b) = (s.at(t - 1e-12), s.at(t + 1e-12));
            assert!((a.value - b.value).abs() < 1e-9);
            assert!(a.rate.abs() < 1e-9 && b.rate.abs() < 1e-9);
            assert!(a.accel.abs() < 1e-9 && b.accel.abs() < 1e-9);
        }
        // A smoothstep ramp is symmetric about its midpoint: its integral is
        // the mean of its end values times its duration.
        let expected = 2.0 * 3.0 + 0.5 * (2.0 - 1.0) * 4.0 + 0.5 * (-1.0 + 5.0) * 2.5 + 5.0 * 1.0;
        assert!((s.integral(10.5) - expected).abs() < 1e-12);
        assert!((s.integral(12.5) - expected - 10.0).abs() < 1e-12);
        assert_eq!(s.at(100.0).value, 5.0);
    }
}
