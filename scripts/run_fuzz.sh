#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) with clang into build-fuzz/ and runs
# each for a short campaign with a fixed seed from its committed corpus
# (tests/fuzz/corpus/NAME); fails on the first crash, sanitizer report, leak or
# input slower than FUZZ_TIMEOUT seconds. The inputs a campaign discovers go to
# a scratch folder and are thrown away; what it finds wrong is saved as
# build-fuzz/artifacts/TARGET-crash-* (or timeout-*, leak-*).
# Usage: scripts/run_fuzz.sh [TARGET...]      (default: every target)
# Environment: BUILD_DIR (the main build, default build: its libraries are
# linked), FUZZ_BUILD_DIR (default build-fuzz), FUZZ_SCALE (multiplies the
# runs, default 1), FUZZ_SEED (default 1), FUZZ_TIMEOUT (s per input, default 10),
# JOBS. docs/reliability.md describes the campaigns and how to run them longer.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR=${BUILD_DIR:-build}
FUZZ_BUILD_DIR=${FUZZ_BUILD_DIR:-build-fuzz}
SCALE=${FUZZ_SCALE:-1}
SEED=${FUZZ_SEED:-1}
TIMEOUT=${FUZZ_TIMEOUT:-10}

# Runs per campaign (at FUZZ_SCALE=1 about a minute in all on a 2-core machine).
declare -A RUNS=(
  [fuzz_mesh]=16000
  [fuzz_config]=6000
  [fuzz_sequence]=3000
  [fuzz_calibration]=10000
  [fuzz_mavlink_parser]=300000
  [fuzz_scs_parser]=600000
  [fuzz_bag]=600
)
declare -A CORPUS=(
  [fuzz_mesh]=mesh [fuzz_config]=config [fuzz_sequence]=sequence
  [fuzz_calibration]=calibration [fuzz_mavlink_parser]=mavlink [fuzz_scs_parser]=scs
  [fuzz_bag]=bag
)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_mesh fuzz_config fuzz_sequence fuzz_calibration
                                     fuzz_mavlink_parser fuzz_scs_parser fuzz_bag)

if [ ! -f "$FUZZ_BUILD_DIR/build.ninja" ]; then
  cmake -S tests/fuzz -B "$FUZZ_BUILD_DIR" -G Ninja -DCMAKE_C_COMPILER=clang \
    -DCMAKE_CXX_COMPILER=clang++ -DAEROGRASP_BUILD_DIR="$(realpath "$BUILD_DIR")"
fi
cmake --build "$FUZZ_BUILD_DIR" -j "${JOBS:-$(nproc)}" --target "${targets[@]}"

mkdir -p "$FUZZ_BUILD_DIR/artifacts"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
start=$(date +%s)
for target in "${targets[@]}"; do
  runs=$(( ${RUNS[$target]} * SCALE ))
  mkdir -p "$scratch/$target"
  t0=$(date +%s)
  if ! "$FUZZ_BUILD_DIR/$target" -seed="$SEED" -runs="$runs" -timeout="$TIMEOUT" \
      -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
      -artifact_prefix="$FUZZ_BUILD_DIR/artifacts/$target-" \
      "$scratch/$target" "tests/fuzz/corpus/${CORPUS[$target]}" > "$scratch/$target.log" 2>&1; then
    tail -n 60 "$scratch/$target.log"
    echo "run_fuzz: $target FAILED (seed $SEED, $runs runs); inputs in $FUZZ_BUILD_DIR/artifacts" >&2
    exit 1
  fi
  echo "run_fuzz: $target: $runs runs, seed $SEED, $(( $(date +%s) - t0 )) s," \
       "$(grep -o 'cov: [0-9]*' "$scratch/$target.log" | tail -n 1)"
done
echo "run_fuzz: ${#targets[@]} campaigns in $(( $(date +%s) - start )) s"
