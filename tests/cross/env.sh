# Sourced by tests/cross/*.sh (and by hand: `source tests/cross/env.sh`): the environment in which
# cargo runs the Windows build's tests under Wine and the ARM Linux build's under qemu-user.
#
# The Wine prefix lives outside the clone, so that fresh clones on one machine share it; Wine's
# debug chatter is off; cargo runs every x86_64-pc-windows-gnu test executable through Wine, and
# every aarch64-unknown-linux-gnu one through qemu-aarch64 with Debian's arm64 C library
# (libc6-arm64-cross) as the root of its dynamic loader and libraries.
export WINEPREFIX="${VIBROFRIC_WINEPREFIX:-$HOME/.cache/vibrofric/wine}"
export WINEDEBUG=-all
export WINEDLLOVERRIDES="mscoree,mshtml="
export CARGO_TARGET_X86_64_PC_WINDOWS_GNU_RUNNER=wine
export CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER="qemu-aarch64 -L /usr/aarch64-linux-gnu"
