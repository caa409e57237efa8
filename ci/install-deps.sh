#!/usr/bin/env bash
# Installs what shadelab needs on Debian/Ubuntu, only where it is missing:
# the Vulkan loader, Mesa lavapipe (software Vulkan), the Khronos validation
# layer, the C/C++ toolchain and cmake that the glslang crate builds with,
# and Chromium, which tests/compare_present.rs renders report.html in.
# Safe to run again: it installs nothing that is already there.
set -euo pipefail

missing=()
have_file() { compgen -G "$1" >/dev/null; }

ldconfig -p 2>/dev/null | grep -q 'libvulkan\.so\.1' || missing+=(libvulkan1)
have_file '/usr/share/vulkan/icd.d/lvp_icd*.json' || missing+=(mesa-vulkan-drivers)
have_file '/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json' || missing+=(vulkan-validationlayers)
command -v cmake >/dev/null || missing+=(cmake)
command -v c++ >/dev/null || missing+=(g++)
command -v cc >/dev/null || missing+=(gcc)
command -v chromium >/dev/null || missing+=(chromium)

if [ ${#missing[@]} -gt 0 ]; then
    echo "ci/install-deps.sh: installing ${missing[*]}"
    sudo=""
    if [ "$(id -u)" -ne 0 ]; then
        command -v sudo >/dev/null || { echo "need root or sudo to install: ${missing[*]}" >&2; exit 1; }
        sudo="sudo"
    fi
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

if ! command -v cargo >/dev/null; then
    echo "ci/install-deps.sh: cargo (Rust 1.85 or newer) is required; install it with rustup (https://rustup.rs)" >&2
    exit 1
fi
