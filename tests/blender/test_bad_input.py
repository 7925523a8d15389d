# SPDX-License-Identifier: GPL-3.0-or-later
"""Bad input never crashes Blender: each case runs a separate `blender -b`.

A scene is built by a script and saved, then rendered the way a render farm
does: `blender -b --addons phos FILE -E PHOS -o OUT -F OPEN_EXR -f 1` (EXR
on purpose: Blender 3.4.1 segfaults on EXR output when an engine delivers no
result). Expected outcomes:
- fatal input: an `Error:` line that says what and where, exit code 1, no
  signal;
- recoverable input: a `Warning:` line, exit code 0, the image written;
- harmless oddities: exit code 0, the image written, finite pixels.
"""

import os
import re
import shutil
import subprocess

import numpy as np
import pytest

import phostest as pt

BUILD_PRELUDE = r'''
import math, sys, bpy, phostest as pt
sc = pt.reset_file()
assert pt.addon_enabled(), "add-on not enabled"
pt.add_camera(sc, location=(0, -5, 2), target=(0, 0, 0.5))
pt.set_world(sc, (0.2, 0.2, 0.2))
pt.add_plane(sc, "Floor", size=6, material=pt.diffuse("Floor", (0.8, 0.8, 0.8)))
pt.add_light(sc, "POINT", 200.0, location=(1, -1, 3))
pt.configure_output(sc, 24, 16)
pt.configure_phos(sc, 4, max_bounces=4)
sc.render.engine = "PHOS"
'''

BUILD_SAVE = r'''
bpy.ops.wm.save_as_mainfile(filepath=sys.argv[sys.argv.index("--") + 1])
print("SAVED")
'''


def build_and_render(tmp_path, scene_code, env=None):
    blend = os.path.join(str(tmp_path), "case.blend")
    rc, out = pt.run_script(BUILD_PRELUDE + scene_code + BUILD_SAVE, tmp_path, args=[blend])
    assert rc == 0 and "SAVED" in out, "building the scene failed:\n" + out[-3000:]
    out_base = os.path.join(str(tmp_path), "frame_")
    rc, out = pt.render_blend_cli(blend, tmp_path, out_base, env=env)
    image = out_base + "0001.exr"
    return rc, out, image


def assert_no_crash(rc, out):
    assert rc >= 0, "Blender died of %s:\n%s" % (pt.signal_name(rc), out[-3000:])
    assert rc in (0, 1), "unexpected exit code %d:\n%s" % (rc, out[-3000:])
    assert "Segmentation fault" not in out and "Writing: /tmp/" not in out, out[-3000:]


def error_lines(out):
    return [line for line in out.splitlines() if line.startswith("Error:")]


def warning_lines(out):
    return [line for line in out.splitlines() if line.startswith("Warning:")]


def assert_rendered(rc, out, image):
    assert rc == 0, out[-3000:]
    assert not error_lines(out), error_lines(out)
    assert os.path.isfile(image), "no image written:\n" + out[-3000:]
    px = pt.load_image_array(image)
    assert np.all(np.isfinite(px)), "non-finite pixels"
    return px


# ------------------------------------------------------------ fatal input

def test_no_camera_is_a_clear_error(tmp_path):
    rc, out, image = build_and_render(tmp_path, r'''
cam = sc.camera
sc.camera = None
bpy.data.objects.remove(cam)
''')
    assert_no_crash(rc, out)
    errors = error_lines(out)
    # Blender refuses a frame without a camera before the engine runs
    # ("No camera found in scene"); Phos says the same if it gets there.
    assert rc == 1 and errors and any("camera" in e.lower() for e in errors), out[-3000:]
    assert "Traceback" not in out, out[-3000:]


def _fake_library(tmp_path, major, minor):
    """A libphos.so that exports only phos_version(), returning major.minor.0."""
    gcc = shutil.which("gcc") or shutil.which("cc")
    if gcc is None:
        pytest.skip("no C compiler to build the fake library")
    src = os.path.join(str(tmp_path), "fake.c")
    lib = os.path.join(str(tmp_path), "fake", "libphos.so")
    os.makedirs(os.path.dirname(lib))
    with open(src, "w") as f:
        f.write("unsigned int phos_version(void) { return (%du << 16) | (%du << 8); }\n" % (major, minor))
    subprocess.run([gcc, "-shared", "-fPIC", "-o", lib, src], check=True)
    return lib


def test_library_of_another_version_is_a_clear_error(tmp_path):
    from phos import core
    major, minor = core.EXPECTED_VERSION
    lib = _fake_library(tmp_path, major, minor + 1)
    rc, out, image = build_and_render(tmp_path, "", env={"PHOS_LIBRARY": lib})
    assert_no_crash(rc, out)
    errors = error_lines(out)
    assert rc == 1 and errors, out[-3000:]
    wanted = ("library version %d.%d.0" % (major, minor + 1), "needs %d.%d.x" % (major, minor))
    assert any(all(w in e for w in wanted) for e in errors), (
        "the error should name both versions %s: %s" % (wanted, errors))


def test_missing_library_is_a_clear_error(tmp_path):
    missing = os.path.join(str(tmp_path), "nowhere", "libphos.so")
    rc, out, image = build_and_render(tmp_path, "", env={"PHOS_LIBRARY": missing})
    assert_no_crash(rc, out)
    errors = error_lines(out)
    assert rc == 1 and errors, out[-3000:]
    assert any(missing in e for e in errors), "the error should name the library path: %s" % errors


MISSING_LIBRARY_RESULT = r'''
import os, numpy as np
os.environ  # PHOS_LIBRARY is set by the test
try:
    bpy.ops.render.render()
    print("NO ERROR")
except RuntimeError as ex:
    print("RENDER ERROR:", ex)
out = sys.argv[sys.argv.index("--") + 1]
bpy.data.images["Render Result"].save_render(out, scene=sc)
px = pt.load_image_array(out)
print("RESULT", px.shape, float(np.abs(px).max()))
'''


def test_missing_library_delivers_a_result(tmp_path):
    """The placeholder result is delivered (a full-size, empty image), in-script render."""
    out_exr = os.path.join(str(tmp_path), "placeholder.exr")
    rc, out = pt.run_script(BUILD_PRELUDE + MISSING_LIBRARY_RESULT, tmp_path, args=[out_exr],
                            env={"PHOS_LIBRARY": os.path.join(str(tmp_path), "missing.so")})
    assert_no_crash(rc, out)
    assert "RENDER ERROR:" in out and "missing.so" in out, out[-3000:]
    assert "RESULT (16, 24, 4) 0.0" in out, out[-3000:]


def test_absurd_camera_clipping(tmp_path):
    code = r'''
cam = sc.camera.data
cam.clip_start, cam.clip_end = 50.0, 1.0   # start beyond end
'''
    rc, out, image = build_and_render(tmp_path, code)
    assert_no_crash(rc, out)
    if rc == 1:
        assert error_lines(out), out[-3000:]
        assert "Traceback" not in out
    else:
        assert os.path.isfile(image)


# ------------------------------------------------------- recoverable input

def test_missing_image_file_warns_and_renders(tmp_path):
    code = r'''
img = bpy.data.images.new("Ghost", 4, 4)
img.source = "FILE"
img.filepath = "/nonexistent/ghost.png"
mat = bpy.data.materials.new("Ghost Material")
pt.use_nodes(mat)
nt = mat.node_tree
tex = nt.nodes.new("ShaderNodeTexImage")
tex.image = img
nt.links.new(tex.outputs["Color"], nt.nodes["Principled BSDF"].inputs["Base Color"])
pt.add_sphere(sc, "Ghost Sphere", location=(0, 0, 0.5), material=mat)
'''
    rc, out, image = build_and_render(tmp_path, code)
    assert_no_crash(rc, out)
    assert_rendered(rc, out, image)
    assert any("Ghost" in w for w in warning_lines(out)), (
        "a missing image should be a warning naming it:\n" + out[-3000:])


def test_missing_environment_image_warns_and_renders_the_colour(tmp_path):
    """An HDR world whose file is gone: one warning naming the image, and
    the world lights the scene with its Background colour, as an unlinked
    Environment Texture would."""
    code = r'''
img = bpy.data.images.new("Lost HDR", 8, 4, float_buffer=True)
img.source = "FILE"
img.filepath = "/nonexistent/lost.exr"
world = pt.set_world(sc, (0.3, 0.3, 0.3))
env = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
env.image = img
world.node_tree.links.new(env.outputs["Color"], world.node_tree.nodes["Background"].inputs["Color"])
'''
    rc, out, image = build_and_render(tmp_path, code)
    assert_no_crash(rc, out)
    assert_rendered(rc, out, image)
    ours = [w for w in warning_lines(out) if "Lost HDR" in w]
    assert len(ours) == 1, "one warning naming the missing HDR:\n" + out[-3000:]


NON_FINITE_VERTEX = r'''
import numpy as np
ob = pt.add_cube(sc, "Broken Cube", location=(0, 0, 0.5))
co = np.empty(len(ob.data.vertices) * 3, np.float32)
ob.data.vertices.foreach_get("co", co)
co[9:12] = (VALUE, 0.0, 0.0)       # vertex 3 (through foreach_set: `.co =` clamps ±inf)
ob.data.vertices.foreach_set("co", co)
ob.data.update()
pt.add_sphere(sc, "Fine", location=(1.2, 0, 0.5))
'''


@pytest.mark.parametrize("value", ["nan", "inf"])
def test_non_finite_vertex_skips_its_triangles(value, tmp_path):
    """A mesh with a NaN or Inf vertex: the triangles that use it are
    skipped (Cycles renders the rest too), one warning names the object and
    the count, and the frame renders."""
    rc, out, image = build_and_render(tmp_path, NON_FINITE_VERTEX.replace(
        "VALUE", "float(%r)" % value))
    assert_no_crash(rc, out)
    px = assert_rendered(rc, out, image)
    ours = [w for w in warning_lines(out) if "Broken Cube" in w]
    assert len(ours) == 1, "one warning naming the object:\n" + out[-3000:]
    assert re.search(r"\b[3-6] triangles with non-finite \(NaN/Inf\) vertices", ours[0]), ours[0]
    assert px[..., :3].max() > 0.0


def test_degenerate_triangles_warn_and_render(tmp_path):
    rc, out, image = build_and_render(tmp_path, r'''
me = bpy.data.meshes.new("Slivers")
me.from_pydata([(0, 0, 1), (0, 0, 1), (0, 0, 1), (1, 0, 1), (2, 0, 1), (0, 0, 2), (1, 0, 2), (0, 1, 2)],
               [], [(0, 1, 2), (0, 3, 4), (5, 6, 7)])
sc.collection.objects.link(bpy.data.objects.new("Slivers", me))
''')
    assert_no_crash(rc, out)
    assert_rendered(rc, out, image)
    ours = [w for w in warning_lines(out) if "Slivers" in w]
    assert ours == ["Warning: Phos: object 'Slivers': 2 degenerate triangles skipped"], out[-3000:]


def test_empty_scene_warns_and_renders_the_world(tmp_path):
    rc, out, image = build_and_render(tmp_path, r'''
for ob in list(sc.objects):
    if ob.type != "CAMERA":
        bpy.data.objects.remove(ob)
''')
    assert_no_crash(rc, out)
    px = assert_rendered(rc, out, image)
    assert any("no objects or lights" in w for w in warning_lines(out)), out[-3000:]
    assert np.allclose(px[..., :3], 0.2, atol=1e-4)


@pytest.mark.parametrize("integrator", ["PHOTON", "PATH"])
def test_no_light_source_warns_and_renders_black(integrator, tmp_path):
    """Objects but no light, no emission and a black world: the core renders
    black (PHOTON with empty photon maps); Phos says why."""
    rc, out, image = build_and_render(tmp_path, r'''
for ob in list(sc.objects):
    if ob.type == "LIGHT":
        bpy.data.objects.remove(ob)
pt.set_world(sc, (0.0, 0.0, 0.0))
pt.add_sphere(sc, "Ball", location=(0, 0, 0.5))
sc.phos.integrator = "%s"
''' % integrator)
    assert_no_crash(rc, out)
    px = assert_rendered(rc, out, image)
    ours = [w for w in warning_lines(out) if "no light source" in w]
    assert len(ours) == 1, out[-3000:]
    if integrator == "PHOTON":
        assert "no photons can be emitted" in ours[0] and "photon maps are empty" in ours[0], ours[0]
    assert np.all(px[..., :3] == 0.0)


def test_node_tree_with_a_cycle_warns_and_renders(tmp_path):
    """Mix Shader → Mix Shader → back: Blender marks the link that closes the
    cycle invalid; the export ignores it (as Cycles does) and names the material."""
    rc, out, image = build_and_render(tmp_path, r'''
mat = bpy.data.materials.new("Loop Material")
pt.use_nodes(mat)
nt = mat.node_tree
nt.nodes.clear()
out = nt.nodes.new("ShaderNodeOutputMaterial")
m1, m2 = nt.nodes.new("ShaderNodeMixShader"), nt.nodes.new("ShaderNodeMixShader")
d = nt.nodes.new("ShaderNodeBsdfDiffuse")
nt.links.new(m1.outputs[0], out.inputs["Surface"])
nt.links.new(m2.outputs[0], m1.inputs[1])
nt.links.new(d.outputs[0], m1.inputs[2])
nt.links.new(m1.outputs[0], m2.inputs[1])   # closes the cycle
pt.add_sphere(sc, "Looped", location=(0, 0, 0.5), material=mat)
''')
    assert_no_crash(rc, out)
    assert_rendered(rc, out, image)
    ours = [w for w in warning_lines(out) if "Loop Material" in w]
    assert ours and any("cycle" in w for w in ours), out[-3000:]


def test_unsupported_node_warns_with_its_type_and_renders(tmp_path):
    rc, out, image = build_and_render(tmp_path, r'''
mat = pt.node_material("Toon Material", "ShaderNodeBsdfToon", {"Color": (0.2, 0.6, 0.2)})
mat.node_tree.nodes["Toon BSDF"].name = "Cel Shading"
pt.add_sphere(sc, "Toon Ball", location=(0, 0, 0.5), material=mat)
''')
    assert_no_crash(rc, out)
    px = assert_rendered(rc, out, image)
    ours = [w for w in warning_lines(out) if "Toon Material" in w]
    assert len(ours) == 1, out[-3000:]
    assert "'Cel Shading' (Toon BSDF) is not supported" in ours[0] and "diffuse" in ours[0], ours[0]
    # The fallback, a diffuse of the node's colour, is lit: the ball is green.
    r, g, b = px[6:12, 9:15, :3].reshape(-1, 3).mean(axis=0)
    assert g > r and g > b, (r, g, b)


@pytest.mark.parametrize("crop", [False, True])
def test_zero_area_border(crop, tmp_path):
    """A border with min == max: Blender itself refuses the frame ("Image too
    small", for Cycles too) before the engine runs. No crash, an error."""
    rc, out, image = build_and_render(tmp_path, r'''
r = sc.render
r.use_border, r.use_crop_to_border = True, %r
r.border_min_x = r.border_max_x = 0.5
r.border_min_y = r.border_max_y = 0.5
''' % crop)
    assert_no_crash(rc, out)
    if os.path.isfile(image):  # a Blender that renders it must give finite pixels
        assert np.all(np.isfinite(pt.load_image_array(image)))
    else:
        assert error_lines(out), out[-3000:]
    assert "Traceback" not in out, out[-3000:]


# ------------------------------------------------------ harmless oddities

@pytest.mark.parametrize("case", ["degenerate_triangles", "huge_coordinates", "empty_scene",
                                  "one_pixel", "zero_filter", "negative_scale"])
def test_odd_but_valid_input_renders(case, tmp_path):
    code = {
        "degenerate_triangles": r'''
me = bpy.data.meshes.new("Degenerate")
me.from_pydata([(0, 0, 1), (0, 0, 1), (0, 0, 1), (1, 0, 1), (2, 0, 1)], [], [(0, 1, 2), (0, 3, 4)])
sc.collection.objects.link(bpy.data.objects.new("Degenerate", me))
pt.add_sphere(sc, "Fine", location=(0, 0, 0.5))
''',
        "huge_coordinates": r'''
pt.add_cube(sc, "Far", size=1e6, location=(1e12, 1e12, 1e12))
pt.add_sphere(sc, "Near", location=(0, 0, 0.5))
''',
        "empty_scene": r'''
for ob in list(sc.objects):
    if ob.type != "CAMERA":
        bpy.data.objects.remove(ob)
''',
        "one_pixel": r'''
pt.configure_output(sc, 1, 1)
''',
        "zero_filter": r'''
sc.phos.filter_width = 0.0
pt.add_sphere(sc, "Ball", location=(0, 0, 0.5))
''',
        "negative_scale": r'''
ob = pt.add_sphere(sc, "Mirrored", location=(0, 0, 0.5))
ob.scale = (-1, 1, 1)
''',
    }[case]
    rc, out, image = build_and_render(tmp_path, code)
    assert_no_crash(rc, out)
    px = assert_rendered(rc, out, image)
    if case == "empty_scene":
        # Only the world (0.2) remains: a uniform image.
        assert np.allclose(px[..., :3], 0.2, atol=1e-4)
