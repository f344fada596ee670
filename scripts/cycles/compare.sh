#!/usr/bin/env bash
# Compares our dense relight of a scene with Blender Cycles (direct light, or
# up to K bounces with --bounces K; the same lattice lighting, local lights,
# camera and materials: render_cycles.py), and
# Cycles with itself under another seed (its own noise). Not part of CI: needs
# Debian's `blender` (apt-get install blender) and a few minutes per scene.
#
#   bash scripts/cycles/compare.sh SCENE.json ENV OUT_DIR [options]
#     ENV: any --env of relight, or none (local lights alone)
#     --light SPEC (repeatable: point or sphere, as relight's --light)
#     --closed-form (one sphere light over a one-plane scene: Cycles and ours
#       against the closed form a L (r/D)^2 cos theta as well)
#     --size WxH (160x120)  --camera SPEC (auto:65,150 or none)
#     --samples N (Cycles samples per pixel, 1024)  --spp N (ours, 16)  --cubemap R (32)
#     --texel-rays N (ours, 1: shadow rays per lattice texel)
#     --bounces K (0: direct light)  --indirect-samples N (ours, 64: paths per traced sample)
#     --model (also the transport compressed by adaptive-quad, relit
#       the same way, against the same Cycles render)
#     --sun auto|off|K (auto: relight's --sun. A map's sources found by it are
#       split off: Cycles' world is the lattice of the map less them and each
#       is a Sun lamp of its angle and irradiance; ours lights them exactly,
#       and `--sun off` (the whole map on the lattice) is compared as
#       "lattice", with both within 2 px of the brightest source's shadow
#       edges: compare_shadow_edges.py)
#
# Writes OUT_DIR/{t.h5, ours.exr, lattice.exr, cycles.exr, cycles-2.exr,
# comparison.json; with --model m.h5 and model.exr} and prints relative L2 (all covered pixels, full pixels,
# edge pixels) and the energy ratio, ours against Cycles and Cycles against
# itself.
set -euo pipefail
cd "$(dirname "$0")/../.."
scene=$1 env=$2 out=$3
shift 3
size=160x120 camera=auto:65,150 samples=1024 spp=16 cubemap=32 texel_rays=1 bounces=0 sun=auto
indirect_samples=64
lights=() closed_form=() model=0
while [ $# -gt 0 ]; do
  case $1 in
    --light) lights+=(--light "$2") ;;
    --closed-form) closed_form=(--closed-form); shift; continue ;;
    --model) model=1; shift; continue ;;
    --size) size=$2 ;;
    --camera) camera=$2 ;;
    --samples) samples=$2 ;;
    --spp) spp=$2 ;;
    --cubemap) cubemap=$2 ;;
    --texel-rays) texel_rays=$2 ;;
    --bounces) bounces=$2 ;;
    --indirect-samples) indirect_samples=$2 ;;
    --sun) sun=$2 ;;
    *) echo "compare.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift 2
done
command -v blender >/dev/null || { echo "compare.sh: needs blender (apt-get install blender)" >&2; exit 1; }
cli=build/tools/adaptive-cpca
[ -x "$cli" ] || bash scripts/build.sh >/dev/null
mkdir -p "$out"
camera_flag=()
[ "$camera" != none ] && camera_flag=(--camera "$camera")
# Every sample traced (--aa full): Cycles integrates the whole pixel too.
"$cli" precompute --scene "$scene" --size "$size" --spp "$spp" --aa full --cubemap "$cubemap" \
  --texel-rays "$texel_rays" --bounces "$bounces" --indirect-samples "$indirect_samples" \
  --precision f32 "${camera_flag[@]}" --quiet --out "$out/t.h5"
env_flag=() lattice=none sources=() also=()
if [ "$env" != none ]; then
  env_flag=(--env "$env") lattice="$out/lattice.exr"
  # The lattice as Cycles sees it: piecewise constant per texel, 2048x1024,
  # less the map's sources, which Cycles gets as Sun lamps.
  without=()
  [ "$sun" != off ] && without=(--without-sources)
  "$cli" envmap "$env" --cubemap "$cubemap" --size 2048x1024 --sun "$sun" "${without[@]}" \
    --quiet --json "$out/sources.json" --out "$lattice"
  sources=(--sources "$out/sources.json")
fi
"$cli" relight "$out/t.h5" "${env_flag[@]}" "${lights[@]}" --sun "$sun" --background black \
  --exr-float --quiet --out "$out/ours.exr"
brightest=$(python3 -c '
import json, sys
s = json.load(open(sys.argv[1])).get("sources", [])
if s:
    r = s[0]["radiance"]
    lum = 0.2126 * r[0] + 0.7152 * r[1] + 0.0722 * r[2]
    print("sun:%r,%r,%r,%r" % (s[0]["theta_deg"], s[0]["phi_deg"], 2 * s[0]["radius_deg"], lum))
' "$out/sources.json" 2>/dev/null || true)
if [ -n "$brightest" ]; then
  # The whole map on the lattice, and the brightest source alone (its
  # shadow edges).
  "$cli" relight "$out/t.h5" "${env_flag[@]}" "${lights[@]}" --sun off --background black \
    --exr-float --quiet --out "$out/lattice-sun.exr"
  "$cli" relight "$out/t.h5" --env "$brightest" --background black --exr-float --quiet \
    --out "$out/sun-alone.exr"
  also+=(--also "lattice=$out/lattice-sun.exr")
fi
if [ "$model" = 1 ]; then
  "$cli" compress "$out/t.h5" --method adaptive-quad --quiet --out "$out/m.h5"
  "$cli" relight "$out/m.h5" "${env_flag[@]}" "${lights[@]}" --sun "$sun" --background black --exr-float \
    --quiet --out "$out/model.exr"
  also+=(--also "model=$out/model.exr")
fi
cam=$("$cli" info "$out/t.h5" --json - | python3 -c '
import json, sys
c = json.load(sys.stdin)["camera"]
print(",".join(repr(float(v)) for v in c["eye"] + c["target"] + c["up"] + [c["fov"]]))')
width=${size%x*} height=${size#*x}
render() {  # seed, output, image to compare with, json
  rm -f "$2" "$4"
  blender -b --factory-startup --python-exit-code 1 --python scripts/cycles/render_cycles.py -- \
    --scene "$scene" --width "$width" --height "$height" --camera "$cam" \
    --env "$lattice" "${sources[@]}" "${lights[@]}" "${closed_form[@]}" --samples "$samples" --seed "$1" \
    --bounces "$bounces" --out "$2" --ours "$3" "${@:5}" \
    --json "$4" >"$out/blender-$1.log" 2>&1 || { tail -30 "$out/blender-$1.log" >&2; exit 1; }
}
render 1 "$out/cycles.exr" "$out/ours.exr" "$out/ours-vs-cycles.json" "${also[@]}"
render 2 "$out/cycles-2.exr" "$out/cycles.exr" "$out/cycles-noise.json"
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
ours = json.load(open(f"{out}/ours-vs-cycles.json"))
noise = json.load(open(f"{out}/cycles-noise.json"))
json.dump({"ours_vs_cycles": ours, "cycles_seed_1_vs_2": noise},
          open(f"{out}/comparison.json", "w"), indent=2)
rows = [("ours vs Cycles", ours)] + [(f"ours ({k}) vs Cycles", r)
                                     for k, r in ours.get("also", {}).items()]
for name, r in rows + [("Cycles vs Cycles (noise)", noise)]:
    print(f"{name:26s} relative L2 {100 * r['relative_l2']:.2f}% "
          f"(full pixels {100 * r['relative_l2_full_pixels']:.2f}%, "
          f"{r['edge_pixels']} edge pixels {100 * r['relative_l2_edge_pixels']:.2f}%), "
          f"energy ratio {r['energy_ratio']:.4f}")
PY
# Edges as our labels draw them as well: a covered pixel is interior when it
# is full in Cycles and its 3x3 neighbourhood's first hits are all one object
# (a silhouette against a floor is full yet an edge).
PYTHONPATH=build/python /usr/bin/python3 - "$out" <<'PY'
import json, sys
import numpy as np
import adaptive_cpca as ac
out = sys.argv[1]
objects = ac.Relighter(f"{out}/t.h5").labels("object")["object"]
cycles = ac.read_image(f"{out}/cycles.exr")
interior = cycles[..., 3] > 0.999
padded = np.pad(objects, 1, mode="edge")
h, w = objects.shape
for dy in range(3):
    for dx in range(3):
        interior &= padded[dy:dy + h, dx:dx + w] == objects
edges = (cycles[..., 3] > 0) & ~interior
norm = (cycles[..., :3] ** 2).sum(-1)
report = json.load(open(f"{out}/comparison.json"))
for name in ("ours", "model", "lattice-sun"):
    try:
        image = ac.read_image(f"{out}/{name}.exr")
    except ac.Error:
        continue
    err = ((image[..., :3] - cycles[..., :3]) ** 2).sum(-1)
    rel = lambda m: float(np.sqrt(err[m].sum() / norm[m].sum()))
    report[f"{name}_by_object_edges"] = {"interior_pixels": int(interior.sum()),
                                         "relative_l2_interior": rel(interior),
                                         "edge_pixels": int(edges.sum()),
                                         "relative_l2_edges": rel(edges)}
    print(f"{name + ' vs Cycles':26s} {100 * rel(interior):.2f}% over {interior.sum()} interior "
          f"pixels, {100 * rel(edges):.2f}% over {edges.sum()} edge pixels (object edges too)")
json.dump(report, open(f"{out}/comparison.json", "w"), indent=2)
PY
python3 - "$out" <<'PY'
import json, sys
out = sys.argv[1]
ours = json.load(open(f"{out}/ours-vs-cycles.json"))
for name in ("cycles_vs_closed_form", "ours_vs_closed_form"):
    if name in ours:
        r = ours[name]
        print(f"{name.replace('_', ' '):26s} relative L2 {100 * r['relative_l2']:.2f}% over "
              f"{r['pixels']} full pixels, energy ratio {r['energy_ratio']:.4f}")
PY
if [ -n "$brightest" ]; then
  PYTHONPATH=build/python /usr/bin/python3 scripts/cycles/compare_shadow_edges.py "$out"
fi
