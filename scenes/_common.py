# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared helpers for the scene scripts in scenes/.

A scene script builds its scene from Blender's factory startup and then
hands over to :func:`finish`, which applies the command-line options:

    blender -b --factory-startup --python scenes/SCENE.py -- [options]

    --render OUTPUT_BASE   render and write OUTPUT_BASE.png (8-bit, through
                           the scene's view transform) and OUTPUT_BASE.exr
                           (32-bit float, linear scene-referred)
    --save FILE.blend      save the built scene
    --samples N            samples per pixel (Phos and Cycles alike)
    --engine PHOS|CYCLES   the engine to render with and to leave selected
    --resolution W H       output size in pixels
    --seed N               seed of both engines
    --integrator PATH|PHOTON   Phos's integrator (each scene has its default)
    --global-photons N, --caustic-photons N
                           photons stored in Phos's photon maps (PHOTON)

The add-on is imported from this source tree (<repo>/addon), not from an
installed copy, so a script always renders with the code beside it (unless
PHOS_ADDON_MODULE names an installed one: the tests of an extension).
Cycles is configured for parity with Phos whatever the engine: same samples,
bounces, seed and pixel filter, no clamping, no glossy blur, no denoising,
no adaptive sampling, caustics on.
"""

import argparse
import os
import sys
import time

import addon_utils
import bpy

REPO_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ADDON_DIR = os.path.join(REPO_DIR, "addon")
# The add-on's module: "phos" from this source tree, or an installed copy's
# (PHOS_ADDON_MODULE, e.g. "bl_ext.user_default.phos" for the extension).
ADDON_NAME = os.environ.get("PHOS_ADDON_MODULE", "phos")
ENGINES = ("PHOS", "CYCLES")


def log(msg):
    print("[scene] %s" % msg, flush=True)


# ------------------------------------------------------------------ add-on

def enable_addon():
    """Import the add-on from the source tree (or the installed ADDON_NAME)
    and enable it; True on success."""
    if ADDON_NAME == "phos" and ADDON_DIR not in sys.path:
        sys.path.insert(0, ADDON_DIR)
    _default, loaded = addon_utils.check(ADDON_NAME)
    if not loaded:
        mod = addon_utils.enable(ADDON_NAME, default_set=True)
        if mod is None:
            return False
    return hasattr(bpy.types.Scene, "phos") and "PHOS" in _engine_ids()


def _engine_ids():
    # 4.x lists engine classes without a bl_idname (HydraRenderEngine).
    return {getattr(cls, "bl_idname", None) for cls in bpy.types.RenderEngine.__subclasses__()
            if getattr(cls, "is_registered", True)} - {None}


# ------------------------------------------------------- Blender versions
# What Blender 5.0 changed, done the way each version needs; the tests and
# the benchmark use these too.

def use_nodes(id_data):
    """Give a material or world its node tree (Blender 5.0 deprecated
    use_nodes: there every new one has a tree already); returns the tree."""
    if bpy.app.version < (5, 0, 0):
        id_data.use_nodes = True
    return id_data.node_tree


def set_multilayer_exr(image_settings):
    """Multilayer OpenEXR (32-bit float, lossless) in every Blender: 5.0
    chooses it by media type, and writes single-part files (which exrread
    reads) only with use_exr_interleave."""
    if hasattr(image_settings, "media_type"):
        image_settings.media_type = 'MULTI_LAYER_IMAGE'
        if hasattr(image_settings, "use_exr_interleave"):
            image_settings.use_exr_interleave = True
    else:
        image_settings.file_format = 'OPEN_EXR_MULTILAYER'
    image_settings.color_depth, image_settings.exr_codec = '32', 'ZIP'


def set_single_exr(image_settings):
    if hasattr(image_settings, "media_type"):
        image_settings.media_type = 'IMAGE'
    image_settings.file_format = 'OPEN_EXR'
    image_settings.color_depth, image_settings.exr_codec = '32', 'ZIP'


def compositor_tree(scene):
    """The scene's compositor node tree, made if needed: scene.node_tree
    before 5.0, a node group in scene.compositing_node_group in 5.0–5.2,
    the node group of the scene's first compositor effect from 5.3 (which
    deprecates compositing_node_group)."""
    if hasattr(scene.render, "compositor_device"):
        scene.render.compositor_device = 'CPU'   # 5.3 defaults to the GPU, which this has not
    if hasattr(scene, "compositor_effects"):
        effects = scene.compositor_effects
        effect = effects[0] if len(effects) else effects.new(name="Compositing")
        if effect.node_group is None:
            effect.node_group = bpy.data.node_groups.new("Compositing", "CompositorNodeTree")
        return effect.node_group
    if hasattr(scene, "compositing_node_group"):
        if scene.compositing_node_group is None:
            scene.compositing_node_group = bpy.data.node_groups.new("Compositing", "CompositorNodeTree")
        return scene.compositing_node_group
    scene.use_nodes = True
    return scene.node_tree


def compositor_output(tree):
    """The input the render writes out: the Composite node's (before 5.0) or
    the node group's output (5.0)."""
    if hasattr(bpy.types, "CompositorNodeComposite"):
        node = next((n for n in tree.nodes if n.bl_idname == "CompositorNodeComposite"), None) \
            or tree.nodes.new("CompositorNodeComposite")
        return node.inputs["Image"]
    if not any(getattr(i, "in_out", None) == 'OUTPUT' for i in tree.interface.items_tree):
        tree.interface.new_socket(name="Image", in_out='OUTPUT', socket_type='NodeSocketColor')
    node = next((n for n in tree.nodes if n.bl_idname == "NodeGroupOutput"), None) \
        or tree.nodes.new("NodeGroupOutput")
    return node.inputs[0]


def denoise_in_compositor(scene):
    """Compositor: Render Layers → Denoise (image, Denoising Albedo and
    Denoising Normal) → the output, with both passes enabled for Phos and
    Cycles. The Denoise node is OpenImageDenoise where Blender has it."""
    vl = scene.view_layers[0]
    vl.phos.use_pass_denoising_albedo = vl.phos.use_pass_denoising_normal = True
    vl.cycles.denoising_store_passes = True
    tree = compositor_tree(scene)
    tree.nodes.clear()
    layers = tree.nodes.new("CompositorNodeRLayers")
    denoise = tree.nodes.new("CompositorNodeDenoise")
    for output, input in (("Image", "Image"), ("Denoising Albedo", "Albedo"), ("Denoising Normal", "Normal")):
        tree.links.new(layers.outputs[output], denoise.inputs[input])
    tree.links.new(denoise.outputs["Image"], compositor_output(tree))
    scene.render.use_compositing = True


# --------------------------------------------------------------- arguments

def script_argv(argv=None):
    """The arguments after '--' on Blender's command line."""
    argv = sys.argv if argv is None else argv
    return argv[argv.index("--") + 1:] if "--" in argv else []


INTEGRATORS = ("PATH", "PHOTON")


def parse_args(description, default_resolution=(512, 512), default_samples=256, argv=None,
               default_integrator="PATH"):
    p = argparse.ArgumentParser(prog=os.path.basename(sys.argv[0]) if sys.argv else "scene",
                                description=description)
    p.add_argument("--render", metavar="OUTPUT_BASE",
                   help="render and save OUTPUT_BASE.png and OUTPUT_BASE.exr")
    p.add_argument("--save", metavar="FILE.blend", help="save the scene as a .blend file")
    p.add_argument("--samples", type=int, default=default_samples, metavar="N")
    p.add_argument("--engine", default="PHOS", type=str.upper, choices=ENGINES)
    p.add_argument("--resolution", type=int, nargs=2, metavar=("W", "H"),
                   default=list(default_resolution))
    p.add_argument("--seed", type=int, default=0, metavar="N")
    p.add_argument("--integrator", default=default_integrator, type=str.upper, choices=INTEGRATORS)
    p.add_argument("--global-photons", type=int, default=None, metavar="N")
    p.add_argument("--caustic-photons", type=int, default=None, metavar="N")
    args, extra = p.parse_known_args(script_argv(argv))
    if args.samples < 1:
        p.error("--samples must be >= 1")
    if min(args.resolution) < 1:
        p.error("--resolution must be positive")
    args.extra = extra
    return args


# ------------------------------------------------------------ scene setup

def geometry_node_group(name):
    """A new geometry-nodes group with one Geometry input and output, and
    its Group Input and Group Output nodes: (tree, group output node). The
    group's interface is tree.interface from 4.0, the tree's own sockets in
    3.x."""
    tree = bpy.data.node_groups.new(name, "GeometryNodeTree")
    if hasattr(tree, "interface"):
        tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:
        tree.inputs.new("NodeSocketGeometry", "Geometry")
        tree.outputs.new("NodeSocketGeometry", "Geometry")
    tree.nodes.new("NodeGroupInput")
    return tree, tree.nodes.new("NodeGroupOutput")


def clear_factory_scene():
    """Delete the factory startup's objects and the data they used."""
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
    for coll in (bpy.data.meshes, bpy.data.lights, bpy.data.cameras,
                 bpy.data.materials, bpy.data.worlds):
        for block in list(coll):
            if block.users == 0:
                coll.remove(block)


def set_sharp(bsdf):
    """A perfectly smooth Glossy/Glass BSDF: the 'SHARP' distribution on 3.x;
    4.0 removed it, there GGX with roughness 0 is the same (Phos and Cycles
    both treat such a GGX as a delta lobe)."""
    if bpy.app.version < (4, 0, 0):
        bsdf.distribution = "SHARP"
    else:
        bsdf.distribution = "GGX"
    bsdf.inputs["Roughness"].default_value = 0.0


def look_at_rotation(location, target, up_axis="Y"):
    """Euler rotation that points an object's −Z at target (camera/light convention)."""
    from mathutils import Vector
    d = Vector(target) - Vector(location)
    return d.to_track_quat("-Z", up_axis).to_euler()


# The benchmark's reference for a caustic seen close up
# (scenes/metal_ring_cusp.py, scenes/glass_sphere_focus.py): Phos with
# consistent methods only (bench/quality.py), sharper than its default
# Phos recipe because there the fixed estimate's blur is what is measured:
# 2 photons in the first radius instead of 4 and alpha 0.3, 4 chunks of
# 4096 samples (docs/benchmarks.md, "The ring's cusp close up"). Cycles
# finds such caustics only where a path happens to hit the light through
# the specular object, and not in any reasonable time.
CLOSE_UP_REFERENCE = {
    "engine": "PHOS", "chunks": 4, "chunk_samples": 4096,
    "settings": {"use_progressive_caustics": True, "photon_view": "PATH_TRACED", "irradiance_cache": "OFF",
                 "progressive_caustic_photons": 20000, "progressive_first_photons": 2, "progressive_alpha": 0.3,
                 "caustic_photons": 4000000, "caustic_estimate_photons": 20, "final_gather_rays": 1},
}


def close_up(scene, lens_mm, target):
    """The scene's camera, where it stands, with a longer lens aimed at target."""
    scene.camera.data.lens = lens_mm
    scene.camera.rotation_euler = look_at_rotation(scene.camera.location, target)
    return scene


def configure_cycles(scene, samples, max_bounces, seed=0, filter_width=1.5):
    """Cycles settings that make it an unbiased reference for Phos."""
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.preview_samples = samples
    c.seed = seed
    c.use_animated_seed = False
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.use_preview_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.use_fast_gi = False
    c.max_bounces = max_bounces
    c.diffuse_bounces = max_bounces
    c.glossy_bounces = max_bounces
    c.transmission_bounces = max_bounces
    c.transparent_max_bounces = max_bounces
    c.volume_bounces = 0
    c.light_sampling_threshold = 0.0  # no stochastic light culling
    c.pixel_filter_type = "BLACKMAN_HARRIS"
    c.filter_width = filter_width
    c.film_exposure = 1.0


def configure_phos(scene, samples, max_bounces, seed=0, filter_width=1.5, integrator="PATH",
                   photon_settings=None):
    """Phos's settings; photon_settings: scene.phos property → value (photon counts...)."""
    if not hasattr(scene, "phos"):
        return
    p = scene.phos
    p.integrator = integrator
    for name, value in (photon_settings or {}).items():
        setattr(p, name, value)
    p.samples = samples
    p.preview_samples = samples
    p.seed = seed
    p.max_bounces = max_bounces
    p.filter_width = filter_width


def configure_output(scene, resolution):
    r = scene.render
    r.resolution_x, r.resolution_y = resolution
    r.resolution_percentage = 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_border = False
    r.film_transparent = False


# ---------------------------------------------------------------- rendering

def render_and_save(scene, output_base):
    """Render the scene and write OUTPUT_BASE.png and OUTPUT_BASE.exr."""
    output_base = os.path.abspath(output_base)
    os.makedirs(os.path.dirname(output_base), exist_ok=True)
    r = scene.render
    engine = r.engine
    if engine == "PHOS" and hasattr(scene, "phos"):
        engine = "PHOS (%s)" % scene.phos.integrator
    log("rendering %dx%d with %s, %d samples -> %s.{png,exr}"
        % (r.resolution_x * r.resolution_percentage // 100,
           r.resolution_y * r.resolution_percentage // 100,
           engine, samples_of(scene), output_base))
    # In background mode Blender (up to 4.x; Phos itself on 5.x) prints the
    # engine's progress and stats lines ("Phos | Rendering ... | Tile 3/16").
    t0 = time.time()
    bpy.ops.render.render()
    log("render finished in %.1f s" % (time.time() - t0))

    result = bpy.data.images["Render Result"]
    fmt = scene.render.image_settings
    saved = (fmt.file_format, fmt.color_mode, fmt.color_depth)
    try:
        fmt.file_format, fmt.color_mode, fmt.color_depth = "PNG", "RGBA", "8"
        result.save_render(output_base + ".png", scene=scene)
        fmt.file_format, fmt.color_mode, fmt.color_depth = "OPEN_EXR", "RGBA", "32"
        fmt.exr_codec = "ZIP"
        result.save_render(output_base + ".exr", scene=scene)
    finally:
        fmt.file_format, fmt.color_mode, fmt.color_depth = saved
    log("saved %s.png (view transform '%s') and %s.exr (linear)"
        % (output_base, scene.view_settings.view_transform, output_base))


def samples_of(scene):
    if scene.render.engine == "CYCLES":
        return scene.cycles.samples
    if hasattr(scene, "phos"):
        return scene.phos.samples
    return 0


def finish(scene, args, max_bounces, photon_settings=None):
    """Apply the command-line options to a built scene: settings, --save, --render.

    photon_settings: the scene's own scene.phos photon settings (counts,
    estimate sizes...); --global-photons/--caustic-photons override them.

    Returns the process exit code (0 on success); scripts pass it to sys.exit.
    """
    phos_ok = enable_addon()
    if not phos_ok:
        log("warning: the Phos add-on could not be enabled from %s" % ADDON_DIR)
    configure_output(scene, args.resolution)
    configure_cycles(scene, args.samples, max_bounces, seed=args.seed)
    photon_settings = dict(photon_settings or {})
    if getattr(args, "global_photons", None) is not None:
        photon_settings["global_photons"] = args.global_photons
    if getattr(args, "caustic_photons", None) is not None:
        photon_settings["caustic_photons"] = args.caustic_photons
    configure_phos(scene, args.samples, max_bounces, seed=args.seed,
                   integrator=getattr(args, "integrator", "PATH"), photon_settings=photon_settings)
    if args.engine == "PHOS" and not phos_ok:
        log("error: --engine PHOS needs the add-on")
        return 1
    scene.render.engine = args.engine

    if args.save:
        path = os.path.abspath(args.save)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        bpy.ops.wm.save_as_mainfile(filepath=path, check_existing=False)
        log("saved %s" % path)
    if args.render:
        try:
            render_and_save(scene, args.render)
        except RuntimeError as ex:  # an ERROR report of the engine
            log("error: render failed: %s" % ex)
            return 1
    return 0


def run_scene(build, description, max_bounces, photon_settings=None, **parse_kwargs):
    """The whole main of a scene script: parse the options, build the scene
    from the factory startup, then finish(); exits with its code on failure.

    parse_kwargs go to parse_args (default_samples, default_integrator...).
    """
    args = parse_args(description, **parse_kwargs)
    if args.extra:
        log("error: unknown arguments %s" % args.extra)
        sys.exit(2)
    scene = bpy.context.scene
    build(scene)
    rc = finish(scene, args, max_bounces, photon_settings=photon_settings)
    if rc:
        sys.exit(rc)
