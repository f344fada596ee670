#!/usr/bin/env bash
# Runs one stage of CI (.ci/run) within a time budget of its own:
#   scripts/ci-stage.sh NAME SECONDS COMMAND [ARGS...]
# The stage passes only when COMMAND exits 0 before its budget runs out. A
# stage that fails, or that its budget stops unfinished, fails CI: a green CI
# means every stage ran to its end (tests/ci_stage_test.sh holds this).
set -uo pipefail
if [ $# -lt 3 ] || ! [[ "$2" =~ ^[0-9]+$ ]] || [ "$2" -lt 1 ]; then
  echo "usage: ci-stage.sh NAME SECONDS COMMAND [ARGS...] (SECONDS a whole number >= 1)" >&2
  exit 2
fi
name="$1" budget="$2"
shift 2
start=$SECONDS
echo "ci: stage '$name' starts, budget ${budget} s" >&2
# timeout signals COMMAND's whole process group: its children stop with it.
timeout --kill-after=30 "$budget" "$@"
status=$?
took=$((SECONDS - start))
if [ "$status" -eq 124 ] || [ "$status" -eq 137 ]; then
  echo "ci: stage '$name' FAILED: stopped unfinished by its budget of ${budget} s (its output is above)" >&2
  exit 124
fi
if [ "$status" -ne 0 ]; then
  echo "ci: stage '$name' FAILED with exit status $status after ${took} s" >&2
  exit "$status"
fi
echo "ci: stage '$name' passed in ${took} s of its ${budget} s" >&2
