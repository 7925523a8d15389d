#!/usr/bin/env bash
# Checks that the add-on installs and renders in the Blender on this machine,
# the way a user would use it.
#
#   tools/check-addon.sh --zip dist/phos-X.zip   install the zip with Blender's own
#                                                add-on installer into throw-away user
#                                                folders, then render
#   tools/check-addon.sh --extension FILE.zip    Blender 4.2+: install the zip as an
#                                                extension (blender --command extension
#                                                install-file -r user_default -e) into
#                                                throw-away user folders, then render
#   tools/check-addon.sh --installed             use the add-on `make install` put in
#                                                the user's add-on folder, then render
#
# The render is `blender -b [--addons phos] FILE.blend -E PHOS -f 1` on a tiny
# .blend made here (the factory cube, light and camera, 32x24); the check fails
# on a Python traceback, a missing or black output, or a library that is not
# the add-on's own lib/libphos.so, does not load or reports another version.
# PHOS_LIBRARY is ignored: the check is about the library the add-on carries.
set -euo pipefail
cd "$(dirname "$0")/.."
BLENDER=${BLENDER:-blender}
mode=${1:-}
work=$(mktemp -d /tmp/phos-check.XXXXXX)
trap 'rm -rf "$work"' EXIT
version=$(python3 tools/version.py)
unset PHOS_LIBRARY

module=phos            # the add-on's Python module name
startup=(--factory-startup)
render_addons=(--addons phos)
case "$mode" in
  --zip)
    zip=$(realpath "${2:?usage: check-addon.sh --zip FILE.zip}")
    export BLENDER_USER_SCRIPTS="$work/scripts" BLENDER_USER_CONFIG="$work/config"
    install_py="bpy.ops.preferences.addon_install(filepath='$zip')
addon_utils.enable('phos', default_set=True, handle_error=None)"
    ;;
  --extension)
    zip=$(realpath "${2:?usage: check-addon.sh --extension FILE.zip}")
    # Every user folder of Blender 4.2+ in the throw-away folder; the
    # preferences there (saved by install-file -e) enable the extension, so
    # no --factory-startup and no --addons below.
    export BLENDER_USER_RESOURCES="$work/user" BLENDER_USER_CONFIG="$work/user/config" \
           BLENDER_USER_SCRIPTS="$work/user/scripts" BLENDER_USER_EXTENSIONS="$work/user/extensions" \
           BLENDER_USER_DATAFILES="$work/user/datafiles"
    "$BLENDER" --command extension validate "$zip" >"$work/validate.log" 2>&1 \
      || { cat "$work/validate.log" >&2; echo "check-addon: blender rejects $zip as an extension" >&2; exit 1; }
    "$BLENDER" --command extension install-file -r user_default -e "$zip" >"$work/install.log" 2>&1 \
      || { cat "$work/install.log" >&2; echo "check-addon: extension install-file failed" >&2; exit 1; }
    grep -q 'Installed "phos"' "$work/install.log" \
      || { cat "$work/install.log" >&2; echo "check-addon: install-file did not install phos" >&2; exit 1; }
    module=bl_ext.user_default.phos
    startup=()
    render_addons=()
    install_py="assert '$module' in {a.module for a in bpy.context.preferences.addons}, 'the extension is not enabled'"
    ;;
  --installed)
    install_py="addon_utils.enable('phos', default_set=True, handle_error=None)"
    ;;
  *)
    sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
    ;;
esac

# 1. Install (zip mode) or check the install, enable, load the library, save a tiny scene.
cat > "$work/setup.py" <<PY
import bpy, addon_utils, ctypes, os, sys
$install_py
mod = sys.modules.get("$module")
assert mod is not None, "module $module is not loaded"
here = os.path.dirname(os.path.realpath(mod.__file__))
core = sys.modules["$module.core"]
err = core.load_error()
assert not err, "the add-on reports: " + err
lib = os.path.join(here, "lib", "libphos.so")
assert os.path.realpath(core.loaded_path()) == lib, "the add-on loaded %s, not its own %s" % (core.loaded_path(), lib)
v = ctypes.CDLL(lib).phos_version()
got = "%d.%d.%d" % (v >> 16, (v >> 8) & 255, v & 255)
assert got == "$version", "libphos reports %s, expected $version" % got
assert "PHOS" in {getattr(c, "bl_idname", None) for c in bpy.types.RenderEngine.__subclasses__()}, "engine PHOS not registered"
scene = bpy.context.scene
scene.render.engine = "PHOS"
scene.render.resolution_x, scene.render.resolution_y = 32, 24
scene.render.resolution_percentage = 100
bpy.ops.wm.save_as_mainfile(filepath="$work/tiny.blend")
print("PHOS_CHECK add-on %s from %s, library %s" % ("$module", here, got))
PY
"$BLENDER" -b "${startup[@]}" --python-exit-code 1 --python "$work/setup.py" >"$work/setup.log" 2>&1 \
  || { cat "$work/setup.log" >&2; echo "check-addon: install/enable failed" >&2; exit 1; }
grep '^PHOS_CHECK' "$work/setup.log" | sed 's/^PHOS_CHECK/check-addon:/'

# 2. Render it the documented way.
"$BLENDER" -b "${render_addons[@]}" "$work/tiny.blend" -E PHOS -o "$work/out_####" -F PNG -f 1 \
  >"$work/render.log" 2>&1 || { cat "$work/render.log" >&2; echo "check-addon: render failed" >&2; exit 1; }
if grep -qE 'Traceback|Error:|not available' "$work/render.log" || [[ ! -s "$work/out_0001.png" ]]; then
  cat "$work/render.log" >&2
  echo "check-addon: the render did not complete cleanly" >&2
  exit 1
fi

# 3. The image shows the lit cube: not black (a failed render delivers black).
"$BLENDER" -b --factory-startup --python-exit-code 1 --python-expr "
import bpy, numpy as np
img = bpy.data.images.load('$work/out_0001.png')
px = np.empty(img.size[0] * img.size[1] * img.channels, np.float32)
img.pixels.foreach_get(px)
rgb = px.reshape(-1, img.channels)[:, :3]
print('PHOS_CHECK %dx%d, mean %.3f, %.0f%% of the pixels not black'
      % (img.size[0], img.size[1], rgb.mean(), 100 * (rgb.max(axis=1) > 0.02).mean()))
assert rgb.mean() > 0.02 and (rgb.max(axis=1) > 0.02).mean() > 0.5, 'the render is black'
" >"$work/pixels.log" 2>&1 || { cat "$work/pixels.log" >&2; echo "check-addon: the rendered image is black" >&2; exit 1; }
echo "check-addon: blender -b ${render_addons[*]:+${render_addons[*]} }FILE.blend -E PHOS -f 1 rendered" \
  "$(sed -n 's/^PHOS_CHECK //p' "$work/pixels.log")"
