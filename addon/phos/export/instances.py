# SPDX-License-Identifier: GPL-3.0-or-later
"""Depsgraph object instances → core meshes, instances and lights.

`depsgraph.object_instances` yields exactly what Blender renders: real
objects, collection instances, particle and geometry-nodes instances, and
the mesh component of curves, text, surfaces and metaballs (yielded as a
MESH instance of their own). Each yielded item is only valid during its
iteration step, so the matrix is copied and the mesh converted inside the
loop.

Geometry is shared: the key is the evaluated mesh datablock. Objects using
the same mesh without modifiers, collection instances of them and
geometry-nodes instances of one geometry all point at one evaluated mesh,
while an object with modifiers gets its own evaluated mesh, so the key
tells them apart without comparing modifier stacks.
"""

import collections
import re
import time

import numpy as np

from .. import core
from . import light, material, mesh, mesh_attributes
from .hashing import hash_uint2

# How often (wall time, s) the export asks `cancelled` and reports progress.
# Counted over every depsgraph instance, not over objects: one object can
# scatter 10^5 geometry-nodes or particle instances, and an export that
# asked once per 16 objects could not be cancelled at all there. A clock
# read per instance costs ~0.1 µs against the several µs the instance
# itself takes, so cancel returns within about CANCEL_CHECK_SECONDS plus
# one instance (a single huge mesh conversion cannot be interrupted).
CANCEL_CHECK_SECONDS = 0.02

# Object types whose geometry arrives as a MESH instance, or that do not render.
_SILENT_TYPES = {'CURVE', 'FONT', 'SURFACE', 'META', 'EMPTY', 'CAMERA', 'ARMATURE',
                 'LATTICE', 'SPEAKER', 'LIGHT_PROBE'}


_VISIBILITY = ("visible_camera", "visible_diffuse", "visible_glossy", "visible_transmission",
               "visible_shadow")


def _hash_string(text):
    h = 0
    for ch in text.encode("utf-8"):
        h = (h * 37 + ch) & 0xFFFFFFFF
    return h


def object_random(inst, ob):
    """Object Info's Random as Cycles computes it: an instance's random id,
    or for an object itself the hash of its name, over 2^32 − 1."""
    rid = inst.random_id & 0xFFFFFFFF if inst.is_instance else hash_uint2(_hash_string(ob.name), 0)
    return float(np.float32(rid * (1.0 / 0xFFFFFFFF)))


def _check_object(ob, ctx):
    """Warn about per-object render settings the core does not have (once per object)."""
    if any(not getattr(ob, name, True) for name in _VISIBILITY) or \
            getattr(ob, "is_holdout", False) or getattr(ob, "is_shadow_catcher", False):
        ctx.warn("Phos: object '%s': ray visibility, holdout and shadow catcher settings are "
                 "not supported; rendered as a normal visible object" % ob.name)
    for psys in getattr(ob, "particle_systems", ()):
        settings = psys.settings
        if settings.type == 'HAIR' and settings.render_type == 'PATH':
            ctx.warn("Phos: object '%s': hair particles are not supported; skipped" % ob.name)


def _materials(ob, ctx):
    """Core material ids per material slot (respecting Object/Data links)."""
    ids = [material.add_material(slot.material, ctx) for slot in ob.material_slots]
    return ids or [material.default_material(ctx)]


def _attribute_keys(material_ids, ctx):
    """The mesh attributes the materials read (mesh_attributes.py)."""
    keys = set()
    for mat_id in material_ids:
        keys |= ctx.material_attributes.get(mat_id, frozenset())
    return keys


class _PendingInstances:
    """Instances gathered for one phos_scene_add_instances call per BATCH:
    one ctypes call per instance cost more than the rest of its export in a
    geometry-nodes scatter of a million. Each instance keeps the entry of
    the (object, mesh) it shares with the others of that pair (mesh id,
    materials, pass index, object name)."""

    BATCH = 65536

    def __init__(self, ctx):
        self.ctx = ctx
        self.transforms = np.empty((self.BATCH, 12), dtype=np.float32)
        self._clear()

    def _clear(self):
        self.entries, self.randoms = [], []

    def add(self, entry, matrix, random):
        n = len(self.entries)
        # A Matrix's rows unpacked: a sixth of np.array(matrix)'s cost.
        self.transforms[n] = (*matrix[0], *matrix[1], *matrix[2])
        self.entries.append(entry)
        self.randoms.append(random)
        if n + 1 == self.BATCH:
            self.flush()

    def flush(self):
        n = len(self.entries)
        if n == 0:
            return
        transforms, entries, randoms = self.transforms[:n], self.entries, self.randoms
        finite = np.isfinite(transforms).all(axis=1)
        if not finite.all():
            for name in sorted({entries[k].name for k in np.flatnonzero(~finite)}):
                self.ctx.warn("Phos: object '%s': its transform is not finite (NaN/Inf); skipped" % name)
            keep = np.flatnonzero(finite)
            transforms = transforms[keep]
            entries = [entries[k] for k in keep]
            randoms = [randoms[k] for k in keep]
        try:
            self.ctx.core.add_instances([e.mesh_id for e in entries], transforms, [e.materials for e in entries],
                                        randoms, [e.pass_index for e in entries])
        except core.PhosError as ex:
            # The core names the instance by its index in the call.
            m = re.search(r"instance (\d+) of \d+: (.*)", str(ex))
            if m and int(m.group(1)) < len(entries):
                raise core.PhosError("object '%s': %s" % (entries[int(m.group(1))].name, m.group(2)),
                                     ex.status) from None
            raise
        self.ctx.stats["instances"] += len(entries)
        self._clear()


# What the instances of one evaluated mesh under one object share.
_Entry = collections.namedtuple("_Entry", "mesh_id materials pass_index name")


def object_shading(ob):
    """What an object gives shading besides its geometry and transform: its
    slots' materials and Object Info's colour and index (compared by
    Persistent Data and the viewport, engine._changes_in_place)."""
    return (tuple(slot.material.original.as_pointer() if slot.material else 0 for slot in ob.material_slots),
            tuple(getattr(ob, "color", ())), float(getattr(ob, "pass_index", 0)))


def _entry(ob, ctx):
    """The core mesh, materials and pass index of an object's evaluated mesh
    (None if the mesh has nothing to render)."""
    ctx.object_shading[ob.original.as_pointer()] = object_shading(ob)
    # Materials first: the mesh exports the attributes they read.
    mats = _materials(ob, ctx)
    key = ob.data.as_pointer()
    attribute_keys = _attribute_keys(mats, ctx)
    if attribute_keys:
        # Objects sharing mesh data share a core mesh when their materials
        # read the same attributes (object-linked materials may not), and
        # Object attributes, constants of each object, agree.
        object_keys = sorted(k for k in attribute_keys if k[0] == "object")
        key = (key, frozenset(attribute_keys),
               tuple(mesh_attributes.object_rgba(ob, k[1]) for k in object_keys))
    if key not in ctx.meshes:
        ctx.meshes[key] = mesh.add_mesh(ob, ctx, attribute_keys)
    mesh_id = ctx.meshes[key]
    if mesh_id is None:
        return None
    return _Entry(mesh_id, mats, float(getattr(ob, "pass_index", 0)), ob.name)


def export_instances(depsgraph, ctx, progress=None, cancelled=None):
    """Add every visible mesh and light instance of the depsgraph.

    `progress(done, total)` is called now and then with the number of
    objects handled; `cancelled()` returning True stops the export early
    (both at most every CANCEL_CHECK_SECONDS). Returns False when cancelled.
    """
    total = len(depsgraph.objects)
    done = 0
    entries = {}  # (object, evaluated mesh) → _Entry (or None): its instances share it
    pending = _PendingInstances(ctx)
    clock = time.monotonic
    next_check = clock() + CANCEL_CHECK_SECONDS
    for inst in depsgraph.object_instances:
        if clock() >= next_check:
            if progress is not None:
                progress(done, total)
            if cancelled is not None and cancelled():
                return False
            next_check = clock() + CANCEL_CHECK_SECONDS
        ob = inst.object
        is_instance = inst.is_instance
        if not is_instance:
            done += 1
        kind = ob.type
        if kind == 'LIGHT':
            matrix = np.array(inst.matrix_world, dtype=np.float64)
            if np.isfinite(matrix).all():
                light.add_light(ob, matrix, ctx, is_instance=is_instance)
            else:
                ctx.warn("Phos: light '%s': its transform is not finite (NaN/Inf); skipped" % ob.name)
            continue
        if kind != 'MESH':
            if kind not in _SILENT_TYPES:
                ctx.warn("Phos: objects of type %s are not supported; '%s' skipped"
                         % (kind.replace('_', ' ').lower(), ob.name))
            continue
        if not is_instance:
            _check_object(ob, ctx)
        if not inst.show_self:
            continue  # an emitter whose particles render but not itself
        key = (ob.original.as_pointer(), ob.data.as_pointer())
        entry = entries.get(key, False)
        if entry is False:
            entry = entries[key] = _entry(ob, ctx)
        if entry is None:
            continue
        pending.add(entry, inst.matrix_world, object_random(inst, ob))
    pending.flush()
    ctx.stats["objects"] = total
    if progress is not None:
        progress(total, total)
    return True
