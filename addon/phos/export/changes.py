# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender's edits → a kept core scene, changed in place (phos.h, scene
updates): what Persistent Data's next F12 (engine.py) and the viewport
(viewport.py) do with depsgraph.updates instead of a new export.

A kept scene is kept with its export context, which maps Blender's
datablocks to core ids, and with the signature of what it was exported
from. Lights and materials are replaced in place; anything the core
cannot take that way asks for a new export (None / False below).
"""

import bpy

from . import instances, light, material


def signature(depsgraph):
    """What the export reads that depsgraph.updates may not list as a change
    of its own: the world assigned, and which objects the render sees (an
    object hidden or shown, or moved into another collection, is tagged
    without a change of geometry, transform or shading)."""
    world = depsgraph.scene.world
    return (world.original.as_pointer() if world is not None else 0,
            frozenset(ob.original.as_pointer() for ob in depsgraph.objects))


def changes_in_place(depsgraph, ctx, exported_signature):
    """The changes the depsgraph reports since the scene of export context
    `ctx` (exported with `exported_signature`) was last rendered, if that
    scene can take them in place: (light objects, materials), evaluated,
    both empty when nothing needs changing; else None.

    Cameras (the caller sets the camera again), the scene's own settings
    (render settings reach the core through the render) and collections need
    nothing; a light object or its light data, and a material or its node
    tree, are changed in place. Blender 4.x tags objects for shading when a
    material they use is edited, and every object when a datablock is added
    (a relations update): an object tagged for shading alone is no change
    while its materials and Object Info values are as exported. Anything
    else (geometry, objects moved, the world, images) needs an export, as
    do objects added, removed, hidden or shown (signature)."""
    if signature(depsgraph) != exported_signature:
        return None
    lights, light_data, materials, trees = {}, set(), {}, set()
    for update in depsgraph.updates:
        block = update.id
        if isinstance(block, bpy.types.Object):
            ob = block.evaluated_get(depsgraph)
            if ob.type == 'LIGHT':
                lights[ob.original.as_pointer()] = ob
            elif ob.type != 'CAMERA':
                if update.is_updated_geometry or update.is_updated_transform:
                    return None
                if update.is_updated_shading and \
                        instances.object_shading(ob) != ctx.object_shading.get(ob.original.as_pointer()):
                    return None
        elif isinstance(block, bpy.types.Light):
            light_data.add(block.original.as_pointer())
        elif isinstance(block, bpy.types.Material):
            mat = block.evaluated_get(depsgraph)
            materials[mat.original.as_pointer()] = mat
        elif isinstance(block, bpy.types.NodeTree):
            trees.add(block.original.as_pointer())
        elif isinstance(block, bpy.types.Mesh):
            # 4.x tags the mesh data of an edited material's objects too;
            # its slots are compared with its objects' (object_shading).
            if update.is_updated_geometry or update.is_updated_transform:
                return None
        elif not isinstance(block, (bpy.types.Camera, bpy.types.Scene, bpy.types.Collection)):
            return None
    # Light data and node trees only with the object, light or material that uses them.
    if light_data - {ob.data.original.as_pointer() for ob in lights.values()}:
        return None
    owned = {m.node_tree.original.as_pointer() for m in materials.values() if m.node_tree is not None}
    # Lights have node trees too (used by default from Blender 5.0).
    owned |= {ob.data.node_tree.original.as_pointer() for ob in lights.values()
              if getattr(ob.data, "node_tree", None) is not None}
    if trees - owned:
        return None
    return list(lights.values()), list(materials.values())


def apply_changes(depsgraph, ctx, changes):
    """Replace the changed lights and materials (changes_in_place) in the
    kept scene; False if one cannot be changed in place (an instanced
    light, one that stops emitting or becomes a portal, a material that now
    reads other mesh attributes), and the caller exports afresh. No render
    may hold the scene."""
    ctx.scene, ctx.view_layer = depsgraph.scene, depsgraph.view_layer
    lights, materials = changes
    return all(light.update_light(ob, ctx) for ob in lights) and \
        all(material.update_material(mat, ctx) for mat in materials)
