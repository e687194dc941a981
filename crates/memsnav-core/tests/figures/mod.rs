//! The figures a test measures that the docs quote. Each test owns a
//! record, `docs/data/<name>.json` (the schema of `docs/figures.py`:
//! date, commit, machine, figures), and the pages show its figures through
//! placeholders rendered from it. A test checks what it measures against
//! its record within a stated tolerance (half the last digit the page
//! shows); run with `MEMSNAV_WRITE_FIGURES=1` it writes the record instead
//! (then `python docs/figures.py --write` re-renders the pages).

#![allow(dead_code)]

use serde_json::{json, Map, Value};
use std::process::Command;

/// The figures one test measures: name, value, tolerance.
pub struct Figures {
    record: &'static str,
    figures: Vec<(&'static str, f64, f64)>,
}

impl Figures {
    /// The figures of `docs/data/<record>.json`.
    pub fn new(record: &'static str) -> Self {
        Self {
            record,
            figures: Vec::new(),
        }
    }

    /// Adds a figure measured now, to agree with the record within
    /// `tolerance` (0 for a count).
    pub fn add(&mut self, name: &'static str, value: f64, tolerance: f64) -> &mut Self {
        self.figures.push((name, value, tolerance));
        self
    }

    fn path(&self) -> String {
        format!(
            "{}/../../docs/data/{}.json",
            env!("CARGO_MANIFEST_DIR"),
            self.record
        )
    }

    /// Checks each figure against the record (panics naming the record
    /// and the figure), or writes the record when `MEMSNAV_WRITE_FIGURES`
    /// is set.
    pub fn check_or_write(&self) {
        if std::env::var_os("MEMSNAV_WRITE_FIGURES").is_some() {
            self.write();
            return;
        }
        let path = self.path();
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| {
            panic!("{path}: {e} (write it: MEMSNAV_WRITE_FIGURES=1 cargo test)")
        });
        let record: Value = serde_json::from_str(&text).unwrap();
        let recorded = record["figures"].as_object().expect("a figures object");
        let names: Vec<&str> = self.figures.iter().map(|f| f.0).collect();
        let mut kept: Vec<&str> = recorded.keys().map(String::as_str).collect();
        kept.sort_unstable();
        let mut measured = names.clone();
        measured.sort_unstable();
        assert_eq!(kept, measured, "docs/data/{}.json", self.record);
        for &(name, value, tolerance) in &self.figures {
            let kept = recorded[name].as_f64().unwrap();
            assert!(
                (value - kept).abs() <= tolerance + 1e-12 * kept.abs(),
                "{name}: measured {value}, docs/data/{}.json {kept} (tolerance {tolerance})",
                self.record
            );
        }
    }

    fn write(&self) {
        let mut figures = Map::new();
        for &(name, value, _) in &self.figures {
            figures.insert(name.to_string(), json!(value));
        }
        let record = json!({
            "generated": output("date", &["-u", "+%F"]),
            "commit": commit(),
            "machine": machine(),
            "figures": figures,
        });
        let text = serde_json::to_string_pretty(&record).unwrap() + "\n";
        std::fs::write(self.path(), text).unwrap();
    }
}

fn output(program: &str, args: &[&str]) -> String {
    let out = Command::new(program)
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    String::from_utf8(out.stdout).unwrap().trim().to_string()
}

/// HEAD's short hash, with `+` when the work tree has changes.
fn commit() -> String {
    let dirty = !output("git", &["status", "--porcelain", "--untracked-files=no"]).is_empty();
    output("git", &["rev-parse", "--short", "HEAD"]) + if dirty { "+" } else { "" }
}

/// Architecture, cores, system: what `docs/figures.py` records.
fn machine() -> String {
    let os = std::env::consts::OS;
    let cpus = std::thread::available_parallelism().map_or(1, |n| n.get());
    format!(
        "{}, {cpus} CPUs, {}{}",
        std::env::consts::ARCH,
        os[..1].to_uppercase(),
        &os[1..]
    )
}
