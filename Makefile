# The fast loop for working on memsnav. CI runs .ci/run (the README's test
# command, then the linters and the stub check); `make ci` runs the same.
#
#   make dev        build the package into the active environment, without
#                   link-time optimisation (a rebuild takes a minute, not five)
#   make test-fast  Rust unit tests of the core and the Python tests not
#                   marked slow
#   make test       every test, as CI runs them
#   make lint       fmt, clippy, ruff, mypy (strict) and the stub check
#   make fmt        format Rust and Python in place
#   make docs       the stub's docstrings, the API and reference pages, the figures
#   make bench      the criterion benchmarks

PYTHON ?= python3
FAST_BUILD = CARGO_PROFILE_RELEASE_LTO=off CARGO_PROFILE_RELEASE_INCREMENTAL=true \
	CARGO_PROFILE_RELEASE_CODEGEN_UNITS=16
PY_DIRS = python tests benches docs

.PHONY: dev test-fast test lint fmt docs bench ci

dev:
	$(FAST_BUILD) $(PYTHON) -m pip install -e ".[dev]"

test-fast:
	$(FAST_BUILD) cargo test -p memsnav-core --release --lib
	$(PYTHON) -m pytest tests -m "not slow" -q

test:
	cargo test --workspace --release
	$(PYTHON) -m pytest tests -q

lint:
	cargo fmt --all -- --check
	cargo clippy --workspace --all-targets --release -- -D warnings
	$(PYTHON) -m ruff check $(PY_DIRS)
	$(PYTHON) -m ruff format --check $(PY_DIRS)
	$(PYTHON) -m mypy python/memsnav
	$(PYTHON) -m mypy.stubtest memsnav._memsnav --allowlist .ci/stubtest-allowlist.txt

fmt:
	cargo fmt --all
	$(PYTHON) -m ruff check --fix $(PY_DIRS)
	$(PYTHON) -m ruff format $(PY_DIRS)

docs:
	$(PYTHON) docs/build_stub_docs.py
	$(PYTHON) docs/build_api.py
	$(PYTHON) docs/build_reference.py
	$(PYTHON) docs/figures.py --write
	$(PYTHON) docs/figures.py --check

bench:
	cargo bench -p memsnav-benches

ci:
	.ci/run
