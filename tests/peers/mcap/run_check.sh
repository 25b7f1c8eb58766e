#!/usr/bin/env bash
# MCAP check: aerograsp's MCAP files opened by an independent reader
# (@mcap/core, CRCs validated) and decoded by @foxglove/rosmsg2-serialization.
# Usage: run_check.sh TOOL [AEROGRASP]   (TOOL: the built mcap_check_tool; AEROGRASP:
#        the built command, whose short simulated mission's MCAP is checked too)
#        run_check.sh --file FILE.mcap   (any MCAP aerograsp wrote, e.g. the main job's)
# Installs the pinned npm packages (package-lock.json) when node_modules is missing.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
if [ ! -d "$here/node_modules/@mcap/core" ] || [ ! -d "$here/node_modules/@foxglove/rosmsg2-serialization" ]; then
  (cd "$here" && npm ci --no-audit --no-fund --loglevel=error)
fi
if [ "${1:-}" = "--file" ]; then
  exec node "$here/check_mcap.js" check "$2"
fi
tool="$1"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
for compression in none lz4 zstd; do
  mkdir -p "$work/$compression"
  "$tool" write "$work/$compression" "$compression"
  node "$here/check_mcap.js" check "$work/$compression/telemetry.mcap" "$work/$compression/expected.json"
done
"$tool" full-disk "$work"
node "$here/check_mcap.js" partial "$work/full.mcap"
if [ -n "${2:-}" ]; then
  "$2" mission --seed 1 --object u_shape --timeout 14 --out "$work/mission" > "$work/mission.txt" || true
  grep -q "Wrote $work/mission/mission.mcap" "$work/mission.txt" || { cat "$work/mission.txt"; exit 1; }
  node "$here/check_mcap.js" check "$work/mission/mission.mcap"
fi
