# SPDX-License-Identifier: GPL-3.0-or-later
"""Phos settings stored in .blend files, and the add-on preferences.

One PropertyGroup per datablock: `scene.phos` (render settings) and
`view_layer.phos` (the pass toggles; Blender keeps passes per view layer,
and a PropertyGroup on ViewLayer is stored with the scene). Enum items carry
explicit indices: Blender stores the index, so reordering or inserting items
later must not silently change saved files.
"""

import os
import textwrap

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty

from . import core

INTEGRATOR_ITEMS = (
    ('PATH', "Path Tracing", "Unbiased path tracer with next-event estimation and MIS", 0),
    ('PHOTON', "Photon Mapping",
     "Photon mapping (Jensen): direct light and mirror/glass by ray tracing, caustics from a "
     "caustic photon map, indirect light by final gathering on a global photon map", 1),
)

# Property value → core enum value.
INTEGRATORS = {
    'PATH': core.PHOS_INTEGRATOR_PATH,
    'PHOTON': core.PHOS_INTEGRATOR_PHOTON,
}

PHOTON_VIEW_ITEMS = (
    ('FINAL_GATHER', "Final Gathering",
     "Indirect diffuse light by gather rays that read the global photon map where they land", 0),
    ('FAST', "Fast Estimate",
     "The global photon map's radiance estimate read directly at the first diffuse surface: "
     "fast, shows the photon map's blotches", 1),
)

PHOTON_VIEWS = {
    'FINAL_GATHER': core.PHOS_PHOTON_VIEW_FINAL_GATHER,
    'FAST': core.PHOS_PHOTON_VIEW_FAST,
}

# View layer pass toggles: (property, render pass name, core pass, description).
# Order = the order the passes are registered and listed in.
PASSES = (
    ("use_pass_emission", "Emission", core.PHOS_PASS_EMISSION,
     "Emitters seen directly (lights, emissive surfaces, the world)"),
    ("use_pass_direct", "Direct", core.PHOS_PASS_DIRECT,
     "Light from the emitters after one diffuse scattering"),
    ("use_pass_specular", "Specular", core.PHOS_PASS_SPECULAR,
     "Light seen through a specular or glossy first bounce (mirrors, glass)"),
    ("use_pass_caustics", "Caustics", core.PHOS_PASS_CAUSTICS,
     "Light focused onto diffuse surfaces by specular bounces (L S+ D E)"),
    ("use_pass_indirect", "Indirect", core.PHOS_PASS_INDIRECT,
     "Diffuse interreflection: light after further non-specular bounces"),
    ("use_pass_photon_map", "Photon Map", core.PHOS_PASS_PHOTON_MAP,
     "Debug: the global photon map's radiance estimate at the first diffuse surface seen"),
    ("use_pass_caustic_map", "Caustic Map", core.PHOS_PASS_CAUSTIC_MAP,
     "Debug: the caustic photon map's radiance estimate at the first diffuse surface seen"),
    ("use_pass_photons", "Photons", core.PHOS_PASS_PHOTONS,
     "Debug: every stored photon drawn as a dot where it lies in the image"),
)
LIGHT_PASSES = PASSES[:5]
DEBUG_PASSES = PASSES[5:]


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
    # Photon mapping (the PHOTON integrator, and the photon debug passes).
    global_photons: IntProperty(
        name="Global Photons",
        description="Photons stored in the global photon map (indirect light); "
                    "photons are emitted until this many are stored",
        default=200000, min=0, soft_max=10000000,
    )
    caustic_photons: IntProperty(
        name="Caustic Photons",
        description="Photons stored in the caustic photon map (light focused by mirrors and glass)",
        default=50000, min=0, soft_max=10000000,
    )
    global_estimate_photons: IntProperty(
        name="Global Estimate",
        description="Nearest photons used in a radiance estimate of the global map",
        default=50, min=1, soft_max=1000,
    )
    caustic_estimate_photons: IntProperty(
        name="Caustic Estimate",
        description="Nearest photons used in a (cone-filtered) radiance estimate of the caustic map",
        default=80, min=1, soft_max=1000,
    )
    max_radius: FloatProperty(
        name="Max Radius",
        description="Largest search radius of a radiance estimate; 0 chooses it from the "
                    "scene's size (its diagonal / 40)",
        default=0.0, min=0.0, soft_max=10.0, subtype='DISTANCE', unit='LENGTH',
    )
    final_gather_rays: IntProperty(
        name="Final Gather Rays",
        description="Gather rays per camera sample at the first diffuse surface",
        default=32, min=1, soft_max=1024,
    )
    photon_view: EnumProperty(
        name="Indirect Light",
        description="How the global photon map gives indirect diffuse light",
        items=PHOTON_VIEW_ITEMS,
        default='FINAL_GATHER',
    )
    max_photons_emitted: IntProperty(
        name="Max Emitted (Millions)",
        description="Stop filling the photon maps after this many million emitted photon paths "
                    "(for scenes where most photons escape)",
        default=50, min=1, soft_max=1000,
    )


def _update_render_passes(self, context):
    """A pass was toggled: let Blender ask the engine for its passes again
    (the compositor's Render Layers node shows them at once)."""
    view_layer = None
    try:  # the view layer owning these settings: 'view_layers["Name"].phos'
        view_layer = self.id_data.path_resolve(self.path_from_id().rpartition(".")[0])
    except (ValueError, AttributeError, TypeError):
        view_layer = getattr(context, "view_layer", None)
    if view_layer is not None and hasattr(view_layer, "update_render_passes"):
        view_layer.update_render_passes()


_PASS_DESCRIPTIONS = {label: description for _p, label, _i, description in PASSES}


def _pass_property(label):
    return BoolProperty(name=label, description=_PASS_DESCRIPTIONS[label], default=False,
                        update=_update_render_passes)


class PhosViewLayerSettings(bpy.types.PropertyGroup):
    """Render passes of a view layer, `view_layer.phos`."""

    use_pass_emission: _pass_property("Emission")
    use_pass_direct: _pass_property("Direct")
    use_pass_specular: _pass_property("Specular")
    use_pass_caustics: _pass_property("Caustics")
    use_pass_indirect: _pass_property("Indirect")
    use_pass_photon_map: _pass_property("Photon Map")
    use_pass_caustic_map: _pass_property("Caustic Map")
    use_pass_photons: _pass_property("Photons")


def enabled_passes(view_layer):
    """(render pass name, core pass) of the passes enabled on a view layer, in PASSES order."""
    settings = getattr(view_layer, "phos", None)
    if settings is None:
        return []
    return [(label, pass_id) for prop, label, pass_id, _d in PASSES if getattr(settings, prop, False)]


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
    PhosViewLayerSettings,
    PhosPreferences,
)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.phos = PointerProperty(
        type=PhosSceneSettings, name="Phos", description="Phos render settings")
    bpy.types.ViewLayer.phos = PointerProperty(
        type=PhosViewLayerSettings, name="Phos", description="Phos render passes of the view layer")


def unregister():
    del bpy.types.ViewLayer.phos
    del bpy.types.Scene.phos
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
