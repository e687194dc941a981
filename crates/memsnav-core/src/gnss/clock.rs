//! Two-state receiver clock: offset b (m) and drift ḃ (m/s) driven by white
//! noise (Brown & Hwang, *Introduction to Random Signals and Applied Kalman
//! Filtering*, 4th ed., §9.3; Groves 2nd ed. §9.4.2.2 and table 9.x).
//!
//! Continuous model: ḃ_offset = drift + w_f, ḋrift = w_g with white-noise
//! PSDs S_f = c² h0 / 2 and S_g = c² 2π² h−2 (h_α: Allan-variance
//! power-law coefficients of the oscillator). Over Δt the exact discrete
//! process noise is (Brown & Hwang eq. 9.3.11):
//! Q = [[S_f Δt + S_g Δt³/3, S_g Δt²/2], [S_g Δt²/2, S_g Δt]].

use nalgebra::{Matrix2, Vector2};
use rand_distr::{Distribution, StandardNormal};

use crate::geodesy::domain::{MAX_DISTANCE_M, MAX_SPEED_M_S};
use crate::geodesy::wgs84::SPEED_OF_LIGHT_M_S;
use crate::random::Rng;
use crate::{validate, Error, Result};

/// Largest Allan-variance coefficient (h0, h−2) accepted: 10¹³ times a
/// TCXO's. Its noise densities (c² h ≈ 9e16 h) times any step of a
/// simulation stay finite (h0 = 1e300 gave 360 NaN pseudoranges
/// of 366; huge values overflowed the clock's process noise).
pub const MAX_ALLAN_COEFFICIENT: f64 = 1e-6;

/// Parameters of the receiver clock.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReceiverClockModel {
    /// White frequency noise coefficient h0, s. Default 2e-19 (temperature
    /// compensated crystal oscillator, Brown & Hwang table 9.1).
    pub h0: f64,
    /// Random-walk frequency noise coefficient h−2, 1/s. Default 2e-20
    /// (TCXO, Brown & Hwang table 9.1).
    pub h_minus2: f64,
    /// One-sigma of the initial clock offset, m. Default 30 m (100 ns).
    pub initial_offset_std_m: f64,
    /// One-sigma of the initial clock drift, m/s. Default 1 m/s (3.3 ns/s;
    /// a TCXO's frequency error after the receiver's steering).
    pub initial_drift_std_m_s: f64,
}

impl Default for ReceiverClockModel {
    fn default() -> Self {
        ReceiverClockModel {
            h0: 2e-19,
            h_minus2: 2e-20,
            initial_offset_std_m: 30.0,
            initial_drift_std_m_s: 1.0,
        }
    }
}

/// Clock offset (m) and drift (m/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClockState {
    /// Receiver clock offset, m (c × the offset in s).
    pub offset_m: f64,
    /// Receiver clock drift, m/s.
    pub drift_m_s: f64,
}

impl ReceiverClockModel {
    /// Checks every coefficient and initial std; the error names the Python keyword.
    pub fn validate(&self) -> Result<()> {
        validate::magnitude("clock_h0", self.h0, MAX_ALLAN_COEFFICIENT)?;
        validate::magnitude("clock_h_minus2", self.h_minus2, MAX_ALLAN_COEFFICIENT)?;
        // An offset no larger than the ranges of the geodesy's domain (3 s),
        // a drift no faster than its speeds (330 ppm; crystals hold 50).
        validate::magnitude(
            "clock_initial_offset_std",
            self.initial_offset_std_m,
            MAX_DISTANCE_M,
        )?;
        validate::magnitude(
            "clock_initial_drift_std",
            self.initial_drift_std_m_s,
            MAX_SPEED_M_S,
        )
    }

    /// The model of an oscillator class, by name (initial stds as the
    /// default's):
    ///
    /// - `"ocxo"`: oven-controlled crystal, h0 = 8e-20, h−2 = 4e-23
    ///   (Brown & Hwang table 9.1);
    /// - `"tcxo"`: temperature-compensated crystal, h0 = 2e-19, h−2 = 2e-20
    ///   (Brown & Hwang table 9.1; Groves' S_cf ≈ 0.04 m²/s³);
    /// - `"consumer"`: the TCXO of a consumer receiver moved through
    ///   temperature changes (in a hand, a car cabin), h0 = 2e-19,
    ///   h−2 = 2e-18 (S_cf ≈ 3.5 m²/s³, a hundred times the TCXO's): the
    ///   u-blox receiver of walk_0827 changed its drift by 20 m/s over its
    ///   133.75 s log (docs/reference/configuration.md), which a TCXO's 0.19 m/s/√s random
    ///   walk makes a 9.2σ event and this model a 0.92σ one.
    pub fn oscillator(name: &str) -> Result<Self> {
        let (h0, h_minus2) = match name {
            "ocxo" => (8e-20, 4e-23),
            "tcxo" => (2e-19, 2e-20),
            "consumer" => (2e-19, 2e-18),
            _ => {
                return Err(Error::invalid(
                    "receiver_clock",
                    format!("must be \"ocxo\", \"tcxo\" or \"consumer\", got {name:?}"),
                ))
            }
        };
        Ok(Self {
            h0,
            h_minus2,
            ..Self::default()
        })
    }

    /// White-noise PSD of the offset, S_f = c² h0 / 2, m²/s.
    pub fn offset_psd_m2_s(&self) -> f64 {
        SPEED_OF_LIGHT_M_S * SPEED_OF_LIGHT_M_S * self.h0 / 2.0
    }

    /// White-noise PSD of the drift, S_g = c² 2π² h−2, m²/s³.
    pub fn drift_psd_m2_s3(&self) -> f64 {
        SPEED_OF_LIGHT_M_S * SPEED_OF_LIGHT_M_S * 2.0 * std::f64::consts::PI.powi(2) * self.h_minus2
    }

    /// The discrete process-noise covariance over `dt_s` (module docs).
    pub fn process_noise(&self, dt_s: f64) -> Matrix2<f64> {
        let sf = self.offset_psd_m2_s();
        let sg = self.drift_psd_m2_s3();
        Matrix2::new(
            sf * dt_s + sg * dt_s.powi(3) / 3.0,
            sg * dt_s * dt_s / 2.0,
            sg * dt_s * dt_s / 2.0,
            sg * dt_s,
        )
    }

    /// A random initial state.
    pub fn initial(&self, rng: &mut Rng) -> ClockState {
        let z_offset: f64 = StandardNormal.sample(rng);
        let z_drift: f64 = StandardNormal.sample(rng);
        ClockState {
            offset_m: self.initial_offset_std_m * z_offset,
            drift_m_s: self.initial_drift_std_m_s * z_drift,
        }
    }

    /// One exact step of the process: x ← Φ x + w, Φ = [[1, Δt], [0, 1]],
    /// w ~ N(0, Q(Δt)) drawn through Q's Cholesky factor.
    pub fn step(&self, state: &ClockState, dt_s: f64, rng: &mut Rng) -> Result<ClockState> {
        validate::non_negative("dt", dt_s)?;
        let z: Vector2<f64> = Vector2::new(StandardNormal.sample(rng), StandardNormal.sample(rng));
        let q = self.process_noise(dt_s);
        if !q.iter().all(|v| v.is_finite()) {
            return Err(Error::invalid(
                "clock",
                format!(
                    "the process noise over a step of {dt_s:e} s overflows (h0 {:e}, h−2 {:e}): \
                     the step is too long for this clock model",
                    self.h0, self.h_minus2
                ),
            ));
        }
        let w = if q[(0, 0)] > 0.0 && q[(1, 1)] > 0.0 {
            let l = q
                .cholesky()
                .ok_or_else(|| Error::invalid("clock", "process noise is not positive definite"))?;
            l.l() * z
        } else {
            // One of the PSDs is zero: Q is diagonal or rank one.
            Vector2::new(q[(0, 0)].sqrt() * z.x, q[(1, 1)].sqrt() * z.y)
        };
        Ok(ClockState {
            offset_m: state.offset_m + state.drift_m_s * dt_s + w.x,
            drift_m_s: state.drift_m_s + w.y,
        })
    }
}
