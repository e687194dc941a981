//! The figures a docs page quotes from a test's run, read from the page so
//! that the test compares them with what it computed (every
//! quoted figure is generated or checked).

#![allow(dead_code)]

/// The unsigned numbers (digits with an optional decimal part) of
/// `docs/<page>` between the first `before` and the next `after`, in the
/// page's whitespace-normalised text: "6.7 GPS (6-8)" gives 6.7, 6, 8.
/// Panics naming the page when it no longer quotes `before` … `after`.
pub fn quoted_numbers(page: &str, before: &str, after: &str) -> Vec<f64> {
    let path = format!("{}/../../docs/{page}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
    let start = text
        .find(before)
        .unwrap_or_else(|| panic!("docs/{page} no longer quotes {before:?}"))
        + before.len();
    let length = text[start..]
        .find(after)
        .unwrap_or_else(|| panic!("docs/{page} no longer quotes {before:?} … {after:?}"));
    let mut numbers = Vec::new();
    let mut current = String::new();
    for c in text[start..start + length].chars().chain([' ']) {
        if c.is_ascii_digit() || (c == '.' && !current.is_empty()) {
            current.push(c);
        } else if !current.is_empty() {
            numbers.push(current.trim_end_matches('.').parse().unwrap());
            current.clear();
        }
    }
    numbers
}

/// `value` rounds to `quoted` at the digits it is quoted with (`decimals`
/// after the point).
pub fn rounds_to(value: f64, quoted: f64, decimals: i32) -> bool {
    (value - quoted).abs() <= 0.5 * 10f64.powi(-decimals) + 1e-9
}
