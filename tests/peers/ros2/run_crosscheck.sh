#!/usr/bin/env bash
# aerograsp's ROS 2 topics against independent implementations, on loopback only:
# ros2_publish_tool publishes a fixed script through aerograsp's bridge (Cyclone DDS), the
# Fast DDS peer (ros2_peer, dynamic types) records every message with its bytes, and
# crosscheck.js decodes the bytes with Foxglove's ROS 2 decoder and the ROS 2 definitions.
# Usage: run_crosscheck.sh PUBLISH_TOOL PEER DDS_CONFIG DOMAIN
# Installs the pinned npm packages (package-lock.json) when node_modules is missing.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
tool="$1" peer="$2" dds_config="$3" domain="$4"
if [ ! -d "$here/node_modules/@foxglove/rosmsg2-serialization" ]; then
  (cd "$here" && npm ci --no-audit --no-fund --loglevel=error)
fi
work="$(mktemp -d)"
peer_pid=""
cleanup() { [ -n "$peer_pid" ] && kill "$peer_pid" 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
exchange() {
  rm -f "$work/ready" "$work/received.jsonl" "$work/expected.json"
  "$peer" listen "$domain" aerograsp "$work/received.jsonl" --timeout-s 60 --ready-file "$work/ready" &
  peer_pid=$!
  "$tool" "$domain" aerograsp "$dds_config" "$work/expected.json" "$work/ready"
  wait "$peer_pid"
  peer_pid=""
  node "$here/crosscheck.js" "$work/received.jsonl" "$work/expected.json"
}
# A second exchange when the first fails: about one exchange in ten loses every sample of a
# few topics in transit (best-effort and reliable alike), while a wrong encoding fails both.
exchange || { echo "run_crosscheck: the first exchange failed; a second one decides"; exchange; }
