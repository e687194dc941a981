//! Pieces every text reader of this module shares: the error naming file
//! and line, numbers that must be finite, ranges named in the user's words.

use std::ops::RangeInclusive;

use crate::Error;

/// [`Error::Parse`] at 1-based `line` of `file`.
pub(super) fn parse_error(file: &str, line: usize, reason: impl Into<String>) -> Error {
    Error::Parse {
        file: file.to_string(),
        line,
        reason: reason.into(),
    }
}

/// A finite decimal number. Rust's `f64::from_str` also accepts `inf`,
/// `NaN` and `infinity`: no log means those, so they are refused here.
pub(super) fn finite_number(text: &str) -> Option<f64> {
    text.parse::<f64>().ok().filter(|x| x.is_finite())
}

/// `Ok(value)` when `value` lies in `range`, else a sentence naming the
/// field, its value with `unit` and the accepted range.
pub(super) fn in_range(
    value: f64,
    range: RangeInclusive<f64>,
    field: &str,
    unit: &str,
) -> std::result::Result<f64, String> {
    if range.contains(&value) {
        Ok(value)
    } else {
        Err(format!(
            "{field} = {value} {unit} is out of range ({} to {} {unit})",
            range.start(),
            range.end()
        ))
    }
}

/// The median of `values` (NaN for none); reorders a copy, O(n).
pub(super) fn median(values: &[f64]) -> f64 {
    quantile(values, 0.5)
}

/// The `q`-quantile (nearest rank) of `values` (NaN for none).
pub(super) fn quantile(values: &[f64], q: f64) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    let mut v = values.to_vec();
    let k = ((v.len() - 1) as f64 * q).round() as usize;
    let (_, x, _) = v.select_nth_unstable_by(k, f64::total_cmp);
    *x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_ranges_and_quantiles() {
        assert_eq!(finite_number("1e3"), Some(1000.0));
        for word in ["inf", "-inf", "NaN", "infinity", "1e400", "", "x"] {
            assert_eq!(finite_number(word), None, "{word}");
        }
        assert_eq!(in_range(2.0, 0.0..=3.0, "ns", ""), Ok(2.0));
        let e = in_range(999.0, -90.0..=90.0, "latitude", "°").unwrap_err();
        assert!(
            e.contains("latitude = 999 ° is out of range (-90 to 90 °)"),
            "{e}"
        );
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(quantile(&[5.0, 1.0, 4.0, 2.0, 3.0], 1.0), 5.0);
        assert!(median(&[]).is_nan());
    }
}
