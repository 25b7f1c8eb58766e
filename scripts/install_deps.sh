#!/usr/bin/env bash
# Installs every Debian 12 package aerograsp needs to build, test and run.
# Idempotent: packages already present are skipped; `apt-get update` runs at most once.
# Must run as root (or with sudo available) on Debian 12 (bookworm).
set -euo pipefail

PACKAGES=(
  # toolchain
  build-essential cmake ninja-build ccache pkg-config git clang-format
  # numerics, geometry, vision
  libeigen3-dev libvisp-dev libopencv-dev libpcl-dev libopenmpi-dev
  libfcl-dev libccd-dev liburdfdom-dev liburdfdom-headers-dev libapriltag-dev
  libembree-dev libqhull-dev liborocos-kdl-dev
  # ParallelFor's worker pool (oneTBB)
  libtbb-dev
  # configuration, CLI, logging, output
  libyaml-cpp-dev libcli11-dev libspdlog-dev nlohmann-json3-dev
  # devices: SHA-256 for MAVLink 2 signing
  libssl-dev
  # recordings: RealSense .bag files read with ROS 1's bag libraries (no librealsense)
  librosbag-storage-dev libsensor-msgs-dev libgeometry-msgs-dev libstd-msgs-dev
  libdiagnostic-msgs-dev
  # MCAP logs: chunk compression
  liblz4-dev libzstd-dev
  # the reports' interactive charts: Chart.js, built into the program
  libjs-chart.js
  # ROS 2 topics over DDS: Cyclone DDS and its IDL compiler; Fast DDS as the tests' independent peer
  cyclonedds-dev cyclonedds-tools libfastrtps-dev libfastcdr-dev
  # tests and benchmarks; Chromium loads the report pages headless in the tests
  libgtest-dev libgmock-dev libbenchmark-dev chromium
  # the parsers' fuzz campaigns (scripts/run_fuzz.sh): clang with libFuzzer and the sanitizers
  clang libclang-rt-14-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
# Node.js and npm run the independent peers of the tests (tests/peers/mavlink,
# tests/peers/mcap). Any
# node >= 18 will do (NodeSource's nodejs bundles npm), so Debian's packages are
# installed only when the commands are missing.
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
  missing+=(nodejs npm)
fi

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "install_deps: need root to install: ${missing[*]}" >&2; exit 1
  fi
fi

echo "install_deps: installing ${#missing[@]} packages: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install_deps: done"
