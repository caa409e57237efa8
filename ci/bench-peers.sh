#!/usr/bin/env bash
# Peer benchmark: shadelab against the renderers a user would pick instead, on the same work,
# in one run, with a table of figures and ratios. Not part of CI except as --smoke.
# See ci/peers/README.md for what each peer does and how the figures compare.
set -euo pipefail

usage() {
    cat <<'EOF'
usage: ci/bench-peers.sh [options]

Measures shadelab (target/release/shadelab) against its peers on the same work, in one run:
  rays-sphereSEG     ray tracer at --depth 0 (primary + shadow rays) on the peers' UV sphere
                     (SEG 100: 40k triangles, 316: 400k) vs Embree 3 and Mitsuba 3 llvm_ad_rgb
                     (scalar_rgb too with --all), and vs shadelab's own CPU twin
  rt-four-spheres    ray tracer on 4 spheres + plane, mirror depth 2, vs a wgpu compute tracer
  twin-SCENE         ray tracer GPU vs its CPU twin on assets/*.toml, the default scene and
                     the bench mesh (ci/make-bench-mesh.py); on the default scene and the four
                     spheres also the tracer specialised to the scene vs every feature compiled in
  raster-sphereSEG   flat/gouraud/phong vs wgpu's constant colour/gouraud/phong
  image-SCENE        time to image: the whole `shadelab render` command as fresh processes, warm
                     and with empty caches, vs the CPU twin's command (the default scene at its
                     own size, Phong and ray traced; the first sphere at --size, depth 0; the
                     four spheres), and vs the peers' first image in a fresh process, cold and
                     warm: Mitsuba llvm_ad_rgb on the sphere, the wgpu tracer on four spheres
  estimators-box     secondary illumination on assets/diffuse-box.toml: shadelab's backward
                     and forward tracers against Mitsuba 3's path and ptracer (agreement, and
                     time to the same RMSE; Mitsuba's LLVM variant on Debian's libllvm19)
and prints a Markdown table (also written as JSON). Peers are installed on first use under
${SHADELAB_PEERS_DIR:-$HOME/.cache/shadelab-peers} (a Python venv with pinned numpy, wgpu,
mitsuba; Debian's libembree-dev and g++ through apt-get when missing; the Embree caster).

options:
  --smoke          CI check: shadelab side only (no peers, no installs), 64x64, small spheres,
                   --runs 1; fails if a shadelab command fails or the report cannot be built
  --runs N         timed runs per measurement, after warm-up (default 5; smoke 1)
  --rounds N       run every job N times, in alternating order, and give each ratio as the
                   median of the rounds' ratios with their range (default 1): each round runs
                   the two sides of a row back to back, so drift on a shared machine between
                   rounds cancels in every round's ratio
  --size N         image width and height (default 1024; smoke 64)
  --only REGEX     run only the jobs whose name matches (bash regex), e.g. 'rays|raster'
  --all            also run the slow peers (Mitsuba scalar_rgb)
  --list           print the job names this run would run, and exit
  --setup          install the peers and exit
  --work DIR       scenes and results folder (default target/bench-peers, smoke: .../smoke)
  --json-out FILE  where to write the report as JSON (default WORK/report.json)
  -h, --help       this text
environment: SHADELAB_BIN (default target/release/shadelab), SHADELAB_PEERS_DIR,
             BENCH_PEERS_TIMEOUT (seconds per job; default 900, smoke 120)
EOF
}

die() { echo "bench-peers: error: $*" >&2; exit 1; }
warn() { echo "bench-peers: warning: $*" >&2; }
note() { echo "bench-peers: $*" >&2; }

export PYTHONDONTWRITEBYTECODE=1 # no __pycache__ in ci/peers/
repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
src=$repo/ci/peers
bin=${SHADELAB_BIN:-$repo/target/release/shadelab}
peers_dir=${SHADELAB_PEERS_DIR:-$HOME/.cache/shadelab-peers}

smoke=0 all=0 list=0 setup_only=0 runs='' rounds='' size='' only='' work='' json_out=''
value() { if [ $# -lt 2 ] || [ -z "$2" ]; then die "$1 needs a value (try --help)"; fi; }
while [ $# -gt 0 ]; do
    case $1 in
        --smoke) smoke=1 ;;
        --all) all=1 ;;
        --list) list=1 ;;
        --setup) setup_only=1 ;;
        --runs) value "$@"; runs=$2; shift ;;
        --runs=*) runs=${1#*=} ;;
        --rounds) value "$@"; rounds=$2; shift ;;
        --rounds=*) rounds=${1#*=} ;;
        --size) value "$@"; size=$2; shift ;;
        --size=*) size=${1#*=} ;;
        --only) value "$@"; only=$2; shift ;;
        --only=*) only=${1#*=} ;;
        --work) value "$@"; work=$2; shift ;;
        --work=*) work=${1#*=} ;;
        --json-out) value "$@"; json_out=$2; shift ;;
        --json-out=*) json_out=${1#*=} ;;
        -h | --help) usage; exit 0 ;;
        *) die "unknown argument '$1' (try --help)" ;;
    esac
    shift
done

if [ "$smoke" = 1 ]; then
    runs=${runs:-1} size=${size:-64} segs=(6 12) timeout_s=${BENCH_PEERS_TIMEOUT:-120}
    work=${work:-$repo/target/bench-peers/smoke}
else
    runs=${runs:-5} size=${size:-1024} segs=(100 316) timeout_s=${BENCH_PEERS_TIMEOUT:-900}
    work=${work:-$repo/target/bench-peers}
fi
if ! [[ $runs =~ ^[0-9]{1,4}$ ]] || [ "$runs" -lt 1 ] || [ "$runs" -gt 1000 ]; then die "--runs $runs: expected 1 to 1000"; fi
rounds=${rounds:-1}
if ! [[ $rounds =~ ^[0-9]{1,2}$ ]] || [ "$rounds" -lt 1 ] || [ "$rounds" -gt 20 ]; then die "--rounds $rounds: expected 1 to 20"; fi
if ! [[ $size =~ ^[0-9]{1,4}$ ]] || [ "$size" -lt 1 ] || [ "$size" -gt 8192 ]; then die "--size $size: expected 1 to 8192"; fi
[[ $timeout_s =~ ^[0-9]+$ ]] || die "BENCH_PEERS_TIMEOUT=$timeout_s: expected seconds"
if [ -n "$only" ]; then
    # An invalid regex makes [[ =~ ]] return 2: catch it here, not per job.
    rc=0; [[ x =~ $only ]] || rc=$?
    [ "$rc" -le 1 ] || die "--only '$only' is not a valid regular expression"
fi
command -v python3 >/dev/null || die "python3 is needed (for the scenes and the report)"
mkdir -p "$work"
work=$(cd "$work" && pwd)
json_out=${json_out:-$work/report.json}
case $json_out in /*) ;; *) json_out=$PWD/$json_out ;; esac
scenes=$work/scenes
res=$work/results
venv_py=$peers_dir/venv/bin/python
embree_exe=$peers_dir/bin/embree_caster

# --- the jobs -------------------------------------------------------------------------------
# job NAME KIND -- COMMAND...: KIND is shadelab, embree or python (a peer in the venv).
# define_jobs runs in three modes: list (print names), plan (collect what to install), run.
bench_cpu=0  # whether `shadelab bench` has --cpu (times the CPU twin itself)
bench_uber=0 # whether it has --every-feature (the uber-shader build)
bench_query=0 # whether it has --traversal (the ray-query engine) and the device runs it
bench_tti=0  # whether it has --time-to-image (the whole render command, cold and warm)
twin_scenes=()
for f in "$repo"/assets/*.toml; do twin_scenes+=("$f"); done
twin_scenes+=(default "$repo/target/bench/mesh.toml")

# Scanned meshes, whole command against the CPU twin's: the Stanford bunny (69k triangles) and
# the ogre (124k), from alecjacobson/common-3d-test-models, made into scenes by
# ci/make-scan-scene.py.
scans=(bunny ogre)
declare -A scan_obj=([bunny]=stanford-bunny.obj [ogre]=ogre.obj)
scan_url=https://raw.githubusercontent.com/alecjacobson/common-3d-test-models/master/data

define_jobs() {
    local seg s name scene sarg cpu=() uber=() spec=()
    [ "$bench_cpu" = 1 ] && cpu=(--cpu)
    # What specialising the tracer saves, where bench can say (--every-feature).
    [ "$bench_uber" = 1 ] && uber=(--every-feature)
    local size_args=(--runs "$runs" --width "$size" --height "$size" --json)
    job info shadelab -- "$bin" info --json
    for seg in "${segs[@]}"; do
        s=$scenes/sphere-$seg
        job "rays-sphere$seg.shadelab" shadelab -- \
            "$bin" bench "$s.toml" --shading raytrace --depth 0 "${cpu[@]}" "${size_args[@]}"
        [ "$bench_query" = 0 ] || job "rays-sphere$seg.shadelab-query" shadelab -- \
            "$bin" bench "$s.toml" --shading raytrace --depth 0 --traversal query "${size_args[@]}"
        [ "$bench_cpu" = 1 ] || job "rays-sphere$seg.cpu" shadelab -- \
            python3 "$src/cpu_twin.py" "$bin" "$runs" "$size" 0 "$s.toml"
        job "rays-sphere$seg.embree" embree -- "$embree_exe" "$seg" "$size" "$size" "$runs"
        job "rays-sphere$seg.mitsuba-llvm" python -- \
            "$venv_py" "$src/mitsuba_peer.py" llvm_ad_rgb "$s.ply" "$size" "$runs"
        [ "$all" = 0 ] || job "rays-sphere$seg.mitsuba-scalar" python -- \
            "$venv_py" "$src/mitsuba_peer.py" scalar_rgb "$s.ply" "$size" "$runs"
    done
    if [ "$bench_tti" = 1 ]; then
        # The whole `render` command, fresh processes, warm and with empty caches, against
        # the CPU twin's command: the default scene at its own size (the smoke run's size in
        # --smoke), and the 40k sphere (the first SEG) at --size.
        local own_size=()
        [ "$smoke" = 1 ] && own_size=(--width "$size" --height "$size")
        job image-default.shadelab shadelab -- \
            "$bin" bench --shading phong,raytrace --time-to-image --runs "$runs" "${own_size[@]}" --json
        job "image-sphere${segs[0]}.shadelab" shadelab -- \
            "$bin" bench "$scenes/sphere-${segs[0]}.toml" --shading raytrace --depth 0 --time-to-image \
            "${size_args[@]}"
        # The peers' first image in a fresh process, cold and warm (first_image.py): Mitsuba
        # on the same sphere, the wgpu tracer on the four spheres.
        job "image-sphere${segs[0]}.mitsuba-llvm" python -- "$venv_py" "$src/first_image.py" "$runs" \
            "$src/mitsuba_peer.py" llvm_ad_rgb "$scenes/sphere-${segs[0]}.ply" "$size" 1
        # The scanned meshes (issue 58), not in --smoke (they are downloaded on first use).
        if [ "$smoke" = 0 ]; then
            for scan in "${scans[@]}"; do
                job "image-scan-$scan.shadelab" shadelab -- \
                    "$bin" bench "$repo/target/bench/scan-$scan.toml" --shading raytrace --time-to-image \
                    "${size_args[@]}"
            done
        fi
        job image-four-spheres.shadelab shadelab -- \
            "$bin" bench "$src/four-spheres.toml" --shading raytrace --time-to-image "${size_args[@]}"
        job image-four-spheres.wgpu python -- "$venv_py" "$src/first_image.py" "$runs" \
            "$src/wgpu_rt_peer.py" "$size" 1
    fi
    job rt-four-spheres.shadelab shadelab -- \
        "$bin" bench "$src/four-spheres.toml" --shading raytrace "${uber[@]}" "${size_args[@]}"
    [ "$bench_query" = 0 ] || job rt-four-spheres.shadelab-query shadelab -- \
        "$bin" bench "$src/four-spheres.toml" --shading raytrace --traversal query "${size_args[@]}"
    job rt-four-spheres.wgpu python -- "$venv_py" "$src/wgpu_rt_peer.py" "$size" "$runs"
    for scene in "${twin_scenes[@]}"; do
        if [ "$scene" = default ]; then
            name=default sarg=()
        else
            name=$(basename "$scene" .toml) sarg=("$scene")
            if [ "$scene" = "$repo/target/bench/mesh.toml" ]; then name=bench-mesh; fi
        fi
        spec=()
        [ "$name" = default ] && spec=("${uber[@]}")
        job "twin-$name.shadelab" shadelab -- \
            "$bin" bench "${sarg[@]}" --shading raytrace "${cpu[@]}" "${spec[@]}" "${size_args[@]}"
        [ "$bench_cpu" = 1 ] || job "twin-$name.cpu" shadelab -- \
            python3 "$src/cpu_twin.py" "$bin" "$runs" "$size" - "${sarg[@]}"
    done
    for seg in "${segs[@]}"; do
        job "raster-sphere$seg.shadelab" shadelab -- \
            "$bin" bench "$scenes/sphere-$seg.toml" --shading flat,gouraud,phong "${size_args[@]}"
        job "raster-sphere$seg.wgpu" python -- "$venv_py" "$src/wgpu_raster_peer.py" "$seg" "$size" "$runs"
        # Four samples per pixel on both sides (issue 34).
        job "raster-sphere$seg-msaa4.shadelab" shadelab -- \
            "$bin" bench "$scenes/sphere-$seg.toml" --shading flat,gouraud,phong --msaa 4 "${size_args[@]}"
        job "raster-sphere$seg-msaa4.wgpu" python -- "$venv_py" "$src/wgpu_raster_peer.py" "$seg" "$size" "$runs" 4
    done
}

mode=list queue=() need_python=0 need_embree=0 have_python=1 have_embree=1 failed=() njobs=0
job() {
    local name=$1 kind=$2
    shift 3
    # `info` (the driver's name for the report's header) runs whatever --only says.
    if [ -n "$only" ] && [ "$name" != info ] && ! [[ $name =~ $only ]]; then return 0; fi
    if [ "$smoke" = 1 ] && [ "$kind" != shadelab ]; then return 0; fi
    case $mode in
        list) echo "$name"; return 0 ;;
        plan)
            [ "$name" = info ] || njobs=$((njobs + 1))
            [ "$kind" = python ] && need_python=1
            [ "$kind" = embree ] && need_embree=1
            return 0 ;;
        queue)
            queue+=("$(printf '%q ' "$name" "$kind" "$@")")
            return 0 ;;
    esac
}

# run_job NAME KIND COMMAND...: runs one job into $round_res.
run_job() {
    local name=$1 kind=$2
    shift 2
    local out=$round_res/$name.json log=$round_res/$name.log started rc=0
    if { [ "$kind" = python ] && [ "$have_python" = 0 ]; } || { [ "$kind" = embree ] && [ "$have_embree" = 0 ]; }; then
        printf '%s\t%s\tunavailable\t-\t0\n' "$name" "$kind" >>"$round_res/jobs.tsv"
        failed+=("$name$round_note")
        return 0
    fi
    note "running $name${round_note}"
    started=$(date +%s)
    timeout --kill-after=10 "$timeout_s" "$@" >"$out" 2>"$log" </dev/null || rc=$?
    local status=ok
    if [ "$rc" -ne 0 ]; then
        status=failed
        [ "$rc" -eq 124 ] && status=timeout
        failed+=("$name$round_note")
        warn "$name: $status (exit $rc): $(grep -v '^[[:space:]]*$' "$log" | tail -n 1 || true)"
    fi
    printf '%s\t%s\t%s\t%s\t%s\n' "$name" "$kind" "$status" "$rc" "$(($(date +%s) - started))" >>"$round_res/jobs.tsv"
}

# --- shadelab -------------------------------------------------------------------------------
if [ -x "$bin" ]; then
    bench_help=$("$bin" bench --help 2>&1) || die "$bin bench --help failed: $(tail -n 1 <<<"$bench_help")"
    if [[ $bench_help == *--cpu* ]]; then bench_cpu=1; fi
    if [[ $bench_help == *--every-feature* ]]; then bench_uber=1; fi
    if [[ $bench_help == *--time-to-image* ]]; then bench_tti=1; fi
    if [[ $bench_help == *--traversal* ]] &&
        "$bin" info --json 2>/dev/null | grep -q '"no_ray_query_because":null'; then bench_query=1; fi
elif [ "$setup_only" = 0 ] && [ "$list" = 0 ]; then
    die "no shadelab binary at $bin (build it: cargo build --release)"
fi
if [ "$list" = 1 ]; then
    define_jobs
    if [ "$smoke" = 0 ] && { [ -z "$only" ] || [[ estimators-box =~ $only ]]; }; then echo estimators-box; fi
    exit 0
fi

# --- peers, installed outside the repository ------------------------------------------------
apt_install() {
    local sudo=()
    [ "$(id -u)" -eq 0 ] || sudo=(sudo)
    note "apt-get install $*"
    if ! "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null 2>&1; then
        "${sudo[@]}" apt-get update -qq >/dev/null 2>&1 || true
        "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null
    fi
}

install_python() {
    local venv=$peers_dir/venv stamp=$peers_dir/venv/shadelab-requirements.txt
    # Mitsuba's LLVM variant dies on point lights with LLVM 15 ("Cannot select: fminimum");
    # Debian 12 has libllvm19, which mitsuba_box.py finds (the newest libLLVM).
    if ! ls /usr/lib/*/libLLVM.so.19* /usr/lib/*/libLLVM-19.so* >/dev/null 2>&1 && command -v apt-get >/dev/null; then
        apt_install libllvm19 || warn "apt-get install libllvm19 failed: Mitsuba's path and ptracer may not run"
    fi
    if [ -x "$venv_py" ] && cmp -s "$src/requirements.txt" "$stamp"; then return 0; fi
    note "installing the Python peers into $venv (numpy, wgpu, mitsuba; pinned in ci/peers/requirements.txt)"
    [ -x "$venv_py" ] || python3 -m venv "$venv" ||
        { warn "python3 -m venv failed (on Debian: apt-get install python3-venv)"; return 1; }
    "$venv_py" -m pip install -q --disable-pip-version-check -r "$src/requirements.txt" ||
        { warn "pip install into $venv failed"; return 1; }
    cp "$src/requirements.txt" "$stamp"
}

install_embree() {
    local missing=()
    command -v g++ >/dev/null || missing+=(g++)
    [ -f /usr/include/embree3/rtcore.h ] || missing+=(libembree-dev)
    if [ ${#missing[@]} -gt 0 ]; then
        command -v apt-get >/dev/null || { warn "no apt-get to install ${missing[*]}"; return 1; }
        apt_install "${missing[@]}" || { warn "apt-get install ${missing[*]} failed"; return 1; }
    fi
    if [ ! -x "$embree_exe" ] || [ "$src/embree_caster.cpp" -nt "$embree_exe" ]; then
        note "compiling $embree_exe"
        mkdir -p "$peers_dir/bin"
        g++ -O3 -march=native -std=c++17 -o "$embree_exe.tmp" "$src/embree_caster.cpp" -lembree3 -lpthread ||
            { rm -f "$embree_exe.tmp"; warn "compiling the Embree caster failed"; return 1; }
        mv "$embree_exe.tmp" "$embree_exe"
    fi
}

mode=plan
define_jobs
estimators_only=0
if [ "$smoke" = 0 ] && [ -n "$only" ] && [[ estimators-box =~ $only ]]; then
    need_python=1
    [ "$njobs" -gt 0 ] || estimators_only=1
fi
[ "$njobs" -gt 0 ] || [ "$estimators_only" = 1 ] || die "--only '$only' selects no job (see --list)"
if [ "$setup_only" = 1 ]; then need_python=1 need_embree=1; fi
if [ "$smoke" = 0 ]; then
    mkdir -p "$peers_dir"
    if [ "$need_python" = 1 ]; then install_python || { have_python=0; warn "the wgpu and Mitsuba peers are unavailable"; }; fi
    if [ "$need_embree" = 1 ]; then install_embree || { have_embree=0; warn "the Embree peer is unavailable"; }; fi
fi
if [ "$setup_only" = 1 ]; then
    if [ "$have_python" = 0 ] || [ "$have_embree" = 0 ]; then die "the peers' setup failed"; fi
    note "peers ready in $peers_dir"
    exit 0
fi

# --- scenes ---------------------------------------------------------------------------------
mkdir -p "$scenes"
for seg in "${segs[@]}"; do
    if [ ! -f "$scenes/sphere-$seg.ply" ] || [ "$src/sphere_scene.py" -nt "$scenes/sphere-$seg.ply" ]; then
        python3 "$src/sphere_scene.py" "$seg" "$scenes" || die "writing the sphere scene (SEG $seg) failed"
    fi
done
mesh=$repo/target/bench/mesh.toml
if [ ! -f "$mesh" ] || [ "$repo/ci/make-bench-mesh.py" -nt "$mesh" ]; then
    python3 "$repo/ci/make-bench-mesh.py" >&2 || die "ci/make-bench-mesh.py failed"
fi

for scan in "${scans[@]}"; do
    scene_file=$repo/target/bench/scan-$scan.toml
    obj=$peers_dir/scans/${scan_obj[$scan]}
    if [ "$smoke" = 1 ] || { [ -f "$scene_file" ] && [ "$scene_file" -nt "$repo/ci/make-scan-scene.py" ]; }; then
        continue
    fi
    if [ -n "$only" ] && ! [[ "image-scan-$scan.shadelab" =~ $only ]]; then continue; fi
    mkdir -p "$peers_dir/scans"
    if [ ! -s "$obj" ]; then
        curl -fsSL --retry 2 -o "$obj.part" "$scan_url/${scan_obj[$scan]}" && mv "$obj.part" "$obj" ||
            { warn "could not download ${scan_obj[$scan]}: the $scan rows will be missing"; continue; }
    fi
    python3 "$repo/ci/make-scan-scene.py" "$scan" "$obj" >&2 || warn "ci/make-scan-scene.py $scan failed"
done

# --- run ------------------------------------------------------------------------------------
# Run a copy of the binary, so that a rebuild during the run cannot mix two versions.
tmp=$(mktemp -d "${TMPDIR:-/tmp}/bench-peers.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
bin_built=$(date -r "$bin" '+%Y-%m-%d %H:%M:%S %z')
bin_path=$bin
cp "$bin" "$tmp/shadelab"
bin=$tmp/shadelab
if [ "$estimators_only" = 0 ]; then
    rm -rf "$res"
    mkdir -p "$res"
    note "$njobs jobs at ${size}x$size, $runs timed runs each, $rounds round(s); results in $res"
    mode=queue
    define_jobs
    # One round: every job once, into results/ (or results/round-R with --rounds). Each row's two
    # sides are next to each other in the order; even rounds run it backwards, so that neither
    # side of a row always runs first.
    round_dirs=()
    for ((round = 1; round <= rounds; round++)); do
        round_res=$res round_note=''
        if [ "$rounds" -gt 1 ]; then round_res=$res/round-$round round_note=" (round $round of $rounds)"; fi
        mkdir -p "$round_res"
        round_dirs+=("$round_res")
        printf 'name\tkind\tstatus\trc\tseconds\n' >"$round_res/jobs.tsv"
        for ((k = 0; k < ${#queue[@]}; k++)); do
            entry=${queue[k]}
            if ((round % 2 == 0)); then entry=${queue[${#queue[@]} - 1 - k]}; fi
            eval "run_job $entry"
        done
    done

    # --- report ---------------------------------------------------------------------------------
    report_args=(--size "$size" --runs "$runs" --segs "$(IFS=,; echo "${segs[*]}")" --shadelab "$bin_path ($bin_built)"
        --json-out "$json_out" --md-out "$work/report.md")
    [ "$smoke" = 1 ] && report_args+=(--smoke)
    [ "$bench_cpu" = 1 ] && report_args+=(--bench-cpu)
    python3 "$src/report.py" "${round_dirs[@]}" "${report_args[@]}" || die "the report could not be built from $res"
    note "report: $work/report.md, $json_out"
fi
# The two estimators of secondary illumination against Mitsuba 3's (issue 45): the diffuse
# box with `path` and `ptracer`, agreement and time to the same RMSE, a table of its own
# (ci/peers/estimators_vs_mitsuba.py); selected as the job `estimators-box`.
if [ "$smoke" = 0 ] && [ "$have_python" = 1 ] && { [ -z "$only" ] || [[ estimators-box =~ $only ]]; }; then
    note "running estimators-box (shadelab's backward and forward against Mitsuba's path and ptracer)"
    if "$venv_py" "$src/estimators_vs_mitsuba.py" "$bin" "$work/estimators" >"$work/estimators.md" 2>"$work/estimators.log"; then
        cat "$work/estimators.md"
        note "estimators: $work/estimators.md, $work/estimators/estimators.json"
    else
        failed+=(estimators-box)
        warn "estimators-box failed: $(tail -n 1 "$work/estimators.log")"
    fi
fi
if [ ${#failed[@]} -gt 0 ]; then
    die "${#failed[@]} job run(s) failed or unavailable: ${failed[*]} (logs in $res)"
fi
