# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender depsgraph → core scene, one module per datablock.

    context.py    per-frame state: core scene, caches, warnings
    instances.py  depsgraph.object_instances → meshes, instances, lights
    mesh.py       evaluated meshes → triangle arrays (numpy, foreach_get)
    material.py   Cycles node trees → closures
    image.py      images → linear float pixels
    light.py      lights → physical units of the running Blender version
    camera.py     the scene camera
    world.py      the world background
    changes.py    Blender's edits applied to a kept core scene (Persistent
                  Data, the viewport) instead of a new export

Everything here runs on the thread that called RenderEngine.render() and
never touches bpy.context.
"""

import bpy

from .context import ExportContext
from . import camera, instances, world


def _check_render_settings(ctx):
    """Scene-wide features the core does not have: say so instead of ignoring them silently."""
    r = ctx.scene.render
    if r.use_motion_blur:
        ctx.warn("Phos: motion blur is not supported; rendering the frame without it")
    if r.use_multiview:
        ctx.warn("Phos: stereoscopy / multi-view is not supported; only the first view is rendered")
    # Blender 5.0's working colour space of a file: Phos's colours are Rec. 709.
    working = getattr(getattr(bpy.data, "colorspace", None), "working_space", "Linear Rec.709")
    if working != "Linear Rec.709":
        ctx.warn("Phos: the file's working colour space is %s; Phos renders as if it were Linear Rec.709"
                 % working)


def _check_contents(ctx):
    """Say so when nothing but the world can show up, or nothing gives light."""
    s = ctx.stats
    if s["instances"] == 0 and s["lights"] == 0:
        ctx.warn("Phos: the scene has no objects or lights to render; the image shows only the world")
    elif s["lights"] == 0 and s["emissive_materials"] == 0 and not ctx.world_emits:
        photon = getattr(ctx.scene.phos, "integrator", None) == 'PHOTON'
        ctx.warn("Phos: the scene has no light source (no lights, no emissive materials, a black "
                 "world): %sthe image is black" % (
                     "no photons can be emitted, the photon maps are empty and " if photon else ""))


def export_scene(depsgraph, core_scene, camera_object, camera_matrix, is_preview=False,
                 progress=None, cancelled=None):
    """Fill `core_scene` (a core.Scene, not yet committed) from an evaluated depsgraph.

    Returns the ExportContext, whose `warnings` and `stats` the engine
    reports (`cancelled` is True when `cancelled()` stopped the export).
    Raises core.PhosError if the core rejects something.
    """
    ctx = ExportContext(depsgraph.scene, core_scene, is_preview)
    ctx.view_layer = depsgraph.view_layer
    _check_render_settings(ctx)
    if camera_object is not None:  # None: the caller sets the camera (the viewport's view)
        camera.export_camera(camera_object, camera_matrix, ctx)
    world.export_world(ctx)
    ctx.cancelled = not instances.export_instances(depsgraph, ctx, progress, cancelled)
    if not ctx.cancelled:
        _check_contents(ctx)
    return ctx
