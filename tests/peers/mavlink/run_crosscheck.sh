#!/usr/bin/env bash
# MAVLink 2 cross-check between aerograsp's codec and node-mavlink, both ways.
# Usage: run_crosscheck.sh TOOL   (TOOL: the built mavlink_crosscheck_tool)
# Installs the pinned npm packages (package-lock.json) when node_modules is missing.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
tool="$1"
if [ ! -d "$here/node_modules/node-mavlink" ]; then
  (cd "$here" && npm ci --no-audit --no-fund --loglevel=error)
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$tool" write "$work/ours.json"
node "$here/crosscheck.js" check "$work/ours.json"
node "$here/crosscheck.js" write "$work/theirs.json"
"$tool" read "$work/theirs.json"
