# SPDX-License-Identifier: GPL-3.0-or-later
"""One farm task, inside the Blender that renders it (docs/farm.md).

    blender -b scene.blend --python-exit-code 1 --python-expr BOOTSTRAP -- \\
        cache  --job-dir DIR --frames 1-250 --key-frames 1,2,…
        frame  --job-dir DIR --frame F [--caches per-frame]
        region --job-dir DIR --frame F --region I --regions CxR [--caches per-frame]
        stitch --job-dir DIR --frame F --regions CxR

- cache: one final render of the first key frame that traces the photon
  maps and fills the irradiance cache, for its camera and every other key
  frame's camera (phos_render_add_view), saves them to DIR/caches, and
  renders no pixel. caches.json says which caches the settings use.
- frame, region: the frame (or region) rendered with those caches loaded,
  written as a 32-bit float OpenEXR to DIR/frames (DIR/regions). A cache
  made for another scene is refused by the core, naming what differs.
  With --caches per-frame the task makes its frame's caches itself.
- stitch: the regions of a frame placed where Blender's border put them
  (engine.border_rect), written as the whole frame.

Every file is written under a temporary name and renamed, so a task
killed half-way and run again never leaves half a frame. Any failure
raises: Blender then exits with 1 and the manager sees the task fail.
"""

import argparse
import json
import os
import sys

import bpy
import numpy as np

from .. import core, engine
from ..export import camera as camera_export
from ..properties import CACHE_FILES, render_settings
from .job import format_frames, parse_frames, parse_regions, read_json, region_border, write_json_atomically

CACHES_FILE = "caches.json"
# The core stage that makes each kind of cache file.
MADE_BY = {core.PHOS_CACHE_PHOTON_MAPS: core.PHOS_STAGE_TRACING_PHOTONS,
           core.PHOS_CACHE_IRRADIANCE: core.PHOS_STAGE_FILLING_IRRADIANCE_CACHE}
# (scene.phos prefix, the core stage that makes it, file name in caches/),
# the file named as the scene's default file is.
CACHE_KINDS = tuple((prefix, MADE_BY[kind], os.path.basename(default))
                    for kind, prefix, _what, default in CACHE_FILES)


class TaskError(Exception):
    """A task that cannot do what it was asked; the message says why."""


def _say(text):
    print("Phos farm: " + text, flush=True)


def _resolution(scene):
    """The rendered size, in integers as Blender computes it (size ·
    percentage / 100, truncated)."""
    r = scene.render
    return r.resolution_x * r.resolution_percentage // 100, r.resolution_y * r.resolution_percentage // 100


def check_scene(scene):
    """What the farm cannot render as one machine would, refused before
    any work."""
    if scene.render.engine != 'PHOS':
        raise TaskError("the scene renders with %s, not Phos: set Render Engine to Phos" % scene.render.engine)
    layers = [layer.name for layer in scene.view_layers if layer.use]
    if len(layers) != 1:
        # Each layer's render would save and load the caches of its own
        # objects under one file name.
        raise TaskError("the farm renders scenes of one view layer; this one renders %d (%s): untick "
                        "'Use for Rendering' on all but one" % (len(layers), ", ".join(layers) or "none"))
    if scene.phos.time_limit > 0.0:
        _say("warning: a time limit (%.0f s) makes each frame depend on its node's speed: a requeued or "
             "resubmitted task, or a region, is not the same image" % scene.phos.time_limit)


def check_regions(scene):
    """A split frame equals the whole only where every pixel depends on
    its own samples alone."""
    if scene.phos.filter != 'NONE':
        raise TaskError("regions: the noise filter reads pixels a region cuts off, so the stitched frame would "
                        "differ from the whole; render whole frames (regions 1x1) or turn the filter off")
    if _compositor_active(scene):
        raise TaskError("regions: the compositor runs on each region alone, so the stitched frame would differ "
                        "from the whole; render whole frames (regions 1x1) or turn compositing off")


def _compositor_active(scene):
    """Whether a render's result goes through the compositor: a node tree
    in use before Blender 5.0, a compositing node group in 5.0-5.2, a
    compositor effect from 5.3."""
    if not scene.render.use_compositing:
        return False
    if bpy.app.version < (5, 0, 0):
        return bool(scene.use_nodes and scene.node_tree is not None and len(scene.node_tree.nodes))
    if len(getattr(scene, "compositor_effects", ())):
        return True
    return getattr(scene, "compositing_node_group", None) is not None


def _render(scene):
    """One final render of the scene as it is set; raises with the
    engine's message if Phos failed."""
    engine.last_render_error = None
    try:
        bpy.ops.render.render()
    except RuntimeError as ex:  # the engine's ERROR report, raised by the operator in the background
        raise TaskError(engine.last_render_error or str(ex)) from None
    if engine.last_render_error is not None:
        raise TaskError(engine.last_render_error)


def _output_settings(scene):
    """Every image the farm writes: 32-bit float RGBA OpenEXR, lossless,
    scene-linear, so regions stitch into the frame bit for bit."""
    s = scene.render.image_settings
    if hasattr(s, "media_type"):  # Blender 5.0 chooses formats by media type
        s.media_type = 'IMAGE'
    s.file_format = 'OPEN_EXR'
    s.color_mode = 'RGBA'
    s.color_depth = '32'
    s.exr_codec = 'ZIP'


def _save_render_result(scene, path):
    result = bpy.data.images.get("Render Result")
    if result is None:
        raise TaskError("the render left no image")
    tmp = "%s.%d.tmp.exr" % (path, os.getpid())
    result.save_render(tmp, scene=scene)
    os.replace(tmp, path)


def frame_path(job_dir, frame):
    return os.path.join(job_dir, "frames", "frame_%04d.exr" % frame)


def region_path(job_dir, frame, index):
    return os.path.join(job_dir, "regions", "frame_%04d_r%02d.exr" % (frame, index))


# ------------------------------------------------------------------ cache

def _caches_used(scene):
    """The caches a render of this scene's settings makes, as
    (scene.phos prefix, file name)."""
    w, h = _resolution(scene)
    plan = core.settings_stages(render_settings(scene, w, h))
    return [(prefix, name) for prefix, stage, name in CACHE_KINDS if stage in plan]


def _key_views(scene, key_frames):
    """The core camera of each key frame after the first, as evaluated at
    that frame (the render evaluates its own camera likewise)."""
    views = []
    for f in key_frames[1:]:
        scene.frame_set(f)
        cam = scene.camera
        if cam is None:
            raise TaskError("frame %d has no active camera" % f)
        evaluated = cam.evaluated_get(bpy.context.evaluated_depsgraph_get())
        views.append(camera_export.camera_desc(evaluated, evaluated.matrix_world, scene, _say))
    scene.frame_set(key_frames[0])
    return views


def run_cache(scene, job_dir, key_frames):
    caches = _caches_used(scene)
    os.makedirs(os.path.join(job_dir, "caches"), exist_ok=True)
    listing = os.path.join(job_dir, "caches", CACHES_FILE)
    if not caches:
        _say("the scene's settings use no photon map and no irradiance cache: nothing to make")
        write_json_atomically(listing, {"caches": {}, "key_frames": format_frames(key_frames)})
        return
    views = _key_views(scene, key_frames)
    tmp = {}
    for prefix, name in caches:
        tmp[prefix] = os.path.join(job_dir, "caches", "%s.%d.tmp" % (name, os.getpid()))
        setattr(scene.phos, prefix + "_mode", 'SAVE')
        setattr(scene.phos, prefix, tmp[prefix])
    _say("making %s for %d key frame(s): %s"
         % (" and ".join(n for _, n in caches), len(key_frames), format_frames(key_frames)))
    engine.cache_job_views = views
    try:
        _render(scene)
    finally:
        engine.cache_job_views = None
    files = {}
    for prefix, name in caches:
        if not os.path.isfile(tmp[prefix]):
            raise TaskError("the render saved no %s" % name)
        os.replace(tmp[prefix], os.path.join(job_dir, "caches", name))
        files[prefix] = name
    write_json_atomically(listing, {"caches": files, "key_frames": format_frames(key_frames)})
    _say("saved " + ", ".join(files.values()))


# ---------------------------------------------------------- frame, region

def _load_caches(scene, job_dir, shared):
    """Set the scene to read the job's caches (or, not shared, to make
    its own and keep none); their names."""
    for prefix, _stage, _name in CACHE_KINDS:  # never the scene's own cache files: tasks run side by side
        setattr(scene.phos, prefix + "_mode", 'NONE')
    if not shared:
        return []
    listing = read_json(os.path.join(job_dir, "caches", CACHES_FILE))
    if listing is None:
        raise TaskError("%s has no caches: the cache task has not run, or failed" % job_dir)
    for prefix, name in listing["caches"].items():
        setattr(scene.phos, prefix + "_mode", 'LOAD')
        setattr(scene.phos, prefix, os.path.join(job_dir, "caches", name))
    return sorted(listing["caches"].values())


def run_frame(scene, job_dir, frame, region=None, regions=(1, 1), shared=True):
    loaded = _load_caches(scene, job_dir, shared)
    scene.frame_set(frame)
    _output_settings(scene)
    r = scene.render
    if region is None:
        r.use_border = False
        out = frame_path(job_dir, frame)
    else:
        r.use_border, r.use_crop_to_border = True, True
        r.border_min_x, r.border_max_x, r.border_min_y, r.border_max_y = region_border(region, *regions)
        out = region_path(job_dir, frame, region)
    _say("rendering frame %d%s with %s" % (frame, "" if region is None else " region %d" % region,
                                           ", ".join(loaded) + " loaded" if loaded else "caches of its own"))
    try:
        _render(scene)
    except TaskError as ex:
        if shared and "is not used: it was made for other" in str(ex):
            raise TaskError("%s (if objects, lights or materials animate, submit the job with --caches "
                            "per-frame)" % ex) from None
        raise
    os.makedirs(os.path.dirname(out), exist_ok=True)
    _save_render_result(scene, out)
    _say("wrote " + out)


# ------------------------------------------------------------------ stitch

def _read_rgba(path):
    img = bpy.data.images.load(path, check_existing=False)
    try:
        w, h = img.size
        px = np.empty(w * h * 4, dtype=np.float32)
        img.pixels.foreach_get(px)
        return px.reshape(h, w, 4)
    finally:
        bpy.data.images.remove(img)


def run_stitch(scene, job_dir, frame, regions):
    width, height = _resolution(scene)
    full = np.zeros((height, width, 4), dtype=np.float32)
    for i in range(regions[0] * regions[1]):
        path = region_path(job_dir, frame, i)
        if not os.path.isfile(path):
            raise TaskError("region %d of frame %d is missing (%s): its task has not run, or failed" % (i, frame, path))
        x, y, w, h = engine.border_rect(width, height, *region_border(i, *regions))
        px = _read_rgba(path)
        if px.shape[:2] != (h, w):
            raise TaskError("region %d of frame %d is %d × %d pixels where the frame's border gives %d × %d: "
                            "was the resolution changed after it rendered?" % (i, frame, px.shape[1], px.shape[0], w, h))
        full[y:y + h, x:x + w] = px
    img = bpy.data.images.new("phos_stitch", width, height, alpha=True, float_buffer=True)
    try:
        img.pixels.foreach_set(full.ravel())
        _output_settings(scene)
        out = frame_path(job_dir, frame)
        tmp = "%s.%d.tmp.exr" % (out, os.getpid())
        img.save_render(tmp, scene=scene)
        os.replace(tmp, out)
    finally:
        bpy.data.images.remove(img)
    _say("stitched %d regions into %s" % (regions[0] * regions[1], out))


# -------------------------------------------------------------------- main

def _parse(argv):
    p = argparse.ArgumentParser(prog="phos farm task")
    p.add_argument("task", choices=("cache", "frame", "region", "stitch"))
    p.add_argument("--job-dir", required=True)
    p.add_argument("--frames")
    p.add_argument("--key-frames")
    p.add_argument("--frame", type=int)
    p.add_argument("--region", type=int)
    p.add_argument("--regions", default="1x1")
    p.add_argument("--caches", default="shared", choices=("shared", "per-frame"))
    return p.parse_args(argv)


def run(argv):
    a = _parse(argv)
    scene = bpy.context.scene
    check_scene(scene)
    if a.task in ("region", "stitch"):
        check_regions(scene)
    if a.task == "cache":
        keys = parse_frames(a.key_frames or a.frames, "key frames")
        run_cache(scene, a.job_dir, keys)
    elif a.frame is None:
        raise TaskError("%s needs --frame" % a.task)
    elif a.task == "frame":
        run_frame(scene, a.job_dir, a.frame, shared=a.caches == "shared")
    elif a.task == "region":
        regions = parse_regions(a.regions)
        if a.region is None or not 0 <= a.region < regions[0] * regions[1]:
            raise TaskError("--region must be 0 to %d for regions %s" % (regions[0] * regions[1] - 1, a.regions))
        run_frame(scene, a.job_dir, a.frame, a.region, regions, shared=a.caches == "shared")
    else:
        run_stitch(scene, a.job_dir, a.frame, parse_regions(a.regions))


def main():
    """The bootstrap's entry: the arguments after Blender's `--`."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    try:
        run(argv)
    except Exception as ex:  # every failure must fail the task, with its reason first
        _say("error: %s" % ex)
        raise
