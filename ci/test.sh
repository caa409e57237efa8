#!/usr/bin/env bash
# The test suite, as CI runs it: formatting, lints, the API docs (rustdoc
# warnings are errors), then every test in release mode with the Khronos
# validation layer on (a validation message fails the test that caused it).
# Python's venv is installed too (the package's tests); Chromium too: tests/cpu/compare_present.rs renders report.html in
# it, and fails (does not skip) where it is missing; so are Slurm and MUNGE,
# which tests/cli/shards.rs runs a one-node cluster of (--shard auto).
set -euo pipefail
cd "$(dirname "$0")/.."
bash ci/install-deps.sh --with-chromium --with-slurm --with-python
rustup component list --installed 2>/dev/null | grep -q rustfmt || rustup component add rustfmt clippy 2>/dev/null || true
cargo fmt --all -- --check
# The code as a map (docs/architecture.md): no file over 800 lines, no
# function over 100, no import loop between files.
PYTHONDONTWRITEBYTECODE=1 python3 -m unittest discover -s ci -p test_layout_check.py
python3 ci/layout-check.py
cargo clippy --release --workspace --all-targets -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --release --no-deps
export SHADELAB_VALIDATION=1
cargo test --release
# The Python package (python/): built with maturin into a virtual
# environment under target/, its pytest suite run with the validation layer
# on (docs/python.md).
bash ci/python-tests.sh
# GPU against the CPU reference on every scene, as a CI job of a user's
# would run it: images and a JUnit report are kept under target/check/.
./target/release/shadelab check --out target/check --junit target/check/default.xml
./target/release/shadelab check assets/*.toml --out target/check --junit target/check/assets.xml
./target/release/shadelab check assets/hard/*.toml --out target/check --junit target/check/hard.xml
# The lecture's formula written as a user's lighting hook, compiled at run
# time into every mode, holds check's thresholds as the built-in one does.
./target/release/shadelab check assets/*.toml --lighting examples/lighting/phong.glsl \
    --out target/check-hook --junit target/check-hook/assets.xml
# Forward ray tracing (photons from the lights) against its f64 twin, which
# traces the same photons: limits from the noise (docs/check.md).
./target/release/shadelab check assets/*.toml assets/hard/*.toml --shading forward \
    --out target/check-forward --images failures --junit target/check-forward/assets.xml
# Secondary illumination, both estimators, on every asset: two diffuse bounces.
./target/release/shadelab check assets/*.toml --shading raytrace,forward --bounces 2 \
    --out target/check-bounces --images failures --junit target/check-bounces/assets.xml
# Four samples per pixel in the raster modes: the GPU and the reference
# sample, depth-test and average the same points (docs/check.md).
./target/release/shadelab check assets/*.toml assets/hard/*.toml --shading flat,gouraud,phong \
    --msaa 4 --out target/check-msaa --images failures --junit target/check-msaa/assets.xml
# And shaded per sample, a pass per sample on the GPU.
./target/release/shadelab check assets/*.toml assets/hard/*.toml --shading flat,gouraud,phong \
    --msaa 4,per-sample --out target/check-msaa-per-sample --images failures \
    --junit target/check-msaa-per-sample/assets.xml
# The ray tracer's packets at another subgroup size: lavapipe on 128-bit
# vectors (as on a CPU without AVX) runs subgroups of 4 lanes, not 8.
LP_NATIVE_VECTOR_WIDTH=128 ./target/release/shadelab check assets/*.toml --shading raytrace,forward \
    --out target/check-4-lanes --junit target/check-4-lanes/assets.xml
# Two eye rays a lane at 4 lanes too (the paired walk against the single
# one, bit for bit).
LP_NATIVE_VECTOR_WIDTH=128 cargo test --release --test gpu paired_rays
# The peer benchmark's shadelab side at 64x64 with no peers, so that the
# script and its report cannot rot (the full run is ci/bench-peers.sh), in
# two rounds so that the merging of rounds is run too; and the checks of
# that merging.
bash ci/bench-peers.sh --smoke --rounds 2 >/dev/null
PYTHONDONTWRITEBYTECODE=1 python3 -m unittest discover -s ci/peers -p 'test_*.py'
