# SPDX-License-Identifier: GPL-3.0-or-later
"""Evaluated meshes → core meshes (object space, triangles).

Everything is read with foreach_get into numpy arrays: a Python loop over
vertices would take seconds on a production mesh, foreach_get takes
milliseconds. The mesh is evaluated (modifiers, geometry nodes applied) by
`Object.to_mesh()` on the evaluated object and freed right after.
"""

import numpy as np

from .. import core


def read_mesh(ob, ctx):
    """Triangle arrays of an evaluated object, or None if it has no triangles.

    Returns a dict with positions (V*3 float32), indices (T*3 uint32),
    normals (T*9 float32: per-corner split normals, which are the face normal
    on flat-shaded faces and the smoothed/custom normal elsewhere), uvs
    (T*6 float32 or None) and material_slots (T uint32 or None).
    """
    try:
        me = ob.to_mesh()
    except RuntimeError as ex:
        ctx.warn("Phos: object '%s' could not be converted to a mesh (%s); skipped" % (ob.name, ex))
        return None
    if me is None:
        return None
    try:
        me.calc_loop_triangles()
        if not ctx.at_least(4, 1):
            # Split normals are computed on demand before 4.1 (the call is gone in 4.1).
            me.calc_normals_split()
        vertex_count = len(me.vertices)
        triangle_count = len(me.loop_triangles)
        if vertex_count == 0 or triangle_count == 0:
            return None

        positions = np.empty(vertex_count * 3, dtype=np.float32)
        me.vertices.foreach_get("co", positions)

        tris = me.loop_triangles
        indices = np.empty(triangle_count * 3, dtype=np.int32)
        tris.foreach_get("vertices", indices)
        normals = np.empty(triangle_count * 9, dtype=np.float32)
        tris.foreach_get("split_normals", normals)
        slots = np.empty(triangle_count, dtype=np.int32)
        tris.foreach_get("material_index", slots)

        uvs = None
        # The UV map marked for rendering (the camera icon), else the active one.
        uv_layer = next((layer for layer in me.uv_layers if layer.active_render),
                        me.uv_layers.active)
        if uv_layer is not None:
            corners = np.empty(triangle_count * 3, dtype=np.int32)
            tris.foreach_get("loops", corners)
            loop_uvs = np.empty(len(me.loops) * 2, dtype=np.float32)
            uv_layer.data.foreach_get("uv", loop_uvs)
            uvs = np.ascontiguousarray(loop_uvs.reshape(-1, 2)[corners].reshape(-1))

        return {
            "positions": positions,
            "indices": indices.view(np.uint32),
            "normals": normals,
            "uvs": uvs,
            # Material slot 0 everywhere is the core's default: skip the array then.
            "material_slots": slots.view(np.uint32) if slots.any() else None,
        }
    finally:
        ob.to_mesh_clear()


def add_mesh(ob, ctx):
    """Add the evaluated object's geometry to the core scene; the mesh id or None."""
    arrays = read_mesh(ob, ctx)
    if arrays is None:
        return None
    try:
        mesh_id = ctx.core.add_mesh(**arrays)
    except core.PhosError as ex:
        raise core.PhosError("object '%s': %s" % (ob.name, ex), ex.status) from None
    ctx.stats["meshes"] += 1
    ctx.stats["triangles"] += arrays["indices"].size // 3
    return mesh_id
