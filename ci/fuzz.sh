#!/usr/bin/env bash
# Fuzzing: the parsers that read untrusted input, under libFuzzer.
#
#   scene_toml    the TOML scene loader (src/scene/toml_format.rs)
#   gltf_import   the glTF/GLB importer (src/scene/gltf_import.rs)
#   image_read    diff's PNG and EXR readers (src/output.rs)
#
# Usage: ci/fuzz.sh [--seconds N] [TARGET...]   (default: every target, 600 s each)
#
# Needs the nightly toolchain (`rustup toolchain install nightly`) and
# cargo-fuzz (`cargo install cargo-fuzz`); both are installed here when
# missing. A release habit, not CI. Each target starts from its seeds in
# fuzz/seeds/TARGET (committed) plus what earlier runs found in
# fuzz/corpus/TARGET (not committed); a crash lands in fuzz/artifacts/TARGET
# and ends that target's run: turn it into a regression test under tests/
# (tests/fuzz_regressions.rs). The last lines of each run (executions,
# coverage, corpus) go to target/fuzz-TARGET.log and a summary is printed.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=600 targets=()
while [ $# -gt 0 ]; do
    case "$1" in
        --seconds) seconds="$2"; shift ;;
        -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
        *) targets+=("$1") ;;
    esac
    shift
done
[ ${#targets[@]} -eq 0 ] && targets=(scene_toml gltf_import image_read)

rustup toolchain list | grep -q '^nightly' || rustup toolchain install nightly --profile minimal
command -v cargo-fuzz >/dev/null || cargo install cargo-fuzz --locked

cargo +nightly fuzz build -O
mkdir -p target
status=0
for t in "${targets[@]}"; do
    mkdir -p "fuzz/corpus/$t"
    log="target/fuzz-$t.log"
    echo "fuzz: $t for $seconds s"
    if ! cargo +nightly fuzz run -O "$t" "fuzz/corpus/$t" "fuzz/seeds/$t" -- \
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
