# SPDX-License-Identifier: GPL-3.0-or-later
"""Evaluated meshes → core meshes (object space, triangles).

Everything is read with foreach_get into numpy arrays: a Python loop over
vertices would take seconds on a production mesh, foreach_get takes
milliseconds. The mesh is evaluated (modifiers, geometry nodes applied) by
`Object.to_mesh()` on the evaluated object and freed right after.

Two repairs happen here, both in numpy over whole arrays (no loop over
triangles: meshes have millions):

- Broken geometry is dropped, not fatal (`_drop_broken`). The core refuses
  non-finite positions, normals and UVs, and would have to invent a normal
  for a triangle of zero area; Cycles renders the rest of such a mesh. So
  triangles that use a non-finite (NaN/Inf) vertex and degenerate ones are
  skipped, with one warning per object that counts them.
- Smooth normals are made the same in every evaluation
  (`_deterministic_vertex_normals`): Blender 3.4 accumulates vertex normals
  on several threads, so two evaluations of one mesh differ in the last bit.
"""

import math

import numpy as np

from .. import core
from . import mesh_attributes

# A triangle is degenerate when |e1 × e2| ≤ DEGENERATE_SINE · |e1| · |e2|,
# e1 and e2 its edges from the first corner, computed in float64 from the
# float32 positions (products and most differences are exact there, so 0
# means exactly collinear or coincident corners; repeated indices give 0
# too). The core computes a triangle's normal and area as e1 × e2 in float32
# (Embree's geometric normal, emissive triangles in lights/light.c), with a
# rounding error of about 2^-23·|e1||e2|: when the sine of the angle at the
# first corner is below 2^-23 (float32's epsilon) that normal is rounding
# noise and can be exactly 0, a NaN once normalised. Such a triangle is a
# sliver thinner than float32 resolves, so dropping it opens no visible gap.
# The test is scale-free: a tiny well-shaped triangle is kept.
DEGENERATE_SINE = 2.0 ** -23

# A vertex normal recomputed here replaces Blender's when they agree within
# this (per component). Both are the same angle-weighted sum; they differ by
# float32 rounding (Blender's and this one's): measured up to
# 1.1e-5 on a subdivided Suzanne, 4.9e-6 on a 64 × 32 UV sphere, 1.2e-7 to
# 4.8e-7 on a torus, an icosphere and a cylinder (Blender 3.4). The jitter
# between evaluations is far smaller: on the UV spheres of
# scenes/cornell_box.py (35 712 normal values each), over 30 renders in one
# session, 26–28 of 1 986 vertices, 574–610 values, by up to 8.9e-8 (1.5
# ulp of 1.0; components near 0 by up to 2.9e-9). 1e-3 is 100× the rounding
# and 10^4× the jitter, so the choice is the same in every evaluation; a
# difference beyond it is one of method (a vertex without faces, which
# Blender gives its normalised position), where Blender's value is kept.
VERTEX_NORMAL_TOLERANCE = 1e-3


# A corner normal this close (per component) to Blender's vertex normal of
# its vertex is that vertex normal, copied or summed again over a fan that
# is the whole vertex (see _smooth_normals).
CORNER_NORMAL_TOLERANCE = 1e-5


def _foreach(collection, attr, count, dtype):
    out = np.empty(count, dtype=dtype)
    collection.foreach_get(attr, out)
    return out


def _deterministic_vertex_normals(me, positions, loop_vertices):
    """(stable, Blender's): vertex normals (V, 3) float32, the first the same
    in every evaluation.

    Blender's vertex normal is the sum of the normals of the faces around
    the vertex, each weighted by the face's angle at the vertex (Thürmer and
    Wüthrich, "Computing vertex normals from polygonal facets", JGT 3(1),
    1998), normalised. Blender 3.4 sums with atomic float adds on several
    threads, so the order of the additions, and the last bit of the result,
    changes from one evaluation to the next (not with `blender -t 1`): two
    renders of a smooth mesh in one session were not bit-identical.
    Snapping each component to a grid does not cure it: a value next to a
    grid boundary still falls either way (on those spheres, with a 2^-20
    grid 12 of the ~600 jittering values still differed, with 2^-24 154 to
    190).

    So the same sum is computed by the core in a fixed order
    (phos_vertex_normals, in C: 33 ms for a million triangles, where the
    same sum in numpy took 0.24 s), from Blender's face normals (each computed by one thread, so
    stable) and corner angles from the positions. Where it agrees with
    Blender's within VERTEX_NORMAL_TOLERANCE it replaces it; elsewhere
    (vertices whose faces nearly cancel, non-finite input, an invalid
    mesh) Blender's value is kept.
    """
    theirs = _foreach(me.vertices, "normal", len(me.vertices) * 3, np.float32).reshape(-1, 3)
    polys = me.polygons
    face_count = len(polys)
    if face_count == 0:
        return theirs, theirs
    totals = _foreach(polys, "loop_total", face_count, np.uint32)
    starts = _foreach(polys, "loop_start", face_count, np.uint32)
    face_normals = _foreach(polys, "normal", face_count * 3, np.float32)
    try:
        mine = core.vertex_normals(positions, starts, totals, face_normals, loop_vertices).reshape(-1, 3)
    except core.PhosError:
        return theirs, theirs  # a face of fewer than 3 corners, a corner out of range: an invalid mesh
    with np.errstate(invalid="ignore"):
        diff = np.abs(mine - theirs)
        far = ~(diff[:, 0] <= VERTEX_NORMAL_TOLERANCE)                    # NaN: far
        far |= ~(diff[:, 1] <= VERTEX_NORMAL_TOLERANCE)
        far |= ~(diff[:, 2] <= VERTEX_NORMAL_TOLERANCE)
    mine[far] = theirs[far]
    return mine, theirs


def _corner_normal_domain(me, smooth):
    """Where the corner normals come from: 'POINT' (vertex normals), 'FACE'
    (face normals) or 'CORNER' (anything else: auto smooth, custom normals,
    flat and smooth faces mixed)."""
    domain = getattr(me, "normals_domain", None)  # Blender 4.1+
    if domain is not None:
        return domain
    if me.use_auto_smooth or me.has_custom_normals:
        return 'CORNER'
    if smooth.all():
        return 'POINT'
    return 'FACE' if not smooth.any() else 'CORNER'


def _smooth_normals(me, tris, positions, loop_vertices, indices, smooth):
    """Corner normals of the triangles (T*9 float32), the same in every evaluation.

    Face normals are computed face by face and so stable; vertex normals
    are made stable by _deterministic_vertex_normals. With auto smooth,
    custom normals or flat and smooth faces mixed ('CORNER'), every corner
    normal within CORNER_NORMAL_TOLERANCE of Blender's vertex normal of its
    vertex takes the stable one: Blender 3.4 sets them from the vertex
    normal, or sums a smooth fan that is the whole vertex (bit-equal or
    within 1.8e-7 of the vertex normal on an auto-smooth UV sphere, and
    jittering as much); fans split by a sharp edge and custom normals
    differ by far more (0.1 or more on an auto-smooth cylinder).
    """
    domain = _corner_normal_domain(me, smooth)
    if domain == 'FACE':
        return _foreach(tris, "split_normals", len(tris) * 9, np.float32)
    stable, theirs = _deterministic_vertex_normals(me, positions, loop_vertices)
    if domain == 'POINT':
        return stable[indices].reshape(-1)
    normals = _foreach(tris, "split_normals", len(tris) * 9, np.float32)
    corner = normals.reshape(-1, 3)
    tol = np.float32(CORNER_NORMAL_TOLERANCE)
    with np.errstate(invalid="ignore"):
        near = np.abs(corner[:, 0] - theirs[:, 0][indices]) <= tol
        near &= np.abs(corner[:, 1] - theirs[:, 1][indices]) <= tol
        near &= np.abs(corner[:, 2] - theirs[:, 2][indices]) <= tol
    corner[near] = stable[indices[near]]
    return normals


def _plural(count, word):
    return "%d %s%s" % (count, word, "" if count == 1 else "s")


def _cross_and_lengths(p, tri, dtype):
    """e1 × e2 (3 arrays), |e1|² and |e2|² of triangles, in `dtype`;
    p is (3, V) component-major, tri (T, 3) vertex indices."""
    e1, e2 = [], []
    for c in range(3):
        q = p[c].astype(dtype, copy=False)
        q0 = q[tri[:, 0]]
        e1.append(q[tri[:, 1]] - q0)
        e2.append(q[tri[:, 2]] - q0)
    cross = (e1[1] * e2[2] - e1[2] * e2[1],
             e1[2] * e2[0] - e1[0] * e2[2],
             e1[0] * e2[1] - e1[1] * e2[0])
    l1 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]
    l2 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2]
    return cross, l1, l2


def _degenerate(p, tri):
    """Boolean mask of degenerate triangles (see DEGENERATE_SINE), exact in float64.

    A float32 pass finds the candidates first, with a bound 2^5 times
    wider than the test (float32 rounds each of e1 × e2's components by
    about 2^-22·|e1||e2|); only those are tested again in float64, so the
    cost is that of float32 arithmetic on the whole mesh.
    """
    with np.errstate(invalid="ignore", over="ignore", under="ignore"):
        cross, l1, l2 = _cross_and_lengths(p, tri, np.float32)
        area2 = cross[0] * cross[0]
        area2 += cross[1] * cross[1]
        area2 += cross[2] * cross[2]
        l1 *= l2
        l1 *= np.float32((32.0 * DEGENERATE_SINE) ** 2)
        # Not strictly above the bound: also a NaN from an overflow (inf − inf).
        candidates = np.flatnonzero(~(area2 > l1))
        degenerate = np.zeros(tri.shape[0], dtype=bool)
        if candidates.size:
            cross, l1, l2 = _cross_and_lengths(p, tri[candidates], np.float64)
            area2 = cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]
            degenerate[candidates] = area2 <= DEGENERATE_SINE * DEGENERATE_SINE * l1 * l2
    return degenerate


def _drop_broken(name, positions, indices, normals, uvs, slots, ctx, tangents=None, attributes=()):
    """Drop triangles with a non-finite vertex and degenerate ones; repair the rest.

    Arrays are flat (positions V*3, indices T*3, normals T*9, uvs T*6 or None,
    slots T or None; tangents T*12 or None; attributes (id, type, T*12) each).
    Returns them, possibly filtered (T may become 0), after one
    warning naming the object and the counts. Vertices that are not finite
    are set to 0 (no triangle uses them any more, and the core refuses
    them); non-finite normals of the triangles kept become the triangle's
    own normal, non-finite UVs 0.
    """
    p = np.ascontiguousarray(positions.reshape(-1, 3).T)     # (3, V)
    tri = indices.reshape(-1, 3)
    bad_vertex = nonfinite = None
    if not np.isfinite(positions).all():
        bad_vertex = ~(np.isfinite(p[0]) & np.isfinite(p[1]) & np.isfinite(p[2]))
        nonfinite = bad_vertex[tri[:, 0]] | bad_vertex[tri[:, 1]] | bad_vertex[tri[:, 2]]
    degenerate = _degenerate(p, tri)
    if nonfinite is not None:
        degenerate &= ~nonfinite
    n_nonfinite = int(np.count_nonzero(nonfinite)) if nonfinite is not None else 0
    n_degenerate = int(np.count_nonzero(degenerate))

    if n_nonfinite or n_degenerate:
        keep = ~degenerate
        if nonfinite is not None:
            keep &= ~nonfinite
        parts = []
        if n_nonfinite:
            parts.append("%s with non-finite (NaN/Inf) vertices" % _plural(n_nonfinite, "triangle"))
        if n_degenerate:
            parts.append(_plural(n_degenerate, "degenerate triangle"))
        left = int(np.count_nonzero(keep))
        ctx.warn("Phos: object '%s': %s skipped%s" % (
            name, " and ".join(parts), "" if left else "; no triangles are left, the object is not rendered"))
        tri = tri[keep]
        indices = tri.reshape(-1)
        normals = np.ascontiguousarray(normals.reshape(-1, 9)[keep]).reshape(-1)
        if uvs is not None:
            uvs = np.ascontiguousarray(uvs.reshape(-1, 6)[keep]).reshape(-1)
        if tangents is not None:
            tangents = np.ascontiguousarray(tangents.reshape(-1, 12)[keep]).reshape(-1)
        attributes = [(i, kind, np.ascontiguousarray(values.reshape(-1, 12)[keep]).reshape(-1))
                      for i, kind, values in attributes]
        if slots is not None:
            slots = slots[keep]
        if bad_vertex is not None:
            positions = positions.copy()
            positions.reshape(-1, 3)[bad_vertex] = 0.0
            p[:, bad_vertex] = 0.0

    # Normals and UVs that are not finite on triangles that are (a smooth
    # normal next to a dropped NaN vertex, a broken custom normal or UV map).
    if not np.isfinite(normals).all():
        corner = normals.reshape(-1, 3, 3)
        rows, corners = np.nonzero(~np.isfinite(corner).all(axis=2))
        cross, _, _ = _cross_and_lengths(p, tri[rows], np.float64)
        face = np.stack(cross, axis=1)
        face /= np.sqrt(np.einsum("ij,ij->i", face, face))[:, None]  # > 0: not degenerate
        corner[rows, corners] = face
    if uvs is not None and not np.isfinite(uvs).all():
        uvs[~np.isfinite(uvs)] = 0.0
    if tangents is not None and not np.isfinite(tangents).all():
        tangents[~np.isfinite(tangents)] = 0.0
    for _, _, values in attributes:
        values[~np.isfinite(values)] = 0.0
    return positions, indices, normals, uvs, slots, tangents, attributes


def _texture_space(me):
    """(location, size) of the mesh's texture space, which Generated
    coordinates map to [0, 1]³ (Blender computes the automatic one)."""
    loc = getattr(me, "texspace_location", None)
    size = getattr(me, "texspace_size", None)
    if loc is None or size is None:
        return None
    loc, size = tuple(loc), tuple(abs(x) for x in size)
    if not all(math.isfinite(x) for x in loc + size):
        return None  # a mesh with non-finite vertices: the core's automatic one
    return loc, size


def _tree_has(tree, bl_idname, seen=None):
    seen = set() if seen is None else seen
    if tree is None or tree.as_pointer() in seen:
        return False
    seen.add(tree.as_pointer())
    for n in tree.nodes:
        if n.bl_idname == bl_idname and getattr(n, "space", 'TANGENT') == 'TANGENT' and not n.mute:
            return True
        if n.bl_idname == 'ShaderNodeGroup' and _tree_has(n.node_tree, bl_idname, seen):
            return True
    return False


def _reads_tangents(ob):
    """Whether a material of the object has a tangent-space Normal Map or a
    Tangent node (whose UV map mode reads them)."""
    for slot in getattr(ob, "material_slots", ()):
        mat = slot.material
        if mat is not None and mat.node_tree is not None and (_tree_has(mat.node_tree, 'ShaderNodeNormalMap') or
                                                              _tree_has(mat.node_tree, 'ShaderNodeTangent')):
            return True
    return False


def _corner_tangents(me, ob, uv_layer, corners, ctx):
    """Per-corner MikkTSpace tangents (x, y, z, bitangent sign) of the UV
    map, as Blender computes them for Cycles; None where it cannot (faces
    of more than four corners), with a warning."""
    try:
        me.calc_tangents(uvmap=uv_layer.name)
    except RuntimeError as ex:
        ctx.warn("Phos: object '%s': tangents for its normal map could not be computed (%s); the map is "
                 "ignored" % (ob.name, ex))
        return None
    n = len(me.loops)
    t = _foreach(me.loops, "tangent", n * 3, np.float32).reshape(-1, 3)
    sign = _foreach(me.loops, "bitangent_sign", n, np.float32)
    loops = np.concatenate([t, sign[:, None]], axis=1)
    return np.ascontiguousarray(loops[corners].reshape(-1))


def read_mesh(ob, ctx, attribute_keys=()):
    """Triangle arrays of an evaluated object, or None if it has no triangles.

    Returns a dict with positions (V*3 float32), indices (T*3 uint32),
    normals (T*9 float32: per-corner split normals, which are the face normal
    on flat-shaded faces and the smoothed/custom normal elsewhere), uvs
    (T*6 float32 or None), material_slots (T uint32 or None) and the
    attributes of `attribute_keys` that the mesh has (mesh_attributes.py).
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

        positions = _foreach(me.vertices, "co", vertex_count * 3, np.float32)
        tris = me.loop_triangles
        # The UV map marked for rendering (the camera icon), else the active one.
        uv_layer = next((layer for layer in me.uv_layers if layer.active_render),
                        me.uv_layers.active)
        polys = me.polygons
        smooth = _foreach(polys, "use_smooth", len(polys), bool)
        corners = loop_vertices = None
        if uv_layer is not None or smooth.any() or attribute_keys:
            # Triangle corners as loops, then loops → vertices: faster than
            # the triangles' own "vertices" (3 ints per item through RNA),
            # and the loops are needed for UVs and smooth normals anyway.
            corners = _foreach(tris, "loops", triangle_count * 3, np.int32)
            loop_vertices = _foreach(me.loops, "vertex_index", len(me.loops), np.int32)
            indices = loop_vertices[corners]
        else:
            indices = _foreach(tris, "vertices", triangle_count * 3, np.int32)
        if smooth.any():
            normals = _smooth_normals(me, tris, positions, loop_vertices, indices, smooth)
        else:
            # Face normals (flat shading, or custom normals on flat faces):
            # each computed on its own, the same in every evaluation.
            normals = _foreach(tris, "split_normals", triangle_count * 9, np.float32)
        # Blender keeps the faces' material slots as the "material_index"
        # attribute only once a face's slot is set; without it every slot
        # is 0, the core's default, and reading 0 per triangle through RNA
        # cost 0.19 s at 5 M triangles (docs/benchmarks.md, export).
        slots = None
        if me.attributes.get("material_index") is not None:
            slots = _foreach(tris, "material_index", triangle_count, np.int32)

        uvs = tangents = None
        if uv_layer is not None:
            loop_uvs = _foreach(uv_layer.data, "uv", len(me.loops) * 2, np.float32)
            uvs = np.ascontiguousarray(loop_uvs.reshape(-1, 2)[corners].reshape(-1))
            if _reads_tangents(ob):
                tangents = _corner_tangents(me, ob, uv_layer, corners, ctx)

        attributes = []
        if attribute_keys:
            tri_faces = _foreach(tris, "polygon_index", triangle_count, np.int64)
            topo = mesh_attributes.Topology(me, corners, loop_vertices, tri_faces)
            vertex_normals = _foreach(me.vertices, "normal", vertex_count * 3, np.float32).reshape(-1, 3)
            attributes = mesh_attributes.read_attributes(ob, topo, attribute_keys, positions, vertex_normals,
                                                         ctx)

        positions, indices, normals, uvs, slots, tangents, attributes = _drop_broken(
            ob.name, positions, indices, normals, uvs, slots, ctx, tangents, attributes)
        if indices.size == 0:
            return None

        return {
            "positions": positions,
            "indices": indices.view(np.uint32),
            "normals": normals,
            "uvs": uvs,
            "tangents": tangents,
            "attributes": attributes,
            "texspace": _texture_space(me),
            # Material slot 0 everywhere is the core's default: skip the array then.
            "material_slots": slots.view(np.uint32) if slots is not None and slots.any() else None,
        }
    finally:
        ob.to_mesh_clear()


def add_mesh(ob, ctx, attribute_keys=()):
    """Add the evaluated object's geometry to the core scene, with the
    attributes its materials read; the mesh id or None."""
    arrays = read_mesh(ob, ctx, attribute_keys)
    if arrays is None:
        return None
    try:
        mesh_id = ctx.core.add_mesh(**arrays)
    except core.PhosError as ex:
        raise core.PhosError("object '%s': %s" % (ob.name, ex), ex.status) from None
    ctx.stats["meshes"] += 1
    ctx.stats["triangles"] += arrays["indices"].size // 3
    return mesh_id


def update_mesh(ob, ctx, mesh_id, attribute_keys=()):
    """Replace core mesh `mesh_id` by the evaluated object's geometry
    (scene updates); False if it no longer has triangles to render."""
    arrays = read_mesh(ob, ctx, attribute_keys)
    if arrays is None:
        return False
    try:
        ctx.core.update_mesh(mesh_id, **arrays)
    except core.PhosError as ex:
        raise core.PhosError("object '%s': %s" % (ob.name, ex), ex.status) from None
    return True
