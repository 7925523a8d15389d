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
        self.entries, self.randoms, self.owners = [], [], []

    def add(self, entry, matrix, random, owner):
        """owner: the object's original pointer when the instance is the
        object itself (not instanced), else None."""
        n = len(self.entries)
        # A Matrix's rows unpacked: a sixth of np.array(matrix)'s cost.
        self.transforms[n] = (*matrix[0], *matrix[1], *matrix[2])
        self.entries.append(entry)
        self.randoms.append(random)
        self.owners.append(owner)
        if n + 1 == self.BATCH:
            self.flush()

    def flush(self):
        n = len(self.entries)
        if n == 0:
            return
        transforms, entries, randoms, owners = self.transforms[:n], self.entries, self.randoms, self.owners
        finite = np.isfinite(transforms).all(axis=1)
        if not finite.all():
            for name in sorted({entries[k].name for k in np.flatnonzero(~finite)}):
                self.ctx.warn("Phos: object '%s': its transform is not finite (NaN/Inf); skipped" % name)
            for k in np.flatnonzero(~finite):
                if owners[k] is not None:
                    self.ctx.object_instances[owners[k]] = None  # not placed: a move must export again
            keep = np.flatnonzero(finite)
            transforms = transforms[keep]
            entries = [entries[k] for k in keep]
            randoms = [randoms[k] for k in keep]
            owners = [owners[k] for k in keep]
        try:
            first = self.ctx.core.add_instances([e.mesh_id for e in entries], transforms,
                                                [e.materials for e in entries], randoms,
                                                [e.pass_index for e in entries])
        except core.PhosError as ex:
            # The core names the instance by its index in the call.
            m = re.search(r"instance (\d+) of \d+: (.*)", str(ex))
            if m and int(m.group(1)) < len(entries):
                raise core.PhosError("object '%s': %s" % (entries[int(m.group(1))].name, m.group(2)),
                                     ex.status) from None
            raise
        # Objects placed as themselves can later move, or change shape, in
        # place (move_object, reshape_object).
        for k, owner in enumerate(owners):
            placed = self.ctx.object_instances.setdefault(owner, []) if owner is not None else None
            if placed is not None:
                placed.append(_Placed(first + k, entries[k], randoms[k]))
        self.ctx.stats["instances"] += len(entries)
        self._clear()


# What the instances of one evaluated mesh under one object share.
_Entry = collections.namedtuple("_Entry", "mesh_id materials pass_index name")
# A core instance of an object placed as itself: its id, entry and Object Info random.
_Placed = collections.namedtuple("_Placed", "instance_id entry random")


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
    ctx.mesh_users.setdefault(mesh_id, set()).add(ob.original.as_pointer())
    return _Entry(mesh_id, mats, float(getattr(ob, "pass_index", 0)), ob.name)


def _placed(ob, ctx):
    """The core instances of an object placed as itself, or None if an edit
    of it cannot be applied in place: it was not exported as itself (new,
    empty, or not a mesh), instances others or is instanced, or a material
    reads its place (Texture Coordinate's Object)."""
    original = ob.original.as_pointer()
    if original in ctx.instanced or original in ctx.referenced_objects:
        return None
    return ctx.object_instances.get(original)


def move_object(ob, ctx):
    """Move an exported object's instances to its new transform (scene
    updates, phos.h); False if that cannot stand for an export."""
    placed = _placed(ob, ctx)
    m = ob.matrix_world
    transform = (*m[0], *m[1], *m[2])
    if placed is None or not np.isfinite(transform).all():
        return False
    for p in placed:
        e = p.entry
        ctx.core.update_instance(p.instance_id, e.mesh_id, transform, e.materials, p.random, e.pass_index)
    return True


def reshape_objects(obs, ctx):
    """Replace the core meshes of objects whose geometry changed (scene
    updates); False if that cannot stand for an export: an object not
    placed as itself, a core mesh also used by an object not in `obs`, by
    an instance, or by objects whose evaluated meshes now differ, or
    geometry that no longer renders."""
    meshes, evaluated = {}, {}
    for ob in obs:
        placed = _placed(ob, ctx)
        if not placed:
            return False
        for p in placed:
            meshes.setdefault(p.entry.mesh_id, (ob, p.entry))
            evaluated.setdefault(p.entry.mesh_id, set()).add(ob.data.as_pointer())
    changed = {ob.original.as_pointer() for ob in obs}
    for mesh_id, (ob, e) in meshes.items():
        # A shared core mesh stays shared only if its objects still share
        # one evaluated mesh (a modifier added to one of them parts them).
        if mesh_id in ctx.instanced_meshes or not ctx.mesh_users.get(mesh_id, set()) <= changed or \
                len(evaluated[mesh_id]) > 1:
            return False
        if not mesh.update_mesh(ob, ctx, mesh_id, _attribute_keys(e.materials, ctx)):
            return False
    return True


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
        original = ob.original.as_pointer()
        key = (original, ob.data.as_pointer())
        entry = entries.get(key, False)
        if entry is False:
            entry = entries[key] = _entry(ob, ctx)
        if is_instance:
            # Instanced geometry, and what instances it: only a new export
            # follows their edits.
            ctx.instanced.add(original)
            if inst.parent is not None:
                ctx.instanced.add(inst.parent.original.as_pointer())
            if entry is not None:
                ctx.instanced_meshes.add(entry.mesh_id)
        if entry is None:
            if not is_instance:
                ctx.object_instances[original] = None  # nothing to render now: an edit must export again
            continue
        pending.add(entry, inst.matrix_world, object_random(inst, ob), None if is_instance else original)
    pending.flush()
    ctx.stats["objects"] = total
    if progress is not None:
        progress(total, total)
    return True
