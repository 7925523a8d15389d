# SPDX-License-Identifier: GPL-3.0-or-later
"""Registration of the add-on: engine, properties, panels, re-registration."""

import addon_utils
import bpy
import pytest

import phostest as pt

# Built-in panels Phos must reuse (engine-independent settings).
REQUIRED_BUILTIN_PANELS = (
    "RENDER_PT_format",
    "RENDER_PT_frame_range",
    "RENDER_PT_output",
    "RENDER_PT_color_management",
    "RENDER_PT_stamp",
    "DATA_PT_context_camera",
    "DATA_PT_lens",
    "DATA_PT_camera",
    "DATA_PT_context_light",
    "OBJECT_PT_visibility",
)
# EEVEE-only panels: they show settings Phos ignores (light specular factor,
# shadow maps...), so they must not appear for Phos.
EEVEE_ONLY_PANELS = ("DATA_PT_EEVEE_light", "DATA_PT_EEVEE_shadow", "RENDER_PT_eevee_sampling")


def _enable(name=pt.ADDON_NAME):
    errors = []
    mod = addon_utils.enable(name, default_set=True, handle_error=errors.append)
    assert not errors, "enable raised: %r" % errors
    assert mod is not None
    return pt.alias_addon_modules(mod)


def _disable(name=pt.ADDON_NAME):
    errors = []
    addon_utils.disable(name, default_set=True, handle_error=errors.append)
    assert not errors, "disable raised: %r" % errors


def _panels_with(engine):
    out = []
    for name in dir(bpy.types):
        cls = getattr(bpy.types, name, None)
        engines = getattr(cls, "COMPAT_ENGINES", None)
        if isinstance(engines, set) and engine in engines:
            out.append(cls)
    return out


def test_engine_registered_and_selectable(scene):
    assert "PHOS" in pt.engine_ids()
    scene.render.engine = "PHOS"
    assert scene.render.engine == "PHOS"
    engine_cls = next(c for c in bpy.types.RenderEngine.__subclasses__()
                      if getattr(c, "bl_idname", None) == "PHOS" and c.is_registered)
    assert engine_cls.bl_label
    # docs/blender.md §2: the standard shader nodes must stay visible, previews on.
    assert engine_cls.bl_use_shading_nodes_custom is False
    assert engine_cls.bl_use_preview is True


def test_disable_enable_enable(scene):
    """unregister → register → register (enable on an enabled add-on re-registers)."""
    _disable()
    assert "PHOS" not in pt.engine_ids()
    assert not hasattr(bpy.types.Scene, "phos")
    with pytest.raises(TypeError):
        bpy.context.scene.render.engine = "PHOS"
    assert not _panels_with("PHOS"), "panels still list PHOS after unregister: %s" % [
        c.__name__ for c in _panels_with("PHOS")]
    _enable()
    _enable()  # addon_utils calls unregister() then register() again
    assert "PHOS" in pt.engine_ids()
    assert hasattr(bpy.types.Scene, "phos")
    sc = bpy.context.scene
    sc.render.engine = "PHOS"
    assert sc.phos.samples >= 1
    # Still exactly one engine class and no duplicated panels.
    assert sum(1 for c in bpy.types.RenderEngine.__subclasses__()
               if getattr(c, "bl_idname", None) == "PHOS" and c.is_registered) == 1
    names = [c.__name__ for c in _panels_with("PHOS")]
    assert len(names) == len(set(names))


def test_disable_twice_and_reenable(scene):
    _disable()
    _disable()  # harmless on a disabled add-on
    _enable()
    assert "PHOS" in pt.engine_ids()


def _settings_rna():
    return bpy.types.Scene.bl_rna.properties["phos"].fixed_type


def test_scene_properties_and_defaults(scene):
    p = scene.phos
    for name in ("integrator", "samples", "preview_samples", "seed", "max_bounces",
                 "filter_width", "tile_size"):
        assert hasattr(p, name), "scene.phos.%s missing" % name
    props = _settings_rna().properties
    # A fresh scene holds the declared defaults.
    for name in ("integrator", "samples", "preview_samples", "seed", "max_bounces",
                 "filter_width", "tile_size"):
        assert getattr(p, name) == props[name].default, name
    # Defaults the design fixes.
    assert p.integrator == "PATH"
    assert p.filter_width == pytest.approx(1.5)  # like Cycles' filter_width
    assert p.seed == 0
    assert p.samples >= 1 and p.preview_samples >= 1
    assert p.preview_samples <= p.samples
    assert p.max_bounces >= 1
    assert props["tile_size"].hard_min >= 8  # phos.h: tile_size >= 8
    assert props["samples"].hard_min >= 1


def test_properties_round_trip(scene):
    p = scene.phos
    p.samples, p.preview_samples, p.seed, p.max_bounces = 7, 3, 12345, 4
    p.filter_width, p.tile_size = 2.0, 32
    assert (p.samples, p.preview_samples, p.seed, p.max_bounces, p.tile_size) == (7, 3, 12345, 4, 32)
    assert p.filter_width == pytest.approx(2.0)


def test_enum_items_have_explicit_indices(scene):
    """Saved files store enum indices: every item must carry an explicit, unique one."""
    settings_cls = type(scene.phos)
    checked = 0
    for cls in [settings_cls] + [c for c in bpy.types.PropertyGroup.__subclasses__()
                                 if pt.addon_module_of(c)]:
        for name, prop in getattr(cls, "__annotations__", {}).items():
            if getattr(prop, "function", None) is not bpy.props.EnumProperty:
                continue
            items = prop.keywords.get("items")
            assert not callable(items), "%s.%s: dynamic items cannot be checked" % (cls.__name__, name)
            assert all(len(item) >= 4 for item in items), (
                "%s.%s: items without explicit index: %s" % (cls.__name__, name, items))
            indices = [item[-1] if len(item) == 4 else item[4] for item in items]
            assert len(set(indices)) == len(indices), "%s.%s: duplicate indices" % (cls.__name__, name)
            checked += 1
    assert checked >= 1, "no EnumProperty found (integrator should be one)"
    rna_items = _settings_rna().properties["integrator"].enum_items
    assert rna_items["PATH"].value == 0


def test_builtin_panels_list_phos(scene):
    missing = [n for n in REQUIRED_BUILTIN_PANELS if "PHOS" not in getattr(bpy.types, n).COMPAT_ENGINES]
    assert not missing, "built-in panels without PHOS: %s" % missing


def test_cycles_and_eevee_panels_do_not_list_phos(scene):
    cycles_panels = [c.__name__ for c in _panels_with("PHOS") if c.__module__.startswith("cycles")]
    assert not cycles_panels, "Cycles panels list PHOS: %s" % cycles_panels
    cycles_set = bpy.types.CYCLES_RENDER_PT_sampling.COMPAT_ENGINES
    assert "PHOS" not in cycles_set
    eevee = [n for n in EEVEE_ONLY_PANELS if hasattr(bpy.types, n)
             and "PHOS" in getattr(bpy.types, n).COMPAT_ENGINES]
    assert not eevee, "EEVEE-only panels list PHOS: %s" % eevee
    # Whatever this Blender calls them (EEVEE's panels and engine id were
    # renamed in 4.2 and again in 5.0): no panel only EEVEE uses lists PHOS.
    eevee_ids = {"BLENDER_EEVEE", "BLENDER_EEVEE_NEXT"}
    eevee = [c.__name__ for c in _panels_with("PHOS")
             if c.COMPAT_ENGINES - {"PHOS"} and c.COMPAT_ENGINES - {"PHOS"} <= eevee_ids]
    assert not eevee, "EEVEE-only panels list PHOS: %s" % eevee


def test_light_settings_drawn_once(scene):
    """Either Blender's DATA_PT_light or a Phos light panel shows the light for Phos, not both."""
    light_panels = [c.__name__ for c in _panels_with("PHOS")
                    if getattr(c, "bl_context", "") == "data" and getattr(c, "bl_label", "") == "Light"]
    assert len(light_panels) == 1, "light panels for PHOS: %s" % light_panels


def test_library_loaded(addon):
    from phos import core
    assert core.load() is not None, core.load_error()
    assert core.load_error() == ""
    assert core.version_string().startswith("%d.%d." % core.EXPECTED_VERSION)


class _Layout:
    """A stand-in for bpy.types.UILayout in background mode: records the
    properties a panel draws and checks that each exists on its data."""

    def __init__(self, drawn, labels=None):
        self.drawn = drawn
        self.labels = labels if labels is not None else []
        self.active = True
        self.use_property_split = self.use_property_decorate = False
        self.alert = False

    def prop(self, data, name, text=None, **_kw):
        assert name in data.bl_rna.properties, "%s has no property %r" % (data, name)
        self.drawn.append(name)
        rna = data.bl_rna.properties[name]
        # A checkbox's text sits in the value column, not the label's.
        if rna.type != 'BOOLEAN':
            self.labels.append(text if text is not None else rna.name)

    def label(self, **_kw):
        pass

    def column(self, **_kw):
        return self

    row = box = column
    separator = label


def _fake_panel(cls, drawn, labels=None):
    """An object that draw() can take as `self`: the stand-in layout, and
    the panel class's own attributes and methods (bound to it)."""
    class Fake:
        def __getattr__(self, name):
            value = getattr(cls, name)
            return value.__get__(self) if callable(value) and hasattr(value, "__get__") else value
    fake = Fake()
    fake.layout = _Layout(drawn, labels)
    return fake


# The longest row label that Blender's property split shows uncut in a
# Properties editor of its default width (measured on Blender 3.4 at UI
# scale 1: "Estimate Global", 15 characters, showed as "Estimate Glo…").
LABEL_MAX = 13


def _render_panels():
    from phos import ui
    return [c for c in ui.classes if issubclass(c, bpy.types.Panel) and getattr(c, "bl_context", "") == "render"]


def test_render_tab_reads_as_cycles(scene):
    """The Render tab as a Cycles user reads it: Sampling first (Blender's
    Simplify, which registers first, is replaced by a Phos panel below Light
    Paths); every row's label fits the default width and names one thing in
    its panel; the Photon Mapping panel is hidden when no map is built."""
    from phos import ui
    names = [c.__name__ for c in _render_panels() if not getattr(c, "bl_parent_id", "")]
    assert names[0] == "PHOS_RENDER_PT_sampling", names
    assert names.index("PHOS_RENDER_PT_simplify") > names.index("PHOS_RENDER_PT_light_paths"), names
    shown = [c.__name__ for c in _panels_with("PHOS") if getattr(c, "bl_context", "") == "render"
             and not getattr(c, "bl_parent_id", "") and getattr(c, "bl_order", 0) <= 0
             and not c.__name__.startswith("PHOS_")]
    assert not shown, "built-in Render panels that sit above Sampling: %s" % shown
    scene.render.engine = "PHOS"
    context = type("Context", (), {"scene": scene, "view_layer": scene.view_layers[0], "engine": "PHOS"})()
    for integrator in ("PATH", "PHOTON"):
        scene.phos.integrator = integrator
        assert ui.PHOS_RENDER_PT_photon_mapping.poll(context) == (integrator == "PHOTON"), integrator
        for cls in _render_panels():
            drawn, labels = [], []
            fake = _fake_panel(cls, drawn, labels)
            for method in ("draw_header", "draw"):
                if method in vars(cls) or any(method in vars(b) for b in cls.__mro__[1:] if pt.addon_module_of(b)):
                    getattr(cls, method)(fake, context)
            too_long = [t for t in labels if len(t) > LABEL_MAX]
            assert not too_long, "%s: labels cut at the default width: %s" % (cls.__name__, too_long)
            named = [t for t in labels if t]
            assert len(set(named)) == len(named), "%s: two rows named alike: %s" % (cls.__name__, named)
    # The Irradiance Cache panel is active exactly when the core's plan
    # fills the cache.
    for integrator, view, cache, used in (("PATH", "FINAL_GATHER", "PHOTON", False),
                                          ("PATH", "FINAL_GATHER", "ALWAYS", True),
                                          ("PHOTON", "FINAL_GATHER", "PHOTON", True),
                                          ("PHOTON", "FAST", "ALWAYS", False),
                                          ("PHOTON", "FINAL_GATHER", "OFF", False)):
        scene.phos.integrator, scene.phos.photon_view, scene.phos.irradiance_cache = integrator, view, cache
        assert ui.cache_used(context) == used, (integrator, view, cache)
    scene.phos.photon_view, scene.phos.irradiance_cache = "FINAL_GATHER", "PHOTON"
    scene.phos.integrator = "PATH"
    scene.view_layers[0].phos.use_pass_photons = True  # a photon debug pass builds the maps under PATH
    assert ui.PHOS_RENDER_PT_photon_mapping.poll(context)


def test_phos_panels_draw(scene):
    """Every Phos panel of the render and view-layer tabs draws, for each
    integrator and cache mode, naming only properties that exist (an
    exception in draw() leaves an empty panel in Blender and a traceback
    in its console)."""
    from phos import ui
    panels = [c for c in ui.classes if issubclass(c, bpy.types.Panel)
              and getattr(c, "bl_context", "") in ("render", "view_layer")]
    assert panels
    scene.render.engine = "PHOS"
    context = type("Context", (), {"scene": scene, "view_layer": scene.view_layers[0]})()
    scene.view_layers[0].phos.use_pass_irradiance_cache = True
    names = set()
    for integrator in ("PATH", "PHOTON"):
        for cache in ("OFF", "PHOTON", "ALWAYS"):
            scene.phos.integrator, scene.phos.irradiance_cache = integrator, cache
            for cls in panels:
                drawn = []
                fake = _fake_panel(cls, drawn)
                for method in ("draw_header", "draw"):
                    if method in vars(cls) or any(method in vars(b) for b in cls.__mro__[1:] if pt.addon_module_of(b)):
                        getattr(cls, method)(fake, context)
                names.update(drawn)
    assert {"irradiance_cache", "ic_accuracy", "ic_rays", "use_pass_irradiance_cache"} <= names, sorted(names)


def test_light_panel_draws_what_phos_reads(scene):
    """The light panel shows each kind's settings Phos reads: Cycles' portal
    flag on area lights (a portal emits nothing, so no colour or power),
    the radius and (4.1+) soft falloff of point and spot lamps."""
    from phos import ui
    for kind in ("POINT", "SPOT", "SUN", "AREA"):
        light = bpy.data.lights.new("L_" + kind, kind)
        portal_values = (False, True) if kind == "AREA" and hasattr(getattr(light, "cycles", None), "is_portal") \
            else (False,)
        for portal in portal_values:
            if kind == "AREA" and len(portal_values) == 2:
                light.cycles.is_portal = portal
            context = type("Context", (), {"scene": scene, "light": light, "engine": "PHOS"})()
            drawn = []
            ui.PHOS_LIGHT_PT_light.draw(_fake_panel(ui.PHOS_LIGHT_PT_light, drawn), context)
            assert ("energy" in drawn) == (not portal), (kind, portal, drawn)
            if kind == "AREA" and len(portal_values) == 2:
                assert "is_portal" in drawn, drawn
            if kind in ("POINT", "SPOT"):
                assert "shadow_soft_size" in drawn
                assert ("use_soft_falloff" in drawn) == hasattr(light, "use_soft_falloff"), drawn
