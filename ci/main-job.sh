#!/usr/bin/env bash
# The main job: renders the built-in default scene in every mode to
# out/default-<mode>.png (and a linear EXR of the Phong render).
set -euo pipefail
cd "$(dirname "$0")/.."
bash ci/install-deps.sh
cargo build --release --quiet
mkdir -p out
for mode in flat gouraud phong raytrace; do
    ./target/release/shadelab render --shading "$mode" --out "out/default-$mode.png"
done
./target/release/shadelab render --shading phong --out out/default-phong.exr
