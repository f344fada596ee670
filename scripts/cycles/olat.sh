#!/usr/bin/env bash
# Captured transport against Cycles (docs/results.md, "Captured transport"):
# Cycles renders a one-light-at-a-time set of the textured Collada duck on a
# floor (N distant lamps of equal irradiance on a light stage's dome, direct
# light), `import` turns it into a transport, and we relight it under Debian
# world HDRIs. Cycles then renders the same scene lit by N distant lamps, lamp
# k at light k's direction with the irradiance Phi_k that the HDRI's integral
# over cell k gives (`Relighter.lighting(env).values`): the lighting is the
# same, so only the transport can differ. Cycles under the whole HDRI gives
# the discretization a stage of N lights pays. Each Cycles render is repeated
# with another seed for its noise. Not part of CI: needs Debian's `blender`
# and about 40 minutes at the defaults on 2 cores.
#
#   bash scripts/cycles/olat.sh OUT_DIR [--lights "156 331"] [--size WxH (200x150)]
#     [--olat-samples N (128)] [--samples N (Cycles under lamps or HDRI, 2048)]
#     [--hdris "forest city"] (names in Blender's studio lights, or paths)
#     [--resume] (keep the Cycles renders a run left in OUT_DIR; redo the rest)
#
# Writes OUT_DIR/nN/{olat/, olat-2/ (the set under a second seed), olat.h5,
# olat-2.h5, model.h5, HDRI/{lamps.json, ours.exr, ours-2.exr, model.exr,
# cycles.exr, cycles-2.exr}}, OUT_DIR/HDRI-full{,-2}.exr and
# OUT_DIR/comparison.json (scripts/cycles/compare_olat.py), and prints the
# table.
set -euo pipefail
cd "$(dirname "$0")/../.."
out=$1
shift
lights="156 331" size=200x150 olat_samples=128 samples=2048 hdris="forest city" resume=0
while [ $# -gt 0 ]; do
  case $1 in
    --resume) resume=1; shift; continue ;;
    --lights) lights=$2 ;;
    --size) size=$2 ;;
    --olat-samples) olat_samples=$2 ;;
    --samples) samples=$2 ;;
    --hdris) hdris=$2 ;;
    *) echo "olat.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
command -v blender >/dev/null || { echo "olat.sh: needs blender (apt-get install blender)" >&2; exit 1; }
cli=$PWD/build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
scene=data/scenes/cycles/duck-diffuse.json
width=${size%x*} height=${size#*x}
studio=/usr/share/blender/datafiles/studiolights/world
mkdir -p "$out"
cycles() {  # OUTPUT LOG, then render_olat.py's mode and options
  local output=$1 log=$2
  shift 2
  if [ "$resume" = 1 ] && [ -f "$output" ]; then return; fi
  blender -b --factory-startup --python-exit-code 1 --python scripts/cycles/render_olat.py -- \
    --scene "$scene" --width "$width" --height "$height" "$@" >"$log" 2>&1 ||
    { tail -30 "$log" >&2; exit 1; }
}
hdri_path() { case $1 in */*) echo "$1" ;; *) echo "$studio/$1.exr" ;; esac; }
for n in $lights; do
  dir=$out/n$n
  mkdir -p "$dir/olat" "$dir/olat-2"
  # A light stage's dome: a golden spiral from the zenith to 30 degrees below
  # the horizon, each sun of irradiance pi (a white surface facing it shows 1).
  /usr/bin/python3 - "$dir" "$n" <<'PY'
import math, sys
out, n = sys.argv[1], int(sys.argv[2])
lines = []
with open(f"{out}/directions.csv", "w") as dirs:
    for i in range(n):
        y = 1 - 1.5 * (i + 0.5) / n
        r = math.sqrt(1 - y * y)
        a = math.pi * (3 - math.sqrt(5)) * i
        x, z = r * math.cos(a), r * math.sin(a)
        dirs.write(f"{x!r},{y!r},{z!r}\n")
        lines.append(f"olat_{i:03d}.exr,{x!r},{y!r},{z!r},{math.pi!r},{math.pi!r},{math.pi!r}\n")
for folder in ("olat", "olat-2"):
    with open(f"{out}/{folder}/lights.csv", "w") as csv:
        csv.write("image,x,y,z,r,g,b\n" + "".join(lines))
PY
  # The set twice, with two seeds: the second measures the set's own noise.
  for seed in 1 2; do
    set_dir=$dir/olat$([ $seed = 1 ] || echo -2)
    echo "== $n lights: Cycles renders the set (seed $seed)"
    SECONDS=0
    last=$set_dir/olat_$(printf %03d $((n - 1))).exr
    cycles "$last" "$set_dir/render.log" --olat "$dir/directions.csv" --out-dir "$set_dir" \
      --irradiance 3.141592653589793 --samples "$olat_samples" --seed $seed
    echo "   $SECONDS s"
    # Alpha is coverage whatever the light: the first image is the mask.
    "$cli" import "$set_dir/lights.csv" --mask "$dir/olat/olat_000.exr" --precision f32 \
      --out "$set_dir.h5" --quiet
  done
  "$cli" compress "$dir/olat.h5" --method adaptive-binary --out "$dir/model.h5" --quiet
  for hdri in $hdris; do
    map=$(hdri_path "$hdri")
    name=$(basename "$map" .exr)
    mkdir -p "$dir/$name"
    PYTHONPATH=build/python /usr/bin/python3 - "$dir/olat.h5" "$map" "$dir/$name/lamps.json" <<'PY'
import json, sys
import h5py
import adaptive_cpca as ac
transport, env, out = sys.argv[1:]
values = ac.Relighter(transport).lighting(ac.Environment(env)).values
with h5py.File(transport) as f:
    directions = f["light_direction"][:]
json.dump({"lamps": [{"direction": list(map(float, d)), "irradiance": list(map(float, v))}
                     for d, v in zip(directions, values)]}, open(out, "w"))
PY
    for input in olat:ours olat-2:ours-2 model:model; do
      "$cli" relight "$dir/${input%%:*}.h5" --env "$map" --background black --exr-float --quiet \
        --out "$dir/$name/${input##*:}.exr"
    done
    echo "== $n lights, $name: Cycles under the $n lamps"
    for seed in 1 2; do
      render=$dir/$name/cycles$([ $seed = 1 ] || echo -2).exr
      cycles "$render" "$dir/$name/cycles-$seed.log" --lamps "$dir/$name/lamps.json" \
        --samples "$samples" --seed $seed --out "$render"
    done
  done
done
for hdri in $hdris; do
  map=$(hdri_path "$hdri")
  name=$(basename "$map" .exr)
  echo "== $name: Cycles under the whole map"
  for seed in 1 2; do
    render=$out/$name-full$([ $seed = 1 ] || echo -2).exr
    cycles "$render" "$out/$name-full-$seed.log" --hdri "$map" --samples "$samples" \
      --seed $seed --out "$render"
  done
done
names=$(for hdri in $hdris; do basename "$(hdri_path "$hdri")" .exr; done)
PYTHONPATH=build/python /usr/bin/python3 scripts/cycles/compare_olat.py "$out" "$lights" "$names"
