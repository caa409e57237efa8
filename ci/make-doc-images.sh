#!/usr/bin/env bash
# Regenerates every picture in docs/images/ from the release binary, so that
# the README's images show what shadelab renders now. Run from a fresh clone
# after `bash ci/install-deps.sh`:
#
#   bash ci/make-doc-images.sh
#
# It builds target/release/shadelab if needed, renders into a temporary
# folder, copies the results over docs/images/ under the same names and
# prints each file it wrote. On a 2-core machine it takes about a minute once
# the binary is built, nearly all of it the two compare runs (the lighting
# hooks' first compile, cached in $SHADELAB_CACHE_DIR, adds a few seconds).
# The compare plots' GPU times are measured on this machine: run it on an
# otherwise idle one, or the points move (the errors do not).
#
#   default-{flat,gouraud,phong,raytrace}.png
#       shadelab render --shading MODE (the built-in default scene, 640x480)
#   diff-gouraud-vs-phong.png
#       shadelab diff default-phong.png default-gouraud.png --heatmap ...
#       (FLIP heat map; diff exits 1 because the images differ, as expected)
#   compare-speed-vs-error.png, compare-contact-sheet.png
#       shadelab compare on the default scene with its default variants
#       (28 variants, 640x480, 3 runs each): speed-vs-error.png, contact-sheet.png
#   hooks-speed-vs-error.png
#       shadelab compare assets/spheres.toml with each mode (Phong, Gouraud and
#       flat at 64 segments, ray tracing at depth 2) built in and with the
#       hooks examples/lighting/{blinn-phong,schlick-pow,half-precision}.glsl,
#       5 runs each (run in examples/lighting/ so the plot names the hooks
#       by file name)
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
started=$(date +%s)

cargo build --release --quiet
bin=$repo/target/release/shadelab
dest=$repo/docs/images

tmp=$(mktemp -d "${TMPDIR:-/tmp}/shadelab-doc-images.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
say() { echo "make-doc-images: $*" >&2; }

# The default scene in every mode.
for mode in flat gouraud phong raytrace; do
    say "rendering the default scene, $mode"
    "$bin" render --shading "$mode" --out "$tmp/default-$mode.png" >/dev/null
done

# Gouraud's FLIP error against Phong. diff exits 1 when a figure is over its
# threshold, which it is here: only a status above 1 (bad input) is an error.
say "diff: Gouraud against Phong"
rc=0
"$bin" diff "$tmp/default-phong.png" "$tmp/default-gouraud.png" \
    --heatmap "$tmp/diff-gouraud-vs-phong.png" >/dev/null 2>&1 || rc=$?
if [ "$rc" -gt 1 ] || [ ! -s "$tmp/diff-gouraud-vs-phong.png" ]; then
    say "shadelab diff failed (exit $rc)"
    exit 1
fi

# The default scene's compare report: plot and contact sheet.
say "compare: the default scene, default variants (about a minute)"
"$bin" compare --out "$tmp/compare-default" >/dev/null 2>"$tmp/compare-default.log" ||
    { cat "$tmp/compare-default.log" >&2; exit 1; }
cp "$tmp/compare-default/speed-vs-error.png" "$tmp/compare-speed-vs-error.png"
cp "$tmp/compare-default/contact-sheet.png" "$tmp/compare-contact-sheet.png"

# The lighting hooks on the spheres scene.
say "compare: the lighting hooks on assets/spheres.toml (a minute or two)"
variants=()
for mode in phong:segments=64 gouraud:segments=64 flat:segments=64 raytrace:depth=2; do
    variants+=("$mode")
    for hook in blinn-phong schlick-pow half-precision; do
        variants+=("$mode,lighting=$hook.glsl")
    done
done
(
    cd examples/lighting
    "$bin" compare "$repo/assets/spheres.toml" --width 640 --height 480 --runs 5 \
        --variants "$(IFS=';'; echo "${variants[*]}")" --out "$tmp/compare-hooks" \
        >/dev/null 2>"$tmp/compare-hooks.log"
) || { cat "$tmp/compare-hooks.log" >&2; exit 1; }
cp "$tmp/compare-hooks/speed-vs-error.png" "$tmp/hooks-speed-vs-error.png"

images=(default-flat default-gouraud default-phong default-raytrace diff-gouraud-vs-phong
    compare-speed-vs-error compare-contact-sheet hooks-speed-vs-error)
mkdir -p "$dest"
for name in "${images[@]}"; do
    cp "$tmp/$name.png" "$dest/$name.png"
    echo "wrote docs/images/$name.png"
done
# A picture in docs/images/ that this script does not make would go stale.
for f in "$dest"/*; do
    case " ${images[*]} " in *" $(basename "$f" .png) "*) ;; *) say "warning: $f is not made by this script" ;; esac
done
say "done in $(($(date +%s) - started)) s"
