//! Whether the gyro's turns have the size the GNSS course says: the one
//! reference a log has for the gyro's scale while it moves, so the one
//! check that can tell a gyro read in the wrong unit (degrees for radians
//! or the reverse: a factor π/180) before the filter goes astray on it.
//!
//! Between two consecutive GNSS epochs with a well-defined course, the
//! course changes by Δχ; the gyro turns the body about the local vertical
//! by Δψ = (∫ω_ib^b dt) · d^b, d^b the down direction in body axes taken
//! from the mean specific force over the interval (d^b = −f̄^b/|f̄^b|: at
//! rest or in gentle motion f ≈ −g). From the Euler-angle rates,
//! ψ̇ = (ω_y sin φ + ω_z cos φ)/cos θ, and d^b = (−sin θ, sin φ cos θ,
//! cos φ cos θ), so ω · d^b = cos²θ ψ̇ − sin θ ω_x: the heading rate to a
//! few per cent at the pitch of land vehicles and people. Neither the
//! mounting nor the axis convention enters (ω and f are in the same axes),
//! nor the Earth's rate (7.3e-5 rad/s, nothing over a few seconds).
//!
//! The gyro's scale against the course is the least-squares slope of Δχ on
//! Δψ, inverted: r = Σ Δψ² / Σ Δχ Δψ. The slope is taken that way round
//! because the course's noise (the GNSS velocity's σ over the speed) is in
//! Δχ, the dependent variable, where it adds scatter but no bias; the
//! other way round it would shrink the slope towards zero on noisy
//! courses. On the shared real logs r is 0.98 (car, RTK velocities), 0.99
//! (another car, standalone u-blox velocities) and 1.11 (a hand-held walk);
//! the same logs with the rates divided or multiplied by 180/π give
//! 0.017-0.019 and 56-63 (docs/how-to/when-a-run-fails.md).

use nalgebra::Vector3;

use super::align::GnssKinematics;
use crate::attitude::wrap_angle_rad;
use crate::ins::ImuSample;

/// Longest interval between the two epochs of a pair, s.
const MAX_PAIR_INTERVAL_S: f64 = 2.0;
/// Largest course one-sigma of an epoch used, rad (11°).
const MAX_COURSE_STD_RAD: f64 = 0.2;
/// Fewest pairs for a verdict.
const MIN_PAIRS: usize = 20;
/// Least course change over the pairs for a verdict, rad (a quarter turn):
/// a straight run says nothing about the gyro's scale.
const MIN_TURN_RAD: f64 = std::f64::consts::FRAC_PI_2;
/// Largest relative one-sigma of the slope for a verdict.
const MAX_RELATIVE_STD: f64 = 0.25;

/// The gyro's turns against the GNSS course's over a log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GyroScale {
    /// r: how many times the GNSS course's turn the gyro's turn is (1 for
    /// a gyro read in its unit, π/180 for radians read as degrees).
    pub ratio: f64,
    /// One-sigma of the fitted slope over the slope.
    pub relative_std: f64,
    /// Σ |Δχ| over the pairs, rad.
    pub course_turn_rad: f64,
    /// Pairs of consecutive epochs used.
    pub pairs: usize,
}

impl GyroScale {
    /// Whether the fit can say anything: enough pairs, enough turning, a
    /// slope known to `MAX_RELATIVE_STD` and of the right sign.
    pub fn conclusive(&self) -> bool {
        self.pairs >= MIN_PAIRS
            && self.course_turn_rad >= MIN_TURN_RAD
            && self.relative_std <= MAX_RELATIVE_STD
            && self.ratio > 0.0
    }

    /// A warning naming `gyro_unit` and the likely unit when the ratio is
    /// nearer π/180 or 180/π than 1 (on a log scale: beyond √(180/π) =
    /// 7.6 either way, where the real logs give 0.98-1.11), else None.
    pub fn unit_warning(&self) -> Option<String> {
        let factor = 1.0_f64.to_degrees();
        let boundary = factor.sqrt();
        if !self.conclusive() || (1.0 / boundary..=boundary).contains(&self.ratio) {
            return None;
        }
        let (looks, hint) = if self.ratio < 1.0 {
            (
                "radians read as degrees",
                "\"rad/s\" (\"rad\" for angle increments)",
            )
        } else {
            (
                "degrees read as radians",
                "\"deg/s\" (\"deg\" for angle increments)",
            )
        };
        Some(format!(
            "gyro_unit: the gyro turns {:.4} times as much as the GNSS course about the vertical \
             ({} pairs of GNSS epochs turning {:.0}° in all; 1/{factor:.1} or {factor:.1} is a \
             unit mistake): the angular rates look like {looks}: is gyro_unit {hint}?",
            self.ratio,
            self.pairs,
            self.course_turn_rad.to_degrees(),
        ))
    }
}

/// The gyro's turns against the GNSS course's (module docs) over the IMU
/// samples (`time_s` on GNSS time, body or sensor axes alike) and the GNSS
/// epochs; None without a single usable pair of epochs or without any
/// gyro turn.
pub fn gyro_scale(
    time_s: &[f64],
    imu: &[ImuSample],
    kinematics: &[GnssKinematics],
) -> Option<GyroScale> {
    if time_s.len() < 2 {
        return None;
    }
    // Running sums: ∫ω dt by the trapezoid rule, and Σ f, so each pair's
    // turn and mean specific force take two lookups.
    let mut turn = Vec::with_capacity(time_s.len());
    let mut force = Vec::with_capacity(time_s.len() + 1);
    turn.push(Vector3::zeros());
    force.push(Vector3::zeros());
    for k in 0..time_s.len() {
        force.push(force[k] + imu[k].specific_force_b);
        if k > 0 {
            let dt = time_s[k] - time_s[k - 1];
            let mean = 0.5 * (imu[k].angular_rate_b + imu[k - 1].angular_rate_b);
            turn.push(turn[k - 1] + mean * dt);
        }
    }
    let sample = |t: f64| time_s.partition_point(|&s| s < t).min(time_s.len() - 1);
    let courses: Vec<Option<(f64, f64)>> = kinematics
        .iter()
        .map(|g| {
            let inside = g.time_s >= time_s[0] && g.time_s <= time_s[time_s.len() - 1];
            g.course()
                .filter(|&(_, _, std)| inside && std <= MAX_COURSE_STD_RAD)
                .map(|(_, course, _)| (g.time_s, course))
        })
        .collect();
    let (mut syy, mut sgy, mut sgg, mut turned, mut pairs) = (0.0, 0.0, 0.0, 0.0, 0);
    for w in courses.windows(2) {
        let (Some((ta, ca)), Some((tb, cb))) = (w[0], w[1]) else {
            continue;
        };
        if !(tb > ta && tb - ta <= MAX_PAIR_INTERVAL_S) {
            continue;
        }
        let (a, b) = (sample(ta), sample(tb));
        if b <= a {
            continue;
        }
        let mean_force = (force[b + 1] - force[a]) / (b + 1 - a) as f64;
        let down = -mean_force.normalize();
        let gyro = (turn[b] - turn[a]).dot(&down);
        let course = wrap_angle_rad(cb - ca);
        if !(gyro.is_finite() && course.is_finite()) {
            continue;
        }
        syy += gyro * gyro;
        sgy += course * gyro;
        sgg += course * course;
        turned += course.abs();
        pairs += 1;
    }
    if pairs < 2 || syy <= 0.0 {
        return None;
    }
    let slope = sgy / syy;
    // Σ (Δχ − s Δψ)² = Σ Δχ² − s Σ Δχ Δψ at the least-squares s.
    let residual = (sgg - slope * sgy).max(0.0);
    let std = (residual / (pairs - 1) as f64 / syy).sqrt();
    Some(GyroScale {
        ratio: 1.0 / slope,
        relative_std: std / slope.abs(),
        course_turn_rad: turned,
        pairs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geodesy::{c_n_e, geodetic_to_ecef, Geodetic};
    use nalgebra::Matrix3;

    /// A vehicle at 10 m/s driving circles of radius 100 m (0.1 rad/s),
    /// level, with its gyro reading `scale` times the true yaw rate and its
    /// course known to 0.01 rad: a known answer for the ratio.
    fn circles(scale: f64, course_noise: f64) -> Option<GyroScale> {
        let rate = 0.1;
        let time: Vec<f64> = (0..12_000).map(|k| k as f64 * 0.01).collect();
        let imu: Vec<ImuSample> = time
            .iter()
            .map(|_| ImuSample {
                specific_force_b: Vector3::new(0.0, 1.0, -9.81),
                angular_rate_b: Vector3::new(0.0, 0.0, scale * rate),
            })
            .collect();
        let site = Geodetic {
            latitude_rad: 0.7,
            longitude_rad: 0.02,
            height_m: 100.0,
        };
        let r = geodetic_to_ecef(site);
        let cne = c_n_e(site.latitude_rad, site.longitude_rad);
        let kinematics = (0..120)
            .map(|i| {
                let t = i as f64;
                // A deterministic scatter of the course, alternating sign.
                let course = rate * t + course_noise * if i % 2 == 0 { 1.0 } else { -1.0 };
                let v_ned = 10.0 * Vector3::new(course.cos(), course.sin(), 0.0);
                GnssKinematics {
                    time_s: t,
                    position_ecef: r,
                    position_covariance: Matrix3::identity(),
                    velocity_ecef: Some(cne * v_ned),
                    velocity_covariance: Matrix3::identity() * 0.01,
                    velocity_from_positions: false,
                }
            })
            .collect::<Vec<_>>();
        gyro_scale(&time, &imu, &kinematics)
    }

    #[test]
    fn the_ratio_is_the_gyro_scale_and_a_unit_mistake_is_named() {
        let right = circles(1.0, 0.01).unwrap();
        assert!((right.ratio - 1.0).abs() < 0.02, "{right:?}");
        assert!(right.conclusive() && right.unit_warning().is_none());
        // 12 turns of 0.1 rad/s over 119 pairs: the course turned 11.9 rad.
        assert!((right.course_turn_rad - 11.9).abs() < 0.3, "{right:?}");
        let small = circles(1.0_f64.to_radians(), 0.01).unwrap();
        assert!(
            (small.ratio - 1.0_f64.to_radians()).abs() < 1e-3,
            "{small:?}"
        );
        let w = small.unit_warning().unwrap();
        assert!(
            w.starts_with("gyro_unit: ") && w.contains("is gyro_unit \"rad/s\""),
            "{w}"
        );
        let large = circles(1.0_f64.to_degrees(), 0.01).unwrap();
        assert!(
            (large.ratio / 1.0_f64.to_degrees() - 1.0).abs() < 0.02,
            "{large:?}"
        );
        assert!(large
            .unit_warning()
            .unwrap()
            .contains("is gyro_unit \"deg/s\""));
        // A scale error of a few per cent is not a unit.
        assert!(circles(1.05, 0.01).unwrap().unit_warning().is_none());
    }

    #[test]
    fn a_noisy_course_widens_the_fit_without_biasing_it() {
        // A course scatter of ±0.05 rad around 0.1 rad turns per pair.
        let noisy = circles(1.0, 0.05).unwrap();
        assert!((noisy.ratio - 1.0).abs() < 0.1, "{noisy:?}");
        assert!(noisy.relative_std > circles(1.0, 0.01).unwrap().relative_std);
    }

    #[test]
    fn no_turn_no_verdict() {
        // Driving straight: the gyro's noise against no course change.
        let time: Vec<f64> = (0..3000).map(|k| k as f64 * 0.01).collect();
        let imu: Vec<ImuSample> = (0..3000)
            .map(|k| ImuSample {
                specific_force_b: Vector3::new(0.0, 0.0, -9.81),
                angular_rate_b: Vector3::new(0.0, 0.0, if k % 2 == 0 { 1e-3 } else { -2e-3 }),
            })
            .collect();
        let site = Geodetic {
            latitude_rad: 0.7,
            longitude_rad: 0.02,
            height_m: 100.0,
        };
        let r = geodetic_to_ecef(site);
        let cne = c_n_e(site.latitude_rad, site.longitude_rad);
        let kinematics: Vec<GnssKinematics> = (0..30)
            .map(|i| GnssKinematics {
                time_s: i as f64,
                position_ecef: r,
                position_covariance: Matrix3::identity(),
                velocity_ecef: Some(cne * Vector3::new(10.0, 0.0, 0.0)),
                velocity_covariance: Matrix3::identity() * 0.01,
                velocity_from_positions: false,
            })
            .collect();
        let check = gyro_scale(&time, &imu, &kinematics).unwrap();
        assert!(
            !check.conclusive() && check.unit_warning().is_none(),
            "{check:?}"
        );
    }
}
