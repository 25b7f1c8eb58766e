#!/usr/bin/env bash
# The main job: installs what is missing, builds, and flies the simulated
# mission (aerograsp mission): take-off, approach, detect, grasp with both
# arms, lift, home, land, with its report (index.html, summary.json,
# mission.log, mission.mcap for Foxglove and the ROS 2 tools). Then the supporting flows: a recorded hover replayed through
# perception against the ground truth, and the left arm's camera-to-arm
# calibration. Results go to OUT_DIR (default build/main_job).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
BUILD_DIR=${BUILD_DIR:-build}
OUT_DIR=${OUT_DIR:-$BUILD_DIR/main_job}
# Seed 1 switches pairs when the first becomes unreachable; its first attempt closes on nothing;
# on the second the left gripper holds and the right aims again (docs/mission.md).
"$BUILD_DIR/app/aerograsp" mission --seed 1 --out "$OUT_DIR/mission" --overwrite
"$BUILD_DIR/app/aerograsp" record --out "$OUT_DIR/sequence" --frames 90 --seed 1 --motion crawl --overwrite
"$BUILD_DIR/app/aerograsp" replay "$OUT_DIR/sequence" --out "$OUT_DIR/replay" --filter-frame world --overwrite
"$BUILD_DIR/app/aerograsp" calibrate --arm left --out "$OUT_DIR/calibration" --overwrite
# The mission's MCAP log opened by an independent reader (@mcap/core, CRCs checked) and every
# message decoded with its ROS 2 definition; its channels, message counts and size are printed.
bash tests/peers/mcap/run_check.sh --file "$OUT_DIR/mission/mission.mcap"
echo "Mission report: $OUT_DIR/mission/index.html"
