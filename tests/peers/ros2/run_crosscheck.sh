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
# Up to three exchanges: on an idle machine about one exchange in ten loses every sample of a
# few topics in transit (best-effort and reliable alike), on one running two other jobs two in a
# row did; a wrong encoding fails every exchange.
for attempt in 1 2 3; do
  if exchange; then exit 0; fi
  echo "run_crosscheck: exchange $attempt failed"
done
exit 1
