#!/usr/bin/env bash
# The GUI tests (tests/gui/test_*.py; their harness tests/gui/guitest.py and
# the screen reader tests/gui/xscreen.py are not tests):
# Blender's window on a virtual X server (tools/xvfb.sh); the viewport in
# Rendered shading with Phos, and previews. Skipped, with a message saying
# why, where Xvfb cannot start.
#
#   tools/test-gui.sh BLENDER RESULT_DIR
set -uo pipefail
cd "$(dirname "$0")/.."
source tools/xvfb.sh
blender=${1:?usage: tools/test-gui.sh BLENDER RESULT_DIR}
results=${2:?usage: tools/test-gui.sh BLENDER RESULT_DIR}
xvfb_usable test-gui || exit 0
mkdir -p "$results"
failed=0
for script in tests/gui/test_*.py; do
  name=$(basename "$script" .py)
  result=$results/$name.json
  log=$results/$name.log
  rm -f "$result"
  xvfb_blender "$blender" "$log" --python "$script" -- "$result"
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
