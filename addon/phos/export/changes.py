# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender's edits → a kept core scene, changed in place (phos.h, scene
updates): what Persistent Data's next F12 (engine.py) and the viewport
(viewport.py) do with depsgraph.updates instead of a new export.

A kept scene is kept with its export context, which maps Blender's
datablocks to core ids, and with the signature of what it was exported
from. Lights, materials, objects' transforms and their meshes are replaced
in place; anything the core cannot take that way asks for a new export
(None / False below).
"""

import collections

import bpy

from . import instances, light, material, world as world_export


def signature(depsgraph):
    """What the export reads that depsgraph.updates may not list as a change
    of its own: the world assigned, and which objects the render sees (an
    object hidden or shown, or moved into another collection, is tagged
    without a change of geometry, transform or shading)."""
    world = depsgraph.scene.world
    return (world.original.as_pointer() if world is not None else 0,
            frozenset(ob.original.as_pointer() for ob in depsgraph.objects))


class Changes(collections.namedtuple("Changes", "lights materials moved reshaped worlds")):
    """What changes_in_place found to change, evaluated datablocks each:
    light objects, materials, objects moved, objects whose geometry
    changed, and the world (at most one: the scene's)."""

    def __bool__(self):
        return any(len(part) for part in self)

    def summary(self):
        return ", ".join("%d %s" % (len(part), name) for name, part in zip(
            ("lights", "materials", "objects moved", "meshes", "worlds"), self))


def changes_in_place(depsgraph, ctx, exported_signature):
    """The changes the depsgraph reports since the scene of export context
    `ctx` (exported with `exported_signature`) was last rendered, if that
    scene can take them in place: a Changes, false when nothing needs
    changing; else None.

    Cameras (the caller sets the camera again), the scene's own settings
    (render settings reach the core through the render) and collections need
    nothing; a light object or its light data, a material or its node tree,
    the world or its node tree, an object's transform and an object's
    geometry (with its mesh data) are changed in place where apply_changes
    can. Blender 4.x tags objects for
    shading when a material they use is edited, and every object when a
    datablock is added (a relations update): an object tagged for shading
    alone is no change while its materials and Object Info values are as
    exported. Anything else (images, other datablocks) needs an
    export, as do objects added, removed, hidden or shown (signature)."""
    if signature(depsgraph) != exported_signature:
        return None
    lights, light_data, materials, trees = {}, set(), {}, set()
    moved, reshaped, mesh_data, worlds = {}, {}, set(), {}
    for update in depsgraph.updates:
        block = update.id
        if isinstance(block, bpy.types.Object):
            ob = block.evaluated_get(depsgraph)
            key = ob.original.as_pointer()
            if ob.type == 'LIGHT':
                lights[key] = ob
            elif ob.type != 'CAMERA':
                if update.is_updated_transform:
                    moved[key] = ob
                if update.is_updated_geometry:
                    reshaped[key] = ob
                if update.is_updated_shading and instances.object_shading(ob) != ctx.object_shading.get(key):
                    return None
        elif isinstance(block, bpy.types.Light):
            light_data.add(block.original.as_pointer())
        elif isinstance(block, bpy.types.Material):
            mat = block.evaluated_get(depsgraph)
            materials[mat.original.as_pointer()] = mat
        elif isinstance(block, bpy.types.World):
            # The scene's own (the signature holds which world is assigned).
            w = block.evaluated_get(depsgraph)
            worlds[w.original.as_pointer()] = w
        elif isinstance(block, bpy.types.NodeTree):
            trees.add(block.original.as_pointer())
        elif isinstance(block, bpy.types.Mesh):
            # Edited with its object (4.x also tags the mesh data of an
            # edited material's objects; their slots are compared with
            # object_shading).
            if update.is_updated_geometry or update.is_updated_transform:
                mesh_data.add(block.original.as_pointer())
        elif not isinstance(block, (bpy.types.Camera, bpy.types.Scene, bpy.types.Collection)):
            return None
    # Light data, mesh data and node trees only with the object, light or
    # material that uses them.
    if light_data - {ob.data.original.as_pointer() for ob in lights.values()}:
        return None
    if mesh_data - {ob.original.data.as_pointer() for ob in reshaped.values() if ob.original.data is not None}:
        return None
    owned = {m.node_tree.original.as_pointer() for m in materials.values() if m.node_tree is not None}
    # Lights have node trees too (used by default from Blender 5.0).
    owned |= {ob.data.node_tree.original.as_pointer() for ob in lights.values()
              if getattr(ob.data, "node_tree", None) is not None}
    owned |= {w.node_tree.original.as_pointer() for w in worlds.values() if w.node_tree is not None}
    if trees - owned:
        return None
    return Changes(list(lights.values()), list(materials.values()), list(moved.values()),
                   list(reshaped.values()), list(worlds.values()))


def apply_changes(depsgraph, ctx, changes):
    """Apply changes_in_place's Changes to the kept scene: the world set
    again, lights and materials replaced, objects' instances moved, their
    meshes replaced.
    False if one cannot be changed in place (an instanced light or object,
    a light that stops emitting or becomes a portal, a material that now
    reads other mesh attributes, a mesh shared with what did not change),
    and the caller exports afresh. No render may hold the scene."""
    ctx.scene, ctx.view_layer = depsgraph.scene, depsgraph.view_layer
    if changes.worlds:
        world_export.export_world(ctx)
    return all(light.update_light(ob, ctx) for ob in changes.lights) and \
        all(material.update_material(mat, ctx) for mat in changes.materials) and \
        all(instances.move_object(ob, ctx) for ob in changes.moved) and \
        (not changes.reshaped or instances.reshape_objects(changes.reshaped, ctx))
