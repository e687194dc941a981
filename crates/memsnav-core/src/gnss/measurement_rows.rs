//! GNSS measurements given one satellite at a time (a long table's rows,
//! the slots of padded arrays) checked and grouped into epochs: the one
//! gate every outside measurement passes before the fix solver or a
//! filter sees it.
//!
//! NaN policy (docs/reference/robustness.md): a measurement with a NaN or infinite
//! time, satellite position or velocity, pseudorange or pseudorange σ is
//! refused with an error naming it; NaN is accepted only for a rate (and
//! its σ), where it means "this satellite has no rate at this epoch". A
//! carrier phase, when present, needs a finite range and a finite positive
//! σ (the converters turn a NaN carrier slot into no carrier).

use super::plausible;
use super::{CarrierPhase, GnssEpoch, SatelliteMeasurement};

/// Largest satellite distance from the Earth's centre accepted, m (well
/// beyond geostationary orbit, 4.2e7 m).
pub const MAX_SATELLITE_RADIUS_M: f64 = 1e8;
/// Largest satellite speed accepted, m/s.
pub const MAX_SATELLITE_SPEED_M_S: f64 = 1e4;
/// `m` checked, or a sentence naming the offending field. A NaN rate
/// drops the rate's σ too (no rate at all); a finite rate needs a
/// finite positive σ, and so does a carrier phase's range. A finite
/// pseudorange, rate or carrier range however large passes:
/// an outlier is the fix solver's and the filters' to diagnose, naming
/// the satellite.
pub fn check_measurement(m: &SatelliteMeasurement) -> Result<SatelliteMeasurement, String> {
    let vector_ok =
        |v: &nalgebra::Vector3<f64>, max: f64| v.iter().all(|x| x.is_finite()) && v.norm() <= max;
    if !vector_ok(&m.position_ecef, MAX_SATELLITE_RADIUS_M) {
        return Err(format!(
            "satellite position {:?} m is not finite or beyond {MAX_SATELLITE_RADIUS_M:e} m",
            m.position_ecef.as_slice()
        ));
    }
    if !vector_ok(&m.velocity_ecef, MAX_SATELLITE_SPEED_M_S) {
        return Err(format!(
            "satellite velocity {:?} m/s is not finite or faster than {MAX_SATELLITE_SPEED_M_S:e} m/s",
            m.velocity_ecef.as_slice()
        ));
    }
    if !m.pseudorange_m.is_finite() {
        return Err(format!(
            "pseudorange = {} m (must be finite; leave the satellite out instead of a NaN)",
            m.pseudorange_m
        ));
    }
    plausible::check(
        m.pseudorange_m,
        plausible::PSEUDORANGE_M,
        "pseudorange",
        "m",
    )?;
    if !(m.pseudorange_std_m.is_finite() && m.pseudorange_std_m > 0.0) {
        return Err(format!(
            "pseudorange_std = {} m (must be finite and positive)",
            m.pseudorange_std_m
        ));
    }
    if let Some(c) = m.carrier {
        if !c.range_m.is_finite() {
            return Err(format!(
                "carrier_phase = {} m (must be finite; NaN means no carrier at that slot)",
                c.range_m
            ));
        }
        if !(c.std_m.is_finite() && c.std_m > 0.0) {
            return Err(format!(
                "carrier_phase_std = {} m with a carrier phase of {} m (must be finite and positive)",
                c.std_m, c.range_m
            ));
        }
    }
    let mut out = *m;
    if m.pseudorange_rate_m_s.is_nan() {
        out.pseudorange_rate_std_m_s = f64::NAN;
        return Ok(out);
    }
    if !m.pseudorange_rate_m_s.is_finite() {
        return Err(format!(
            "pseudorange_rate = {} m/s (NaN for none, else finite)",
            m.pseudorange_rate_m_s
        ));
    }
    plausible::check(
        m.pseudorange_rate_m_s,
        plausible::PSEUDORANGE_RATE_M_S,
        "pseudorange_rate",
        "m/s",
    )?;
    if !(m.pseudorange_rate_std_m_s.is_finite() && m.pseudorange_rate_std_m_s > 0.0) {
        return Err(format!(
            "pseudorange_rate_std = {} m/s with a rate of {} m/s (must be finite and positive)",
            m.pseudorange_rate_std_m_s, m.pseudorange_rate_m_s
        ));
    }
    Ok(out)
}

/// The carrier phase of one table row or array slot from its carrier range
/// (NaN: no carrier there, whatever its σ and flag), σ, m, and
/// loss-of-lock flag (1 or 0; NaN, an empty cell, is 0). The range and σ
/// are [`check_measurement`]'s to check; a flag other than 0, 1 or NaN is
/// refused.
pub fn carrier_of(
    range_m: f64,
    std_m: f64,
    loss_of_lock: f64,
) -> Result<Option<CarrierPhase>, String> {
    let loss_of_lock = if loss_of_lock == 1.0 {
        true
    } else if loss_of_lock == 0.0 || loss_of_lock.is_nan() {
        false
    } else {
        return Err(format!(
            "loss_of_lock = {loss_of_lock} (must be 1, 0 or empty)"
        ));
    };
    Ok((!range_m.is_nan()).then_some(CarrierPhase {
        range_m,
        std_m,
        loss_of_lock,
    }))
}

/// A satellite number from a float: a whole number 0..=65535.
pub fn sat_id(value: f64) -> Result<u16, String> {
    if value.is_finite() && value >= 0.0 && value <= f64::from(u16::MAX) && value.fract() == 0.0 {
        Ok(value as u16)
    } else {
        Err(format!(
            "sat_id = {value} is not a satellite number (0 to 65535)"
        ))
    }
}

/// Epochs from measurements in time order, one `(time_s, measurement)`
/// per satellite and epoch (each checked by [`check_measurement`]); rows of
/// one epoch share its time exactly. The error is the index of the
/// offending row and a sentence: a time not finite or going back, a
/// satellite twice in an epoch, a bad measurement.
pub fn epochs_from_rows(
    rows: impl IntoIterator<Item = (f64, SatelliteMeasurement)>,
) -> Result<Vec<GnssEpoch>, (usize, String)> {
    let mut epochs: Vec<GnssEpoch> = Vec::new();
    for (i, (time_s, m)) in rows.into_iter().enumerate() {
        if !time_s.is_finite() {
            return Err((i, format!("time = {time_s} s is not finite")));
        }
        let m = check_measurement(&m).map_err(|e| (i, e))?;
        match epochs.last_mut() {
            Some(e) if e.time_s == time_s => {
                if e.measurements.iter().any(|x| x.sat_id == m.sat_id) {
                    return Err((
                        i,
                        format!("satellite {} appears twice at time {time_s} s", m.sat_id),
                    ));
                }
                e.measurements.push(m);
            }
            Some(e) if e.time_s > time_s => {
                return Err((
                    i,
                    format!(
                        "time = {time_s} s goes back from {} s (rows must be in time order)",
                        e.time_s
                    ),
                ))
            }
            _ => epochs.push(GnssEpoch {
                time_s,
                measurements: vec![m],
            }),
        }
    }
    Ok(epochs)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn measurement(sat_id: u16) -> SatelliteMeasurement {
        SatelliteMeasurement {
            sat_id,
            system: super::super::GnssSystem::Gps,
            position_ecef: Vector3::new(2.0e7, 1.0e7, 1.0e7),
            velocity_ecef: Vector3::new(1000.0, 2000.0, 0.0),
            pseudorange_m: 2.2e7,
            pseudorange_rate_m_s: f64::NAN,
            pseudorange_std_m: 3.0,
            pseudorange_rate_std_m_s: 0.1,
            carrier: None,
        }
    }

    #[test]
    fn rows_group_into_epochs() {
        let rows = [
            (0.0, measurement(1)),
            (0.0, measurement(2)),
            (1.0, measurement(1)),
        ];
        let epochs = epochs_from_rows(rows).unwrap();
        assert_eq!(epochs.len(), 2);
        assert_eq!(epochs[0].measurements.len(), 2);
        // A NaN rate drops its σ: no rate at all.
        assert!(epochs[0].measurements[0].pseudorange_rate_std_m_s.is_nan());
    }

    #[test]
    fn bad_rows_are_named() {
        let twice = [(0.0, measurement(1)), (0.0, measurement(1))];
        assert_eq!(epochs_from_rows(twice).unwrap_err().0, 1);
        let back = [(1.0, measurement(1)), (0.0, measurement(2))];
        assert!(epochs_from_rows(back).unwrap_err().1.contains("goes back"));
        let mut nan = measurement(3);
        nan.pseudorange_m = f64::NAN;
        let e = epochs_from_rows([(0.0, measurement(1)), (0.0, nan)]).unwrap_err();
        assert_eq!(e.0, 1);
        assert!(e.1.starts_with("pseudorange = NaN"), "{}", e.1);
        let mut no_std = measurement(4);
        no_std.pseudorange_rate_m_s = 5.0;
        no_std.pseudorange_rate_std_m_s = f64::NAN;
        assert!(check_measurement(&no_std)
            .unwrap_err()
            .contains("pseudorange_rate_std"));
        let mut far = measurement(5);
        far.position_ecef.x = 1e67;
        assert!(check_measurement(&far).is_err());
        let carrier = |range_m: f64, std_m: f64| {
            let mut m = measurement(6);
            m.carrier = Some(super::super::CarrierPhase {
                range_m,
                std_m,
                loss_of_lock: false,
            });
            check_measurement(&m)
        };
        assert!(carrier(2.2e7, 0.003).is_ok());
        assert!(carrier(f64::INFINITY, 0.003)
            .unwrap_err()
            .starts_with("carrier_phase = inf"));
        for std in [0.0, -1.0, f64::NAN] {
            assert!(carrier(2.2e7, std)
                .unwrap_err()
                .starts_with("carrier_phase_std = "));
        }
        assert_eq!(carrier_of(f64::NAN, f64::NAN, 1.0), Ok(None));
        assert!(carrier_of(1.0, 0.003, 1.0).unwrap().unwrap().loss_of_lock);
        assert!(
            !carrier_of(1.0, 0.003, f64::NAN)
                .unwrap()
                .unwrap()
                .loss_of_lock
        );
        assert!(carrier_of(1.0, 0.003, 2.0)
            .unwrap_err()
            .starts_with("loss_of_lock = 2"));
        assert!(sat_id(3.5).is_err() && sat_id(-1.0).is_err() && sat_id(f64::NAN).is_err());
        assert_eq!(sat_id(12.0), Ok(12));
    }
}
