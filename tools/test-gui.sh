#!/usr/bin/env bash
# The GUI test (tests/gui/viewport.py): Blender's window on a virtual X
# server (Xvfb) drawn by Mesa's software OpenGL, a 3D view switched to
# Rendered shading with Phos. Skipped, with a message saying why, where
# Xvfb cannot start (no xvfb-run, or the X server fails).
#
#   tools/test-gui.sh BLENDER RESULT.json
set -uo pipefail
cd "$(dirname "$0")/.."
blender=${1:?usage: tools/test-gui.sh BLENDER RESULT.json}
result=${2:?usage: tools/test-gui.sh BLENDER RESULT.json}
if ! command -v xvfb-run >/dev/null; then
  echo "test-gui: SKIPPED: xvfb-run is not installed (tools/install-deps.sh --gui)"
  exit 0
fi
if ! xvfb-run -a -s "-screen 0 320x200x24" true >/dev/null 2>&1; then
  echo "test-gui: SKIPPED: the virtual X server (Xvfb) does not start here"
  exit 0
fi
mkdir -p "$(dirname "$result")"
rm -f "$result"
log=${result%.json}.log
# The test ends Blender itself (os._exit); the bound only catches a hang.
timeout 300 xvfb-run -a -s "-screen 0 1280x800x24" "$blender" --factory-startup \
  --python tests/gui/viewport.py -- "$result" >"$log" 2>&1
status=$?
grep '^GUI ' "$log"
if [[ $status -ne 0 || ! -s "$result" ]]; then
  tail -n 40 "$log" >&2
  echo "test-gui: FAILED (exit $status; log in $log)" >&2
  exit 1
fi
echo "test-gui: passed"
