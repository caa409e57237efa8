#!/usr/bin/env bash
# Instructions one ray-tracing dispatch takes, for each shadelab binary given:
# a figure the shared machines cannot blur, for an A/B of a shader change.
#
#   ci/shader-instructions.sh [--scene FILE] [--size N] [--] BIN [BIN...] [-- BENCH_ARGS...]
#
# For each binary, valgrind's cachegrind counts the instructions of
# `bench --runs 1` and of `--runs 2`; the difference is one dispatch (and the
# host's per-run work, the same for both binaries when the pipeline is). Each
# count is taken twice, the first to fill Mesa's shader cache for valgrind's
# CPU (which lacks AVX-512, so lavapipe compiles a variant of its own).
#
# What it cannot see: latency. A change that shortens a chain of divisions
# or misses the cache less leaves the count as it is (docs/performance.md,
# "How it is measured"). Needs valgrind (Debian's `valgrind`).
set -euo pipefail
cd "$(dirname "$0")/.."
scene=assets/spheres.toml
size=512
bins=()
while [ $# -gt 0 ]; do
    case "$1" in
        --scene) scene=$2; shift 2 ;;
        --size) size=$2; shift 2 ;;
        --) shift; break ;;
        -h | --help) sed -n '2,15p' "$0"; exit 0 ;;
        *) bins+=("$1"); shift ;;
    esac
done
bench_args=("$@")
[ ${#bins[@]} -gt 0 ] || { echo "shader-instructions: give at least one shadelab binary" >&2; exit 2; }
command -v valgrind >/dev/null || { echo "shader-instructions: needs valgrind (apt-get install valgrind)" >&2; exit 2; }

count() { # BIN RUNS: instructions of one bench process
    LP_NUM_THREADS=1 valgrind --tool=cachegrind --cache-sim=no --cachegrind-out-file=/dev/null \
        "$1" bench "$scene" --shading raytrace --width "$size" --height "$size" --runs "$2" \
        ${bench_args[@]+"${bench_args[@]}"} 2>&1 |
        awk '/I *refs:/ { gsub(",", "", $NF); print $NF }'
}

printf '%-40s %16s\n' binary instructions_per_run
for bin in "${bins[@]}"; do
    [ -x "$bin" ] || { echo "shader-instructions: $bin is not an executable" >&2; exit 2; }
    count "$bin" 1 >/dev/null
    one=$(count "$bin" 1)
    two=$(count "$bin" 2)
    if [ -z "$one" ] || [ -z "$two" ]; then
        echo "shader-instructions: valgrind gave no count for $bin" >&2
        exit 1
    fi
    printf '%-40s %16d\n' "$bin" $((two - one))
done
