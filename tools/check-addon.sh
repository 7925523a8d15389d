#!/usr/bin/env bash
# Checks that the add-on installs and renders in the Blender on this machine,
# the way a user would use it.
#
#   tools/check-addon.sh --zip dist/phos-X.zip   install the zip with Blender's own
#                                                add-on installer into throw-away user
#                                                folders, then render
#   tools/check-addon.sh --installed             use the add-on `make install` put in
#                                                the user's add-on folder, then render
#
# The render is `blender -b --addons phos FILE.blend -E PHOS -f 1` on a tiny
# .blend made here; the check fails on a Python traceback, a missing output,
# or a library that does not load or reports another version.
set -euo pipefail
cd "$(dirname "$0")/.."
BLENDER=${BLENDER:-blender}
mode=${1:-}
work=$(mktemp -d /tmp/phos-check.XXXXXX)
trap 'rm -rf "$work"' EXIT
version=$(python3 tools/version.py)

case "$mode" in
  --zip)
    zip=$(realpath "${2:?usage: check-addon.sh --zip FILE.zip}")
    export BLENDER_USER_SCRIPTS="$work/scripts" BLENDER_USER_CONFIG="$work/config"
    install_py="bpy.ops.preferences.addon_install(filepath='$zip')"
    ;;
  --installed)
    install_py="None"
    ;;
  *)
    sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
    ;;
esac

# 1. Install (zip mode), enable, load the library, save a tiny scene.
cat > "$work/setup.py" <<PY
import bpy, addon_utils, ctypes, os, sys
$install_py
addon_utils.enable("phos", default_set=True, handle_error=None)
mod = sys.modules["phos"]
lib = os.path.join(os.path.dirname(mod.__file__), "lib", "libphos.so")
v = ctypes.CDLL(lib).phos_version()
got = "%d.%d.%d" % (v >> 16, (v >> 8) & 255, v & 255)
assert got == "$version", "libphos reports %s, expected $version" % got
core = sys.modules.get("phos.core")
err = core.load_error() if hasattr(core, "load_error") else ""
assert not err, "the add-on reports: " + err
assert "PHOS" in {c.bl_idname for c in bpy.types.RenderEngine.__subclasses__()}, "engine PHOS not registered"
scene = bpy.context.scene
scene.render.engine = "PHOS"
scene.render.resolution_x, scene.render.resolution_y = 32, 24
scene.render.resolution_percentage = 100
bpy.ops.wm.save_as_mainfile(filepath="$work/tiny.blend")
print("PHOS_CHECK add-on from", os.path.dirname(mod.__file__), "library", got)
PY
"$BLENDER" -b --factory-startup --python-exit-code 1 --python "$work/setup.py" >"$work/setup.log" 2>&1 \
  || { cat "$work/setup.log" >&2; echo "check-addon: install/enable failed" >&2; exit 1; }
grep '^PHOS_CHECK' "$work/setup.log" | sed 's/^PHOS_CHECK/check-addon:/'

# 2. Render it the documented way.
"$BLENDER" -b --addons phos "$work/tiny.blend" -E PHOS -o "$work/out_####" -F PNG -f 1 \
  >"$work/render.log" 2>&1 || { cat "$work/render.log" >&2; echo "check-addon: render failed" >&2; exit 1; }
if grep -qE 'Traceback|Error:|not available' "$work/render.log" || [[ ! -s "$work/out_0001.png" ]]; then
  cat "$work/render.log" >&2
  echo "check-addon: the render did not complete cleanly" >&2
  exit 1
fi
echo "check-addon: blender -b --addons phos FILE.blend -E PHOS -f 1 rendered $work/out_0001.png"
