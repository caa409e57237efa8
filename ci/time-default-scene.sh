#!/usr/bin/env bash
# Median render time of the default scene per raster mode at 1024x1024 over
# RUNS runs (default 7), from the CLI's own --json timings: `total_ms` is the
# whole render (pipeline, uploads, draw, read-back), `gpu_ms` the timestamped
# draw, `pipeline_ms` pipeline creation. Process start-up, device creation and
# PNG encoding are excluded, and reported separately as wall time.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${RUNS:-7}
cargo build --release --quiet
bin=./target/release/shadelab
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '%-8s %10s %10s %12s %12s\n' mode total_ms gpu_ms pipeline_ms process_ms
for mode in flat gouraud phong; do
    for _ in $(seq "$runs"); do
        start=$(date +%s%N)
        "$bin" render --shading "$mode" --width 1024 --height 1024 --out "$tmp/x.png" --json >>"$tmp/$mode.jsonl"
        echo $(( ($(date +%s%N) - start) / 1000000 )) >>"$tmp/$mode.wall"
    done
    python3 - "$tmp/$mode.jsonl" "$tmp/$mode.wall" "$mode" <<'PY'
import json, statistics, sys
rows = [json.loads(l)["timings_ms"] for l in open(sys.argv[1])]
wall = [float(l) for l in open(sys.argv[2])]
med = lambda k: statistics.median(r[k] for r in rows)
print(f"{sys.argv[3]:<8} {med('total_ms'):10.1f} {med('gpu_ms'):10.1f} {med('pipeline_ms'):12.1f} {statistics.median(wall):12.0f}")
PY
done
