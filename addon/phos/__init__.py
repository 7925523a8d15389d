# SPDX-License-Identifier: GPL-3.0-or-later
"""Phos — a photon-mapping render engine for Blender.

Package layout (lower modules never import higher ones):

    core.py         ctypes binding of libphos (lib/libphos.so), no bpy
    properties.py   scene.phos settings and the add-on preferences
    export/         depsgraph → core scene, one module per datablock
    engine.py       the RenderEngine: export, start, poll, deliver tiles
    ui.py           panels, and 'PHOS' added to Blender's own panels

Works as a legacy add-on (bl_info, Blender 3.4+) and as a 4.2+ extension
(blender_manifest.toml); all imports are relative.
"""

bl_info = {
    "name": "Phos",
    "author": "Phos developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties › Render › Render Engine › Phos",
    "description": "Photon-mapping render engine with Cycles-compatible materials and lights",
    "category": "Render",
}

if "bpy" in locals():
    # Re-running this file (F8 / script reload): reload the submodules in dependency order.
    import importlib
    for _name in ("core", "properties", "export.context", "export.image", "export.material",
                  "export.mesh", "export.light", "export.camera", "export.world",
                  "export.instances", "export", "engine", "ui"):
        importlib.reload(importlib.import_module("." + _name, __package__))

import bpy  # noqa: E402  (after the reload block on purpose)

from . import core, properties, engine, ui  # noqa: E402

_modules = (properties, engine, ui)


def register():
    for module in _modules:
        module.register()
    # Try the library now so the preferences and the Render tab show a load
    # error at once; a failure never prevents registration.
    core.load()


def unregister():
    for module in reversed(_modules):
        module.unregister()
