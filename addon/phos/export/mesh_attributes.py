# SPDX-License-Identifier: GPL-3.0-or-later
"""Mesh attributes for the Attribute, Color Attribute, UV Map and Geometry
nodes (phos.h, phos_mesh_attribute; docs/architecture.md, "Shader programs").

A material's program reads an attribute by a scene-wide number; the
compiler asks `attribute_id` for the number of a key and remembers the keys
each material reads, and a mesh exports only the attributes its materials
read, so meshes whose materials read none cost nothing. Keys:

    ("name", name)        an attribute by name: a colour, float, vector or
                          2D attribute (point, corner or face domain) or a
                          UV map
    ("render_color",)     the colour attribute marked for rendering (the
                          Color Attribute node with no name)
    ("pointiness",)       Geometry's Pointiness, computed here as Cycles does
    ("random_per_island",) Geometry's Random Per Island, likewise
    ("parametric",)       Geometry's Parametric: the barycentric coordinates
    ("object", name)      an Object attribute: the object's or its data's
                          property, constant over the mesh (the export keeps
                          one mesh per distinct value)
    ("tangent", uv_map)   the MikkTSpace tangents of a UV map (x, y, z and the
                          bitangent sign, as a colour), for a Normal Map

Every attribute goes to the core per triangle corner, 4 floats each, and
the core interpolates it barycentrically: a point-domain value is copied to
the corners of its vertex, a face-domain one to the corners of its face.
"""

import math

import numpy as np

from .. import core
from .hashing import hash_uint

_FLOAT, _FLOAT2, _VECTOR, _COLOR = (core.PHOS_ATTRIBUTE_FLOAT, core.PHOS_ATTRIBUTE_FLOAT2,
                                    core.PHOS_ATTRIBUTE_VECTOR, core.PHOS_ATTRIBUTE_COLOR)

# Blender's attribute data types → (core type, RNA field of a value, floats per value).
_DATA_TYPES = {
    'FLOAT': (_FLOAT, "value", 1),
    'INT': (_FLOAT, "value", 1),
    'INT8': (_FLOAT, "value", 1),
    'BOOLEAN': (_FLOAT, "value", 1),
    'FLOAT2': (_FLOAT2, "vector", 2),
    'FLOAT_VECTOR': (_VECTOR, "vector", 3),
    'FLOAT_COLOR': (_COLOR, "color", 4),
    'BYTE_COLOR': (_COLOR, "color", 4),   # RNA gives the linear colour, as Cycles converts it
}


def attribute_id(ctx, key):
    """The scene-wide number ATTRIBUTE instructions read `key` by."""
    ids = ctx.attribute_ids
    if key not in ids:
        ids[key] = len(ids)
    return ids[key]


class Topology:
    """What the attribute readers need of an evaluated mesh's triangles:
    each corner's loop and vertex, each triangle's face."""

    def __init__(self, me, corners, loop_vertices, tri_faces):
        self.me = me
        self.corners = corners               # (T*3,) loop index per triangle corner
        self.corner_vertices = loop_vertices[corners]
        self.tri_faces = tri_faces           # (T,) face index per triangle

    @property
    def triangle_count(self):
        return self.tri_faces.size


def _per_corner(values, topo, domain):
    """(T*3, n) values per triangle corner from a domain's (count, n) values;
    None for a domain Cycles does not read on meshes (edges)."""
    if domain == 'POINT':
        return values[topo.corner_vertices]
    if domain == 'CORNER':
        return values[topo.corners]
    if domain == 'FACE':
        return np.repeat(values[topo.tri_faces], 3, axis=0)
    return None


def _pack(per_corner):
    """(T*3, n) → the core's T*12 float32: 4 floats per corner."""
    out = np.zeros((per_corner.shape[0], 4), dtype=np.float32)
    out[:, :per_corner.shape[1]] = per_corner
    return out.reshape(-1)


def _read_generic(attr, topo):
    """(type, values) of a Blender attribute, or None for an unsupported one."""
    spec = _DATA_TYPES.get(attr.data_type)
    if spec is None:
        return None
    kind, field, width = spec
    count = len(attr.data)
    dtype = bool if attr.data_type == 'BOOLEAN' else (np.int32 if attr.data_type in {'INT', 'INT8'}
                                                      else np.float32)
    raw = np.empty(count * width, dtype=dtype)
    attr.data.foreach_get(field, raw)
    corner = _per_corner(raw.astype(np.float32).reshape(count, width), topo, attr.domain)
    if corner is None:
        return None
    return kind, _pack(corner)


def _read_uv_layer(layer, topo):
    count = len(layer.data)
    raw = np.empty(count * 2, dtype=np.float32)
    layer.data.foreach_get("uv", raw)
    return _FLOAT2, _pack(raw.reshape(count, 2)[topo.corners])


def _read_named(name, topo):
    """(type, values) of the attribute or UV map called `name`, None if the
    mesh has none or one Phos cannot read, and why."""
    me = topo.me
    uv = me.uv_layers.get(name)
    if uv is not None:
        return _read_uv_layer(uv, topo), None
    attr = me.attributes.get(name)
    if attr is None:
        return None, "has no attribute '%s'" % name
    read = _read_generic(attr, topo)
    if read is None:
        return None, "attribute '%s' (%s on %s) is not supported" % (
            name, attr.data_type.lower(), attr.domain.lower())
    return read, None


def _uv_tangents(name, topo):
    """Blender's MikkTSpace tangents of the UV map `name` per corner (x, y,
    z, bitangent sign), as Cycles computes them for a Normal Map of that map."""
    me = topo.me
    if me.uv_layers.get(name) is None:
        return None, "has no UV map '%s' for its normal map's tangents" % name
    try:
        me.calc_tangents(uvmap=name)
    except RuntimeError as ex:
        return None, "cannot have tangents of UV map '%s' (%s)" % (name, ex)
    n = len(me.loops)
    t = np.empty(n * 3, dtype=np.float32)
    me.loops.foreach_get("tangent", t)
    sign = np.empty(n, dtype=np.float32)
    me.loops.foreach_get("bitangent_sign", sign)
    loops = np.concatenate([t.reshape(-1, 3), sign[:, None]], axis=1)
    return (_COLOR, _pack(loops[topo.corners])), None


def property_rgba(owner, name):
    """A property as the RGBA Cycles reads for an Object or View Layer
    attribute (Blender's find_property_rgba): a custom property of that
    name, else the RNA path; a number gives (v, v, v, 1), an array of up to
    4 numbers fills (0, 0, 0, 1) from the front. None if there is none."""
    if owner is None:
        return None
    value = None
    try:
        if name in owner.keys():
            value = owner[name]
    except (TypeError, AttributeError):
        pass
    if value is None:
        try:
            value = owner.path_resolve(name)
        except (ValueError, TypeError, AttributeError):
            return None
    if isinstance(value, (bool, int, float)):
        v = float(value)
        return (v, v, v, 1.0)
    try:
        numbers = [float(x) for x in value]
    except (TypeError, ValueError):
        return None
    if not 0 < len(numbers) <= 4:
        return None
    return tuple(numbers + [0.0, 0.0, 0.0, 1.0][len(numbers):])


def object_rgba(ob, name):
    """An Object attribute: the object's property, else its data's (Cycles
    without instancer lookup)."""
    value = property_rgba(ob, name)
    if value is None:
        value = property_rgba(getattr(ob, "data", None), name)
    return value


def view_layer_rgba(ctx, name):
    """A View Layer attribute: the view layer's property, else the scene's,
    else the world's (Blender's BKE_view_layer_find_rgba_attribute)."""
    for owner in (ctx.view_layer, ctx.scene, getattr(ctx.scene, "world", None)):
        value = property_rgba(owner, name)
        if value is not None:
            return value
    return None


def _render_color(topo):
    """The colour attribute marked for rendering, as Cycles reads for the
    Color Attribute node without a name."""
    colors = topo.me.color_attributes
    index = getattr(colors, "render_color_index", -1)
    if index is None or not 0 <= index < len(colors):
        return None, "has no colour attribute"
    return _read_generic(colors[index], topo), None


# ------------------------------------------------------------- pointiness

FLT_EPSILON = np.float32(2.0 ** -23)


def _welded(positions):
    """Index of the vertex each vertex is merged with before pointiness is
    measured, as Cycles merges them (so that seams do not show): vertices
    sorted by x + y + z (float32; equal positions by decreasing index),
    each merged with the first after it, within 3·FLT_EPSILON of its sum,
    closer than √FLT_EPSILON; then chains followed to their end."""
    p = positions.astype(np.float32)
    count = p.shape[0]
    sums = (p[:, 0] + p[:, 1]) + p[:, 2]
    order = np.lexsort((-np.arange(count), sums))
    sorted_sums, sorted_p = sums[order], p[order]
    orig = np.arange(count)
    open_ = np.arange(count)          # sorted positions still looking
    k = 1
    while open_.size:
        open_ = open_[open_ + k < count]
        open_ = open_[~(sorted_sums[open_ + k] - sorted_sums[open_] > 3 * FLT_EPSILON)]
        if not open_.size:
            break
        d = sorted_p[open_ + k] - sorted_p[open_]
        near = (d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1] + d[:, 2] * d[:, 2]) < FLT_EPSILON
        orig[order[open_[near]]] = order[open_[near] + k]
        open_ = open_[~near]
        k += 1
    while True:
        nxt = orig[orig]
        if np.array_equal(nxt, orig):
            return orig
        orig = nxt


def pointiness(me, positions, vertex_normals):
    """Geometry's Pointiness per vertex, as Cycles computes it at export:
    the angle between the (welded) vertex normal and the mean direction of
    the vertex's edges, over π, then averaged with the values of its edge
    neighbours (a blur that approximates a two-ring neighbourhood)."""
    count = positions.shape[0]
    orig = _welded(positions)
    normals = np.zeros((count, 3), dtype=np.float64)
    np.add.at(normals, orig, vertex_normals.astype(np.float64))
    length = np.linalg.norm(normals, axis=1)
    normals /= np.where(length > 0.0, length, 1.0)[:, None]

    edges = np.empty(len(me.edges) * 2, dtype=np.int64)
    me.edges.foreach_get("vertices", edges)
    edges = orig[edges.reshape(-1, 2)]
    edges = np.unique(np.sort(edges, axis=1), axis=0)     # each welded edge once
    edges = edges[edges[:, 0] != edges[:, 1]]
    v0, v1 = edges[:, 0], edges[:, 1]
    d = positions[v1].astype(np.float64) - positions[v0]
    d /= np.maximum(np.linalg.norm(d, axis=1), 1e-30)[:, None]
    accum = np.zeros((count, 3))
    np.add.at(accum, v0, d)
    np.add.at(accum, v1, -d)
    counter = np.bincount(v0, minlength=count) + np.bincount(v1, minlength=count)
    mean = accum / np.maximum(counter, 1)[:, None]
    cosine = np.clip(np.einsum("ij,ij->i", normals, mean), -1.0, 1.0)
    raw = np.where(counter > 0, np.arccos(cosine) / math.pi, 0.0)
    raw[orig != np.arange(count)] = 0.0       # duplicates take their original's value below
    blurred = raw.copy()
    np.add.at(blurred, v0, raw[v1])
    np.add.at(blurred, v1, raw[v0])
    blurred /= counter + 1
    return blurred[orig].astype(np.float32)


# ------------------------------------------------------- random per island

def _island_roots(vertex_count, edges):
    """Each vertex's island representative, as Cycles' disjoint set finds
    it: edges joined in order, union by rank, the root of the higher rank
    (the first argument's on a tie) kept."""
    parent = list(range(vertex_count))
    rank = [0] * vertex_count

    def find(x):
        root = x
        while parent[root] != root:
            root = parent[root]
        while parent[x] != root:
            parent[x], x = root, parent[x]
        return root

    for a, b in edges:
        ra, rb = find(a), find(b)
        if ra == rb:
            continue
        if rank[ra] < rank[rb]:
            ra, rb = rb, ra
        parent[rb] = ra
        if rank[ra] == rank[rb]:
            rank[ra] += 1
    return [find(v) for v in range(vertex_count)]


def random_per_island(me, topo):
    """Geometry's Random Per Island per triangle: the hash of its island's
    representative vertex over 2^32 − 1 (Cycles' hash_uint_to_float)."""
    edges = np.empty(len(me.edges) * 2, dtype=np.int64)
    me.edges.foreach_get("vertices", edges)
    roots = np.array(_island_roots(len(me.vertices), edges.reshape(-1, 2).tolist()), dtype=np.int64)
    first_vertex = topo.corner_vertices.reshape(-1, 3)[:, 0]
    table = {}
    values = np.empty(topo.triangle_count, dtype=np.float32)
    for i, root in enumerate(roots[first_vertex].tolist()):
        if root not in table:
            table[root] = np.float32(np.float32(hash_uint(root)) / np.float32(0xFFFFFFFF))
        values[i] = table[root]
    return _pack(np.repeat(values, 3)[:, None])


def parametric(topo, corner_of_first):
    """Geometry's Parametric: (1, 0, 0), (0, 1, 0) and (0, 0, 0) at three of
    each triangle's corners, interpolated into the barycentric coordinates.
    Which corner takes which depends on Cycles' barycentric convention
    (corner_of_first: the triangle corner whose weight is the first value)."""
    basis = np.zeros((3, 3), dtype=np.float32)
    basis[corner_of_first, 0] = 1.0
    basis[(corner_of_first + 1) % 3, 1] = 1.0
    return _pack(np.tile(basis, (topo.triangle_count, 1)))


# ------------------------------------------------------------------ export

def read_attributes(ob, topo, keys, positions, vertex_normals, ctx):
    """[(id, type, T*12 float32)] of the attributes `keys` the object's
    materials read; a missing one is left out (the core reads 0, as Cycles
    does) with a warning."""
    out = []
    me = topo.me
    for key in sorted(keys, key=lambda k: attribute_id(ctx, k)):
        kind = key[0]
        why = None
        if kind == "name":
            read, why = _read_named(key[1], topo)
        elif kind == "render_color":
            read, why = _render_color(topo)
        elif kind == "tangent":
            read, why = _uv_tangents(key[1], topo)
        elif kind == "object":
            value = object_rgba(ob, key[1])
            if value is None:
                # Cycles reads (0, 0, 0, 0): alpha 0, unlike a missing mesh attribute.
                ctx.warn("Phos: object '%s' has no property '%s'; its materials read 0 there, as in Cycles"
                         % (ob.name, key[1]))
                value = (0.0, 0.0, 0.0, 0.0)
            read = _COLOR, _pack(np.tile(np.float32(value), (topo.corners.size, 1)))
        elif kind == "pointiness":
            read = _FLOAT, _pack(pointiness(me, positions.reshape(-1, 3), vertex_normals)
                                 [topo.corner_vertices][:, None])
        elif kind == "random_per_island":
            read = _FLOAT, random_per_island(me, topo)
        elif kind == "parametric":
            read = _VECTOR, parametric(topo, 0)
        else:
            read = None
        if read is None:
            ctx.warn("Phos: object '%s' %s; its materials read 0 there, as in Cycles"
                     % (ob.name, why or "has no attribute %s" % (key,)))
            continue
        out.append((attribute_id(ctx, key), read[0], read[1]))
    return out
