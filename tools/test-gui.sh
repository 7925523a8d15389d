#!/usr/bin/env bash
# The GUI tests (tests/gui/*.py, their harness tests/gui/guitest.py):
# Blender's window on a virtual X server (Xvfb) drawn by Mesa's software
# OpenGL; the viewport in Rendered shading with Phos, and previews. Skipped,
# with a message saying why, where Xvfb cannot start (no xvfb-run, or the
# X server fails).
#
#   tools/test-gui.sh BLENDER RESULT_DIR
set -uo pipefail
cd "$(dirname "$0")/.."
blender=${1:?usage: tools/test-gui.sh BLENDER RESULT_DIR}
results=${2:?usage: tools/test-gui.sh BLENDER RESULT_DIR}
if ! command -v xvfb-run >/dev/null; then
  echo "test-gui: SKIPPED: xvfb-run is not installed (tools/install-deps.sh --gui)"
  exit 0
fi
if ! xvfb-run -a -s "-screen 0 320x200x24" true >/dev/null 2>&1; then
  echo "test-gui: SKIPPED: the virtual X server (Xvfb) does not start here"
  exit 0
fi
mkdir -p "$results"
failed=0
for script in tests/gui/*.py; do
  name=$(basename "$script" .py)
  [[ $name == guitest ]] && continue
  result=$results/$name.json
  log=$results/$name.log
  rm -f "$result"
  timeout 300 xvfb-run -a -s "-screen 0 1280x800x24" "$blender" --factory-startup \
    --python "$script" -- "$result" >"$log" 2>&1
  status=$?
  grep '^GUI ' "$log"
  if [[ $status -ne 0 || ! -s "$result" ]]; then
    tail -n 40 "$log" >&2
    echo "test-gui: $name FAILED (exit $status; log in $log)" >&2
    failed=1
  fi
done
[[ $failed -eq 0 ]] || exit 1
echo "test-gui: passed"
