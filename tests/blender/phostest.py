# SPDX-License-Identifier: GPL-3.0-or-later
"""Helpers shared by the Blender tests (and by the scripts they run in
subprocesses): enabling the add-on from the source tree, resetting the file,
building small scenes, configuring both engines alike and rendering into
numpy arrays.

Only bpy, mathutils, bmesh and numpy are used, so a subprocess script can do
``sys.path.insert(0, TESTS_DIR); import phostest``.
"""

import math
import os
import subprocess
import sys

import addon_utils
import bmesh
import bpy
import numpy as np
from mathutils import Vector

TESTS_DIR = os.path.dirname(os.path.abspath(__file__))
REPO_DIR = os.path.dirname(os.path.dirname(TESTS_DIR))
if os.path.join(REPO_DIR, "scenes") not in sys.path:
    sys.path.insert(0, os.path.join(REPO_DIR, "scenes"))
# What every Blender version needs done its own way (5.0's node trees,
# multilayer EXR, compositor): one copy, in scenes/_common.py.
from _common import (compositor_output, compositor_tree, denoise_in_compositor,  # noqa: E402,F401
                     geometry_node_group, set_multilayer_exr, set_single_exr, use_nodes)
ADDON_DIR = os.path.join(REPO_DIR, "addon")
# The add-on's module: "phos" from this source tree, or with PHOS_ADDON_MODULE
# the module of an installed copy, e.g. "bl_ext.user_default.phos" for the
# 4.2+ extension installed as a user installs it (run_tests.py --extension).
# Tests import it as `phos` either way (alias_addon_modules).
ADDON_NAME = os.environ.get("PHOS_ADDON_MODULE", "phos")
FROM_SOURCE_TREE = ADDON_NAME == "phos"
ENGINE = "PHOS"
# The command that starts a background Blender like this one: the binary, or
# for Blender as a Python module (the official `bpy` builds, which have no
# binary) this interpreter with tools/bpy_blender.py, which reads Blender's
# command line.
BLENDER_COMMAND = ([bpy.app.binary_path] if bpy.app.binary_path else
                   [sys.executable, os.path.join(REPO_DIR, "tools", "bpy_blender.py")])

# Rows of the parity table, filled by test_parity.py, printed by conftest.py.
PARITY_ROWS = []


# ------------------------------------------------------------------ add-on

def engine_ids():
    """bl_idname of every registered RenderEngine (unregistered classes linger in
    __subclasses__ until collected, hence the is_registered filter; 4.x lists
    classes without a bl_idname, e.g. HydraRenderEngine, hence the getattr)."""
    return {getattr(cls, "bl_idname", None) for cls in bpy.types.RenderEngine.__subclasses__()
            if getattr(cls, "is_registered", True)} - {None}


def enable_addon():
    """Enable the add-on (from <repo>/addon, or the installed ADDON_NAME);
    returns the module or None."""
    if FROM_SOURCE_TREE and ADDON_DIR not in sys.path:
        sys.path.insert(0, ADDON_DIR)
    _default, loaded = addon_utils.check(ADDON_NAME)
    if loaded and ENGINE in engine_ids():
        return alias_addon_modules(sys.modules.get(ADDON_NAME))
    return alias_addon_modules(addon_utils.enable(ADDON_NAME, default_set=True))


def alias_addon_modules(module):
    """Make `import phos` and `from phos.export import ...` reach an installed
    add-on whose module has another name (an extension's bl_ext.<repo>.phos),
    so the tests read the same whichever copy they test. Returns module."""
    if module is not None and not FROM_SOURCE_TREE:
        for name, mod in list(sys.modules.items()):
            if name == ADDON_NAME or name.startswith(ADDON_NAME + "."):
                sys.modules["phos" + name[len(ADDON_NAME):]] = mod
    return module


def addon_module_of(cls):
    """Whether a class comes from the add-on (its module is the add-on's)."""
    return cls.__module__ == ADDON_NAME or cls.__module__.startswith(ADDON_NAME + ".")


def addon_enabled():
    return addon_utils.check(ADDON_NAME)[1] and ENGINE in engine_ids()


def reset_file():
    """Factory settings with an empty scene; the add-on enabled again if it was dropped."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    enable_addon()
    return bpy.context.scene


# ---------------------------------------------------------------- building

def link(scene, ob):
    scene.collection.objects.link(ob)
    return ob


def mesh_from_bmesh(name, bm, smooth=False):
    me = bpy.data.meshes.new(name)
    bm.to_mesh(me)
    bm.free()
    if smooth:
        for p in me.polygons:
            p.use_smooth = True
    return me


def add_plane(scene, name="Plane", size=2.0, location=(0, 0, 0), rotation=(0, 0, 0), material=None):
    bm = bmesh.new()
    bmesh.ops.create_grid(bm, x_segments=1, y_segments=1, size=size / 2)
    _ensure_uv(bm)
    me = mesh_from_bmesh(name, bm)
    ob = bpy.data.objects.new(name, me)
    ob.location, ob.rotation_euler = location, rotation
    if material:
        me.materials.append(material)
    return link(scene, ob)


def add_sphere(scene, name="Sphere", radius=0.5, location=(0, 0, 0), material=None,
               segments=32, rings=16, smooth=True, uv=True):
    bm = bmesh.new()
    if uv:
        bm.loops.layers.uv.verify()  # calc_uvs only fills an existing UV layer
    bmesh.ops.create_uvsphere(bm, u_segments=segments, v_segments=rings, radius=radius,
                              calc_uvs=True)
    me = mesh_from_bmesh(name, bm, smooth=smooth)
    ob = bpy.data.objects.new(name, me)
    ob.location = location
    if material:
        me.materials.append(material)
    return link(scene, ob)


def add_cube(scene, name="Cube", size=1.0, location=(0, 0, 0), material=None):
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=size)
    me = mesh_from_bmesh(name, bm)
    ob = bpy.data.objects.new(name, me)
    ob.location = location
    if material:
        me.materials.append(material)
    return link(scene, ob)


def _ensure_uv(bm):
    uv = bm.loops.layers.uv.verify()
    for f in bm.faces:
        for loop in f.loops:
            co = loop.vert.co
            loop[uv].uv = (co.x * 0.5 + 0.5, co.y * 0.5 + 0.5)


def add_camera(scene, location=(0, -5, 2), target=(0, 0, 0.5), lens=50.0, ortho_scale=None,
               name="Camera"):
    cam = bpy.data.cameras.new(name)
    cam.lens = lens
    cam.sensor_fit = "AUTO"
    cam.sensor_width = 36.0
    if ortho_scale is not None:
        cam.type = "ORTHO"
        cam.ortho_scale = ortho_scale
    ob = bpy.data.objects.new(name, cam)
    ob.location = location
    point_at(ob, target)
    link(scene, ob)
    scene.camera = ob
    return ob


def point_at(ob, target):
    d = Vector(target) - Vector(ob.location)
    ob.rotation_euler = d.to_track_quat("-Z", "Y").to_euler()


def add_light(scene, kind, energy, location=(0, 0, 3), target=(0, 0, 0), name=None, **props):
    light = bpy.data.lights.new(name or kind.title(), kind)
    light.energy = energy
    for k, v in props.items():
        setattr(light, k, v)
    ob = bpy.data.objects.new(light.name, light)
    ob.location = location
    point_at(ob, target)
    return link(scene, ob)


def set_world(scene, color=(0.0, 0.0, 0.0), strength=1.0):
    world = bpy.data.worlds.new("World")
    use_nodes(world)
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*color, 1.0)
    bg.inputs["Strength"].default_value = strength
    world.color = color
    scene.world = world
    return world


def studio_hdr(name):
    """Path of one of the HDR environments Blender ships with its data files
    (studiolights/world/NAME.exr): real captured light every machine with
    Blender has, so tests need no download."""
    import os
    path = os.path.join(bpy.utils.system_resource('DATAFILES', path="studiolights/world"), name + ".exr")
    if not os.path.exists(path):
        raise FileNotFoundError("Blender's data files have no studio light %r (%s)" % (name, path))
    return path


def set_world_hdr(scene, name="forest", strength=1.0, rotation_z=0.0, projection='EQUIRECTANGULAR',
                  camera_color=None):
    """A world lit by a studio HDR through Texture Coordinate (Generated) →
    Mapping (rotated about Z by rotation_z radians) → Environment Texture →
    Background. camera_color: the camera sees this colour instead, through a
    Mix Shader by Light Path's Is Camera Ray."""
    world = bpy.data.worlds.new("World")
    use_nodes(world)
    nodes, links = world.node_tree.nodes, world.node_tree.links
    bg = nodes["Background"]
    bg.inputs["Strength"].default_value = strength
    env = nodes.new("ShaderNodeTexEnvironment")
    env.image = bpy.data.images.load(studio_hdr(name), check_existing=True)
    env.projection = projection
    coords = nodes.new("ShaderNodeTexCoord")
    mapping = nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, rotation_z)
    links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    links.new(env.outputs["Color"], bg.inputs["Color"])
    if camera_color is not None:
        out = nodes["World Output"]
        seen = nodes.new("ShaderNodeBackground")
        seen.inputs["Color"].default_value = (*camera_color, 1.0)
        mix = nodes.new("ShaderNodeMixShader")
        path = nodes.new("ShaderNodeLightPath")
        links.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
        links.new(bg.outputs["Background"], mix.inputs[1])
        links.new(seen.outputs["Background"], mix.inputs[2])
        links.new(mix.outputs["Shader"], out.inputs["Surface"])
    scene.world = world
    return world


def sky_types():
    """The Sky Texture's models in the running Blender, by Phos's name:
    SINGLE_SCATTERING is 3.x and 4.x's NISHITA."""
    items = {e.identifier for e in bpy.types.ShaderNodeTexSky.bl_rna.properties['sky_type'].enum_items}
    names = {"SINGLE_SCATTERING": "SINGLE_SCATTERING" if "SINGLE_SCATTERING" in items else "NISHITA"}
    for name in ("MULTIPLE_SCATTERING", "PREETHAM", "HOSEK_WILKIE"):
        if name in items:
            names[name] = name
    return names


def set_world_sky(scene, model="SINGLE_SCATTERING", strength=1.0, **settings):
    """A world lit by a Sky Texture → Background (strength); `model` by
    Phos's name (sky_types), `settings` the node's (sun_elevation in
    radians, ...; dust_density is read as aerosol_density where 5.0
    renamed it)."""
    world = bpy.data.worlds.new("Sky")
    use_nodes(world)
    nodes, links = world.node_tree.nodes, world.node_tree.links
    bg = nodes["Background"]
    bg.inputs["Strength"].default_value = strength
    sky = nodes.new("ShaderNodeTexSky")
    sky.sky_type = sky_types()[model]
    for name, value in settings.items():
        if name == "aerosol_density" and not hasattr(sky, name):
            name = "dust_density"
        setattr(sky, name, value)
    links.new(sky.outputs["Color"], bg.inputs["Color"])
    scene.world = world
    return world


BLENDER_4 = bpy.app.version >= (4, 0, 0)

# Principled BSDF inputs named as in Blender 3.x → their 4.0+ names (Principled
# v2). None: the input is gone in 4.x (the value is dropped, as 4.x's Cycles
# has nothing to apply it to). Tests and scenes give the 3.x names.
PRINCIPLED_4X_NAMES = {
    "Transmission": "Transmission Weight",
    "Transmission Roughness": None,
    "Emission": "Emission Color",
    "Specular": "Specular IOR Level",
    "Subsurface": "Subsurface Weight",
    "Subsurface Color": None,
    "Clearcoat": "Coat Weight",
    "Clearcoat Roughness": "Coat Roughness",
    "Clearcoat Normal": "Coat Normal",
    "Sheen": "Sheen Weight",
}


def input_name(node, name):
    """The name of a node input in this Blender (a 3.x name given); None if it has none."""
    if BLENDER_4 and node.bl_idname == "ShaderNodeBsdfPrincipled":
        return PRINCIPLED_4X_NAMES.get(name, name)
    return name


def setup_node(node, inputs=None, props=None):
    """Set a shader node's properties, then its input values (3.x names and
    values; translated for 4.x). distribution 'SHARP' (removed in 4.0)
    becomes GGX with roughness 0 on 4.x."""
    sharp = False
    for k, v in (props or {}).items():
        if k == "distribution" and v == "SHARP" and BLENDER_4:
            v, sharp = "GGX", True
        setattr(node, k, v)
    for k, v in (inputs or {}).items():
        name = input_name(node, k)
        if name is None:
            continue
        sock = node.inputs[name]
        if isinstance(v, (tuple, list)) and len(v) == 3 and sock.type == "RGBA":
            v = (*v, 1.0)
        sock.default_value = v
    if sharp:
        node.inputs["Roughness"].default_value = 0.0
    return node


def empty_material(name):
    """A new material with nodes and nothing but a Material Output:
    (material, its node tree, the output node)."""
    mat = bpy.data.materials.new(name)
    use_nodes(mat)
    nt = mat.node_tree
    nt.nodes.clear()
    return mat, nt, nt.nodes.new("ShaderNodeOutputMaterial")


def node_material(name, node_type, inputs=None, props=None):
    """A material whose surface is one shader node (type name, input values, properties)."""
    mat, nt, out = empty_material(name)
    node = setup_node(nt.nodes.new(node_type), inputs, props)
    nt.links.new(node.outputs[0], out.inputs["Surface"])
    return mat


def diffuse(name, color):
    return node_material(name, "ShaderNodeBsdfDiffuse", {"Color": color})


def emission(name, color, strength):
    return node_material(name, "ShaderNodeEmission", {"Color": color, "Strength": strength})


def checker_image(path, size=16, squares=4, colors=((0.9, 0.2, 0.1), (0.1, 0.3, 0.9))):
    """Write a checkerboard PNG (8-bit sRGB) and return it loaded as a Blender image."""
    img = bpy.data.images.new("checker_tmp", size, size, alpha=False, float_buffer=False)
    cell = size // squares
    px = np.zeros((size, size, 4), np.float32)
    yy, xx = np.mgrid[0:size, 0:size]
    odd = ((yy // cell + xx // cell) % 2).astype(bool)
    px[~odd, :3] = colors[0]
    px[odd, :3] = colors[1]
    px[..., 3] = 1.0
    img.pixels.foreach_set(px.ravel())
    img.filepath_raw = path
    img.file_format = "PNG"
    img.save()
    bpy.data.images.remove(img)
    return bpy.data.images.load(path, check_existing=False)


# -------------------------------------------------------------- settings

def configure_cycles(scene, samples, max_bounces=8, seed=0, filter_width=1.5):
    """Cycles as an unbiased reference: the same settings the scene scripts
    use (scenes/_common.py), so tests and `make render --engine CYCLES` agree."""
    scenes_dir = os.path.join(REPO_DIR, "scenes")
    if scenes_dir not in sys.path:
        sys.path.insert(0, scenes_dir)
    import _common
    _common.configure_cycles(scene, samples, max_bounces, seed=seed, filter_width=filter_width)


def configure_phos(scene, samples, max_bounces=8, seed=0, filter_width=1.5, tile_size=None):
    p = scene.phos
    p.integrator = "PATH"
    p.samples = samples
    p.seed = seed
    p.max_bounces = max_bounces
    p.filter_width = filter_width
    if tile_size is not None:
        p.tile_size = tile_size


def configure_threads(scene, threads):
    """threads=None: automatic; otherwise a fixed count."""
    if threads is None:
        scene.render.threads_mode = "AUTO"
    else:
        scene.render.threads_mode = "FIXED"
        scene.render.threads = threads


def configure_output(scene, width, height, percentage=100):
    r = scene.render
    r.resolution_x, r.resolution_y = width, height
    r.resolution_percentage = percentage
    r.film_transparent = False
    r.use_compositing = False
    r.use_sequencer = False
    set_single_exr(r.image_settings)  # lossless
    r.image_settings.color_mode = "RGBA"


# --------------------------------------------------------------- rendering

_counter = [0]


def load_image_array(path):
    """Pixels of an image file as float32 (height, width, channels), rows bottom-up."""
    img = bpy.data.images.load(path, check_existing=False)
    try:
        w, h = img.size
        ch = img.channels
        a = np.empty(w * h * ch, np.float32)
        img.pixels.foreach_get(a)
        return a.reshape(h, w, ch)
    finally:
        bpy.data.images.remove(img)


def render_array(scene, out_dir, engine=None, name=None):
    """Render with write_still to an EXR in out_dir and load it back (linear float RGBA).

    An ERROR report of the engine raises RuntimeError (from bpy.ops.render.render).
    """
    if engine is not None:
        scene.render.engine = engine
    _counter[0] += 1
    name = name or "render_%04d" % _counter[0]
    path = os.path.join(str(out_dir), name + ".exr")
    if os.path.exists(path):
        os.remove(path)
    scene.render.filepath = path
    scene.render.use_file_extension = False
    set_single_exr(scene.render.image_settings)
    bpy.ops.render.render(write_still=True, scene=scene.name)
    assert os.path.isfile(path), "the render wrote no %s" % path
    return load_image_array(path)


def border_rect(scene):
    """Blender's pixel rectangle (x0, y0, x1, y1) of the render border, rows bottom-up."""
    r = scene.render
    w = r.resolution_x * r.resolution_percentage // 100
    h = r.resolution_y * r.resolution_percentage // 100
    return (int(r.border_min_x * w), int(r.border_min_y * h),
            int(r.border_max_x * w), int(r.border_max_y * h))


def project(scene, point):
    """Pixel coordinates (x, y from the bottom-left, pixel centres at +0.5) of a world point."""
    from bpy_extras.object_utils import world_to_camera_view
    co = world_to_camera_view(scene, scene.camera, Vector(point))
    r = scene.render
    w = r.resolution_x * r.resolution_percentage / 100
    h = r.resolution_y * r.resolution_percentage / 100
    return co.x * w, co.y * h


def luminance(rgb):
    rgb = np.asarray(rgb)
    return rgb[..., 0] * 0.2126 + rgb[..., 1] * 0.7152 + rgb[..., 2] * 0.0722


# ------------------------------------------------------------- subprocesses

def run_blender(args, env=None, timeout=300, cwd=None):
    """Run a background Blender; returns (returncode, stdout+stderr as text).

    A negative return code means Blender died of a signal (e.g. -11: segfault).
    """
    full_env = dict(os.environ)
    full_env.update(env or {})
    cmd = BLENDER_COMMAND + ["-b", "--factory-startup"] + list(args)
    proc = subprocess.run(cmd, env=full_env, cwd=cwd, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, timeout=timeout)
    return proc.returncode, proc.stdout.decode("utf-8", "replace")


def run_script(script_text, tmp_dir, args=(), env=None, timeout=300, name="script.py"):
    """Write script_text (which may `import phostest`) to tmp_dir and run it in Blender."""
    path = os.path.join(str(tmp_dir), name)
    prelude = "import sys\nsys.path.insert(0, %r)\n" % TESTS_DIR
    with open(path, "w") as f:
        f.write(prelude + script_text)
    return run_blender(["--python-exit-code", "1", "--python", path, "--"] + list(args),
                       env=env, timeout=timeout)


def user_scripts_dir(tmp_dir):
    """A BLENDER_USER_SCRIPTS folder whose addons/phos is this source tree's add-on."""
    root = os.path.join(str(tmp_dir), "user_scripts")
    addons = os.path.join(root, "addons")
    os.makedirs(addons, exist_ok=True)
    link_path = os.path.join(addons, ADDON_NAME)
    if not os.path.lexists(link_path):
        os.symlink(os.path.join(ADDON_DIR, ADDON_NAME), link_path)
    return root


def render_blend_cli(blend, tmp_dir, output_base, file_format="OPEN_EXR", env=None, timeout=300):
    """`blender -b --addons phos FILE -E PHOS -o OUT -F FMT -f 1` as a render farm runs it
    (an installed extension: from the user folders this process uses)."""
    full_env = {"BLENDER_USER_SCRIPTS": user_scripts_dir(tmp_dir)} if FROM_SOURCE_TREE else {}
    full_env.update(env or {})
    return run_blender(["--addons", ADDON_NAME, blend, "-E", ENGINE, "-o", output_base + "####",
                        "-F", file_format, "-x", "1", "-f", "1"], env=full_env, timeout=timeout)


def signal_name(returncode):
    if returncode >= 0:
        return ""
    import signal
    try:
        return signal.Signals(-returncode).name
    except ValueError:
        return "signal %d" % -returncode


def angle(deg):
    return math.radians(deg)
