#!/usr/bin/env bash
# Draws many random scenes over new seeds (issue 55: "the random scene
# explained"), not run by CI, which keeps its fixed seed: tests/gpu/random_scenes.rs
# with SHADELAB_RANDOM_SEED=S for each seed S, SHADELAB_RANDOM_SCENES scenes
# each. A failing seed's log holds its scene, shrunk; the failures go into
# docs/hard-cases.md with their cause, or are fixed.
#
#   ci/random-scenes.sh [SEEDS] [SCENES_PER_SEED] [FIRST_SEED]
set -uo pipefail
cd "$(dirname "$0")/.."
seeds=${1:-20}
per_seed=${2:-50}
first=${3:-10000}
out=${OUT:-target/random-scenes}
mkdir -p "$out"
cargo test --release --test gpu --no-run >/dev/null 2>&1
failed=0
for ((s = first; s < first + seeds; s++)); do
    if SHADELAB_VALIDATION=1 SHADELAB_RANDOM_SEED=$s SHADELAB_RANDOM_SCENES=$per_seed \
        cargo test --release --test gpu random_scenes:: >"$out/seed-$s.log" 2>&1; then
        echo "seed $s: $per_seed scenes passed"
    else
        failed=$((failed + 1))
        echo "seed $s: FAILED (see $out/seed-$s.log)"
    fi
done
echo "$failed of $seeds seeds failed ($((seeds * per_seed)) scenes drawn, a seed stops at its first failure)"
