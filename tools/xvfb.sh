# Sourced by tools/test-gui.sh and tools/bench-viewport.sh: Blender's window
# on a virtual X server (Xvfb) drawn by Mesa's software OpenGL.
#
#   xvfb_usable WHAT     0 if Xvfb can run here; else prints why WHAT is
#                        skipped and returns 1
#   xvfb_blender BLENDER LOG ARGS...
#                        Blender's GUI on a 1280 × 800 screen, output to LOG

xvfb_usable() {
  if ! command -v xvfb-run >/dev/null; then
    echo "$1: SKIPPED: xvfb-run is not installed (tools/install-deps.sh --gui)"
    return 1
  fi
  if ! xvfb-run -a -s "-screen 0 320x200x24" true >/dev/null 2>&1; then
    echo "$1: SKIPPED: the virtual X server (Xvfb) does not start here"
    return 1
  fi
}

xvfb_blender() {
  local blender=$1 log=$2
  shift 2
  # 600 s: the GUI tests give up after 120 s (tests/gui/guitest.py); a
  # Blender still running long after has locked up, and no redraw would end it.
  timeout 600 xvfb-run -a -s "-screen 0 1280x800x24" "$blender" --factory-startup "$@" >"$log" 2>&1
}
