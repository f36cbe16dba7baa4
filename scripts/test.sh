#!/usr/bin/env bash
# Every check of the project, the README's one test command (CI runs it):
# formatting, lints and docs, the Rust tests, then the Python
# package (installed from python/ into a fresh virtual environment, its stubs
# checked by mypy's stubtest, mypy, pytest), then the C API and the FMUs
# (capi/checks: C programs built with cc, FMUs checked with FMPy), then the
# documentation site (scripts/site.sh, with mdBook). Needs rustup's toolchain, python3 with
# venv, and the package registries (crates.io, PyPI, and Debian's for the
# libraries openseespy needs and libclang, installed when run as root).
set -euo pipefail
cd "$(dirname "$0")/.."
export CARGO_TERM_COLOR=never
# A fresh clone gains nothing from incremental compilation but its disk.
if [ -n "${CI:-}" ]; then export CARGO_INCREMENTAL=0; fi

# The checkout must be left as it was found (ignored paths excepted): a
# test that writes into it, or a stale lock file, fails the run at the end.
status_before=$(git status --porcelain 2>/dev/null || echo "not a git checkout")

if command -v rustup >/dev/null 2>&1; then
  rustup component add rustfmt clippy >/dev/null 2>&1 || true
fi
cargo --version

echo "== cargo fmt --check"
cargo fmt --all -- --check
# (the leaves' modules are declared by a macro, which cargo fmt does not
# follow: rustfmt reads their files itself)
rustfmt --edition 2021 --check operators/src/*.rs

echo "== libclang, with which the FMU importer test's fmi crate generates its FMI bindings (bindgen)"
if ! ldconfig -p 2>/dev/null | grep -q 'libclang\(-[0-9.]*\)\?\.so'; then
  if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    apt-get update -qq && apt-get install -y -qq libclang-dev > /dev/null
  else
    echo "the fmi crate (a dev-dependency of hysteron-cli) needs libclang: install Debian's libclang-dev (as root) and run again" >&2
  fi
fi

echo "== cargo clippy"
cargo clippy --workspace --all-targets -- -D warnings

echo "== cargo doc"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet

echo "== cargo test --workspace"
cargo test --workspace

echo "== the vector kernels' contract on AVX2 and without vector kernels (HYSTERON_ISA caps the dispatch)"
for isa in avx2 portable; do
    HYSTERON_ISA=$isa cargo test -q -p hysteron --test contract
    HYSTERON_ISA=$isa cargo test -q -p hysteron-operators --lib -- exp_kernel lanes
    HYSTERON_ISA=$isa cargo test -q -p hysteron-composition --lib -- lanes
    HYSTERON_ISA=$isa cargo test -q -p hysteron-identify --test ensemble
done

echo "== the derivative property test at 10x its default cases"
PROPTEST_CASES=2560 cargo test -q -p hysteron --test derivatives random_compositions

echo "== Python: install hysteron-rs into target/py-venv, and FMPy (an independent FMI 2.0 host)"
python3 -m venv target/py-venv
venv=target/py-venv/bin
"$venv/python" -m pip install -q --upgrade pip
"$venv/python" -m pip install -q "./python[test]" "fmpy>=0.3.20,<0.4"

echo "== openseespy, the OpenSees peer of the degrading Bouc-Wen tests, and the Debian libraries it needs"
if ! ldconfig -p 2>/dev/null | grep -q libgfortran.so.5; then
  if command -v apt-get >/dev/null 2>&1 && [ "$(id -u)" = 0 ]; then
    apt-get update -qq && apt-get install -y -qq libblas3 liblapack3 libgfortran5 > /dev/null
  else
    echo "openseespy needs Debian's libblas3 liblapack3 libgfortran5: install them (as root) and run again" >&2
  fi
fi
"$venv/python" -m pip install -q openseespy
export HYSTERON_REQUIRE_OPENSEES=1

echo "== the release build README's commands use: the CLI (which the bit-identity tests compare with) and libhysteron_c.so"
cargo build --release -q
export HYSTERON_BIN="$PWD/target/release/hysteron"

echo "== Python: stubtest"
(cd target && "../$venv/python" -m mypy.stubtest hysteron_rs)

echo "== Python: mypy on the package, the examples and the benchmark"
"$venv/python" -m mypy python/hysteron_rs examples/python python/bench

echo "== Python: pytest (with every shell and Python block of README.md and of the guide, run as written)"
"$venv/python" -m pytest -q python/tests

echo "== C and FMI: FMPy and the system's cc"
"$venv/python" -m pytest -q capi/checks

echo "== the documentation site: the guide (mdBook) and the API reference (scripts/site.sh)"
if ! command -v mdbook >/dev/null 2>&1; then
  cargo install mdbook --locked --version "^0.4"
fi
bash scripts/site.sh

echo "== fuzz smoke: each cargo-fuzz target (fuzz/) for up to 30 s on its committed corpus"
if cargo +nightly --version >/dev/null 2>&1; then
  if ! cargo +nightly fuzz --version >/dev/null 2>&1; then
    cargo install cargo-fuzz --locked
  fi
  for target in spec_json csv_read operator_contract fit_small; do
    # a scratch copy, so that what the run adds stays out of the committed seeds
    scratch=$(mktemp -d)
    cp fuzz/corpus/"$target"/* "$scratch"/ 2>/dev/null || true
    echo "-- $target"
    (cd fuzz && cargo +nightly fuzz run "$target" "$scratch" -- \
      -max_total_time=30 -rss_limit_mb=2048 -timeout=10 -print_final_stats=1)
    rm -rf "$scratch"
  done
else
  echo "WARNING: ************************************************************"
  echo "WARNING: no nightly toolchain (cargo +nightly --version fails):"
  echo "WARNING: the fuzz smoke (cargo-fuzz targets in fuzz/) was SKIPPED."
  echo "WARNING: install it with: rustup toolchain install nightly"
  echo "WARNING: ************************************************************"
fi

echo "== the checkout is as the test command found it (git status --porcelain)"
status_after=$(git status --porcelain 2>/dev/null || echo "not a git checkout")
if [ "$status_after" != "$status_before" ]; then
  echo "the test command changed the checkout:"
  diff <(echo "$status_before") <(echo "$status_after") || true
  exit 1
fi
