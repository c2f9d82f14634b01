# Sourced by tests/cross/*.sh (and by hand: `source tests/cross/env.sh`): the environment in which
# cargo runs the Windows build's tests under Wine.
#
# The Wine prefix lives outside the clone, so that fresh clones on one machine share it; Wine's
# debug chatter is off; cargo runs every x86_64-pc-windows-gnu test executable through Wine.
export WINEPREFIX="${VIBROFRIC_WINEPREFIX:-$HOME/.cache/vibrofric/wine}"
export WINEDEBUG=-all
export WINEDLLOVERRIDES="mscoree,mshtml="
export CARGO_TARGET_X86_64_PC_WINDOWS_GNU_RUNNER=wine
