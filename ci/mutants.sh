#!/usr/bin/env bash
# Mutation testing: break the code on purpose and watch the tests fail.
# A release habit, not CI (too slow for a 2-core machine). Two halves:
#
#   --glsl   hand mutants of the shaders (cargo-mutants reads Rust only),
#            each applied alone to a scratch copy of the repository; the
#            GPU tests must fail on every one. About 2 minutes a mutant.
#   --rust   cargo-mutants over the Rust files whose bugs GPU-against-CPU
#            agreement cannot see (check's verdict, the metrics, the scene
#            loading, the camera, the CPU reference), or over FILES given
#            with --file (repeatable). Hours for all of them on 2 cores:
#            give a file or two, or use --shard K/N.
#
# Usage: ci/mutants.sh [--glsl] [--rust] [--file PATH]... [--shard K/N] [-- CARGO_TEST_ARGS]
# (cargo test's arguments for the Rust half, e.g. `-- --test cpu check_thresholds::`
# to run only the tests that guard the file; the default is the whole suite.)
# With neither --glsl nor --rust, both. Needs `cargo install cargo-mutants`
# for --rust. Results: target/mutants-glsl.txt and mutants.out/ (cargo-mutants').
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

run_glsl=0 run_rust=0 shard="" files=() test_args=()
while [ $# -gt 0 ]; do
    case "$1" in
        --glsl) run_glsl=1 ;;
        --rust) run_rust=1 ;;
        --file) files+=("$2"); shift ;;
        --shard) shard="$2"; shift ;;
        --) shift; test_args=("$@"); break ;;
        -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
        *) echo "mutants: unknown argument $1" >&2; exit 2 ;;
    esac
    shift
done
[ $run_glsl = 0 ] && [ $run_rust = 0 ] && run_glsl=1 run_rust=1

# The GPU tests a shader mutant must fail: the formula per pixel and per
# vertex against f64, the modes' own rules, the ray tracer's exact answers.
gpu_tests=(--test gpu -- raster_phong:: raster_modes:: raytrace::)

# file | what it breaks | sed expression (applied to that file only)
glsl_mutants=(
    "shaders/include/lighting_hook.glsl|attenuation Il / (d + k + 1)|s|light /= d + k;|light /= d + k + 1.0;|"
    "shaders/include/lighting_hook.glsl|specular term halved|s|reflected += vec3(m.ks \* s);|reflected += vec3(0.5 * m.ks * s);|"
    "shaders/include/lighting.glsl|interpolated normal left unnormalised|s|return len2 > 0.0 ? n \* inversesqrt(len2) : vec3(0.0);|return n;|"
    "shaders/gouraud.vert.glsl|Gouraud intensity off by 1%|s|    out_intensity = intensity;|    out_intensity = intensity * 0.99;|"
    "shaders/flat.vert.glsl|flat's view vector reversed|s|normalize(-P)|normalize(P)|"
    "shaders/include/rt_ray_tree.glsl|refraction ratio inverted|s|float eta = entering ? 1.0 / ior : ior;|float eta = entering ? ior : 1.0 / ior;|"
    "shaders/include/rt_shading.glsl|secondary-ray offset 100x smaller|s|return 1.0e-4 \* max(a.x|return 1.0e-6 * max(a.x|"
)

if [ $run_glsl = 1 ]; then
    report="$root/target/mutants-glsl.txt"
    mkdir -p "$root/target"
    : > "$report"
    scratch=$(mktemp -d)
    trap 'rm -rf "$scratch"' EXIT
    # The repository's own target folder: its dependencies are built
    # already, and the scratch copy's shadelab (another path, so another
    # fingerprint) is built beside the repository's, not over it.
    export CARGO_TARGET_DIR="$root/target"
    export SHADELAB_VALIDATION=1
    survived=0
    for entry in "${glsl_mutants[@]}"; do
        IFS='|' read -r file what expr <<< "$entry"
        expr="${entry#*|*|}"
        rm -rf "$scratch/repo"
        mkdir "$scratch/repo"
        git ls-files -z | xargs -0 cp --parents -t "$scratch/repo"
        before=$(sha1sum "$scratch/repo/$file")
        sed -i "$expr" "$scratch/repo/$file"
        if [ "$(sha1sum "$scratch/repo/$file")" = "$before" ]; then
            echo "NOT APPLIED  $file: $what (the line it edits has changed)" | tee -a "$report"
            survived=1
            continue
        fi
        # A mutant that does not build proves nothing about the tests.
        if ! (cd "$scratch/repo" && cargo test --release --no-run "${gpu_tests[@]}" >/dev/null 2>&1); then
            echo "UNBUILDABLE  $file: $what" | tee -a "$report"
            survived=1
            continue
        fi
        if (cd "$scratch/repo" && cargo test --release "${gpu_tests[@]}" >/dev/null 2>&1); then
            echo "SURVIVED     $file: $what" | tee -a "$report"
            survived=1
        else
            echo "killed       $file: $what" | tee -a "$report"
        fi
    done
    echo "mutants: GLSL results in $report"
    [ $survived = 0 ] || { echo "mutants: a GLSL mutant survived or did not apply" >&2; exit 1; }
fi

if [ $run_rust = 1 ]; then
    command -v cargo-mutants >/dev/null || { echo "mutants: install it with 'cargo install cargo-mutants'" >&2; exit 2; }
    if [ ${#files[@]} = 0 ]; then
        files=(src/check.rs src/metrics src/scene src/camera.rs src/cpu)
    fi
    args=()
    for f in "${files[@]}"; do args+=(--file "$f"); done
    [ -n "$shard" ] && args+=(--shard "$shard")
    # In place: the repository's target folder and its built dependencies
    # (a copy would build everything again); each mutant is undone after.
    # The test arguments go to the build as well (--cargo-arg), so each
    # mutant builds only the test targets that run: a third of the time.
    for a in "${test_args[@]}"; do args+=("--cargo-arg=$a"); done
    SHADELAB_VALIDATION=1 cargo mutants --in-place --profile release "${args[@]}"
fi
