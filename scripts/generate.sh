#!/usr/bin/env bash
# Writes anew every file that says what the registry of operators knows:
# the operator and combinator tables of README.md, the front pages of the
# operators crate and the facade, and the Python constructors' imports,
# names and stubs (python/hysteron_rs/). The test tests/generated.rs fails
# when any of them differs from what this writes.
set -euo pipefail
cd "$(dirname "$0")/.."
HYSTERON_REGENERATE=1 cargo test -q -p hysteron --test generated
