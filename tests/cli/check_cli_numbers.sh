#!/usr/bin/env bash
# The command line refuses NaN, infinities, out-of-range values and negative
# seeds with the option named, and exits non-zero before doing anything.
# Usage: check_cli_numbers.sh PATH/TO/aerograsp
set -uo pipefail
aerograsp=$1
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
failures=0
# expect_refused MESSAGE ARGS...: the command exits non-zero and stderr holds MESSAGE.
expect_refused() {
  local message=$1
  shift
  local err code
  err=$("$aerograsp" "$@" 2>&1 >/dev/null)
  code=$?
  if [ "$code" -eq 0 ] || [[ "$err" != *"$message"* ]]; then
    echo "FAILED: aerograsp $* exited $code, expected an error containing: $message"
    echo "  got: $err"
    failures=$((failures + 1))
  fi
}
expect_refused "--object-xyz: nan is not a finite number" plan crawler --out "$out/p" --object-xyz 0.1 nan 0.4
expect_refused "--object-rpy: inf is not a finite number" plan crawler --out "$out/p" --object-rpy 0 inf 0
expect_refused "--mass: nan is not a finite number" plan crawler --out "$out/p" --mass nan
expect_refused "--mass: -1 is not in [1e-06, 10000]" plan crawler --out "$out/p" --mass -1
expect_refused "--sway: nan is not a finite number" mission --out "$out/m" --sway nan
expect_refused "--timeout: 1e9 is not in [1, 3600]" mission --out "$out/m" --timeout 1e9
expect_refused "--seed: '-5' is not a seed" mission --out "$out/m" --seed -5
expect_refused "--seed: '-5' is not a seed" hardware-check --hardware "$(dirname "$0")/../../data/config/hardware_sim.yaml" --seed -5
expect_refused "--seed: '99999999999999999999' is not a seed" record --out "$out/r" --seed 99999999999999999999
expect_refused "--init-pose: nan is not a finite number" replay "$out" --out "$out/x" --init-pose 0 0 nan 1 0 0 0
expect_refused "--path-scale: inf is not a finite number" bench --out "$out/b" --path-scale inf
if [ -e "$out/p" ] || [ -e "$out/m" ] || [ -e "$out/r" ] || [ -e "$out/b" ]; then
  echo "FAILED: a refused command wrote its output folder"
  failures=$((failures + 1))
fi
# A mission that does not succeed exits 3 (app/exit_codes.h), not 0.
"$aerograsp" mission --out "$out/t" --timeout 1 >/dev/null 2>&1
code=$?
if [ "$code" -ne 3 ]; then
  echo "FAILED: a mission stopped by its time limit exited $code, expected 3"
  failures=$((failures + 1))
fi
[ "$failures" -eq 0 ] && echo "every bad number refused with its option named"
exit "$failures"
