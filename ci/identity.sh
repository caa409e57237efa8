#!/usr/bin/env bash
# Renders the default scene, assets/*.toml and assets/hard/*.toml in all four
# modes, PNG and EXR, on the GPU and with the CPU reference; and the Monte
# Carlo renders (forward tracing, two diffuse bounces, the photon map's
# caustics) of assets/*.toml at 96x72 as EXR on both; and prints one
# SHA-256 per image: a refactoring that must not change a pixel is checked
# by diffing this list before and after (`ci/identity.sh BIN > list`).
#   ci/identity.sh [BINARY] > hashes.txt
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-./target/release/shadelab}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
modes=flat,gouraud,phong,raytrace
for backend in gpu cpu; do
    for ext in png exr; do
        for set in default assets hard; do
            case $set in
                default) scenes=() ;;
                assets) scenes=(assets/*.toml) ;;
                hard) scenes=(assets/hard/*.toml) ;;
            esac
            dir=$out/$backend-$ext-$set
            # A scene a mode refuses is part of what is compared: its
            # refusal is listed (the status), not its image.
            status=0
            "$bin" render ${scenes[@]+"${scenes[@]}"} --quiet --backend "$backend" --shading "$modes" \
                --out-dir "$dir" --name "{scene}-{mode}.$ext" >"$dir.log" 2>&1 || status=$?
            echo "status $backend-$ext-$set $status"
        done
    done
done
# The Monte Carlo renders: their images are sums of fixed-point films (or,
# for caustics, the photon map's), so a refactoring keeps them bit for bit.
for backend in gpu cpu; do
    for run in forward bounces caustics; do
        case $run in
            forward) flags=(assets/*.toml --shading forward) ;;
            bounces) flags=(assets/*.toml --shading raytrace --bounces 2 --samples 4) ;;
            caustics) flags=(assets/caustics.toml --shading raytrace) ;;
        esac
        dir=$out/$backend-mc-$run
        status=0
        "$bin" render "${flags[@]}" --quiet --backend "$backend" --width 96 --height 72 \
            --out-dir "$dir" --name "{scene}-{mode}.exr" >"$dir.log" 2>&1 || status=$?
        echo "status $backend-mc-$run $status"
    done
done
cd "$out"
find . -type f \( -name '*.png' -o -name '*.exr' \) -print0 | sort -z | xargs -0 sha256sum
