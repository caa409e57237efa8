#!/usr/bin/env bash
# Where the ray tracer's time goes inside the compiled shader: lavapipe's own
# listing of it (GALLIVM_DEBUG=asm), each line with the perf samples that
# fell on it.
#
#   ci/shader-profile.sh [--bin BIN] [--out DIR] SCENE [RENDER_ARGS...]
#
# Renders SCENE once with `--shading raytrace` under `perf record` (give a
# large size, e.g. --width 4096 --height 4096, so that the dispatch
# outweighs the compile). The shader is compiled by LLVM at run time, so
# perf has no symbols for it: the samples are matched to the listing by the
# load address that puts the most of them on instruction boundaries.
# Writes DIR/annotated.txt (samples, offset, instruction) and prints the
# hottest windows of 100 instructions. Needs perf (Debian's
# `linux-perf`). docs/performance.md, "Where the time went", used it.
set -euo pipefail
cd "$(dirname "$0")/.."
bin=./target/release/shadelab
out=target/shader-profile
while [ $# -gt 0 ]; do
    case "$1" in
        --bin) bin=$2; shift 2 ;;
        --out) out=$2; shift 2 ;;
        -h | --help) sed -n '2,15p' "$0"; exit 0 ;;
        *) break ;;
    esac
done
[ $# -ge 1 ] || { echo "shader-profile: give a scene file" >&2; exit 2; }
command -v perf >/dev/null || { echo "shader-profile: needs perf (apt-get install linux-perf)" >&2; exit 2; }
mkdir -p "$out"
# The shader cache would skip the compile, and with it the listing.
GALLIVM_DEBUG=asm MESA_SHADER_CACHE_DISABLE=1 perf record -q -o "$out/perf.data" \
    "$bin" render "$@" --shading raytrace --out "$out/image.exr" >"$out/listing.txt" 2>&1
perf script -i "$out/perf.data" -F ip,sym 2>/dev/null |
    awk '$2 == "[unknown]" { print $1 }' | sort | uniq -c >"$out/samples.txt"
python3 - "$out/listing.txt" "$out/samples.txt" "$out/annotated.txt" <<'PY'
import re, sys
from collections import Counter
listing, samples_path, out_path = sys.argv[1:4]
lines = open(listing).read().split("\n")
starts = [i for i, l in enumerate(lines) if l == "cs_co_variant:"]
if not starts:
    sys.exit("shader-profile: no compute shader in the listing (is the scene ray traced?)")
offsets, order = {}, []
for line in lines[starts[-1] + 1:]:
    m = re.match(r"\s*([0-9a-f]+):\t(.*)", line)
    if m:
        offsets[int(m.group(1), 16)] = m.group(2)
        order.append(int(m.group(1), 16))
    elif line.endswith(":") and not line.startswith(" "):
        break
samples = [(int(ip, 16), int(n)) for n, ip in (l.split() for l in open(samples_path))]
votes = Counter()
for ip, n in sorted(samples, key=lambda s: -s[1])[:40]:
    for off in order:
        votes[ip - off] += n
if not votes:
    sys.exit("shader-profile: no samples outside known code")
base = votes.most_common(1)[0][0]
hits = Counter()
for ip, n in samples:
    if ip - base in offsets:
        hits[ip - base] += n
total = sum(hits.values())
with open(out_path, "w") as f:
    for off in order:
        f.write(f"{hits[off]:6d} {off:6x}  {offsets[off]}\n")
print(f"{total} samples in the shader ({total * 100 // max(1, sum(n for _, n in samples))}% of the process's unsymbolled ones)")
windows = [(sum(hits[o] for o in order[k:k + 100]), k) for k in range(0, len(order), 100)]
for n, k in sorted(windows, reverse=True)[:10]:
    print(f"  lines {k + 1}-{min(k + 100, len(order))} of {out_path}: {n * 100 / max(1, total):.1f}%")
PY
