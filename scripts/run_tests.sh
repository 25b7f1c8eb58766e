#!/usr/bin/env bash
# The test command: installs what is missing, builds, checks the formatting, runs every test
# with CTest, then a short fixed-seed fuzz campaign of every parser (scripts/run_fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
bash scripts/check_format.sh
BUILD_DIR=${BUILD_DIR:-build}
ctest --test-dir "$BUILD_DIR" --output-on-failure -j "${JOBS:-$(nproc)}"
bash scripts/run_fuzz.sh
