#!/usr/bin/env bash
# RMSE at equal sample counts of two builds of the ray tracer with bounces:
# how the progressive sample sequence (issue 55) compares with the grid of
# cell centres it replaced. The reference is the newer build's samples 256
# to 1023 of 1024 (three shards of four, merged and scaled): an unbiased
# image that shares no sample, and so no random number, with the renders of
# 4 to 256 samples measured against it. Not run by CI; its table is in
# docs/estimators.md.
#
#   ci/sequence-rmse.sh OLD_BINARY [NEW_BINARY]
set -euo pipefail
cd "$(dirname "$0")/.."
old=${1:?usage: ci/sequence-rmse.sh OLD_BINARY [NEW_BINARY]}
new=${2:-target/release/shadelab}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
render() { "$1" render "$2" --shading raytrace --quiet "${@:3}" >/dev/null 2>&1; }
echo "| scene | samples | grid RMSE | sequence RMSE | sequence / grid |"
echo "| --- | --- | --- | --- | --- |"
for scene in assets/diffuse-box.toml assets/hard/glass-ior-1e3.toml \
    assets/hard/mirror-corridor-64.toml tests/data/budget/subpixel-edge.toml; do
    name=$(basename "$scene" .toml)
    extra=()
    grep -q '^bounces' "$scene" || extra=(--bounces 1)
    for k in 2 3 4; do
        render "$new" "$scene" "${extra[@]}" --samples 1024 --shard "$k/4" --out "$work/$name-ref-$k.film"
    done
    for n in 4 16 64 256; do
        render "$old" "$scene" "${extra[@]}" --samples "$n" --shard 1/1 --out "$work/$name-old-$n.film"
        render "$new" "$scene" "${extra[@]}" --samples "$n" --shard 1/1 --out "$work/$name-new-$n.film"
    done
    python3 - "$work" "$name" <<'PY'
import json, struct, sys
work, name = sys.argv[1], sys.argv[2]
def film(path):
    data = open(path, 'rb').read()
    end = data.index(b'\n', 16)
    head = json.loads(data[16:end])
    sums = struct.unpack('<%dQ' % ((len(data) - end - 1) // 8), data[end + 1:])
    lo, hi = head['range']
    # Terms were divided by the render's samples: scale to the part's own.
    scale = head['settings']['samples'] / (hi - lo) / 2.0**32
    return [s * scale for s in sums], hi - lo
parts = [film(f'{work}/{name}-ref-{k}.film') for k in (2, 3, 4)]
total = sum(n for _, n in parts)
ref = [sum(p[i] * n for p, n in parts) / total for i in range(len(parts[0][0]))]
def rmse(path):
    image, _ = film(path)
    return (sum((a - b) ** 2 for a, b in zip(image, ref)) / len(ref)) ** 0.5
for n in (4, 16, 64, 256):
    a, b = rmse(f'{work}/{name}-old-{n}.film'), rmse(f'{work}/{name}-new-{n}.film')
    print(f'| {name} | {n} | {a:.4g} | {b:.4g} | {b / a:.2f} |')
PY
done
