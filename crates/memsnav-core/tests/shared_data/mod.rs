//! The project's data root for the integration tests, resolved as the
//! Python package resolves it (`memsnav.realdata.config.resolve_data_root`):
//! `$MEMSNAV_DATA_ROOT`, else the nearest `shared/data` above the crate
//! (the README puts the data beside the checkout). Never an absolute path
//! of one machine.

use std::path::PathBuf;

/// `<data root>/<relative>`; panics naming where it looked when the file is
/// not there, since the README's test command needs the shared data.
pub fn shared_data(relative: &str) -> PathBuf {
    let here = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let root = match std::env::var_os("MEMSNAV_DATA_ROOT") {
        Some(root) => PathBuf::from(root),
        None => here
            .ancestors()
            .map(|d| d.join("shared/data"))
            .find(|p| p.is_dir())
            .unwrap_or_else(|| {
                panic!(
                    "no shared/data above {}: put the data beside the checkout \
                     (README) or set MEMSNAV_DATA_ROOT",
                    here.display()
                )
            }),
    };
    let path = root.join(relative);
    assert!(
        path.exists(),
        "{} not found (data root {}; set MEMSNAV_DATA_ROOT to move it)",
        path.display(),
        root.display()
    );
    path
}
