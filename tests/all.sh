#!/usr/bin/env bash
# The one test command: builds, exports dist/ (with the exporter's self-check), runs the Rust
# tests, then the fmpy tests in tests/python against dist/.
set -euo pipefail
cd "$(dirname "$0")/.."

# Python environment with the pinned test packages (fmpy and the partner importers libcosimpy
# and ecospy), (re)made when the pins change.
reqs=(tests/python/requirements.txt tests/python/requirements-partners.txt)
if [ ! -x .venv/bin/python ] || ! cat "${reqs[@]}" | cmp -s - .venv/.requirements; then
    "${PYTHON:-python3}" -m venv .venv
    .venv/bin/python -m pip install --quiet --disable-pip-version-check "${reqs[@]/#/-r}"
    cat "${reqs[@]}" >.venv/.requirements
fi

# fmi-sim, the partner importer from crates.io, pinned; built once into target/partners (its
# build needs libclang, which .ci/run installs). tests/python/test_partners.py finds it by FMI_SIM.
FMI_SIM_VERSION=0.7.0
fmi_sim_root="${CARGO_TARGET_DIR:-target}/partners/fmi-sim-$FMI_SIM_VERSION"
case "$fmi_sim_root" in /*) ;; *) fmi_sim_root="$PWD/$fmi_sim_root" ;; esac
if [ ! -x "$fmi_sim_root/bin/fmi-sim" ]; then
    cargo install fmi-sim --version "=$FMI_SIM_VERSION" --locked --quiet --root "$fmi_sim_root"
fi
export FMI_SIM="$fmi_sim_root/bin/fmi-sim"

cargo build --release --lib --bins --examples
cargo run --release
cargo test --release
.venv/bin/python -m pytest tests/python -q -rA -p no:cacheprovider
