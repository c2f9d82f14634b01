#!/usr/bin/env bash
# Tests the Windows build of the FMU library under Wine and the ARM Linux build under qemu-user,
# and compares both with the x86-64 Linux build:
#
#   1. Windows: the library's unit tests and the importer's (resource-location URIs of both
#      platforms), built for x86_64-pc-windows-gnu and run by Wine (cargo's runner variable,
#      tests/cross/env.sh), and the FMI 2.0 and 3.0 C-interface suites (tests/fmi_calls.rs,
#      tests/fmi_bad_input.rs, tests/fmi3_bad_input.rs), which load vibrofric.dll through the
#      importer crate;
#   2. ARM Linux: the library's and the importer's unit tests, built for aarch64-unknown-linux-gnu
#      (glibc 2.17, linked by zig) and run by qemu-aarch64 with Debian's arm64 C library;
#   3. every FMU of dist/ (exported with --platforms all) co-simulated by the same program built for
#      x86-64 Linux, for Windows and for ARM Linux (crates/vibrofric-import/examples/run_fmus.rs):
#      the Windows DLL inside each FMU, and the aarch64 library (FMI 3.0: aarch64-linux; FMI 2.0:
#      linux64 of dist/aarch64-linux/*.fmu), must give every output at every communication point
#      bit for bit as the x86-64 .so.
#
# `bash tests/cross/test.sh [DIST] [windows|aarch64|all]` (default: dist, all). Needs
# tests/cross/setup.sh first (tests/all.sh runs both). The macOS libraries cannot run here:
# tests/python/test_binaries.py checks them structurally.
set -euo pipefail
cd "$(dirname "$0")/../.."
# shellcheck source=tests/cross/env.sh
source tests/cross/env.sh
# zig and cargo-zigbuild (tests/cross/setup.sh puts them into .venv) link the ARM build.
export PATH="$PWD/.venv/bin:$PATH"
dist=${1:-dist}
which=${2:-all}
case "$which" in windows | aarch64 | all) ;; *)
    echo "error: tests/cross/test.sh: the second argument must be windows, aarch64 or all, not \"$which\"" >&2
    exit 2
    ;;
esac
win=x86_64-pc-windows-gnu
arm=aarch64-unknown-linux-gnu
label=""

part() { echo "  [$label] $* (at $((SECONDS / 60))m$((SECONDS % 60))s)"; }

# Runs a `cargo test` command for a foreign target (its runner from tests/cross/env.sh), shows
# each suite's result line, fails on a failure.
foreign_test() {
    local what=$1
    shift
    part "$what"
    local log
    log=$(mktemp)
    if "$@" >"$log" 2>&1; then
        grep -E '^test result|Running ' "$log" | sed 's/^ *Running /    suite /; s/^test result/      result/'
        rm -f "$log"
    else
        grep -E '^test result|Running |FAILED|panicked|^error' "$log" | sed 's/^/    /' | tail -40
        echo "error: $what: a $label test failed (full output: $log)" >&2
        exit 1
    fi
}

# The x86-64 Linux library's outputs, which every other build must print bit for bit.
out=target/cross
mkdir -p "$out"
cargo build --release -q -p vibrofric-import --example run_fmus
target/release/examples/run_fmus "$dist" >"$out/linux.txt" 2>"$out/linux.log" ||
    { cat "$out/linux.log" >&2; exit 1; }
rows=$(wc -l <"$out/linux.txt")
values=$(awk '{n += NF - 3} END {print n}' "$out/linux.txt")
fmus=$(grep -c 'co-simulated$' "$out/linux.log")

# Compares what run_fmus printed on another platform (file $1) with the Linux library's.
same_as_linux() {
    tr -d '\r' <"$1" >"$1.lf"
    if ! cmp -s "$out/linux.txt" "$1.lf"; then
        echo "error: the $label library's outputs differ from the x86-64 Linux library's:" >&2
        diff "$out/linux.txt" "$1.lf" | head -5 >&2
        exit 1
    fi
    echo "    $fmus FMUs, $rows communication points, $values output values: $label = x86-64 Linux, bit for bit"
}

if [ "$which" != aarch64 ]; then
    label="windows under wine"
    # One cargo invocation for every Windows test, so that the packages' features are unified
    # once and nothing is built twice.
    suites=(-p vibrofric -p vibrofric-import -p vibrofric-cli --lib
        --test fmi_calls --test fmi_bad_input --test fmi3_bad_input)
    # The Windows tests copy the DLL into each test's FMU folder (no symbolic links there): clear
    # what earlier runs left in the Wine prefix's Temp.
    find "$WINEPREFIX/drive_c/users" -maxdepth 3 -name 'vibrofric-test-*' -exec rm -rf {} + 2>/dev/null || true
    part "building the Windows tests (the first time 3-5 minutes)"
    cargo test --release --target "$win" --no-run -q "${suites[@]}"
    foreign_test "the library's and the importer's unit tests, the FMI 2.0 and 3.0 C-interface suites" \
        cargo test --release --target "$win" "${suites[@]}"
    part "co-simulating every FMU of $dist with its Windows and its Linux library"
    cargo build --release -q -p vibrofric-import --example run_fmus --target "$win"
    wine "target/$win/release/examples/run_fmus.exe" "$dist" >"$out/windows.txt" 2>"$out/windows.log" ||
        { cat "$out/windows.log" >&2; exit 1; }
    same_as_linux "$out/windows.txt"
fi

if [ "$which" != windows ]; then
    label="arm linux under qemu"
    # The C-interface suites live in the command line's package, whose dev-dependencies (the
    # report's plots and peers) would be built for aarch64 too: they run under Wine only. The
    # co-simulation below calls every FMU through its C interface.
    suites=(-p vibrofric -p vibrofric-import --lib)
    part "building the ARM Linux tests with cargo-zigbuild (the first time 2-4 minutes)"
    cargo-zigbuild test --release --target "$arm.2.17" --no-run -q "${suites[@]}"
    # Less one: the elastoplastic branch against its reference integration (up to 1.2 million
    # Runge-Kutta steps per case, 60 million in all: 97 s alone under qemu, where the library's
    # unit tests took 106 to 120 s with it). Its arithmetic runs on ARM in the co-simulation
    # below (VibratingContactDupont), which must match x86-64 bit for bit.
    foreign_test "the library's and the importer's unit tests" \
        cargo-zigbuild test --release --target "$arm.2.17" "${suites[@]}" \
        -- --skip physics::elastoplastic::tests::branch_follows_the_rate_to_rounding
    part "co-simulating every FMU of $dist with its aarch64 and its x86-64 Linux library"
    cargo zigbuild --release -q -p vibrofric-import --example run_fmus --target "$arm.2.17"
    [ -d "$dist/aarch64-linux" ] || {
        echo "error: no $dist/aarch64-linux: export with --platforms all (or aarch64-linux)" >&2
        exit 1
    }
    # shellcheck disable=SC2086 # the runner is a command with its options
    $CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER "target/$arm/release/examples/run_fmus" \
        "$dist/aarch64-linux" "$dist/fmi3" >"$out/aarch64.txt" 2>"$out/aarch64.log" ||
        { cat "$out/aarch64.log" >&2; exit 1; }
    same_as_linux "$out/aarch64.txt"
fi
