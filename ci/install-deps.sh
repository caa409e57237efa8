#!/usr/bin/env bash
# Installs what shadelab needs on Debian/Ubuntu, only where it is missing:
# the Vulkan loader, Mesa lavapipe (software Vulkan), the Khronos validation
# layer, the C/C++ toolchain, and the shader compiler's libraries: shaderc
# and glslang (libshaderc-dev, glslang-dev) and SPIRV-Tools (spirv-tools,
# whose spirv-val also checks the ray-query shader at build time), linked
# statically instead of compiled from source.
# Safe to run again: it installs nothing that is already there, and runs no
# apt-get update when nothing is missing.
#
# Usage: ci/install-deps.sh [--with-chromium] [--with-slurm] [--with-python]
#   --with-chromium  also Chromium, which tests/cpu/compare_present.rs renders
#                    report.html in (ci/test.sh asks for it; building and
#                    rendering do not need it).
#   --with-slurm     also Slurm and MUNGE (slurm-wlm, munge), which
#                    tests/cli/shards.rs runs a one-node cluster of, to shard
#                    with --shard auto under a real scheduler (ci/test.sh
#                    asks for it).
#   --with-python    also Python 3 with venv and pip (python3,
#                    python3-venv), which the Python package's tests
#                    (ci/python-tests.sh) build and run in. Any other
#                    argument is an error.
#
# Lavapipe: the ray tracer runs about twice as fast on Mesa 24 or newer.
# Debian 12 (bookworm) ships Mesa 22.3, so on bookworm, where lavapipe is
# missing or older than 24, this script adds bookworm-backports to the apt
# sources (/etc/apt/sources.list.d/bookworm-backports.sources, unless a
# backports entry is there already) and installs from it the
# mesa-vulkan-drivers version in bpo_pin below; only Mesa and the libdrm it
# needs come from backports, everything else from bookworm. Elsewhere
# (Ubuntu; Debian 13 ships Mesa 24+), or where backports cannot be reached,
# it installs the system's mesa-vulkan-drivers and says in one line when
# that is older than 24. A lavapipe of 24 or newer is left as it is.
#   SHADELAB_LAVAPIPE=system  never use backports: keep (or install) the
#                             lavapipe that the system's own sources offer.
# To run shadelab on bookworm's own Mesa 22.3 without installing it, see
# ci/lavapipe-22.sh.
set -euo pipefail

# The backports Mesa that CI runs on. Backports keeps only its newest build:
# when this one is gone, the newer one there is installed and a line says so.
bpo_pin="25.0.7-2~bpo12+1"
bpo_sources=/etc/apt/sources.list.d/bookworm-backports.sources

with_chromium=0
with_slurm=0
with_python=0
for arg in "$@"; do
    case "$arg" in
        --with-chromium) with_chromium=1 ;;
        --with-slurm) with_slurm=1 ;;
        --with-python) with_python=1 ;;
        *) echo "ci/install-deps.sh: unknown argument '$arg' (usage: ci/install-deps.sh [--with-chromium] [--with-slurm] [--with-python])" >&2; exit 2 ;;
    esac
done

lavapipe=${SHADELAB_LAVAPIPE:-backports}
case "$lavapipe" in
    backports | system) ;;
    *) echo "ci/install-deps.sh: SHADELAB_LAVAPIPE must be 'system' or unset, not '$lavapipe'" >&2; exit 1 ;;
esac

missing=()
have_file() { compgen -G "$1" >/dev/null; }

# Not grep -q: it would stop reading early, ldconfig would die of SIGPIPE, and
# pipefail would take that for a missing loader.
ldconfig -p 2>/dev/null | grep 'libvulkan\.so\.1' >/dev/null || missing+=(libvulkan1)
have_file '/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json' || missing+=(vulkan-validationlayers)
# spirv-val validates at build time the shader naga cannot read (ray
# queries); the package also has SPIRV-Tools' static libraries.
command -v spirv-val >/dev/null || missing+=(spirv-tools)
have_file '/usr/lib/*/libSPIRV-Tools-opt.a' || have_file '/usr/lib/libSPIRV-Tools-opt.a' || missing+=(spirv-tools)
# Debian's libshaderc-dev ships shaderc alone; glslang-dev has glslang.
have_file '/usr/lib/*/libshaderc_combined.a' || have_file '/usr/lib/libshaderc_combined.a' || missing+=(libshaderc-dev)
have_file '/usr/lib/*/libglslang.a' || have_file '/usr/lib/libglslang.a' || missing+=(glslang-dev)
command -v c++ >/dev/null || missing+=(g++)
command -v cc >/dev/null || missing+=(gcc)
if [ "$with_chromium" = 1 ]; then
    command -v chromium >/dev/null || missing+=(chromium)
fi
if [ "$with_slurm" = 1 ]; then
    command -v slurmctld >/dev/null || missing+=(slurm-wlm)
    command -v munged >/dev/null || missing+=(munge)
fi
if [ "$with_python" = 1 ]; then
    # A venv with pip in it is what the package's tests need; Debian splits
    # it off python3 (python3-venv). The package is abi3: no headers needed.
    command -v python3 >/dev/null || missing+=(python3)
    python3 -c 'import venv, ensurepip' 2>/dev/null || missing+=(python3-venv)
fi

# Version of the installed mesa-vulkan-drivers (native architecture), empty if none.
mesa_version() {
    { dpkg-query -W -f='${db:Status-Status} ${Version}\n' "mesa-vulkan-drivers:$(dpkg --print-architecture)" 2>/dev/null || true; } |
        awk '$1 == "installed" { print $2; exit }'
}
# True when Debian version $1 is Mesa 24 or newer (epoch ignored).
mesa_24() { dpkg --compare-versions "${1#*:}" ge 24~; }
is_bookworm() {
    # shellcheck source=/dev/null
    [ "$(. /etc/os-release 2>/dev/null && echo "${ID:-}:${VERSION_CODENAME:-}")" = debian:bookworm ]
}
bpo_configured() {
    grep -Eqs '^[^#]*bookworm-backports' /etc/apt/sources.list /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources
}
# The mesa-vulkan-drivers version apt offers from bookworm-backports, empty if none.
bpo_version() {
    apt-cache madison mesa-vulkan-drivers 2>/dev/null |
        awk -F' *[|] *' 'index($3, " bookworm-backports/") && $3 ~ / Packages$/ { print $2; exit }'
}

need_mesa=0 # no lavapipe at all: one must be installed
have_file '/usr/share/vulkan/icd.d/lvp_icd*.json' || need_mesa=1
installed=$(mesa_version)
want_bpo=0 # try bookworm-backports' lavapipe
if [ "$lavapipe" = backports ] && is_bookworm &&
    { [ "$need_mesa" = 1 ] || { [ -n "$installed" ] && ! mesa_24 "$installed"; }; }; then
    want_bpo=1
fi
bpo_failed="" # why backports was not used, for the hint

sudo=""
if [ ${#missing[@]} -gt 0 ] || [ "$need_mesa" = 1 ] || [ "$want_bpo" = 1 ]; then
    if [ "$(id -u)" -ne 0 ]; then
        if command -v sudo >/dev/null; then
            sudo="sudo"
        elif [ ${#missing[@]} -gt 0 ] || [ "$need_mesa" = 1 ]; then
            [ "$need_mesa" = 1 ] && missing+=(mesa-vulkan-drivers)
            echo "need root or sudo to install: ${missing[*]}" >&2
            exit 1
        else
            want_bpo=0 # only an upgrade, and no way to install it
            bpo_failed="no root or sudo"
        fi
    fi
fi

updated=0
if [ "$want_bpo" = 1 ]; then
    added=""
    if ! bpo_configured; then
        echo "ci/install-deps.sh: adding bookworm-backports to the apt sources ($bpo_sources)"
        printf '%s\n' 'Types: deb' 'URIs: http://deb.debian.org/debian' 'Suites: bookworm-backports' \
            'Components: main' 'Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg' |
            $sudo tee "$bpo_sources" >/dev/null
        added=$bpo_sources
    fi
    bpo=""
    if $sudo apt-get update -qq; then
        updated=1
        bpo=$(bpo_version)
    fi
    if [ -z "$bpo" ] || ! mesa_24 "$bpo"; then
        want_bpo=0
        bpo_failed="bookworm-backports could not be reached"
        if [ -n "$added" ]; then
            $sudo rm -f "$added"
            updated=0 # update again without it before installing anything
        fi
    fi
fi

if [ "$need_mesa" = 1 ] && [ "$want_bpo" = 0 ]; then
    missing+=(mesa-vulkan-drivers)
fi
if [ ${#missing[@]} -gt 0 ]; then
    echo "ci/install-deps.sh: installing ${missing[*]}"
    [ "$updated" = 1 ] || $sudo apt-get update -qq
    updated=1
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

if [ "$want_bpo" = 1 ]; then
    if [ "$bpo" != "$bpo_pin" ]; then
        echo "ci/install-deps.sh: bookworm-backports no longer has mesa-vulkan-drivers $bpo_pin; installing its $bpo (update bpo_pin in ci/install-deps.sh)" >&2
    fi
    echo "ci/install-deps.sh: installing mesa-vulkan-drivers $bpo (lavapipe) from bookworm-backports"
    # pkg/release takes the dependencies that bookworm's versions do not
    # satisfy (libdrm) from backports too, and nothing else.
    if ! DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
        "mesa-vulkan-drivers/bookworm-backports"; then
        bpo_failed="installing it from bookworm-backports failed"
        if [ "$need_mesa" = 1 ]; then
            echo "ci/install-deps.sh: installing mesa-vulkan-drivers"
            DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends mesa-vulkan-drivers
        fi
    fi
fi

installed=$(mesa_version)
if [ -n "$installed" ] && ! mesa_24 "$installed"; then
    if is_bookworm; then
        how="install mesa-vulkan-drivers from bookworm-backports (ci/install-deps.sh does, unless SHADELAB_LAVAPIPE=system${bpo_failed:+; this time $bpo_failed})"
    else
        how="install mesa-vulkan-drivers 24 or newer (Debian 13 and Ubuntu 24.04 ship it)"
    fi
    echo "ci/install-deps.sh: lavapipe here is Mesa $installed; the ray tracer runs about twice as fast on Mesa 24 or newer: $how" >&2
fi

if ! command -v cargo >/dev/null; then
    echo "ci/install-deps.sh: cargo (Rust 1.85 or newer) is required; install it with rustup (https://rustup.rs)" >&2
    exit 1
fi
