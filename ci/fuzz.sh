#!/usr/bin/env bash
# Fuzzing: the parsers that read untrusted input, under libFuzzer.
#
#   scene_toml    the TOML scene loader (src/scene/toml/)
#   gltf_import   the glTF/GLB importer (src/scene/gltf/)
#   image_read    diff's PNG and EXR readers (src/output.rs)
#
# Usage: ci/fuzz.sh [--seconds N] [--direct] [TARGET...]
#        (default: every target, 600 s each)
#
# Needs the nightly toolchain (`rustup toolchain install nightly`) and
# cargo-fuzz (`cargo install cargo-fuzz`); both are installed here when
# missing. Where cargo-fuzz is missing and cannot be installed (offline),
# or with --direct, the targets are built without it: `cargo +nightly
# build --offline` with the flags `cargo fuzz build -O -a` passes (coverage
# instrumentation, AddressSanitizer, debug assertions and so overflow
# checks; not -Clink-dead-code) into fuzz/target/direct, and the binaries
# are run by hand with the same arguments. A release habit, not CI. Each
# target starts from its seeds in fuzz/seeds/TARGET (committed) plus what earlier runs found in
# fuzz/corpus/TARGET (not committed); a crash lands in fuzz/artifacts/TARGET
# and ends that target's run: turn it into a regression test under tests/
# (tests/cli/fuzz_regressions.rs). The last lines of each run (executions,
# coverage, corpus) go to target/fuzz-TARGET.log and a summary is printed.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=600 direct=0 targets=()
while [ $# -gt 0 ]; do
    case "$1" in
        --seconds) seconds="$2"; shift ;;
        --direct) direct=1 ;;
        -h|--help) sed -n '2,23p' "$0"; exit 0 ;;
        *) targets+=("$1") ;;
    esac
    shift
done
[ ${#targets[@]} -eq 0 ] && targets=(scene_toml gltf_import image_read)

rustup toolchain list | grep -q '^nightly' || rustup toolchain install nightly --profile minimal
if [ $direct = 0 ] && ! command -v cargo-fuzz >/dev/null &&
    ! cargo install cargo-fuzz --locked; then
    echo "fuzz: cargo-fuzz cannot be installed; building the targets without it" >&2
    direct=1
fi

# Without cargo-fuzz: what cargo-fuzz 0.12 passes for `build -O -a
# --strip-dead-code` on x86-64 Linux (its project module), by hand.
# -Clink-dead-code is left out (as --strip-dead-code does): with it, pulp
# 0.22.3 (under exr) fails to compile on nightly 1.97 (E0080 in its
# CheckSameSize); it matters only for coverage reports.
triple=x86_64-unknown-linux-gnu
direct_dir=fuzz/target/direct
direct_build() {
    local bins=()
    for t in "${targets[@]}"; do bins+=(--bin "$t"); done
    (cd fuzz && RUSTFLAGS="-Cpasses=sancov-module \
        -Cllvm-args=-sanitizer-coverage-level=4 \
        -Cllvm-args=-sanitizer-coverage-inline-8bit-counters \
        -Cllvm-args=-sanitizer-coverage-pc-table \
        -Cllvm-args=-sanitizer-coverage-trace-compares \
        -Cllvm-args=-sanitizer-coverage-stack-depth \
        --cfg fuzzing -Zsanitizer=address \
        -Cdebug-assertions -Coverflow-checks -Ccodegen-units=1 ${RUSTFLAGS:-}" \
        cargo +nightly build --offline --release --target "$triple" \
        --config 'profile.release.debug="line-tables-only"' \
        --target-dir target/direct "${bins[@]}")
}
run_target() { # TARGET ARGS...: one libFuzzer run
    local t="$1"
    shift
    if [ $direct = 1 ]; then
        mkdir -p "fuzz/artifacts/$t"
        ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_odr_violation=0" \
            "$direct_dir/$triple/release/$t" -artifact_prefix="fuzz/artifacts/$t/" \
            "fuzz/corpus/$t" "fuzz/seeds/$t" "$@"
    else
        cargo +nightly fuzz run -O "$t" "fuzz/corpus/$t" "fuzz/seeds/$t" -- "$@"
    fi
}

if [ $direct = 1 ]; then direct_build; else cargo +nightly fuzz build -O; fi
mkdir -p target
status=0
for t in "${targets[@]}"; do
    mkdir -p "fuzz/corpus/$t"
    log="target/fuzz-$t.log"
    echo "fuzz: $t for $seconds s"
    if ! run_target "$t" \
        -max_total_time="$seconds" -rss_limit_mb=4096 -max_len=262144 -print_final_stats=1 \
        >"$log" 2>&1; then
        echo "fuzz: $t FOUND A CRASH; see $log and fuzz/artifacts/$t" >&2
        status=1
    fi
    # libFuzzer's last status line: executions, coverage, features, corpus.
    grep -E '^#[0-9]+.*(DONE|pulse|NEW|REDUCE)' "$log" | tail -1 || true
    grep -E 'stat::number_of_executed_units|stat::average_exec_per_sec|stat::peak_rss_mb' "$log" || true
done
exit $status
