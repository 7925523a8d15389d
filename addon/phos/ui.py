# SPDX-License-Identifier: GPL-3.0-or-later
"""Properties-editor panels for Phos.

Phos draws its own panels for its settings (Render tab), materials, lights
and the world; for everything engine-independent (output, dimensions,
colour management, camera, object and physics panels...) it reuses
Blender's built-in panels by adding 'PHOS' to their COMPAT_ENGINES on
register and removing it on unregister. Only panels listing
'BLENDER_RENDER' are touched: Cycles' panels share one COMPAT_ENGINES set
object, so adding to one of them would show all of them.
"""

import bpy

from . import core
from .export.material import uses_nodes
from .properties import CACHE_PASSES, DEBUG_PASSES, DENOISING_PASSES, LIGHT_PASSES, NOISE_PASSES, enabled_passes, render_settings

ENGINE = 'PHOS'


class PhosButtonsPanel:
    """Base of every Phos panel: shown only while Phos is the render engine."""

    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    COMPAT_ENGINES = {ENGINE}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


def _library_warning(layout):
    """A visible hint in the Render tab when the core library cannot be used."""
    if core.load() is None:
        box = layout.box()
        box.alert = True
        box.label(text="Phos core library not available", icon='ERROR')
        box.label(text="See Edit › Preferences › Add-ons › Phos")


# ------------------------------------------------------------------- render

class PHOS_RENDER_PT_sampling(PhosButtonsPanel, bpy.types.Panel):
    bl_label = "Sampling"
    bl_context = "render"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        _library_warning(layout)
        phos = context.scene.phos
        layout.prop(phos, "integrator")
        col = layout.column(align=True)
        col.prop(phos, "samples", text="Render")
        col.prop(phos, "preview_samples", text="Viewport")
        layout.prop(phos, "sampler")
        layout.prop(phos, "seed")
        layout.prop(phos, "time_limit")


class PHOS_RENDER_PT_sampling_adaptive(PhosButtonsPanel, bpy.types.Panel):
    """Adaptive sampling, as Cycles lays it out: the toggle in the header."""

    bl_label = "Adaptive Sampling"
    bl_context = "render"
    bl_parent_id = "PHOS_RENDER_PT_sampling"

    def draw_header(self, context):
        self.layout.prop(context.scene.phos, "use_adaptive_sampling", text="")

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        phos = context.scene.phos
        layout.active = phos.use_adaptive_sampling
        col = layout.column(align=True)
        col.prop(phos, "adaptive_threshold", text="Threshold")
        col.prop(phos, "adaptive_min_samples", text="Min Samples")


class PHOS_RENDER_PT_sampling_filter(PhosButtonsPanel, bpy.types.Panel):
    """The course's noise filters, run over the image after rendering."""

    bl_label = "Noise Filter"
    bl_context = "render"
    bl_parent_id = "PHOS_RENDER_PT_sampling"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        phos = context.scene.phos
        layout.prop(phos, "filter")
        sub = layout.column()
        sub.active = phos.filter != 'NONE'
        sub.prop(phos, "filter_target", text="Apply To")


def planned_stages(context):
    """The stages a final render of this scene and view layer would run:
    the core's plan (core.settings_stages), so that a panel is shown exactly
    when its stage runs. None if the core cannot say (no library)."""
    try:
        rs = render_settings(context.scene, 1, 1)
        for p in enabled_passes(context.view_layer):
            rs.pass_mask |= 1 << p.pass_id
        return core.settings_stages(rs)
    except core.PhosError:
        return None


def uses_photon_maps(context):
    """Whether a render builds photon maps: PHOTON, or a photon debug pass
    (which builds them under PATH too)."""
    stages = planned_stages(context)
    return stages is None or core.PHOS_STAGE_TRACING_PHOTONS in stages


class PHOS_RENDER_PT_photon_mapping(PhosButtonsPanel, bpy.types.Panel):
    """The photon maps and how they are read; hidden when no map is built.
    Its sub-panels name each map, so their rows need no prefix that the
    default panel width would cut."""

    bl_label = "Photon Mapping"
    bl_context = "render"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and uses_photon_maps(context)

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        phos = context.scene.phos
        layout.prop(phos, "photon_view", text="Indirect")
        sub = layout.column()
        sub.active = phos.photon_view in {'FINAL_GATHER', 'PATH_TRACED'}
        sub.prop(phos, "final_gather_rays", text="Gather Rays")


class PhotonMapPanel(PhosButtonsPanel):
    """A sub-panel of one photon map: its photons stored and per estimate
    (the settings <map>_photons and <map>_estimate_photons)."""

    bl_context = "render"
    bl_parent_id = "PHOS_RENDER_PT_photon_mapping"
    map_name = ""

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        phos = context.scene.phos
        col = layout.column(align=True)
        col.prop(phos, self.map_name + "_photons", text="Photons")
        col.prop(phos, self.map_name + "_estimate_photons", text="Estimate")
        self.draw_more(layout, phos)

    def draw_more(self, layout, phos):
        pass


class PHOS_RENDER_PT_photon_mapping_global(PhotonMapPanel, bpy.types.Panel):
    bl_label = "Global Map"
    map_name = "global"


class PHOS_RENDER_PT_photon_mapping_caustic(PhotonMapPanel, bpy.types.Panel):
    bl_label = "Caustic Map"
    map_name = "caustic"

    def draw_more(self, layout, phos):
        # Glossy lobes smoother than this carry caustics (docs/algorithms.md §12).
        layout.prop(phos, "caustic_roughness", text="Roughness")
        # The share of a pixel's samples that read the map (docs/algorithms.md
        # §4.7); progressive caustics read a map of their own every sample.
        row = layout.row()
        row.active = not phos.use_progressive_caustics
        row.prop(phos, "caustic_sample_share", text="Sample Share")
        # Stochastic progressive photon mapping (docs/algorithms.md §4.6):
        # a map per sample, read within a shrinking radius.
        layout.prop(phos, "use_progressive_caustics")
        col = layout.column(align=True)
        col.active = phos.use_progressive_caustics
        col.prop(phos, "progressive_caustic_photons", text="Per Sample")
        col.prop(phos, "progressive_first_photons", text="First Radius")
        col.prop(phos, "progressive_alpha")


class PHOS_RENDER_PT_photon_mapping_advanced(PhosButtonsPanel, bpy.types.Panel):
    bl_label = "Advanced"
    bl_context = "render"
    bl_parent_id = "PHOS_RENDER_PT_photon_mapping"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        phos = context.scene.phos
        layout.prop(phos, "max_radius")
        layout.prop(phos, "max_photons_emitted", text="Max Paths (M)")
        layout.prop(phos, "photon_map_file_mode", text="File")
        sub = layout.column()
        sub.active = phos.photon_map_file_mode != 'NONE'
        sub.prop(phos, "photon_map_file", text="Path")


def cache_used(context):
    """Whether a render with these settings fills the irradiance cache."""
    stages = planned_stages(context)
    return stages is None or core.PHOS_STAGE_FILLING_IRRADIANCE_CACHE in stages


class PHOS_RENDER_PT_irradiance_cache(PhosButtonsPanel, bpy.types.Panel):
    """Ward's irradiance cache over either integrator's indirect diffuse light."""

    bl_label = "Irradiance Cache"
    bl_context = "render"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        phos = context.scene.phos
        layout.prop(phos, "irradiance_cache", text="Use")
        layout = layout.column()
        layout.active = cache_used(context)
        layout.prop(phos, "ic_accuracy")
        layout.prop(phos, "ic_rays", text="Rays")
        col = layout.column(align=True)
        col.prop(phos, "ic_min_spacing", text="Spacing Min")
        col.prop(phos, "ic_max_spacing", text="Max")
        layout.prop(phos, "ic_file_mode", text="File")
        sub = layout.column()
        sub.active = phos.ic_file_mode != 'NONE'
        sub.prop(phos, "ic_file", text="Path")


class PHOS_RENDER_PT_light_paths(PhosButtonsPanel, bpy.types.Panel):
    bl_label = "Light Paths"
    bl_context = "render"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(context.scene.phos, "max_bounces")


class PHOS_RENDER_PT_simplify(PhosButtonsPanel, bpy.types.Panel):
    """Blender's Simplify settings, here instead of above Sampling (where
    Blender's own panel would sit): the depsgraph applies them before Phos
    sees the geometry."""

    bl_label = "Simplify"
    bl_context = "render"
    bl_options = {'DEFAULT_CLOSED'}

    def draw_header(self, context):
        self.layout.prop(context.scene.render, "use_simplify", text="")

    def draw(self, context):
        pass


class PhosSimplifyPanel(PhosButtonsPanel):
    bl_context = "render"
    bl_parent_id = "PHOS_RENDER_PT_simplify"
    suffix = ""

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        rd = context.scene.render
        layout.active = rd.use_simplify
        col = layout.column()
        col.prop(rd, "simplify_subdivision" + self.suffix, text="Subdivision")
        col.prop(rd, "simplify_child_particles" + self.suffix, text="Children")


class PHOS_RENDER_PT_simplify_viewport(PhosSimplifyPanel, bpy.types.Panel):
    bl_label = "Viewport"


class PHOS_RENDER_PT_simplify_render(PhosSimplifyPanel, bpy.types.Panel):
    bl_label = "Render"
    suffix = "_render"


class PHOS_RENDER_PT_film(PhosButtonsPanel, bpy.types.Panel):
    bl_label = "Film"
    bl_context = "render"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        layout.prop(context.scene.phos, "filter_width")
        layout.prop(context.scene.render, "film_transparent", text="Transparent")


class PHOS_RENDER_PT_performance(PhosButtonsPanel, bpy.types.Panel):
    bl_label = "Performance"
    bl_context = "render"
    bl_options = {'DEFAULT_CLOSED'}

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        rd = context.scene.render
        col = layout.column()
        col.prop(rd, "threads_mode")
        sub = col.column(align=True)
        sub.enabled = rd.threads_mode == 'FIXED'
        sub.prop(rd, "threads")
        layout.prop(context.scene.phos, "tile_size")
        layout.prop(context.scene.phos, "use_progressive_refine")
        layout.prop(context.scene.phos, "preview_start_resolution")


# --------------------------------------------------------------- view layer

class PHOS_VIEW_LAYER_PT_passes(PhosButtonsPanel, bpy.types.Panel):
    bl_label = "Passes"
    bl_context = "view_layer"

    def draw(self, context):
        pass


class PhosPassGroupPanel(PhosButtonsPanel):
    """A group of pass toggles under Passes: `passes` is a slice of
    properties.PASSES."""

    bl_context = "view_layer"
    bl_parent_id = "PHOS_VIEW_LAYER_PT_passes"
    passes = ()

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        settings = context.view_layer.phos
        col = layout.column(heading="Include", align=True)
        for p in self.passes:
            col.prop(settings, p.prop, text=p.name)
        self.draw_note(context, layout)

    def draw_note(self, context, layout):
        pass


class PHOS_VIEW_LAYER_PT_passes_light(PhosPassGroupPanel, bpy.types.Panel):
    """The light components; Combined is their sum."""

    bl_label = "Light"
    passes = LIGHT_PASSES


class PHOS_VIEW_LAYER_PT_passes_denoising(PhosPassGroupPanel, bpy.types.Panel):
    """Features for a denoiser (the compositor's Denoise node takes them as
    its Albedo and Normal)."""

    bl_label = "Denoising Data"
    passes = DENOISING_PASSES


class PHOS_VIEW_LAYER_PT_passes_noise(PhosPassGroupPanel, bpy.types.Panel):
    """Where adaptive sampling and the time limit put the samples, and the
    image before the noise filter."""

    bl_label = "Noise Reduction"
    passes = NOISE_PASSES


class PHOS_VIEW_LAYER_PT_passes_photon_debug(PhosPassGroupPanel, bpy.types.Panel):
    """The photon maps seen directly; they build the maps for either integrator."""

    bl_label = "Photon Map Debug"
    passes = DEBUG_PASSES


class PHOS_VIEW_LAYER_PT_passes_cache_debug(PhosPassGroupPanel, bpy.types.Panel):
    """Where the irradiance cache put its records."""

    bl_label = "Irradiance Cache Debug"
    passes = CACHE_PASSES

    def draw_note(self, context, layout):
        if context.view_layer.phos.use_pass_irradiance_cache and not cache_used(context):
            layout.label(text="The irradiance cache is not used: the pass stays black", icon='INFO')


# --------------------------------------------------------------- node views

def _output_node(tree, bl_idname):
    """The output node Cycles renders from (active, targeting Cycles or All)."""
    node = tree.get_output_node('CYCLES')
    if node is None or node.bl_idname != bl_idname:
        node = next((n for n in tree.nodes if n.bl_idname == bl_idname and n.is_active_output), None)
    return node


def draw_node_view(layout, id_data, output_idname, input_name):
    """Draw the node tree feeding one input of the output node, as Cycles does."""
    tree = id_data.node_tree
    node = _output_node(tree, output_idname)
    if node is None:
        layout.label(text="No output node")
        return
    socket = node.inputs.get(input_name)
    if socket is None:
        layout.label(text="Incompatible output node")
        return
    layout.template_node_view(tree, node, socket)


# ----------------------------------------------------------------- material

class PhosPreviewPanel(PhosButtonsPanel):
    """A datablock's preview, rendered by Phos in Blender's preview scene
    (engine.PREVIEW_SAMPLES): the datablock is context.<datablock>."""

    bl_label = "Preview"
    bl_options = {'DEFAULT_CLOSED'}
    datablock = ""

    @classmethod
    def poll(cls, context):
        return getattr(context, cls.datablock, None) is not None and super().poll(context)

    def draw(self, context):
        self.layout.template_preview(getattr(context, self.datablock))


class PHOS_MATERIAL_PT_preview(PhosPreviewPanel, bpy.types.Panel):
    bl_context = datablock = "material"


class PHOS_MATERIAL_PT_context_material(PhosButtonsPanel, bpy.types.Panel):
    """Material slots and the active material, like Blender's own slot panel."""

    bl_label = ""
    bl_context = "material"
    bl_options = {'HIDE_HEADER'}

    @classmethod
    def poll(cls, context):
        if context.active_object and context.active_object.type in {'GPENCIL', 'GREASEPENCIL'}:
            return False
        return (context.material or context.object) and super().poll(context)

    def draw(self, context):
        layout = self.layout
        mat = context.material
        ob = context.object
        slot = context.material_slot
        space = context.space_data

        if ob:
            is_sortable = len(ob.material_slots) > 1
            rows = 3 if is_sortable else 1
            row = layout.row()
            row.template_list("MATERIAL_UL_matslots", "", ob, "material_slots", ob,
                              "active_material_index", rows=rows)
            col = row.column(align=True)
            col.operator("object.material_slot_add", icon='ADD', text="")
            col.operator("object.material_slot_remove", icon='REMOVE', text="")
            col.separator()
            col.menu("MATERIAL_MT_context_menu", icon='DOWNARROW_HLT', text="")
            if is_sortable:
                col.separator()
                col.operator("object.material_slot_move", icon='TRIA_UP', text="").direction = 'UP'
                col.operator("object.material_slot_move", icon='TRIA_DOWN', text="").direction = 'DOWN'
            if ob.mode == 'EDIT':
                row = layout.row(align=True)
                row.operator("object.material_slot_assign", text="Assign")
                row.operator("object.material_slot_select", text="Select")
                row.operator("object.material_slot_deselect", text="Deselect")

        row = layout.row()
        if ob:
            row.template_ID(ob, "active_material", new="material.new")
            if slot:
                icon_link = 'MESH_DATA' if slot.link == 'DATA' else 'OBJECT_DATA'
                row.prop(slot, "link", icon=icon_link, icon_only=True)
        elif mat:
            row.template_ID(space, "pin_id")


class PHOS_MATERIAL_PT_surface(PhosButtonsPanel, bpy.types.Panel):
    bl_label = "Surface"
    bl_context = "material"

    @classmethod
    def poll(cls, context):
        return context.material is not None and super().poll(context)

    def draw(self, context):
        layout = self.layout
        mat = context.material
        if not uses_nodes(mat):
            if mat.node_tree is None or bpy.app.version < (5, 0, 0):
                layout.prop(mat, "use_nodes", icon='NODETREE')
            layout.separator()
            layout.use_property_split = True
            layout.prop(mat, "diffuse_color", text="Color")
            return
        draw_node_view(layout, mat, 'ShaderNodeOutputMaterial', 'Surface')


# -------------------------------------------------------------------- light

class PHOS_LIGHT_PT_preview(PhosPreviewPanel, bpy.types.Panel):
    bl_context = "data"
    datablock = "light"


class PHOS_LIGHT_PT_light(PhosButtonsPanel, bpy.types.Panel):
    bl_label = "Light"
    bl_context = "data"

    @classmethod
    def poll(cls, context):
        return context.light is not None and super().poll(context)

    def draw(self, context):
        layout = self.layout
        light = context.light
        layout.row().prop(light, "type", expand=True)
        layout.use_property_split = True
        layout.use_property_decorate = False
        col = layout.column()
        # Cycles' portal flag, which Phos reads too (export/light.py): a
        # portal emits nothing, so its colour and power are not shown.
        cycles = getattr(light, "cycles", None)
        portal = light.type == 'AREA' and cycles is not None and getattr(cycles, "is_portal", False)
        if light.type == 'AREA' and cycles is not None and hasattr(cycles, "is_portal"):
            col.prop(cycles, "is_portal", text="Portal")
        if not portal:
            col.prop(light, "color")
            col.prop(light, "energy")
        col.separator()
        if light.type in {'POINT', 'SPOT'}:
            col.prop(light, "shadow_soft_size", text="Radius")
            if hasattr(light, "use_soft_falloff"):  # Blender 4.1+
                col.prop(light, "use_soft_falloff")
        elif light.type == 'SUN':
            col.prop(light, "angle")
        elif light.type == 'AREA':
            col.prop(light, "shape")
            sub = col.column(align=True)
            if light.shape in {'SQUARE', 'DISK'}:
                sub.prop(light, "size")
            else:
                sub.prop(light, "size", text="Size X")
                sub.prop(light, "size_y", text="Y")


class PHOS_LIGHT_PT_spot(PhosButtonsPanel, bpy.types.Panel):
    bl_label = "Spot Shape"
    bl_parent_id = "PHOS_LIGHT_PT_light"
    bl_context = "data"

    @classmethod
    def poll(cls, context):
        light = context.light
        return light is not None and light.type == 'SPOT' and super().poll(context)

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        light = context.light
        col = layout.column()
        col.prop(light, "spot_size", text="Size")
        col.prop(light, "spot_blend", text="Blend", slider=True)
        col.prop(light, "show_cone")


# -------------------------------------------------------------------- world

class PHOS_WORLD_PT_preview(PhosPreviewPanel, bpy.types.Panel):
    bl_context = datablock = "world"


class PHOS_WORLD_PT_surface(PhosButtonsPanel, bpy.types.Panel):
    bl_label = "Surface"
    bl_context = "world"

    @classmethod
    def poll(cls, context):
        return context.world is not None and super().poll(context)

    def draw(self, context):
        layout = self.layout
        world = context.world
        if not uses_nodes(world):
            if world.node_tree is None or bpy.app.version < (5, 0, 0):
                layout.prop(world, "use_nodes", icon='NODETREE')
            layout.separator()
            layout.use_property_split = True
            layout.prop(world, "color")
            return
        draw_node_view(layout, world, 'ShaderNodeOutputWorld', 'Surface')


classes = (
    PHOS_RENDER_PT_sampling,
    PHOS_RENDER_PT_sampling_adaptive,
    PHOS_RENDER_PT_sampling_filter,
    PHOS_RENDER_PT_photon_mapping,
    PHOS_RENDER_PT_photon_mapping_global,
    PHOS_RENDER_PT_photon_mapping_caustic,
    PHOS_RENDER_PT_photon_mapping_advanced,
    PHOS_RENDER_PT_irradiance_cache,
    PHOS_RENDER_PT_light_paths,
    PHOS_RENDER_PT_simplify,
    PHOS_RENDER_PT_simplify_viewport,
    PHOS_RENDER_PT_simplify_render,
    PHOS_RENDER_PT_film,
    PHOS_RENDER_PT_performance,
    PHOS_VIEW_LAYER_PT_passes,
    PHOS_VIEW_LAYER_PT_passes_light,
    PHOS_VIEW_LAYER_PT_passes_denoising,
    PHOS_VIEW_LAYER_PT_passes_noise,
    PHOS_VIEW_LAYER_PT_passes_photon_debug,
    PHOS_VIEW_LAYER_PT_passes_cache_debug,
    PHOS_MATERIAL_PT_preview,
    PHOS_MATERIAL_PT_context_material,
    PHOS_MATERIAL_PT_surface,
    PHOS_LIGHT_PT_preview,
    PHOS_LIGHT_PT_light,
    PHOS_LIGHT_PT_spot,
    PHOS_WORLD_PT_preview,
    PHOS_WORLD_PT_surface,
)


# ---------------------------------------------------- Blender's own panels

# Built-in panels listing BLENDER_RENDER that Phos replaces with its own.
EXCLUDED_PANELS = {
    'DATA_PT_light',          # PHOS_LIGHT_PT_light
    'DATA_PT_area',           # PHOS_LIGHT_PT_light
    'DATA_PT_spot',           # PHOS_LIGHT_PT_spot
    'DATA_PT_falloff_curve',  # falloff curves are not supported
    'NODE_DATA_PT_light',
    # PHOS_RENDER_PT_simplify, below Sampling as in Cycles: Blender's
    # registers first and would sit above every Phos panel.
    'RENDER_PT_simplify',
    'RENDER_PT_simplify_viewport',
    'RENDER_PT_simplify_render',
    'RENDER_PT_simplify_greasepencil',
}

_patched_panels = []


def builtin_panels():
    """Blender's own panels Phos can use: those listing 'BLENDER_RENDER'."""
    for panel in bpy.types.Panel.__subclasses__():
        engines = getattr(panel, "COMPAT_ENGINES", None)
        if not isinstance(engines, set) or 'BLENDER_RENDER' not in engines:
            continue
        if panel.__name__ in EXCLUDED_PANELS:
            continue
        yield panel


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    for panel in builtin_panels():
        if ENGINE not in panel.COMPAT_ENGINES:
            panel.COMPAT_ENGINES.add(ENGINE)
            _patched_panels.append(panel)


def unregister():
    for panel in _patched_panels:
        panel.COMPAT_ENGINES.discard(ENGINE)
    _patched_panels.clear()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
