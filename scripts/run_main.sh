#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the most complete
# flow aerograsp has. Until the simulated mission lands that is the platform
# report of both shipped configurations.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
BUILD_DIR=${BUILD_DIR:-build}
"$BUILD_DIR/app/aerograsp" robot data/config/platform_4dof.yaml
"$BUILD_DIR/app/aerograsp" robot data/config/platform_6dof.yaml
