#!/usr/bin/env bash
# Every check of the project, the README's one test command (CI runs it):
# formatting, lints and docs, the Rust tests, then the Python
# package (installed from python/ into a fresh virtual environment, its stubs
# checked by mypy's stubtest, mypy, pytest), then the C API and the FMUs
# (capi/checks: C programs built with cc, FMUs checked with FMPy). Needs rustup's toolchain, python3 with
# venv, and the package registries (crates.io, PyPI).
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR=never

if command -v rustup >/dev/null 2>&1; then
  rustup component add rustfmt clippy >/dev/null 2>&1 || true
fi
cargo --version

echo "== cargo fmt --check"
cargo fmt --all -- --check

echo "== cargo clippy"
cargo clippy --workspace --all-targets -- -D warnings

echo "== cargo doc"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet

echo "== cargo test --workspace"
cargo test --workspace

echo "== Python: install hysteron-rs into target/py-venv"
python3 -m venv target/py-venv
venv=target/py-venv/bin
"$venv/python" -m pip install -q --upgrade pip
"$venv/python" -m pip install -q "./python[test]"

echo "== Python: the CLI the bit-identity tests compare with, and libhysteron_c.so"
cargo build --release -q -p hysteron-cli -p hysteron-c
export HYSTERON_BIN="$PWD/target/release/hysteron"

echo "== Python: stubtest"
(cd target && "../$venv/python" -m mypy.stubtest hysteron_rs)

echo "== Python: mypy on the package, the examples and the benchmark"
"$venv/python" -m mypy python/hysteron_rs examples/python python/bench

echo "== Python: pytest"
"$venv/python" -m pytest -q python/tests

echo "== C and FMI: FMPy (an independent FMI 2.0 host) and the system's cc"
"$venv/python" -m pip install -q "fmpy>=0.3.20,<0.4"
"$venv/python" -m pytest -q capi/checks
