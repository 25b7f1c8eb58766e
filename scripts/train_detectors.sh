#!/usr/bin/env bash
# Trains an object's detector, OBJECT_FOLDER/detector.onnx (the shipped ones in
# data/objects/NAME, an imported one in its folder: `aerograsp object show NAME`):
# renders the labelled training set with `aerograsp dataset` (C++, the
# simulator's renderer), trains with Debian's python3-torch on one thread,
# exports ONNX (opset 11), and prints the training time and the recall on the
# held-out renders (300 images of another seed).
# Fixed seeds: the same build gives the same training set; torch training is
# seeded too (single thread, deterministic algorithms).
# Usage: scripts/train_detectors.sh [--install-only] [OBJECT...]   (default: crawler u_shape pipe)
#        e.g. scripts/train_detectors.sh my_bracket   (an object brought in with `object import`)
# Environment: BUILD_DIR (default build), WORK_DIR (default /tmp/aerograsp_train),
#              COUNT (training images per object, default 3000; the pipe's 4000),
#              EPOCHS (default 15; the pipe's 100).
# The pipe's renders show it as the world has it, lying on its grey support pipe and seen from the
# vehicle's camera with the arms in view, in 90 % of the images (`dataset --on-support 0.9`): its
# colour barely differs from the support's, and trained on floating pipes only it found 0.4 % of
# the boxes of a replay. It also trains longer, learns the box size around the centre cell, and
# leaves out the images where only a sliver of it shows (fewer than 400 pixels of 640x480, or
# under 5 % of its front-facing surface seen by the depth: labels.csv coverage).
set -euo pipefail
cd "$(dirname "$0")/.."

# Training packages only here: not needed to build, test or run aerograsp.
TRAIN_PACKAGES=(python3-torch python3-onnx python3-numpy python3-opencv)
missing=()
for p in "${TRAIN_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  echo "train_detectors: installing ${missing[*]}"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
[ "${1:-}" = "--install-only" ] && exit 0

BUILD_DIR=${BUILD_DIR:-build}
WORK_DIR=${WORK_DIR:-/tmp/aerograsp_train}
COUNT=${COUNT:-}
EPOCHS=${EPOCHS:-}
OBJECTS=("$@")
[ ${#OBJECTS[@]} -eq 0 ] && OBJECTS=(crawler u_shape pipe)
for object in "${OBJECTS[@]}"; do
  # The object's folder (where every command looks for its detector); fails for an unknown name.
  folder=$("$BUILD_DIR/app/aerograsp" object show "$object" --folder)
  dataset_args=() train_args=() epochs=15 count=3000
  if [ "$object" = pipe ]; then
    dataset_args=(--on-support 0.9) train_args=(--size-radius 1 --min-pixels 400 --min-coverage 0.05)
    epochs=100 count=4000
  fi
  epochs=${EPOCHS:-$epochs}
  count=${COUNT:-$count}
  "$BUILD_DIR/app/aerograsp" dataset --object "$object" --out "$WORK_DIR/$object/train" \
    --count "$count" --seed 1000 --overwrite "${dataset_args[@]}"
  "$BUILD_DIR/app/aerograsp" dataset --object "$object" --out "$WORK_DIR/$object/val" \
    --count 300 --seed 2000 --overwrite "${dataset_args[@]}"
  # Written beside the final file and moved once complete: no half-written detector.
  log="$WORK_DIR/$object/train.log"
  start=$(date +%s)
  # /usr/bin/python3: Debian's interpreter sees python3-torch (a pyenv python3 on PATH does not).
  /usr/bin/python3 tools/train_detector.py --data "$WORK_DIR/$object" --epochs "$epochs" --seed 7 \
    "${train_args[@]}" --out "$WORK_DIR/$object/detector.onnx" | tee "$log"
  seconds=$(( $(date +%s) - start ))
  mv "$WORK_DIR/$object/detector.onnx" "$folder/detector.onnx"
  recall=$(grep -o 'val recall [0-9.]*' "$log" | tail -1 | cut -d' ' -f3)
  echo "train_detectors: $object: $count training renders, $epochs epochs in ${seconds} s;" \
    "recall ${recall:-?} on 300 held-out renders (seed 2000); wrote $folder/detector.onnx"
done
