# SPDX-License-Identifier: GPL-3.0-or-later
"""Phos settings stored in .blend files, and the add-on preferences.

One PropertyGroup per datablock (`scene.phos` for now). Enum items carry
explicit indices: Blender stores the index, so reordering or inserting items
later must not silently change saved files.
"""

import os
import textwrap

import bpy
from bpy.props import EnumProperty, FloatProperty, IntProperty, PointerProperty

from . import core

INTEGRATOR_ITEMS = (
    ('PATH', "Path Tracing", "Unbiased path tracer with next-event estimation and MIS", 0),
)

# Property value → core enum value.
INTEGRATORS = {
    'PATH': core.PHOS_INTEGRATOR_PATH,
}


class PhosSceneSettings(bpy.types.PropertyGroup):
    """Render settings of a scene, `scene.phos`."""

    integrator: EnumProperty(
        name="Integrator",
        description="Method used to compute the light transport",
        items=INTEGRATOR_ITEMS,
        default='PATH',
    )
    samples: IntProperty(
        name="Samples",
        description="Samples per pixel of a final render",
        default=128, min=1, soft_max=4096,
    )
    preview_samples: IntProperty(
        name="Preview Samples",
        description="Samples per pixel of material and light previews",
        default=16, min=1, soft_max=1024,
    )
    seed: IntProperty(
        name="Seed",
        description="Seed of the random numbers: the same seed renders the same image, "
                    "whatever the thread count, tile order or border",
        default=0, min=0,
    )
    max_bounces: IntProperty(
        name="Max Bounces",
        description="Scattering events a path may have after the camera ray",
        default=12, min=0, max=1024,
    )
    filter_width: FloatProperty(
        name="Filter Width",
        description="Width of the Blackman-Harris pixel filter (0 is a box of one pixel)",
        default=1.5, min=0.0, max=10.0, subtype='PIXEL',
    )
    tile_size: IntProperty(
        name="Tile Size",
        description="Edge of the square tiles the image is rendered and delivered in",
        default=64, min=8, max=1024, subtype='PIXEL',
    )


class PhosPreferences(bpy.types.AddonPreferences):
    """Shows where the core library is looked for and why it failed to load.

    bl_idname must be the add-on's package name, which differs between a
    legacy install ("phos") and a 4.2+ extension ("bl_ext.<repo>.phos").
    """

    bl_idname = __package__

    def draw(self, context):
        layout = self.layout
        core.load()  # retried on each draw while it fails: the library may have been built since
        col = layout.column(align=True)
        col.label(text="Core library: " + core.library_path())
        if os.environ.get(core.LIBRARY_ENV, "").strip():
            col.label(text="(set by the environment variable %s)" % core.LIBRARY_ENV)
        error = core.load_error()
        if error:
            box = layout.box()
            box.alert = True
            for i, line in enumerate(textwrap.wrap(error, 90) or [error]):
                box.label(text=line, icon='ERROR' if i == 0 else 'BLANK1')
        else:
            layout.label(text="Loaded version %s" % core.version_string(), icon='CHECKMARK')


classes = (
    PhosSceneSettings,
    PhosPreferences,
)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.phos = PointerProperty(
        type=PhosSceneSettings, name="Phos", description="Phos render settings")


def unregister():
    del bpy.types.Scene.phos
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
