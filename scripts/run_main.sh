#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the most complete
# flow aerograsp has. Until the simulated mission lands: the platform report
# of both shipped configurations, then a simulated hover in front of the
# crawling object recorded as an RGB-D sequence, perception replayed on it
# against the ground truth, and the camera-to-arm calibration of the left arm.
# Results go to OUT_DIR (default build/main_job).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
BUILD_DIR=${BUILD_DIR:-build}
"$BUILD_DIR/app/aerograsp" robot data/config/platform_4dof.yaml
"$BUILD_DIR/app/aerograsp" robot data/config/platform_6dof.yaml
OUT_DIR=${OUT_DIR:-$BUILD_DIR/main_job}
"$BUILD_DIR/app/aerograsp" record --out "$OUT_DIR/sequence" --frames 90 --seed 1 --motion crawl --overwrite
"$BUILD_DIR/app/aerograsp" replay "$OUT_DIR/sequence" --out "$OUT_DIR/replay"
"$BUILD_DIR/app/aerograsp" calibrate --arm left --out "$OUT_DIR/calibration"
