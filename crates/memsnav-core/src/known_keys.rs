//! Strict names: every key of a dict argument, every column of a table,
//! must be one the function knows. An unknown one is an error naming it,
//! the closest known name (what was probably meant) and the full list,
//! never a silent omission (a misspelled optional key would otherwise
//! drop its data without a word).

use crate::{Error, Result};

/// `Ok` when `key` is one of `known`; else [`Error::InvalidArgument`] for
/// `argument` naming the key, the closest known name when one is near
/// (at most a third of the longer name edited, or one name the start of
/// the other) and every known name.
pub fn check(argument: &str, key: &str, known: &[&str]) -> Result<()> {
    if known.contains(&key) {
        return Ok(());
    }
    let hint = closest(key, known)
        .map(|k| format!(" (did you mean {k:?}?)"))
        .unwrap_or_default();
    Err(Error::invalid(
        argument,
        format!(
            "unknown key {key:?}{hint}; expected some of {}",
            known.join(", ")
        ),
    ))
}

/// The known name nearest to `key` in edit distance, when it is near
/// enough to be a misspelling of it.
pub fn closest<'a>(key: &str, known: &[&'a str]) -> Option<&'a str> {
    let key = key.to_lowercase();
    known
        .iter()
        .map(|k| (edit_distance(&key, &k.to_lowercase()), *k))
        .filter(|(d, k)| {
            let k = k.to_lowercase();
            3 * d <= key.chars().count().max(k.chars().count())
                || k.starts_with(&key)
                || key.starts_with(&k)
        })
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k)
}

/// Levenshtein distance in characters (insertions, deletions, substitutions).
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diagonal = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let above = row[j + 1];
            row[j + 1] = (above + 1)
                .min(row[j] + 1)
                .min(diagonal + usize::from(ca != *cb));
            diagonal = above;
        }
    }
    row[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("same", "same"), 0);
    }

    #[test]
    fn a_misspelling_names_what_was_meant() {
        let known = ["pseudorange", "pseudorange_rate", "pseudorange_rate_std"];
        assert!(check("gnss", "pseudorange_rate", &known).is_ok());
        let e = check("gnss", "pseudorange_rates", &known)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(
                "gnss: unknown key \"pseudorange_rates\" (did you mean \"pseudorange_rate\"?)"
            ),
            "{e}"
        );
        assert_eq!(closest("pseudo", &known), Some("pseudorange"));
        let e = check("gnss", "colour", &known).unwrap_err().to_string();
        assert!(!e.contains("did you mean"), "{e}");
        assert!(
            e.contains("expected some of pseudorange, pseudorange_rate"),
            "{e}"
        );
    }
}
