//! Numbers in messages as a reader meets them: plain digits where they fit
//! ("1.33", "0.05", "1463"), scientific with a signed two-digit exponent
//! beyond ("1.81e-04"), never "-0". Rust's `{:e}` writes "1.332e0" and
//! "5.000e-2", which read as code in a report; this is the form of the
//! Python reports (`memsnav.report.numbers.number`), so a message from the
//! core and the report around it agree.

/// `value` to `digits` significant digits (at least one), trailing zeros
/// dropped: plain from 1e-3 to 1e6 (an integer part keeps all its digits:
/// "1463"), scientific beyond; a value that rounds to zero reads "0";
/// NaN and infinities as Rust writes them.
pub fn number(value: f64, digits: usize) -> String {
    if !value.is_finite() {
        return format!("{value}");
    }
    if value == 0.0 {
        return "0".into();
    }
    let digits = digits.max(1);
    let scientific = format!("{:.*e}", digits - 1, value);
    // The exponent after rounding (9.995 to three digits is 1.00e1).
    let (mantissa, exponent) = scientific.split_once('e').unwrap_or((&scientific, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let text = if (-3..6).contains(&exponent) {
        let decimals = (digits as i32 - 1 - exponent).max(0) as usize;
        trim_zeros(&format!("{value:.decimals$}"))
    } else {
        let sign = if exponent < 0 { '-' } else { '+' };
        format!("{}e{sign}{:02}", trim_zeros(mantissa), exponent.abs())
    };
    if text.parse::<f64>() == Ok(0.0) {
        "0".into()
    } else {
        text
    }
}

/// "1.500" → "1.5", "2.000" → "2"; a number without a point unchanged.
fn trim_zeros(text: &str) -> String {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').into()
    } else {
        text.into()
    }
}

#[cfg(test)]
mod tests {
    use super::number;

    /// The cases of tests/test_report_numbers.py's `number`, written the
    /// same way here.
    #[test]
    fn numbers_read_as_in_the_python_reports() {
        for (value, text) in [
            (1.332, "1.33"),
            (5.0e-2, "0.05"),
            (1.805e-3, "0.0018"),
            (1.8049e-4, "1.8e-04"),
            (2.497e-3, "0.0025"),
            (-0.0, "0"),
            (-1e-12, "-1e-12"),
            (2.00002, "2"),
            (1463.0, "1463"),
            (1463.4, "1463"),
            (0.05123, "0.0512"),
            (1.46e7, "1.46e+07"),
            (9.996, "10"),
        ] {
            assert_eq!(number(value, 3), text, "{value}");
        }
        assert_eq!(number(1.805e-3, 4), "0.001805");
        assert_eq!(number(f64::NAN, 3), "NaN");
        assert_eq!(number(-f64::INFINITY, 3), "-inf");
    }
}
