#!/bin/bash
# Cross-builds the FMU's Windows binary, binaries/win64/WheelRailFriction.dll, on Linux.
#
# The target is x86_64-win7-windows-gnu: the standard library of x86_64-pc-windows-gnu imports
# bcryptprimitives.dll (ProcessPrng), which Wine 8 (the Windows that `make test` runs the DLL on) lacks;
# the win7 target imports only DLLs that every Windows from 7 to 11 has (KERNEL32, ADVAPI32, msvcrt, ntdll,
# USERENV, WS2_32; tests/win64 checks the import table). rustup offers no standard library for that target,
# so it is built from source (-Zbuild-std) by Debian's Rust (packages rustc-web, cargo-web, rust-web-src),
# linked by MinGW-w64's gcc (gcc-mingw-w64-x86-64) with the GCC runtime linked statically. RUSTC_BOOTSTRAP
# (which build-std needs) is set for this one build only; the rest of the project stays on its own
# toolchain. The build has its own target directory, target/win64; the FMU's DLL is
# target/win64/WheelRailFriction.dll.
#
# Installs the missing packages with apt-get (needs root; otherwise says what to install and exits 1).
#
# Usage: tools/win64-build.sh [--install-only | --test-library]   (from anywhere; prints the DLL's path last)
#   --install-only   install the cross toolchain and Wine (wine64, wine: what tests/win64 runs the DLL on),
#                    build nothing
#   --test-library   build the library's unit tests for Windows and run them under Wine (cargo's runner for
#                    the target; a temporary Wine prefix, removed afterwards): the table kernels' dispatch
#                    and the physics as on Linux
set -euo pipefail

TARGET=x86_64-win7-windows-gnu
repo=$(cd "$(dirname "$0")/.." && pwd)
out_dir="$repo/target/win64"
built="$out_dir/$TARGET/release/WheelRailFriction.dll"
# what the FMU ships: the built DLL without its symbol table (the export table stays; 6.3 -> 4.4 MB)
dll="$out_dir/WheelRailFriction.dll"

fail() {
    echo "win64-build: FAILED: $*" >&2
    exit 1
}

# The packages and, for each, a file that shows it is installed.
packages=(rustc-web cargo-web rust-web-src gcc-mingw-w64-x86-64)
case "${1:-}" in
--install-only | --test-library) packages+=(wine64 wine) ;;
"") ;;
*) fail "unknown argument $1 (see the header of $0)" ;;
esac
marker() {
    case "$1" in
    rustc-web) echo /usr/bin/rustc ;;
    cargo-web) echo /usr/bin/cargo ;;
    rust-web-src) echo /usr/lib/rustlib/src/rust/library/std/Cargo.toml ;;
    gcc-mingw-w64-x86-64) echo /usr/bin/x86_64-w64-mingw32-gcc ;;
    wine64) echo /usr/lib/wine/wine64 ;;
    wine) echo /usr/bin/wine ;;
    esac
}

missing=()
for p in "${packages[@]}"; do
    [ -e "$(marker "$p")" ] || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
    [ "$(id -u)" = 0 ] || fail "the Windows cross toolchain is incomplete and this is not root: run, as root, apt-get install --no-install-recommends ${missing[*]} (or build the Linux FMU only: make fmu-linux)"
    command -v apt-get >/dev/null || fail "the Windows cross toolchain is incomplete and there is no apt-get: install ${missing[*]} (Debian package names), or build the Linux FMU only: make fmu-linux"
    echo "win64-build: installing ${missing[*]}"
    apt_log=$(mktemp /tmp/wheelrail-win64-apt.XXXXXX)
    if ! (
        export DEBIAN_FRONTEND=noninteractive
        apt-get install -y -q --no-install-recommends "${missing[@]}" ||
            { apt-get update -q && apt-get install -y -q --no-install-recommends "${missing[@]}"; }
    ) >"$apt_log" 2>&1; then
        tail -20 "$apt_log" >&2
        rm -f "$apt_log"
        fail "apt-get could not install ${missing[*]}"
    fi
    rm -f "$apt_log"
    for p in "${missing[@]}"; do
        [ -e "$(marker "$p")" ] || fail "$p was installed but $(marker "$p") is missing"
    done
fi
[ "${1:-}" = --install-only ] && exit 0

# Debian's toolchain only: no rustup proxies, no settings of the project's own toolchain or of a calling cargo.
unset RUSTUP_TOOLCHAIN RUSTUP_HOME CARGO RUSTFLAGS RUSTDOCFLAGS CARGO_BUILD_TARGET CARGO_TARGET_DIR CARGO_ENCODED_RUSTFLAGS
cd "$repo"
cross_cargo() {
    local command=$1
    shift
    PATH=/usr/bin:/bin RUSTC=/usr/bin/rustc RUSTC_BOOTSTRAP=1 CARGO_TARGET_DIR="$out_dir" \
        /usr/bin/cargo "$command" --release --locked --target "$TARGET" -Zbuild-std=std,panic_unwind "$@"
}

if [ "${1:-}" = --test-library ]; then
    prefix=$(mktemp -d /tmp/wheelrail-wine.XXXXXX)
    # the Wine server outlives the tests by a few seconds: stop it before removing its prefix
    trap 'WINEPREFIX="$prefix" wineserver -k 2>/dev/null; rm -rf "$prefix"' EXIT
    runner="CARGO_TARGET_$(echo "$TARGET" | tr a-z- A-Z_)_RUNNER"
    # no Mono or Gecko installers (they would ask through a window) when Wine creates the prefix
    export "$runner=wine" WINEPREFIX="$prefix" WINEDEBUG=-all WINEDLLOVERRIDES="mscoree,mshtml="
    unset DISPLAY
    cross_cargo test -p wheelrail --lib
    exit
fi

cross_cargo build -p wheelrail-fmu --lib
[ -f "$built" ] || fail "the build finished but $built is missing"
if [ ! -f "$dll" ] || [ "$built" -nt "$dll" ]; then
    /usr/bin/x86_64-w64-mingw32-strip --strip-unneeded -o "$dll.tmp" "$built"
    mv "$dll.tmp" "$dll"
fi
echo "$dll"
