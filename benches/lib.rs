//! Benchmarks of memsnav-core live in `benches/`; run them with `cargo bench`.
