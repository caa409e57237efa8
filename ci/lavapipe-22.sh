#!/usr/bin/env bash
# Runs a command on Debian 12's own lavapipe, Mesa 22.3.6, whatever Mesa is
# installed: ci/install-deps.sh installs a newer one from bookworm-backports,
# and this keeps the old driver tested without installing it.
#   ci/lavapipe-22.sh target/release/shadelab info
#   ci/lavapipe-22.sh target/release/shadelab check --out /tmp/check22
# The first run downloads mesa-vulkan-drivers 22.3.6-1+deb12u2 (8 MB) with
# apt-get download (from deb.debian.org with curl or wget where apt has no
# bookworm sources), unpacks it with dpkg-deb -x (no install, no root) into
# ${XDG_CACHE_HOME:-~/.cache}/shadelab-lavapipe-22, and points the unpacked
# ICD json at the unpacked libvulkan_lvp.so. The command then runs with
# VK_DRIVER_FILES and VK_ICD_FILENAMES (older loaders) set to that json,
# so the loader sees that driver only. Libraries it links that the system
# lacks (libLLVM-15 where no bookworm Mesa is installed) are downloaded and
# unpacked beside it and found through LD_LIBRARY_PATH.
set -euo pipefail

version="22.3.6-1+deb12u2"
# SHA256 of mesa-vulkan-drivers_${version}_amd64.deb, checked when it is not
# apt that fetched it.
sha256_amd64="21f9ecf52886c88247d8ef92b635b8f670ab01fd7813c98f8200220aa138f4da"

if [ $# -eq 0 ]; then
    echo "usage: ci/lavapipe-22.sh COMMAND [ARGS...]   (runs COMMAND on lavapipe from Mesa $version)" >&2
    exit 2
fi

arch=$(dpkg --print-architecture)
cache="${XDG_CACHE_HOME:-$HOME/.cache}/shadelab-lavapipe-22"
dir="$cache/$version-$arch" # what is unpacked, ready to use
say() { echo "ci/lavapipe-22.sh: $*" >&2; }

# apt-get download, into the current directory; apt's sandbox user cannot
# write to root's cache, so root downloads as root.
apt_download() {
    local sandbox=()
    [ "$(id -u)" -ne 0 ] || sandbox=(-o APT::Sandbox::User=root)
    apt-get download -qq "${sandbox[@]}" "$@"
}

# Debian package that ships a shared library, for the few that lavapipe 22.3
# links and a system without a bookworm Mesa may lack.
package_of() {
    case "$1" in
        libLLVM-15.so.1) echo libllvm15 ;;
        libicu*.so.72) echo libicu72 ;;
        libz3.so.4) echo libz3-4 ;;
        *) # Debian's naming: libfoo_bar.so.1 -> libfoo-bar1, libfoo2.so.0 -> libfoo2-0
            local name=${1%%.so.*} so=${1##*.so.}
            name=$(echo "${name//_/-}" | tr '[:upper:]' '[:lower:]')
            case "$name" in *[0-9]) echo "$name-$so" ;; *) echo "$name$so" ;; esac ;;
    esac
}

# Sonames that lavapipe ($1) cannot find, with the folders in $2 searched first.
missing_libs() {
    LD_LIBRARY_PATH="$2${LD_LIBRARY_PATH:+${2:+:}$LD_LIBRARY_PATH}" ldd "$1" | awk '/=> not found/ { print $1 }'
}
# Folders under $1 that hold shared libraries, colon-separated.
lib_dirs() { find "$1" -name '*.so*' -printf '%h\n' | sort -u | paste -sd: -; }

if [ ! -e "$dir/ready" ]; then
    mkdir -p "$cache"
    tmp=$(mktemp -d "$cache/tmp.XXXXXX")
    trap 'rm -rf "$tmp"' EXIT
    deb="mesa-vulkan-drivers_${version}_${arch}.deb"
    say "fetching mesa-vulkan-drivers $version into $cache"
    if ! (cd "$tmp" && apt_download "mesa-vulkan-drivers=$version") 2>"$tmp/apt.log"; then
        [ "$arch" = amd64 ] || { cat "$tmp/apt.log" >&2; say "apt-get download failed, and there is no checked URL for $arch"; exit 1; }
        url="https://deb.debian.org/debian/pool/main/m/mesa/${deb//+/%2b}"
        say "apt-get download failed ($(head -n1 "$tmp/apt.log")); trying $url"
        if command -v curl >/dev/null; then
            curl -fsSL -o "$tmp/$deb" "$url"
        else
            wget -q -O "$tmp/$deb" "$url"
        fi
        echo "$sha256_amd64  $tmp/$deb" | sha256sum -c --quiet -
    fi
    mkdir "$tmp/root"
    dpkg-deb -x "$tmp"/mesa-vulkan-drivers_*.deb "$tmp/root"

    lib=$(find "$tmp/root/usr/lib" -name libvulkan_lvp.so | head -n1)
    json=$(find "$tmp/root/usr/share/vulkan/icd.d" -name 'lvp_icd.*.json' | head -n1)
    if [ -z "$lib" ] || [ -z "$json" ]; then
        say "no libvulkan_lvp.so or lvp_icd json in $deb"
        exit 1
    fi
    # Paths as they will be once $tmp is renamed to $dir.
    final_lib="$dir/${lib#"$tmp"/}"
    sed -i -E "s|(\"library_path\"[[:space:]]*:[[:space:]]*)\"[^\"]*\"|\1\"$final_lib\"|" "$json"
    grep -qF "\"$final_lib\"" "$json" || { say "could not rewrite library_path in $json"; exit 1; }

    # Libraries the system lacks: fetch and unpack their bookworm packages too.
    mkdir "$tmp/extra"
    for _ in 1 2 3; do
        mapfile -t need < <(missing_libs "$lib" "$(lib_dirs "$tmp/extra")")
        [ ${#need[@]} -gt 0 ] || break
        mapfile -t pkgs < <(for so in "${need[@]}"; do package_of "$so"; done | sort -u)
        say "the system lacks ${need[*]}; unpacking ${pkgs[*]} beside lavapipe"
        mkdir "$tmp/debs"
        (cd "$tmp/debs" && apt_download "${pkgs[@]}")
        for p in "$tmp"/debs/*.deb; do dpkg-deb -x "$p" "$tmp/extra"; done
        rm -rf "$tmp/debs"
    done
    still=$(missing_libs "$lib" "$(lib_dirs "$tmp/extra")" | paste -sd' ' -)
    [ -z "$still" ] || { say "libvulkan_lvp.so $version still lacks: $still"; exit 1; }
    lib_dirs "$tmp/extra" | sed "s|$tmp/|$dir/|g" > "$tmp/ld_library_path"
    printf '%s\n' "$dir/${json#"$tmp"/}" > "$tmp/json"
    touch "$tmp/ready"
    rm -f "$tmp"/*.deb "$tmp/apt.log"
    [ -e "$dir/ready" ] || rm -rf "$dir" # left by an older version of this script
    mv -T "$tmp" "$dir" 2>/dev/null || [ -e "$dir/ready" ] # another run may have won
    trap - EXIT
    rm -rf "$tmp"
fi

json=$(cat "$dir/json")
extra=$(cat "$dir/ld_library_path")
export VK_DRIVER_FILES="$json" VK_ICD_FILENAMES="$json"
if [ -n "$extra" ]; then
    export LD_LIBRARY_PATH="$extra${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
fi
exec "$@"
