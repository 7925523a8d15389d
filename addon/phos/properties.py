# SPDX-License-Identifier: GPL-3.0-or-later
"""Phos settings stored in .blend files, and the add-on preferences.

One PropertyGroup per datablock: `scene.phos` (render settings) and
`view_layer.phos` (the pass toggles; Blender keeps passes per view layer,
and a PropertyGroup on ViewLayer is stored with the scene). Enum items carry
explicit indices: Blender stores the index, so reordering or inserting items
later must not silently change saved files.

`scene.phos` is declared from the core's settings table (phos.h,
PHOS_RENDER_SETTINGS, mirrored in core.RENDER_SETTINGS): each user setting's
property name, label, description, default, range and kind come from its
row, so the add-on cannot offer a value the core refuses. Only the enum
items' texts, preview_samples and the viewport's preview_start_resolution
are written here.
"""

import collections
import os
import textwrap

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

from . import core

# Items of the settings that choose a value of a core enum, by the enum's
# name in the settings table: (identifier, name, description, core value).
# The core value is the item's index, which .blend files store.
INTEGRATOR_ITEMS = (
    ('PATH', "Path Tracing", "Unbiased path tracer with next-event estimation and MIS",
     core.PHOS_INTEGRATOR_PATH),
    ('PHOTON', "Photon Mapping",
     "Photon mapping (Jensen): direct light and mirror/glass by ray tracing, caustics from a "
     "caustic photon map, indirect light by final gathering on a global photon map",
     core.PHOS_INTEGRATOR_PHOTON),
)

PHOTON_VIEW_ITEMS = (
    ('FINAL_GATHER', "Final Gathering",
     "Indirect diffuse light by gather rays that read the global photon map where they land",
     core.PHOS_PHOTON_VIEW_FINAL_GATHER),
    ('FAST', "Fast Estimate",
     "The global photon map's radiance estimate read directly at the first diffuse surface: "
     "fast, shows the photon map's blotches", core.PHOS_PHOTON_VIEW_FAST),
    ('PATH_TRACED', "Path-Traced Gather",
     "The same gather rays, each continued as an unbiased path instead of reading a photon map "
     "(no global map is traced): the reference final gathering converges to, and slow",
     core.PHOS_PHOTON_VIEW_PATH_TRACED),
)

IRRADIANCE_CACHE_ITEMS = (
    ('OFF', "Off", "Indirect diffuse light gathered at every sample", core.PHOS_IRRADIANCE_CACHE_OFF),
    ('PHOTON', "Photon Mapping",
     "With Photon Mapping, its final gather computed at a few records and interpolated between them "
     "(Ward's irradiance cache); Path Tracing stays the unbiased reference",
     core.PHOS_IRRADIANCE_CACHE_PHOTON),
    ('ALWAYS', "Always",
     "Also with Path Tracing: its hemisphere of paths at the records (Ward's original method; biased, "
     "but converging as the records grow)", core.PHOS_IRRADIANCE_CACHE_ALWAYS),
)

SAMPLER_ITEMS = (
    ('RANDOM', "Random", "Independent random numbers for every sample (the course's fixed random sequence)",
     core.PHOS_SAMPLER_RANDOM),
    ('STRATIFIED', "Stratified",
     "Jittered strata over each pixel's samples, multi-jittered in pairs of dimensions "
     "(a Latin hypercube as well)", core.PHOS_SAMPLER_STRATIFIED),
    ('HALTON', "Halton", "Scrambled Halton points in bases 2 and 3, each pixel from its own offset",
     core.PHOS_SAMPLER_HALTON),
    ('SOBOL', "Sobol", "Owen-scrambled Sobol points: the lowest error per sample on the bench scenes",
     core.PHOS_SAMPLER_SOBOL),
)

NOISE_FILTER_ITEMS = (
    ('NONE', "None", "No filter", core.PHOS_NOISE_FILTER_NONE),
    ('LOWPASS', "3×3 Lowpass", "The mean of each pixel's 3×3 block: blurs noise and detail alike",
     core.PHOS_NOISE_FILTER_LOWPASS),
    ('MEDIAN', "3×3 Median",
     "The colour of the median pixel of each 3×3 block: removes isolated fireflies, and their light",
     core.PHOS_NOISE_FILTER_MEDIAN),
    ('ADAPTIVE_WIDTH', "Adaptive Width",
     "Energy preserving (Rushmeier & Ward 1994): a pixel brighter than its neighbourhood allows "
     "spreads its excess over a disc that grows with the excess", core.PHOS_NOISE_FILTER_ADAPTIVE_WIDTH),
    ('DIFFUSION', "Diffusion",
     "Energy preserving (McCool 1999): anisotropic diffusion that stops at significant steps in colour, "
     "and at normal and albedo edges", core.PHOS_NOISE_FILTER_DIFFUSION),
    ('SPLATTING', "Splatting",
     "Energy preserving (Suykens & Willems 2000): every pixel is spread by a kernel that narrows as its "
     "samples grow", core.PHOS_NOISE_FILTER_SPLATTING),
)

FILTER_TARGET_ITEMS = (
    ('INDIRECT_IRRADIANCE', "Indirect Irradiance",
     "The indirect light over the surface's albedo, filtered, times the albedo: textures, highlights and "
     "caustics stay sharp", core.PHOS_FILTER_TARGET_INDIRECT_IRRADIANCE),
    ('INDIRECT', "Indirect", "The Indirect component as it is", core.PHOS_FILTER_TARGET_INDIRECT),
    ('ALL', "Everything", "The whole image, as the course's slides filter it", core.PHOS_FILTER_TARGET_ALL),
)

ENUM_ITEMS = {
    "phos_noise_filter": NOISE_FILTER_ITEMS,
    "phos_filter_target": FILTER_TARGET_ITEMS,
    "phos_integrator": INTEGRATOR_ITEMS,
    "phos_sampler": SAMPLER_ITEMS,
    "phos_photon_view": PHOTON_VIEW_ITEMS,
    "phos_irradiance_cache": IRRADIANCE_CACHE_ITEMS,
}

# The settings the user chooses (`scene.phos`), in the core's table order;
# the others (resolution, border, threads, passes...) the engine takes from
# Blender's own settings.
USER_SETTINGS = tuple(s for s in core.RENDER_SETTINGS if s.user)

# Blender's IntProperty holds a signed 32-bit int.
_INT_MAX = 2 ** 31 - 1
# Setting kind → Blender subtype and unit.
_KIND_OPTIONS = {
    "NUMBER": {},
    "PIXELS": {"subtype": 'PIXEL'},
    "LENGTH": {"subtype": 'DISTANCE', "unit": 'LENGTH'},
    "FACTOR": {"subtype": 'FACTOR'},
    "SECONDS": {"subtype": 'TIME_ABSOLUTE'},
}


def _property(setting, **override):
    """The Blender property of a row of the core's settings table."""
    s = setting._replace(**override)
    common = {"name": s.label, "description": s.description}
    if s.kind == "ENUM":
        items = ENUM_ITEMS[s.enum]
        default = next(item[0] for item in items if item[3] == s.default)
        return EnumProperty(items=items, default=default, **common)
    if s.kind == "BOOLEAN":
        return BoolProperty(default=bool(s.default), **common)
    options = dict(_KIND_OPTIONS[s.kind], **common)
    if s.ctype == "float":
        if s.soft_max:
            options["soft_max"] = s.soft_max
        return FloatProperty(default=s.default, min=s.min, max=s.max, **options)
    if s.soft_max:
        options["soft_max"] = min(s.soft_max, _INT_MAX)
    return IntProperty(default=s.default, min=s.min, max=min(s.max, _INT_MAX), **options)


def _scene_settings():
    """The annotations of PhosSceneSettings: one property per user setting,
    and preview_samples beside samples (previews are Blender's; the engine
    puts one or the other into the core's samples)."""
    props = {}
    for s in USER_SETTINGS:
        props[s.prop] = _property(s)
        if s.name == "samples":
            props["preview_samples"] = _property(
                s, label="Viewport Samples",
                description="Samples per pixel in the viewport's Rendered shading (material, world and light "
                            "previews render in Blender's preview scene, at a fixed 64)",
                default=16, soft_max=1024)
    # The viewport's alone (viewport.py), as Cycles' Performance → Viewport.
    props["preview_start_resolution"] = IntProperty(
        name="Start Pixels",
        description="The viewport's first images are rendered at most this many pixels wide and high, "
                    "one sample each, doubling up to the full resolution before samples accumulate "
                    "(so that a moved view answers at once)",
        default=64, min=8, max=16384, subtype='PIXEL')
    # Not numbers, so not rows of the core's table: where the caches are
    # kept between renders (phos_render_set_cache_file).
    for kind, prefix, what, default in CACHE_FILES:
        props[prefix + "_mode"] = EnumProperty(
            name="%s File" % what,
            description="Keep the %s in a file, for animations and render farms" % what.lower(),
            items=CACHE_FILE_MODE_ITEMS, default='NONE')
        props[prefix] = StringProperty(
            name="File", description="The %s file ('//' is the .blend file's folder)" % what.lower(),
            subtype='FILE_PATH', default=default)
    return props


# (core enum phos_cache_kind, scene.phos property, what it holds, default file).
CACHE_FILES = (
    (core.PHOS_CACHE_IRRADIANCE, "ic_file", "Irradiance Cache", "//irradiance.phosirc"),
    (core.PHOS_CACHE_PHOTON_MAPS, "photon_map_file", "Photon Map", "//photons.phospmf"),
)

# (identifier, name, description, core value) of the *_file_mode settings.
CACHE_FILE_MODE_ITEMS = (
    ('NONE', "Compute", "Compute it for this render and keep nothing", core.PHOS_CACHE_FILE_NONE),
    ('SAVE', "Compute and Save", "Compute it, then write it to the file", core.PHOS_CACHE_FILE_SAVE),
    ('LOAD', "Load", "Read it from the file instead of computing it (every frame of a walkthrough, every "
     "machine of a farm reads the same one); a file made for another scene or other settings is refused",
     core.PHOS_CACHE_FILE_LOAD),
)


def cache_files(settings):
    """(enum phos_cache_kind, path as written, enum phos_cache_file_mode) of
    each cache file the settings ask for."""
    out = []
    for kind, prefix, _what, _default in CACHE_FILES:
        ident = getattr(settings, prefix + "_mode")
        mode = next(item[3] for item in CACHE_FILE_MODE_ITEMS if item[0] == ident)
        if mode != core.PHOS_CACHE_FILE_NONE:
            out.append((kind, getattr(settings, prefix), mode))
    return out


def render_settings(scene, width, height):
    """The core's settings of a render of `scene` at width × height pixels:
    the user's (scene.phos), by the core's table, then those Blender decides
    (the table's "host" rows: the effective thread count whether
    threads_mode is AUTO or FIXED, the transparent film), with Combined
    alone of the passes."""
    settings = scene.phos
    rs = core.new_render_settings()
    for setting in USER_SETTINGS:
        setattr(rs, setting.name, setting_value(settings, setting))
    rs.width, rs.height = width, height
    rs.threads = scene.render.threads
    rs.transparent_background = 1 if scene.render.film_transparent else 0
    rs.pass_mask = 1 << core.PHOS_PASS_COMBINED
    return rs


def setting_value(settings, setting):
    """The core's value of a user setting in `scene.phos` (an enum item → its index)."""
    value = getattr(settings, setting.prop)
    if setting.kind == "ENUM":
        return next((item[3] for item in ENUM_ITEMS[setting.enum] if item[0] == value), setting.default)
    if setting.kind == "BOOLEAN":
        return int(value)
    return value


# The passes a view layer can add to Combined, from the core's pass table
# (phos.h, PHOS_PASSES), in its order; each has a toggle view_layer.phos.<prop>.
PassToggle = collections.namedtuple("PassToggle", "prop name pass_id group kind channels description")
PASSES = tuple(PassToggle("use_pass_" + p.ident.lower(), p.name, p.id, p.group, p.kind, p.channels,
                          p.description)
               for p in core.PASSES if p.group != core.PHOS_PASS_GROUP_COMBINED)


def passes_of_group(group):
    return tuple(p for p in PASSES if p.group == group)


LIGHT_PASSES = passes_of_group(core.PHOS_PASS_GROUP_LIGHT)
DENOISING_PASSES = passes_of_group(core.PHOS_PASS_GROUP_DENOISING)
DEBUG_PASSES = passes_of_group(core.PHOS_PASS_GROUP_PHOTONS)   # they build the photon maps, whatever the integrator
CACHE_PASSES = passes_of_group(core.PHOS_PASS_GROUP_CACHE)
NOISE_PASSES = passes_of_group(core.PHOS_PASS_GROUP_NOISE)


class PhosSceneSettings(bpy.types.PropertyGroup):
    """Render settings of a scene, `scene.phos`, declared from the core's
    settings table (phos.h, PHOS_RENDER_SETTINGS)."""

    __annotations__ = _scene_settings()


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


class PhosViewLayerSettings(bpy.types.PropertyGroup):
    """Render passes of a view layer, `view_layer.phos`: a toggle per pass
    of the core's table (PASSES)."""

    __annotations__ = {p.prop: BoolProperty(name=p.name, description=p.description, default=False,
                                            update=_update_render_passes)
                       for p in PASSES}


def enabled_passes(view_layer):
    """The PASSES enabled on a view layer, in their order."""
    settings = getattr(view_layer, "phos", None)
    if settings is None:
        return []
    return [p for p in PASSES if getattr(settings, p.prop, False)]


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
