#!/usr/bin/env bash
# Kills precompute, compress, build and batch relight with SIGKILL (no
# handler runs) at random points, POINTS times in all (default 20), and checks
# what the kill leaves: every output that exists is whole (the same as a clean
# run's: bytes for transports, pixels for frames, clusters and cost for
# models, whose files hold their timing), the inputs are byte for byte what
# they were, and the next run clears the dead run's hidden partial files.
# Prints one line per kill and a summary; exits 1 on any violation.
# Usage: bash scripts/kill-at-random.sh [POINTS] [SEED]
set -euo pipefail
cd "$(dirname "$0")/.."
points="${1:-20}"
RANDOM="${2:-7}"
[ -x build/tools/adaptive-cpca ] || bash scripts/build.sh >/dev/null
cli="$(pwd)/build/tools/adaptive-cpca"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

scene=(--scene plant --size 128x128 --cubemap 16 --spp 1)
declare -A command
command[precompute]="$cli precompute ${scene[*]} --quiet --out OUT.h5"
command[compress]="$cli compress $work/in/t.h5 --method adaptive-binary --quiet --out OUT.h5"
command[build]="$cli build ${scene[*]} --sample-rows 2000 --block 32 --tiles-in-flight 1 --quiet --out OUT.h5"
command[relight]="$cli relight $work/in/t.h5 --env sky --rotate 0:360:15 --quiet --out OUT"
names=(precompute compress build relight)

mkdir in ref
"$cli" precompute "${scene[@]}" --quiet --out in/t.h5
sha256sum in/* >inputs.sha256
declare -A seconds
for name in "${names[@]}"; do
  start=$(date +%s.%N)
  (cd ref && eval "${command[$name]//OUT/$name}")
  seconds[$name]=$(echo "$(date +%s.%N) - $start" | bc)
done

same_output() {  # NAME OUTPUT: is it what the clean run wrote?
  local name=$1 out=$2
  case $name in
    precompute) cmp -s "$out" "ref/$name.h5" ;;
    compress | build)
      [ "$("$cli" info "$out" --json - | python3 -c "import json,sys; d=json.load(sys.stdin); print([d[k] for k in ('clusters','cost_per_pixel','global_bases','transport_error')])")" = \
        "$("$cli" info "ref/$name.h5" --json - | python3 -c "import json,sys; d=json.load(sys.stdin); print([d[k] for k in ('clusters','cost_per_pixel','global_bases','transport_error')])")" ] ;;
  esac
}

violations=0
fail() { echo "  VIOLATION: $*"; violations=$((violations + 1)); }
for ((i = 0; i < points; i++)); do
  name=${names[$((i % 4))]}
  run="run$i"
  mkdir "$run"
  # A random point within the first 70% of the clean run (later ones finish).
  delay=$(echo "scale=3; 0.7 * ${seconds[$name]} * $RANDOM / 32767" | bc)
  (cd "$run" && eval "exec ${command[$name]//OUT/$name}") &
  pid=$!
  sleep "$delay"
  kill -9 "$pid" 2>/dev/null && killed=killed || killed=finished
  wait "$pid" 2>/dev/null || true
  left=$(find "$run" -name '.*partial-*' | wc -l)
  printf '%2d %-10s at %6.3f of %6.3f s: %-8s partial files left: %d\n' \
    "$i" "$name" "$delay" "${seconds[$name]}" "$killed" "$left"
  sha256sum --quiet -c inputs.sha256 || fail "an input changed"
  if [ "$name" = relight ]; then
    for frame in ref/relight/*.exr; do
      mine="$run/relight/$(basename "$frame")"
      [ -f "$mine" ] || continue
      idiff -q -fail 0 -warn 0 "$frame" "$mine" >/dev/null 2>&1 || fail "$mine differs from a clean run's"
    done
  elif [ -e "$run/$name.h5" ]; then
    same_output "$name" "$run/$name.h5" || fail "$run/$name.h5 reads as valid but differs from a clean run's"
  fi
  # The next run clears what the dead one left (its process is gone).
  if [ "$left" -gt 0 ] && [ "$name" != build ]; then
    (cd "$run" && eval "${command[$name]//OUT/$name}") 2>/dev/null
    [ "$(find "$run" -name '.*partial-*' | wc -l)" -eq 0 ] || fail "the rerun left the dead run's partial files"
  fi
done
echo "kill-at-random: $points kills, $violations violations"
[ "$violations" -eq 0 ]
