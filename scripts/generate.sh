#!/usr/bin/env bash
# Writes anew every file that says what the registry of operators knows:
# the operator and combinator tables of README.md, the front pages of the
# operators crate and the facade, and the Python constructors' imports,
# names and stubs (python/hysteron_rs/), the guide's reference pages and
# the spec's JSON Schema (docs/reference/), and the reference's loop figures
# (docs/reference/figures/, drawn by the CLI). The tests tests/generated.rs
# and cli/tests/reference_figures.rs fail when any of them differs from
# what this writes.
set -euo pipefail
cd "$(dirname "$0")/.."
HYSTERON_REGENERATE=1 cargo test -q -p hysteron --test generated
rm -rf docs/reference/figures
cargo run -q -p hysteron-cli -- operators --figures docs/reference/figures > /dev/null
