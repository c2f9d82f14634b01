#!/usr/bin/env bash
# Installs what the Windows, macOS and ARM Linux builds of the FMU library and their tests need,
# on a Debian/Ubuntu x86-64 machine; idempotent (a second run checks and changes nothing):
#
#   1. the Rust standard library of each target, with rustup: x86_64-pc-windows-gnu,
#      x86_64-apple-darwin, aarch64-apple-darwin, aarch64-unknown-linux-gnu;
#   2. Debian's mingw-w64 (the Windows linker), Wine (runs the Windows tests), qemu-user with
#      Debian's arm64 C library (libc6-arm64-cross: runs the ARM Linux tests under
#      `qemu-aarch64 -L /usr/aarch64-linux-gnu`), and libclang (bindgen, for building fmi-sim,
#      tests/all.sh);
#   3. zig and cargo-zigbuild (link the glibc 2.17, ARM Linux and macOS libraries) into .venv, pinned in
#      tests/python/requirements-build.txt;
#   4. a Wine prefix for the tests, with a test-only stand-in for bcryptprimitives.dll, which
#      Wine 8 lacks (tests/cross/bcryptprimitives.c says why).
#
# Needs root (or sudo) for step 2 when the packages are missing; fails at the first step it
# cannot do, saying what is missing and how to get it. Prints the environment the Windows and ARM
# tests run in (tests/cross/env.sh sets it: Wine as cargo's runner for x86_64-pc-windows-gnu,
# qemu-aarch64 for aarch64-unknown-linux-gnu).
set -euo pipefail
cd "$(dirname "$0")/../.."

say() { echo "  [cross setup] $*"; }
die() {
    echo "error: $*" >&2
    exit 1
}

# 1. rustup targets.
targets=(x86_64-pc-windows-gnu x86_64-apple-darwin aarch64-apple-darwin aarch64-unknown-linux-gnu)
command -v rustup >/dev/null 2>&1 ||
    die "rustup not found: the cross targets' standard libraries come from rustup (https://rustup.rs)"
installed=$(rustup target list --installed)
for t in "${targets[@]}"; do
    if grep -qx "$t" <<<"$installed"; then
        say "rustup target $t: installed"
    else
        say "rustup target add $t (a download of about 25-30 MB)"
        rustup target add "$t" || die "rustup target add $t failed"
    fi
done

# 2. Debian packages: the mingw-w64 linker, Wine, qemu-user with the arm64 C library, libclang.
packages=()
command -v x86_64-w64-mingw32-gcc >/dev/null 2>&1 || packages+=(gcc-mingw-w64-x86-64)
command -v wine >/dev/null 2>&1 || packages+=(wine64 wine)
command -v qemu-aarch64 >/dev/null 2>&1 || packages+=(qemu-user)
[ -e /usr/aarch64-linux-gnu/lib/ld-linux-aarch64.so.1 ] || packages+=(libc6-arm64-cross)
libs=$({ ldconfig -p || /sbin/ldconfig -p; } 2>/dev/null || true)
grep -q 'libclang\(-[0-9.]*\)\?\.so ' <<<"$libs" || packages+=(libclang-dev)
if [ "${#packages[@]}" -gt 0 ]; then
    sudo=()
    [ "$(id -u)" = 0 ] || sudo=(sudo)
    command -v apt-get >/dev/null 2>&1 ||
        die "missing ${packages[*]} and no apt-get: install mingw-w64's x86_64 gcc, Wine, qemu-user, an arm64 glibc (sysroot /usr/aarch64-linux-gnu) and libclang with your package manager"
    say "installing from Debian: ${packages[*]} (about 1-2 minutes)"
    export DEBIAN_FRONTEND=noninteractive
    "${sudo[@]}" apt-get update -qq || die "apt-get update failed"
    "${sudo[@]}" apt-get install -y -qq "${packages[@]}" >/dev/null ||
        die "apt-get install ${packages[*]} failed"
else
    say "mingw-w64 $(x86_64-w64-mingw32-gcc -dumpversion), $(wine --version 2>/dev/null), $(qemu-aarch64 --version | head -1), the arm64 C library and libclang: installed"
fi

# 3. zig and cargo-zigbuild in .venv (tests/all.sh makes .venv with them; a user who only wants
#    the cross builds gets them here).
if [ -x .venv/bin/cargo-zigbuild ] && [ -x .venv/bin/python ] && .venv/bin/python -c 'import ziglang' 2>/dev/null; then
    say "zig and cargo-zigbuild in .venv: installed"
else
    "${PYTHON:-python3}" -c 'import venv' 2>/dev/null ||
        die "python3 with venv is needed for zig and cargo-zigbuild (Debian: python3-venv)"
    [ -x .venv/bin/python ] || "${PYTHON:-python3}" -m venv .venv
    say "installing zig and cargo-zigbuild into .venv (tests/python/requirements-build.txt, about 100 MB)"
    .venv/bin/python -m pip install --disable-pip-version-check -q --progress-bar off \
        -r tests/python/requirements-build.txt || die "pip could not install zig and cargo-zigbuild"
fi

# 4. The Wine prefix of the tests and the bcryptprimitives.dll stand-in.
# shellcheck source=tests/cross/env.sh
source tests/cross/env.sh
if [ ! -f "$WINEPREFIX/system.reg" ]; then
    say "creating the Wine prefix $WINEPREFIX (about 30 s)"
    mkdir -p "$WINEPREFIX"
    wineboot --init >/dev/null 2>&1 || die "wineboot --init failed for $WINEPREFIX"
    wineserver -w || true
fi
dll="$WINEPREFIX/drive_c/windows/system32/bcryptprimitives.dll"
if [ ! -f "$dll" ] || [ tests/cross/bcryptprimitives.c -nt "$dll" ]; then
    say "building the test-only bcryptprimitives.dll stand-in into the Wine prefix"
    x86_64-w64-mingw32-gcc -O2 -shared -s -o "$dll" tests/cross/bcryptprimitives.c -lbcrypt ||
        die "mingw-w64 could not build tests/cross/bcryptprimitives.c"
else
    say "bcryptprimitives.dll stand-in: installed"
fi
say "ready: Windows tests run with CARGO_TARGET_X86_64_PC_WINDOWS_GNU_RUNNER=$CARGO_TARGET_X86_64_PC_WINDOWS_GNU_RUNNER, WINEPREFIX=$WINEPREFIX"
say "ready: ARM Linux tests run with CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER=\"$CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER\""
