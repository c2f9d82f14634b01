#!/usr/bin/env bash
# Tests the Windows build of the FMU library under Wine, and compares it with the Linux build:
#
#   1. the library's unit tests and the importer's (resource-location URIs of both platforms),
#      built for x86_64-pc-windows-gnu and run by Wine (cargo's runner variable, tests/cross/env.sh);
#   2. the FMI 2.0 and 3.0 C-interface suites (tests/fmi_calls.rs, tests/fmi_bad_input.rs,
#      tests/fmi3_bad_input.rs), which load vibrofric.dll through the importer crate;
#   3. every FMU of dist/ (exported with --platforms all) co-simulated by the same program built for
#      Linux and for Windows (crates/vibrofric-import/examples/run_fmus.rs): the Windows DLL inside
#      each FMU must give every output at every communication point bit for bit as the Linux .so.
#
# Needs tests/cross/setup.sh first (tests/all.sh runs both). The macOS libraries cannot run here:
# tests/python/test_platform.py checks them structurally.
set -euo pipefail
cd "$(dirname "$0")/../.."
# shellcheck source=tests/cross/env.sh
source tests/cross/env.sh
target=x86_64-pc-windows-gnu
dist=${1:-dist}

part() { echo "  [windows under wine] $* (at $((SECONDS / 60))m$((SECONDS % 60))s)"; }

# Runs `cargo test` for Windows under Wine, shows each suite's result line, fails on a failure.
wine_test() {
    local what=$1
    shift
    part "$what"
    local log
    log=$(mktemp)
    if cargo test --release --target "$target" "$@" >"$log" 2>&1; then
        grep -E '^test result|Running ' "$log" | sed 's/^ *Running /    suite /; s/^test result/      result/'
        rm -f "$log"
    else
        grep -E '^test result|Running |FAILED|panicked|^error' "$log" | sed 's/^/    /' | tail -40
        echo "error: $what: a Windows test failed under Wine (full output: $log)" >&2
        exit 1
    fi
}

# One cargo invocation for every Windows test, so that the packages' features are unified once
# and nothing is built twice.
suites=(-p vibrofric -p vibrofric-import -p vibrofric-cli --lib
    --test fmi_calls --test fmi_bad_input --test fmi3_bad_input)
# The Windows tests copy the DLL into each test's FMU folder (no symbolic links there): clear
# what earlier runs left in the Wine prefix's Temp.
find "$WINEPREFIX/drive_c/users" -maxdepth 3 -name 'vibrofric-test-*' -exec rm -rf {} + 2>/dev/null || true

part "building the Windows tests (the first time 3-5 minutes)"
cargo test --release --target "$target" --no-run -q "${suites[@]}"
wine_test "the library's and the importer's unit tests, the FMI 2.0 and 3.0 C-interface suites" \
    "${suites[@]}"

part "co-simulating every FMU of $dist with its Windows and its Linux library"
cargo build --release -q -p vibrofric-import --example run_fmus
cargo build --release -q -p vibrofric-import --example run_fmus --target "$target"
out=target/cross
mkdir -p "$out"
target/release/examples/run_fmus "$dist" >"$out/linux.txt" 2>"$out/linux.log" ||
    { cat "$out/linux.log" >&2; exit 1; }
wine "target/$target/release/examples/run_fmus.exe" "$dist" >"$out/windows.txt" 2>"$out/windows.log" ||
    { cat "$out/windows.log" >&2; exit 1; }
tr -d '\r' <"$out/windows.txt" >"$out/windows.lf.txt"
rows=$(wc -l <"$out/linux.txt")
values=$(awk '{n += NF - 3} END {print n}' "$out/linux.txt")
if ! cmp -s "$out/linux.txt" "$out/windows.lf.txt"; then
    echo "error: the Windows DLL's outputs differ from the Linux library's:" >&2
    diff "$out/linux.txt" "$out/windows.lf.txt" | head -5 >&2
    exit 1
fi
fmus=$(grep -c 'co-simulated$' "$out/linux.log")
echo "    $fmus FMUs, $rows communication points, $values output values: Windows (Wine) = Linux, bit for bit"
