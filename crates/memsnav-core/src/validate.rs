//! Argument checks shared by every public entry point. Each names the
//! argument at fault so the message tells the user what to fix.

use nalgebra::{Matrix3, Vector3};

use crate::{Error, Result};

/// Whether a function checks the long series it is given (an O(n) pass
/// over memory): always for what comes from outside; `Trusted` only
/// inside the crate, for series it generated itself (a random
/// trajectory's truth), where the check cannot fail.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SeriesCheck {
    Finite,
    Trusted,
}

/// Every component of every vector is finite.
pub fn finite_vectors(argument: &str, values: &[Vector3<f64>]) -> Result<()> {
    // A branch-free sweep first (|x| ≤ MAX is false for NaN and ±∞; the
    // non-short-circuit `&` lets it vectorise): long series are validated
    // at memory speed, and the row is searched for only on failure.
    let finite = |v: &Vector3<f64>| {
        (v.x.abs() <= f64::MAX) & (v.y.abs() <= f64::MAX) & (v.z.abs() <= f64::MAX)
    };
    if values.iter().fold(true, |ok, v| ok & finite(v)) {
        return Ok(());
    }
    match values.iter().position(|v| !finite(v)) {
        None => Ok(()),
        Some(k) => Err(Error::invalid(
            argument,
            format!("row {k} contains NaN or infinite values"),
        )),
    }
}

/// Every component of every vector is finite ([`finite_vectors`], whose
/// message a NaN gets) and at most `max` in magnitude; the error names the
/// row.
pub fn bounded_vectors(argument: &str, values: &[Vector3<f64>], max: f64) -> Result<()> {
    finite_vectors(argument, values)?;
    // Branch-free first, as in `finite_vectors`.
    let within = |v: &Vector3<f64>| (v.x.abs() <= max) & (v.y.abs() <= max) & (v.z.abs() <= max);
    if values.iter().fold(true, |ok, v| ok & within(v)) {
        return Ok(());
    }
    let k = values.iter().position(|v| !within(v)).unwrap_or(0);
    Err(Error::invalid(
        argument,
        format!(
            "row {k} holds {:e}, beyond the limit of ±{max:e} (SI units)",
            values[k]
                .iter()
                .copied()
                .find(|x| x.abs() > max)
                .unwrap_or(f64::NAN)
        ),
    ))
}

/// Every value is finite.
pub fn finite_scalars(argument: &str, values: &[f64]) -> Result<()> {
    match values.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(k) => Err(Error::invalid(
            argument,
            format!("element {k} is NaN or infinite"),
        )),
    }
}

/// Every value of an array of `shape` (row-major) is finite; the error
/// gives the index of the first bad value, `[row, column]` for a table.
pub fn finite_array(argument: &str, values: &[f64], shape: &[usize]) -> Result<()> {
    // A branch-free sweep first, as in `finite_vectors`.
    if values.iter().fold(true, |ok, x| ok & (x.abs() <= f64::MAX)) {
        return Ok(());
    }
    let Some(flat) = values.iter().position(|x| !x.is_finite()) else {
        return Ok(());
    };
    let mut index = vec![0; shape.len()];
    let mut rest = flat;
    for (i, &n) in shape.iter().enumerate().rev() {
        if n > 0 {
            index[i] = rest % n;
            rest /= n;
        }
    }
    let at = match index.as_slice() {
        [] => "the value".to_string(),
        [k] => format!("element {k}"),
        [row, column] => format!("row {row}, column {column}"),
        more => format!("index {more:?}"),
    };
    Err(Error::invalid(
        argument,
        format!("{at} is {}", values[flat]),
    ))
}

/// Every element of a matrix is finite and at most `max` in magnitude.
pub fn bounded_matrix(argument: &str, m: &Matrix3<f64>, max: f64) -> Result<()> {
    finite_matrix(argument, m)?;
    match m.iter().copied().find(|x| x.abs() > max) {
        None => Ok(()),
        Some(x) => Err(Error::invalid(
            argument,
            format!("holds {x:e}, beyond the limit of ±{max:e} (SI units)"),
        )),
    }
}

/// A magnitude (a standard deviation, a coefficient): finite,
/// non-negative and at most `max`.
pub fn magnitude(argument: &str, value: f64, max: f64) -> Result<()> {
    non_negative(argument, value)?;
    at_most(argument, value, max)
}

/// A sensor magnitude (a noise std, an instability, an LSB, ...): at most
/// [`MAX_SENSOR_MAGNITUDE`](crate::limits::MAX_SENSOR_MAGNITUDE).
pub fn sensor_magnitude(argument: &str, value: f64) -> Result<()> {
    magnitude(argument, value, crate::limits::MAX_SENSOR_MAGNITUDE)
}

/// A finite matrix.
pub fn finite_matrix(argument: &str, m: &Matrix3<f64>) -> Result<()> {
    if m.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(Error::invalid(argument, "contains NaN or infinite values"))
    }
}

/// A finite value that is zero or more.
pub fn non_negative(argument: &str, value: f64) -> Result<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            argument,
            format!("must be finite and non-negative, got {value}"),
        ))
    }
}

/// A standard deviation or noise density `value` (finite, ≥ 0) whose
/// square (the variance or PSD the filter uses) is finite; returns the
/// square. The message names the user's argument and its own value.
pub fn squared_std(argument: &str, value: f64) -> Result<f64> {
    non_negative(argument, value)?;
    let square = value * value;
    if !square.is_finite() {
        return Err(Error::invalid(
            argument,
            format!("{value:?} is too large: its square overflows (at most about 1e154)"),
        ));
    }
    Ok(square)
}

/// An initial one-sigma `value` (finite, > 0) whose square, the initial
/// variance, is a finite normal number.
pub fn initial_std(argument: &str, value: f64) -> Result<()> {
    positive(argument, value)?;
    let square = value * value;
    if !square.is_finite() || square < f64::MIN_POSITIVE {
        return Err(Error::invalid(
            argument,
            format!(
                "{value:?} is out of range: its square, the initial variance, must be a finite positive number (the std between about 1e-154 and 1e154)"
            ),
        ));
    }
    Ok(())
}

/// Smallest one-sigma of an aiding measurement, in its unit (m, m/s, rad,
/// rad/s): a billionth, far below any sensor's noise. Below it the
/// variance leaves the float range's useful part (1e-300 squares to 0) and
/// the update divides by rounding noise.
pub const MIN_AID_STD: f64 = 1e-9;

/// Largest one-sigma of an aiding measurement, in its unit: beyond it the
/// measurement says nothing, and its square nears the float range's end.
pub const MAX_AID_STD: f64 = 1e9;

/// An aid's one-sigma `value` within [[`MIN_AID_STD`], [`MAX_AID_STD`]].
pub fn aid_std(argument: &str, value: f64) -> Result<()> {
    if (MIN_AID_STD..=MAX_AID_STD).contains(&value) {
        Ok(())
    } else {
        Err(Error::invalid(
            argument,
            format!(
                "{value:e} is outside [{MIN_AID_STD:e}, {MAX_AID_STD:e}]: a one-sigma in the \
                 measurement's unit (m, m/s, rad, rad/s)"
            ),
        ))
    }
}

/// Longest lever arm, m: the size of the largest vehicle (a ship's
/// antenna or wheel tens of metres from its IMU). Beyond it a lever arm is
/// a unit or sign mistake, and its products with the angular rate swamp
/// the velocity it corrects.
pub const MAX_LEVER_ARM_M: f64 = 100.0;

/// A lever arm (m, body axes) no longer than [`MAX_LEVER_ARM_M`].
pub fn lever_arm(argument: &str, lever_arm_m: &Vector3<f64>) -> Result<()> {
    let length = lever_arm_m.norm();
    if length <= MAX_LEVER_ARM_M {
        Ok(())
    } else {
        Err(Error::invalid(
            argument,
            format!(
                "{:?} m is {length:e} m long, beyond a vehicle's size ({MAX_LEVER_ARM_M} m; \
                 metres in body axes expected)",
                lever_arm_m.as_slice()
            ),
        ))
    }
}

/// A finite value greater than zero.
pub fn positive(argument: &str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            argument,
            format!("must be finite and positive, got {value}"),
        ))
    }
}

/// A value at most `max` (checked after finiteness).
pub fn at_most(argument: &str, value: f64, max: f64) -> Result<()> {
    if value <= max {
        Ok(())
    } else {
        Err(Error::invalid(
            argument,
            format!("{value:e} is beyond the limit of {max:e} (SI units)"),
        ))
    }
}

/// Times that are finite and strictly increasing.
pub fn increasing_times(argument: &str, time_s: &[f64]) -> Result<()> {
    finite_scalars(argument, time_s)?;
    match time_s.windows(2).position(|w| w[1] <= w[0]) {
        None => Ok(()),
        Some(k) => Err(Error::invalid(
            argument,
            format!(
                "times must be strictly increasing: element {} ({}) does not follow element {k} ({})",
                k + 1,
                time_s[k + 1],
                time_s[k]
            ),
        )),
    }
}

/// At least one aiding epoch of `epoch_time_s` inside the IMU span
/// `imu_time_s` (increasing), within `tolerance` s; non-finite times are
/// the callers' to refuse. None is when the two
/// are on different time scales (GPS seconds against seconds from the
/// start): said here, with both spans, instead of by whatever first needs
/// the two together (a start with no GNSS velocity blamed the attitude).
pub fn epochs_in_imu_span(
    argument: &str,
    epoch_time_s: &[f64],
    imu_time_s: &[f64],
    tolerance: f64,
) -> Result<()> {
    let (Some(&t0), Some(&t1)) = (imu_time_s.first(), imu_time_s.last()) else {
        return Ok(());
    };
    let finite: Vec<f64> = epoch_time_s
        .iter()
        .copied()
        .filter(|t| t.is_finite())
        .collect();
    let inside = |t: &f64| *t >= t0 - tolerance && *t <= t1 + tolerance;
    if finite.is_empty() || finite.iter().any(inside) {
        return Ok(());
    }
    let first = finite.iter().copied().fold(f64::INFINITY, f64::min);
    let last = finite.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Err(Error::invalid(
        argument,
        format!(
            "no epoch falls inside the IMU span [{t0:.3}, {t1:.3}] s: the epochs span [{first:.3}, \
             {last:.3}] s (are both on one time scale? e.g. GPS seconds against seconds from the \
             start)"
        ),
    ))
}

/// IMU sample intervals the strapdown integration can bridge: a median
/// period of at most [`MAX_IMU_PERIOD_S`](crate::limits::MAX_IMU_PERIOD_S),
/// no interval below a hundredth of it and no gap beyond the larger of
/// 1 s and 100 median periods. Over a
/// longer interval the integrator extrapolates the rates and forces of one
/// sample for the whole of it (a 10⁶ s gap took an INS to 10¹⁷ m; a 10³⁰⁰ s
/// span to NaN). Times are taken as increasing (checked before).
pub fn imu_time_gaps(argument: &str, time_s: &[f64]) -> Result<()> {
    if time_s.len() < 2 {
        return Ok(());
    }
    let mut periods: Vec<f64> = time_s.windows(2).map(|w| w[1] - w[0]).collect();
    let indexed = || periods.iter().copied().enumerate();
    let largest = indexed()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .expect("a period");
    let shortest = indexed()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("a period");
    let middle = periods.len() / 2;
    let median = *periods.select_nth_unstable_by(middle, f64::total_cmp).1;
    let max_period = crate::limits::MAX_IMU_PERIOD_S;
    if median > max_period {
        return Err(Error::invalid(
            argument,
            format!(
                "the median sample period is {median} s, longer than {max_period} s: an IMU \
                 log samples at 1 Hz or faster (times in seconds expected)"
            ),
        ));
    }
    // The other side of the same rule: an interval a hundred times shorter
    // than the median is a mis-stamped or repeated sample, and the cubic
    // through the samples around it overflows (a stamp 1e-300 s after the
    // previous one gave NaN from the next sample on).
    if shortest.1 < 0.01 * median {
        return Err(Error::invalid(
            argument,
            format!(
                "samples {} and {} (times {} s and {} s) are {:e} s apart, less than a \
                 hundredth of the median period {median} s: a repeated or mis-stamped sample",
                shortest.0,
                shortest.0 + 1,
                time_s[shortest.0],
                time_s[shortest.0 + 1],
                shortest.1
            ),
        ));
    }
    let limit = (100.0 * median).max(1.0);
    if largest.1 > limit {
        return Err(Error::invalid(
            argument,
            format!(
                "a gap of {} s between samples {} and {} (times {} s and {} s), more than \
                 {limit} s (the larger of 1 s and 100 times the median period {median} s): \
                 split the log at the gap",
                largest.1,
                largest.0,
                largest.0 + 1,
                time_s[largest.0],
                time_s[largest.0 + 1]
            ),
        ));
    }
    Ok(())
}

/// Two series have the same length.
pub fn same_length(
    argument: &str,
    len: usize,
    reference: &str,
    reference_len: usize,
) -> Result<()> {
    if len == reference_len {
        Ok(())
    } else {
        Err(Error::invalid(
            argument,
            format!("has {len} rows but {reference} has {reference_len}"),
        ))
    }
}

/// A proper rotation matrix: orthonormal to `1e-6` and determinant +1.
pub fn rotation(argument: &str, m: &Matrix3<f64>) -> Result<()> {
    finite_matrix(argument, m)?;
    let orthogonality = (m.transpose() * m - Matrix3::identity()).abs().max();
    if orthogonality > 1e-6 || m.determinant() < 0.0 {
        return Err(Error::invalid(
            argument,
            format!(
                "is not a rotation matrix (|CᵀC − I| = {orthogonality:.2e}, det = {:.6})",
                m.determinant()
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_non_finite_value_is_found_with_its_row() {
        let good: Vec<Vector3<f64>> = (0..1000)
            .map(|k| Vector3::new(k as f64, -1e300, f64::MAX))
            .collect();
        assert!(finite_vectors("f", &good).is_ok());
        assert!(finite_vectors("f", &[]).is_ok());
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for row in [0, 1, 517, 999] {
                for axis in 0..3 {
                    let mut v = good.clone();
                    v[row][axis] = bad;
                    let e = finite_vectors("f", &v).unwrap_err();
                    assert!(e.to_string().contains(&format!("f: row {row} ")), "{e}");
                }
            }
        }
    }

    #[test]
    fn a_nan_in_a_table_is_reported_at_its_row_and_column() {
        let mut values = vec![0.0; 600];
        values[301] = f64::NAN;
        let e = finite_array("xyz", &values, &[200, 3]).unwrap_err();
        assert!(e.to_string().contains("row 100, column 1 is NaN"), "{e}");
        let e = finite_array("t", &values, &[600]).unwrap_err();
        assert!(e.to_string().contains("element 301"), "{e}");
        let e = finite_array("c", &values, &[2, 100, 3]).unwrap_err();
        assert!(e.to_string().contains("[1, 0, 1]"), "{e}");
    }

    #[test]
    fn an_imu_gap_beyond_the_rule_is_refused_with_its_samples() {
        let mut time: Vec<f64> = (0..1000).map(|k| k as f64 * 0.01).collect();
        assert!(imu_time_gaps("time", &time).is_ok());
        // 0.9 s: under 1 s although 90 periods; 1.5 s: beyond both.
        time[500..].iter_mut().for_each(|t| *t += 0.89);
        assert!(imu_time_gaps("time", &time).is_ok());
        time[700..].iter_mut().for_each(|t| *t += 1e6);
        let e = imu_time_gaps("time", &time).unwrap_err().to_string();
        assert!(e.contains("samples 699 and 700"), "{e}");
        // A repeated stamp a hair after its predecessor.
        let mut repeated: Vec<f64> = (0..1000).map(|k| k as f64 * 0.01).collect();
        repeated[301] = repeated[300] + 1e-300;
        let e = imu_time_gaps("time", &repeated).unwrap_err().to_string();
        assert!(e.contains("samples 300 and 301"), "{e}");
        // A slow IMU (1 Hz) may have 5 s gaps but not 200 s ones.
        let mut slow: Vec<f64> = (0..100).map(f64::from).collect();
        slow[50..].iter_mut().for_each(|t| *t += 4.0);
        assert!(imu_time_gaps("time", &slow).is_ok());
        slow[80..].iter_mut().for_each(|t| *t += 200.0);
        assert!(imu_time_gaps("time", &slow).is_err());
    }

    #[test]
    fn epochs_outside_the_imu_span_name_both_spans() {
        let imu = [1.4e9, 1.4e9 + 60.0];
        assert!(epochs_in_imu_span("gnss", &[59.0, 1.4e9 + 30.0], &imu, 0.0).is_ok());
        assert!(epochs_in_imu_span("gnss", &[], &imu, 0.0).is_ok());
        assert!(epochs_in_imu_span("gnss", &[1.4e9 + 60.5], &imu, 1.0).is_ok());
        let e = epochs_in_imu_span("gnss", &[0.0, 1.0, 60.0], &imu, 0.01).unwrap_err();
        assert!(
            e.to_string().contains(
                "gnss: no epoch falls inside the IMU span [1400000000.000, 1400000060.000] s: the \
                 epochs span [0.000, 60.000] s"
            ),
            "{e}"
        );
    }

    #[test]
    fn messages_name_the_argument() {
        let e = increasing_times("time", &[0.0, 1.0, 1.0]).unwrap_err();
        assert!(e.to_string().starts_with("time:"), "{e}");
        let e = finite_vectors("specific_force", &[Vector3::new(0.0, f64::NAN, 0.0)]).unwrap_err();
        assert!(e.to_string().contains("specific_force: row 0"), "{e}");
        assert!(positive("rate", 0.0).is_err());
        assert!(non_negative("noise_std", -1.0).is_err());
        assert!(rotation("attitude", &(Matrix3::identity() * 2.0)).is_err());
        assert!(rotation(
            "attitude",
            &Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0))
        )
        .is_err());
        assert!(rotation("attitude", &Matrix3::identity()).is_ok());
    }
}
