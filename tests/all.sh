#!/usr/bin/env bash
# The one test command: checks the toolchain, makes the Python environment, installs the cross
# toolchains (tests/cross/setup.sh), builds the partner importer fmi-sim for Linux and Windows
# (once per machine), builds, exports dist/ for Linux (x86-64 and aarch64, glibc 2.17), Windows
# and macOS with the exporter's self-check, runs the Rust tests, the Windows tests under Wine and
# the ARM Linux tests under qemu (tests/cross/test.sh), then the fmpy tests in tests/python against
# dist/ (Windows fmi-sim under Wine among them). Each step says what it does and when it started.
set -euo pipefail
cd "$(dirname "$0")/.."

step_no=0
# A line a minute while a step runs, so that no stretch of the run is silent (single crates of
# the examples compile for minutes, the fuzz campaign runs for a minute without output).
ticker=""
stop_ticker() { if [ -n "$ticker" ]; then kill "$ticker" 2>/dev/null || true; ticker=""; fi; }
# The Wine server kept running for the whole run (see below), stopped at the end.
wine_kept=0
# A process and everything it started.
kill_tree() {
    local child
    for child in $(pgrep -P "$1" || true); do kill_tree "$child"; done
    kill "$1" 2>/dev/null || true
}
finish() {
    stop_ticker
    # A background build of fmi-sim (step 1) still running when the run stops early.
    if [ -n "${linux_build:-}" ]; then kill_tree "$linux_build"; fi
    if [ "$wine_kept" = 1 ]; then (source tests/cross/env.sh && wineserver -k) >/dev/null 2>&1 || true; fi
}
trap finish EXIT
step() {
    stop_ticker
    step_no=$((step_no + 1))
    echo
    echo "==> [$step_no/10] $* (at $((SECONDS / 60))m$((SECONDS % 60))s)"
    local n=$step_no
    (while sleep 60; do echo "    ... step $n/10 still running (at $((SECONDS / 60))m$((SECONDS % 60))s)"; done) &
    ticker=$!
}

# Rust: cargo must be at least Cargo.toml's rust-version (Debian's cargo 1.63 is not).
need=$(sed -n 's/^rust-version *= *"\([0-9.]*\)".*/\1/p' Cargo.toml)
step "Rust toolchain: cargo >= $need"
have=$(cargo --version 2>/dev/null | sed -n 's/^cargo \([0-9][0-9.]*\).*/\1/p' || true)
if [ -z "$have" ] || [ "$(printf '%s\n%s\n' "$need" "$have" | sort -V | head -1)" != "$need" ]; then
    echo "error: vibrofric needs Rust >= $need; found ${have:-no cargo}." >&2
    echo "Install it with rustup (https://rustup.rs): curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs | sh" >&2
    echo "or, where rustup is installed: rustup update stable. Distribution packages are often too old." >&2
    exit 1
fi
echo "cargo $have"

# fmi-sim, the partner importer from crates.io, pinned; built once per machine into
# ~/.cache/vibrofric (VIBROFRIC_CACHE), outside the clone, so that every clone on the machine
# shares it (its build needs libclang, which .ci/run and tests/cross/setup.sh install), for this
# machine and for Windows (run under Wine: the Windows importer of tests/python/test_partners.py,
# which finds them by FMI_SIM and FMI_SIM_WINDOWS).
FMI_SIM_VERSION=0.7.0
cache="${VIBROFRIC_CACHE:-$HOME/.cache/vibrofric}"
case "$cache" in /*) ;; *) cache="$PWD/$cache" ;; esac
fmi_sim_root="$cache/fmi-sim-$FMI_SIM_VERSION"
fmi_sim_windows_root="$cache/fmi-sim-$FMI_SIM_VERSION-x86_64-pc-windows-gnu"
# cargo install fmi-sim into root $1 (further arguments to cargo install), cargo's progress shown
# as one numbered line per crate compiled. Unoptimised (opt-level 0, many code-generation units):
# it only drives the FMUs in the partner tests, whose work is the FMU's own. On this 2-core machine
# the Linux build took 2 min 46 s against 8 min 43 s optimised (5 min 47 s at opt-level 1), and the
# 34 Linux fmi-sim tests of tests/python/test_partners.py 53 s against 28 s.
install_fmi_sim() {
    local root=$1
    shift
    # A shell loop, not awk: Debian's awk (mawk) reads a pipe in blocks and would hold the lines.
    CARGO_PROFILE_RELEASE_OPT_LEVEL=0 CARGO_PROFILE_RELEASE_CODEGEN_UNITS=256 \
        cargo install fmi-sim --version "=$FMI_SIM_VERSION" --locked --root "$root" "$@" 2>&1 |
        {
            n=0
            while IFS= read -r line; do
                case "$line" in
                *Compiling*) n=$((n + 1)) && printf '  [%3d] %s\n' "$n" "$line" ;;
                *) printf '%s\n' "$line" ;;
                esac
            done
        }
}
# fmi-sim for Linux needs only Rust and libclang (.ci/run installs it): where both are here it is
# built in the background from now on, beside the next two steps, whose downloads and installs
# leave the two cores mostly idle; step 4 waits for it.
linux_build=""
linux_log="$cache/fmi-sim-$FMI_SIM_VERSION-build.log"
if [ ! -x "$fmi_sim_root/bin/fmi-sim" ] &&
    { { ldconfig -p || /sbin/ldconfig -p; } 2>/dev/null || true; } | grep -q 'libclang\(-[0-9.]*\)\?\.so '; then
    mkdir -p "$cache"
    echo "building fmi-sim $FMI_SIM_VERSION for Linux in the background (step 4 waits for it; log: $linux_log)"
    install_fmi_sim "$fmi_sim_root" >"$linux_log" 2>&1 &
    linux_build=$!
fi

# Python environment with the pinned packages: fmpy and the test tools, the partner importers
# libcosimpy and ecospy, and zig + cargo-zigbuild for the portable build; (re)made when the pins
# change.
reqs=(tests/python/requirements.txt tests/python/requirements-partners.txt tests/python/requirements-build.txt)
step "Python environment .venv (fmpy, pytest, numpy, scipy, libcosimpy, ecospy, ziglang, cargo-zigbuild)"
if [ ! -x .venv/bin/python ] || ! cat "${reqs[@]}" | cmp -s - .venv/.requirements; then
    # The pins (numpy 2.4, scipy 1.17, libcosimpy 0.0.6) need Python >= 3.11.
    if ! "${PYTHON:-python3}" -c 'import sys, venv; sys.exit(sys.version_info < (3, 11))' 2>/dev/null; then
        echo "error: the tests need Python >= 3.11 with venv (Debian: python3 python3-venv); found: $("${PYTHON:-python3}" --version 2>&1 || echo none). Set PYTHON=/path/to/python3.11 to choose one." >&2
        exit 1
    fi
    echo "installing the pinned packages of ${reqs[*]} from PyPI (about 250 MB download)"
    "${PYTHON:-python3}" -m venv .venv
    .venv/bin/python -m pip install --disable-pip-version-check --progress-bar off "${reqs[@]/#/-r}"
    .venv/bin/python -c 'import fmpy, libcosimpy, ecospy, ziglang' # fail here if pip did not install them
    cat "${reqs[@]}" >.venv/.requirements
else
    echo "up to date (pins unchanged)"
fi

step "cross toolchains for the Windows, macOS and ARM Linux libraries and their tests (tests/cross/setup.sh)"
bash tests/cross/setup.sh
# Wine starts a server for each program it runs and stops it 3 s after the last one exits; every
# program under Wine then waits for a new one (about 1 s). Kept running, a Windows program starts
# in 0.1 s: the Windows fmi-sim tests of tests/python/test_partners.py, 66 programs, went from
# 213 s to 36 s.
(source tests/cross/env.sh && wineserver -p) && wine_kept=1

step "fmi-sim $FMI_SIM_VERSION for Linux and for Windows, partner FMI importers for tests/python/test_partners.py"
if [ -n "$linux_build" ]; then
    echo "fmi-sim for Linux: waiting for its build, started at step 1 (log: $linux_log)"
    while kill -0 "$linux_build" 2>/dev/null; do
        sleep 30
        echo "    fmi-sim for Linux: $(grep -c 'Compiling' "$linux_log" || true) crates compiled"
    done
    build_ok=1
    wait "$linux_build" || build_ok=0
    linux_build=""
    if [ "$build_ok" = 0 ] || [ ! -x "$fmi_sim_root/bin/fmi-sim" ]; then
        tail -30 "$linux_log" >&2
        echo "error: fmi-sim was not installed (log: $linux_log)" >&2
        exit 1
    fi
    echo "fmi-sim for Linux: built"
elif [ ! -x "$fmi_sim_root/bin/fmi-sim" ]; then
    echo "building it from crates.io into $fmi_sim_root: done once per machine, 3-8 minutes on 2 cores"
    echo "(about 200 crates; cargo's progress below, one numbered line per crate compiled)"
    install_fmi_sim "$fmi_sim_root"
    [ -x "$fmi_sim_root/bin/fmi-sim" ] || { echo "error: fmi-sim was not installed" >&2; exit 1; }
else
    echo "fmi-sim for Linux: already built"
fi
if [ ! -f "$fmi_sim_windows_root/bin/fmi-sim.exe" ]; then
    echo "building fmi-sim.exe for x86_64-pc-windows-gnu into $fmi_sim_windows_root: done once per"
    echo "machine, 3-8 minutes on 2 cores (bindgen reads the C headers of mingw-w64's sysroot)"
    BINDGEN_EXTRA_CLANG_ARGS_x86_64_pc_windows_gnu="--sysroot=/usr/x86_64-w64-mingw32 -I/usr/x86_64-w64-mingw32/include -I$(x86_64-w64-mingw32-gcc -print-file-name=include)" \
        install_fmi_sim "$fmi_sim_windows_root" --target x86_64-pc-windows-gnu
    [ -f "$fmi_sim_windows_root/bin/fmi-sim.exe" ] ||
        { echo "error: fmi-sim.exe was not installed" >&2; exit 1; }
else
    echo "fmi-sim for Windows: already built"
fi
export FMI_SIM="$fmi_sim_root/bin/fmi-sim"
export FMI_SIM_WINDOWS="$fmi_sim_windows_root/bin/fmi-sim.exe"

step "cargo build --release (FMU library, importer, exporter, examples)"
cargo build --release --workspace --lib --bins --examples

# VIBROFRIC_PORTABLE=1 and --platforms all: the exporter must build the Linux libraries for
# glibc 2.17 (x86-64 and aarch64), the Windows and the macOS ones (docs/platforms.md), so the
# tests below check the binaries users get. The first time, each platform's build takes about as
# long as the host's.
step "export dist/*.fmu for linux64 (glibc 2.17), aarch64-linux, win64 and darwin64, and self-check"
VIBROFRIC_PORTABLE=1 cargo run --release -- export --platforms all --check

step "cargo test --release"
cargo test --release

# The developers' documentation (docs/architecture.md sends contributors there): every link
# resolved, as the public docs and with the private items (about 30 s the first time).
step "cargo doc: every intra-doc link resolved"
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --workspace --quiet
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --workspace --document-private-items --quiet

step "the Windows library under Wine, the ARM Linux library under qemu (tests/cross/test.sh)"
bash tests/cross/test.sh dist

step "fmpy tests (tests/python)"
.venv/bin/python -m pytest tests/python -q -rA -p no:cacheprovider
stop_ticker
echo "all tests passed in $((SECONDS / 60))m$((SECONDS % 60))s"
