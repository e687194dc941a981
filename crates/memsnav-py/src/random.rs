//! The documented seed scheme of memsnav-core (`memsnav_core::random`).

use memsnav_core::random;
use memsnav_py_macros::catch_panics;
use pyo3::prelude::*;

/// The seed of the independent draw named `purpose` made from user seed
/// `seed`: the first output of its own stream of `seed` (see
/// `docs/explanation/concepts.md`, "Seeds"). Use it when one seed must feed several
/// functions that each take a seed, instead of `seed + 1`, `seed + 2`, ...
#[catch_panics]
#[pyfunction]
fn derive_seed(seed: u64, purpose: &str) -> u64 {
    random::derive_seed(seed, purpose)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(derive_seed, m)?)?;
    Ok(())
}
