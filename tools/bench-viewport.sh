#!/usr/bin/env bash
# The viewport's latency against Cycles' (bench/viewport.py) in Blender's
# window on a virtual X server (tools/xvfb.sh); skipped, with a message,
# where Xvfb cannot start.
#
#   tools/bench-viewport.sh BLENDER CSV
set -uo pipefail
cd "$(dirname "$0")/.."
source tools/xvfb.sh
blender=${1:?usage: tools/bench-viewport.sh BLENDER CSV}
csv=${2:?usage: tools/bench-viewport.sh BLENDER CSV}
xvfb_usable bench-viewport || exit 0
mkdir -p "$(dirname "$csv")"
log=${csv%.csv}.log
xvfb_blender "$blender" "$log" --python bench/viewport.py -- --csv "$csv"
status=$?
sed -n '/^Viewport latency/,$p' "$log"
if [[ $status -ne 0 ]]; then
  tail -n 30 "$log" >&2
  echo "bench-viewport: FAILED (exit $status; log in $log)" >&2
  exit 1
fi
