#!/usr/bin/env bash
# The one test command: builds, exports dist/ (with the exporter's self-check), runs the Rust
# tests, then the fmpy tests in tests/python against dist/.
set -euo pipefail
cd "$(dirname "$0")/.."

# Python environment with the pinned test packages, (re)made when the pins change.
if [ ! -x .venv/bin/python ] || ! cmp -s tests/python/requirements.txt .venv/.requirements; then
    "${PYTHON:-python3}" -m venv .venv
    .venv/bin/python -m pip install --quiet --disable-pip-version-check -r tests/python/requirements.txt
    cp tests/python/requirements.txt .venv/.requirements
fi

cargo build --release --lib --bins --examples
cargo run --release
cargo test --release
.venv/bin/python -m pytest tests/python -q -rA -p no:cacheprovider
