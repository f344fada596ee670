#!/usr/bin/env bash
# Proves a change left every output alone: builds the CLI of two revisions
# (default: HEAD~1 and the working tree), runs both over the same work (a
# transport, every method, batches with labels in exr, png and npy, lamps, a
# map's sun, a captured light set, shards, cameras, envmap and info --json)
# and cmp's every file they wrote. Exit 0 when all are byte-identical.
#
#   scripts/check-identical-outputs.sh [BEFORE [AFTER]]
#     BEFORE, AFTER: git revisions; AFTER "worktree" (the default) is the
#     checkout as it stands, uncommitted edits included.
#   ACPCA_BEFORE_CLI=PATH / ACPCA_AFTER_CLI=PATH use CLIs already built.
#   ACPCA_KEEP_OUTPUTS=1 keeps the scratch directory.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
before_rev=${1:-HEAD~1}
after_rev=${2:-worktree}
scratch=$(mktemp -d "${TMPDIR:-/tmp}/acpca-identical.XXXXXX")
cleanup() {
  for tree in "$scratch"/src-*; do
    [[ -d $tree ]] && git -C "$root" worktree remove --force "$tree" >/dev/null 2>&1 || true
  done
  if [[ ${ACPCA_KEEP_OUTPUTS:-0} == 1 ]]; then echo "outputs kept in $scratch"; else rm -rf "$scratch"; fi
}
trap cleanup EXIT

# The CLI of one revision, built in a build directory of its own; ccache
# (scripts/compiler-cache.sh) makes a second build of the same sources cheap.
build_cli() {
  local rev=$1 name=$2 src
  if [[ $rev == worktree ]]; then
    src=$root
  else
    src=$scratch/src-$name
    git -C "$root" worktree add --detach --quiet "$src" "$rev"
  fi
  (
    cd "$src"
    source scripts/compiler-cache.sh
    # Inside the tree, as build/ is: the compiler cache sees the same
    # relative paths and reuses what any earlier build of these sources made.
    cmake -S . -B build-identical -DCMAKE_BUILD_TYPE=Release "${compiler_cache_flags[@]}" >/dev/null
    cmake --build build-identical -j "$(nproc)" --target adaptive-cpca >/dev/null
  )
  echo "$src/build-identical/tools/adaptive-cpca"
}

before_cli=${ACPCA_BEFORE_CLI:-}
after_cli=${ACPCA_AFTER_CLI:-}
[[ -n $before_cli ]] || before_cli=$(build_cli "$before_rev" before)
[[ -n $after_cli ]] || after_cli=$(build_cli "$after_rev" after)

# One run of the whole work with one CLI, into OUT. Every command is
# deterministic: the same inputs give the same bytes whatever the thread count.
run_all() {
  local cli=$1 out=$2
  mkdir -p "$out"
  cd "$out"
  local q=(--quiet --threads 2)
  "$cli" precompute "${q[@]}" --scene plant --size 48x40 --cubemap 8 --out plant.h5
  "$cli" precompute "${q[@]}" --scene plant --size 32x24 --cubemap 8 --bounces 1 \
    --indirect-samples 8 --out bounced.h5
  local m
  for m in global block cpca adaptive-quad adaptive-binary; do
    "$cli" compress "${q[@]}" plant.h5 --method "$m" --tolerance 0.99 --out "model-$m.h5"
    "$cli" relight "${q[@]}" "model-$m.h5" --env sky --out "$m.exr"
  done
  "$cli" compress "${q[@]}" plant.h5 --method adaptive-binary --coeffs i8 --bases f16 \
    --allocate-ranks --out model-i8.h5
  "$cli" relight "${q[@]}" model-i8.h5 --env sky --max-rank 50% --out i8-half-rank.png
  "$cli" relight "${q[@]}" model-i8.h5 --env sky --max-rank 2 --format npy --out i8-rank2.npy
  # Dense ground truth, a map's sun lit exactly and on the lattice, tone curves.
  "$cli" relight "${q[@]}" plant.h5 --env "sun:40,30,0.53,40000" --env constant:0.2 \
    --out dense --format exr,png16,npy --tone aces --exposure -1
  "$cli" relight "${q[@]}" plant.h5 --env "sun:40,30,0.53,40000" --sun off --out sun-off.exr
  "$cli" relight "${q[@]}" bounced.h5 --env sky --out bounced.png
  # A batch: rotations, every label, three formats, COLMAP and shards.
  "$cli" relight "${q[@]}" model-adaptive-binary.h5 --env sky --env constant:0.5,0.4,0.3 \
    --rotate 0:90:45 --aov all --format exr,png,npy --label-format both --lighting-exr \
    --colmap --out batch
  "$cli" relight "${q[@]}" model-adaptive-quad.h5 --env sky --env-sample 5 --seed 7 \
    --exposure-jitter 1 --sample-rotation sphere --shard-size 2 --format png16 --out shards
  # Lamps of every kind, exact and on the lattice, moving along a path.
  "$cli" relight "${q[@]}" model-cpca.h5 --env constant:0.05 \
    --light "point:0,2,1,8" --light "sphere:0.5,1.5,1,0.3,5" --light "spot:0,2,0,0,-1,0,30,10" \
    --lamp-rays 16 --out lamps.exr
  "$cli" relight "${q[@]}" plant.h5 --env constant:0.05 --light "point:0,2,1,8" \
    --light-mode lattice --out lamps-lattice.exr
  printf 'point:0,2,1,8\npoint:1,2,0,8;sphere:0,1.5,1,0.2,4\n' >path.txt
  "$cli" relight "${q[@]}" model-block.h5 --light-path path.txt --env constant:0.1 \
    --format png --out lamp-path
  # A captured light set: eight one-light images relit from the transport.
  local k theta phi
  mkdir -p olat
  printf 'image,x,y,z\n' >olat/lights.csv
  for k in 0 1 2 3 4 5 6 7; do
    theta=$((20 + 8 * k)) phi=$((45 * k))
    "$cli" relight "${q[@]}" plant.h5 --env "sun:$theta,$phi,1,2000" --sun off \
      --background black --format png16 --out "olat/olat_$k.png"
    awk -v t="$theta" -v p="$phi" -v n="olat_$k.png" 'BEGIN {
      r = 3.14159265358979 / 180
      printf "%s,%.9f,%.9f,%.9f\n", n, sin(t*r)*sin(p*r), cos(t*r), -sin(t*r)*cos(p*r) }' \
      >>olat/lights.csv
  done
  "$cli" import "${q[@]}" olat/lights.csv --out captured.h5
  "$cli" relight "${q[@]}" captured.h5 --env sky --rotate 0:180:90 --out captured
  "$cli" compress "${q[@]}" captured.h5 --method cpca --clusters 2 --out captured-model.h5
  "$cli" relight "${q[@]}" captured-model.h5 --env sky --format png --out captured-model.png
  # What the lattice sees of a map, and what info says of every file.
  "$cli" envmap --quiet sky --cubemap 8 --rotate 30 --cross cross.exr --json envmap.json --out envmap.exr
  local f
  for f in *.h5; do "$cli" info "$f" --json "info-${f%.h5}.json" >/dev/null; done
  cd - >/dev/null
}

run_all "$before_cli" "$scratch/before"
run_all "$after_cli" "$scratch/after"

# Every file of each side compared, and none on one side only. Files naming
# the run's own directory (manifests, reports) have it replaced first.
differ=0
compared=0
while IFS= read -r rel; do
  a=$scratch/before/$rel b=$scratch/after/$rel
  if [[ ! -f $b ]]; then echo "only before: $rel"; differ=1; continue; fi
  if ! cmp -s "$a" "$b"; then
    if ! cmp -s <(sed "s#$scratch/before#RUN#g" "$a") <(sed "s#$scratch/after#RUN#g" "$b"); then
      echo "differs: $rel"
      differ=1
    fi
  fi
  compared=$((compared + 1))
done < <(cd "$scratch/before" && find . -type f | sort)
while IFS= read -r rel; do
  [[ -f $scratch/before/$rel ]] || { echo "only after: $rel"; differ=1; }
done < <(cd "$scratch/after" && find . -type f | sort)
if [[ $differ == 0 ]]; then
  echo "identical: $compared files"
else
  echo "outputs differ (before: $before_rev, after: $after_rev)" >&2
  exit 1
fi
