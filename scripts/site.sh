#!/usr/bin/env bash
# Builds the documentation site into one folder (default target/site/):
#   index.html and the chapters   the user guide, mdBook from docs/
#   api/                          the Rust API reference (cargo doc)
# The guide's Rust snippets are compiled and run by `cargo test --doc`, its
# Python and shell snippets by pytest, its links checked by tests/docs.rs;
# this script fails on a missing include, a broken table of contents or a
# rustdoc warning. Needs mdBook 0.4:
#   cargo install mdbook --locked --version "^0.4"
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-target/site}"
if ! command -v mdbook >/dev/null; then
    echo "site.sh: mdbook not found; install it with: cargo install mdbook --locked --version '^0.4'" >&2
    exit 1
fi
rm -rf "$out"
mdbook build --dest-dir "$out"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet
cp -r target/doc "$out/api"
for page in index.html reference/index.html reference/bouc_wen.html api/hysteron/index.html; do
    if [ ! -s "$out/$page" ]; then
        echo "site.sh: $out/$page was not built" >&2
        exit 1
    fi
done
echo "site: $out/index.html (the guide), $out/api/hysteron/index.html (the Rust API)"
