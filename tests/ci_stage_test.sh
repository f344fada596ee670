#!/usr/bin/env bash
# scripts/ci-stage.sh fails a stage that its budget stops, and one that fails;
# it passes one that finishes in time. Run by ctest (ci_stage_runner).
set -uo pipefail
runner="$(dirname "$0")/../scripts/ci-stage.sh"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
fail() { echo "ci_stage_test: $*" >&2; cat "$log" >&2; exit 1; }

bash "$runner" quick 20 true 2>"$log" || fail "a stage that finished in time failed"
grep -q "stage 'quick' passed" "$log" || fail "no word that the stage passed"

start=$SECONDS
bash "$runner" slow 1 bash -c 'sleep 30 & wait' 2>"$log"
status=$?
[ "$status" -ne 0 ] || fail "a stage stopped by its budget passed"
grep -q "stage 'slow' FAILED: stopped unfinished by its budget of 1 s" "$log" ||
  fail "the budget's stop was not named"
[ $((SECONDS - start)) -lt 20 ] || fail "the stopped stage's child outlived its budget"

bash "$runner" broken 20 false 2>"$log" && fail "a failing stage passed"
grep -q "stage 'broken' FAILED with exit status 1" "$log" || fail "the failure was not named"

bash "$runner" odd zero true 2>"$log" && fail "a budget that is not a number was taken"
echo "ci_stage_test: 4 checks passed"
