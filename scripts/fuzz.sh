#!/usr/bin/env bash
# Fuzzes every reader of outside input (fuzz/: transport and model files, their
# HDF5 headers edited field by field, scene JSON, environment images, model
# files through the isolated importer) with
# libFuzzer under ASan + UBSan, for SECONDS each (default 60). Files kept in
# fuzz/regressions/<target>/ (inputs that once crashed) run first. Any crash,
# leak, timeout or out-of-memory fails the run and leaves the input in
# build-fuzz/findings/. CI runs it after the sanitizer tests.
set -euo pipefail
cd "$(dirname "$0")/.."
root="$(pwd)"
seconds="${1:-60}"
# A fixed seed makes a CI run repeatable; set ACPCA_FUZZ_SEED=0 for a random one.
seed="${ACPCA_FUZZ_SEED:-1}"
bash scripts/setup.sh
[ -x build/tools/adaptive-cpca ] || bash scripts/build.sh >/dev/null
source scripts/compiler-cache.sh

targets=(fuzz_transport_file fuzz_model_file fuzz_hdf5_headers fuzz_scene_json fuzz_environment
  fuzz_mesh_file fuzz_light_spec fuzz_lights_file)
# -O1 (as libFuzzer's examples build) with line tables only: reports still
# name the file and line, and a cold build takes far less than -O2 -g.
cmake -S . -B build-fuzz -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only -DNDEBUG" \
  -DACPCA_FUZZ=ON -DACPCA_BUILD_TESTS=OFF "${compiler_cache_flags[@]}" \
  -DACPCA_WERROR="${ACPCA_WERROR:-0}" >/dev/null
cmake --build build-fuzz -j "$(nproc)" --target "${targets[@]}"

# Seeds: small valid inputs of each kind, made by the normal build.
cli=build/tools/adaptive-cpca
seeds=build-fuzz/seeds
rm -rf "$seeds"
mkdir -p "$seeds"/{fuzz_transport_file,fuzz_model_file,fuzz_hdf5_headers,fuzz_scene_json,fuzz_environment,fuzz_mesh_file,fuzz_light_spec,fuzz_lights_file}
"$cli" precompute --scene sphere --size 4x4 --cubemap 2 --quiet --out "$seeds/fuzz_transport_file/f16.h5"
"$cli" precompute --scene step --size 3x3 --cubemap 1 --precision f32 --quiet \
  --out "$seeds/fuzz_transport_file/f32.h5"
"$cli" compress "$seeds/fuzz_transport_file/f16.h5" --method global --quiet \
  --out "$seeds/fuzz_model_file/global.h5"
"$cli" compress "$seeds/fuzz_transport_file/f16.h5" --method cpca --clusters 2 --coeffs i8 \
  --quiet --out "$seeds/fuzz_model_file/cpca_i8.h5"
cp data/scenes/*.json "$seeds/fuzz_scene_json/"
printf 'point:1,2,3,4' >"$seeds/fuzz_light_spec/point"
printf 'sphere:0,3,1,0.5,10,20,30' >"$seeds/fuzz_light_spec/sphere"
printf 'spot:0,4,0,0,-1,0,30,5' >"$seeds/fuzz_light_spec/spot"
printf 'point:-1:1:0.5,2,0:3:1,4' >"$seeds/fuzz_light_spec/sweep"
printf 'image,x,y,z,r,g,b\na.png,0,1,0,1,1,1\nb.png,1,0,0,2,2,2\n' >"$seeds/fuzz_lights_file/csv"
printf '{"center": [0, 1, 0], "lights": [{"image": "a.exr", "position": [0, 5, 0], "intensity": 2}, {"image": "b.exr", "direction": [1, 0, 0], "solid_angle": 0.5}]}' \
  >"$seeds/fuzz_lights_file/json"
"$cli" envmap sky --cubemap 2 --size 8x4 --quiet --out "$seeds/sky.exr"
# The environment target's first byte picks the format: 1 is EXR.
{ printf '\001'; cat "$seeds/sky.exr"; } >"$seeds/fuzz_environment/sky"
rm "$seeds/sky.exr"
# The mesh target's first byte picks the format (fuzz_mesh_file.cpp): small
# real files of each, ours and Debian's assimp-testmodels.
mesh_seed() {  # FORMAT_BYTE FILE
  [ -f "$2" ] || return 0
  { printf "\\$(printf '%03o' "$1")"; cat "$2"; } >"$seeds/fuzz_mesh_file/$(basename "$2")"
}
models=/usr/share/assimp/models
mesh_seed 0 data/meshes/icosahedron.obj
mesh_seed 0 "$models/OBJ/box.obj"
mesh_seed 1 "$models/glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf"
mesh_seed 2 "$models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb"
mesh_seed 3 "$models/PLY/cube.ply"
mesh_seed 3 "$models/PLY/cube_binary.ply"
mesh_seed 4 "$models/OFF/Cube.off"
mesh_seed 5 "$models/Collada/cube_tristrips.dae"
mesh_seed 6 "$models/STL/triangle.stl"

# Each target writes its inputs into a file of its own: here, not /tmp, and
# removed when the run ends.
export TMPDIR
TMPDIR=$(mktemp -d "${TMPDIR:-/tmp}/acpca-fuzz-run.XXXXXX")
trap 'rm -rf "$TMPDIR"' EXIT

status=0
for t in "${targets[@]}"; do
  corpus="build-fuzz/corpus/$t" findings="build-fuzz/findings/$t"
  mkdir -p "$corpus" "$findings" "fuzz/regressions/$t"
  echo "fuzz: $t for ${seconds} s" >&2
  # OpenEXR allocates header attributes (up to 2 GiB each) before OIIO returns
  # an error: the environment target gets room for that.
  rss=2048
  [ "$t" = fuzz_environment ] && rss=4096
  if ! (cd "$findings" && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
        LSAN_OPTIONS="suppressions=$root/scripts/lsan-suppressions.txt" \
        UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
        "../../fuzz/$t" -max_total_time="$seconds" -rss_limit_mb=$rss -timeout=30 -seed="$seed" \
        -print_final_stats=1 "../../../$corpus" "../../../$seeds/$t" \
        "../../../fuzz/regressions/$t" 2>"fuzz.log"); then
    echo "fuzz: $t FAILED; input and log in $findings" >&2
    tail -40 "$findings/fuzz.log" >&2
    status=1
  else
    grep -E "stat::number_of_executed_units|cov:" "$findings/fuzz.log" | tail -2 >&2 || true
  fi
done
exit "$status"
