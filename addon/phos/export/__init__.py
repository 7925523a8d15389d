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

Everything here runs on the thread that called RenderEngine.render() and
never touches bpy.context.
"""

from .context import ExportContext
from . import camera, instances, world


def _check_render_settings(ctx):
    """Scene-wide features the core does not have: say so instead of ignoring them silently."""
    r = ctx.scene.render
    if r.use_motion_blur:
        ctx.warn("Phos: motion blur is not supported; rendering the frame without it")
    if r.use_multiview:
        ctx.warn("Phos: stereoscopy / multi-view is not supported; only the first view is rendered")


def export_scene(depsgraph, core_scene, camera_object, camera_matrix, is_preview=False,
                 progress=None, cancelled=None):
    """Fill `core_scene` (a core.Scene, not yet committed) from an evaluated depsgraph.

    Returns the ExportContext, whose `warnings` and `stats` the engine
    reports. Raises core.PhosError if the core rejects something.
    """
    ctx = ExportContext(depsgraph.scene, core_scene, is_preview)
    _check_render_settings(ctx)
    camera.export_camera(camera_object, camera_matrix, ctx)
    world.export_world(ctx)
    instances.export_instances(depsgraph, ctx, progress, cancelled)
    return ctx
