# SPDX-License-Identifier: GPL-3.0-or-later
"""The generated binding (addon/phos/phos_h.py, from phos.h by
tools/gen_binding.py) against the library and the add-on that use it:

- the load check compares every field's offset: a copy of the binding with
  two same-size fields of phos_render_settings swapped (so every struct size
  still matches) is refused with a message naming the struct and field,
  while an unmodified copy loads;
- scene.phos is the settings table: property names, labels, defaults,
  ranges and kinds of every user setting, and the table's defaults are the
  library's phos_render_settings_init;
- the engine copies every user setting into the core's settings;
- the stats line names the stages of the core's plan.
"""

import ctypes
import importlib
import os
import shutil
import sys

import bpy
import pytest

import phostest as pt

INT_MAX = 2 ** 31 - 1


def _binding_copy(tmp_path, package, edit=None):
    """core.py and phos_h.py copied into a package of their own (core.py does
    not import bpy); edit(text) -> text changes the copied phos_h.py."""
    from phos import core
    src = os.path.dirname(core.__file__)
    dst = tmp_path / package
    dst.mkdir()
    (dst / "__init__.py").write_text("")
    shutil.copy(os.path.join(src, "core.py"), str(dst / "core.py"))
    text = open(os.path.join(src, "phos_h.py"), encoding="utf-8").read()
    (dst / "phos_h.py").write_text(edit(text) if edit else text, encoding="utf-8")
    return dst


def _swap_fields(text, struct, a, b):
    """phos_h.py text with the _fields_ rows of fields a and b of struct swapped."""
    start = text.index("class %s(ctypes.Structure):" % struct)
    end = text.index("    ]\n", start)
    body = text[start:end]
    rows = body.split("\n")
    ia = next(i for i, row in enumerate(rows) if row.strip().startswith('("%s",' % a))
    ib = next(i for i, row in enumerate(rows) if row.strip().startswith('("%s",' % b))
    assert rows[ia].split(",", 1)[1] == rows[ib].split(",", 1)[1], "not the same type: %s / %s" % (
        rows[ia], rows[ib])
    rows[ia], rows[ib] = rows[ib], rows[ia]
    return text[:start] + "\n".join(rows) + text[end:]


def _load_copy(tmp_path, monkeypatch, package):
    from phos import core
    assert core.load() is not None, core.load_error()
    monkeypatch.setenv(core.LIBRARY_ENV, core.loaded_path())
    monkeypatch.syspath_prepend(str(tmp_path))
    try:
        copy = importlib.import_module(package + ".core")
        return copy, copy.load(), copy.load_error()
    finally:
        for name in [m for m in sys.modules if m == package or m.startswith(package + ".")]:
            del sys.modules[name]


# ------------------------------------------------------------ layout check

def test_unmodified_binding_copy_loads(addon, tmp_path, monkeypatch):
    _binding_copy(tmp_path, "binding_same")
    _copy, lib, error = _load_copy(tmp_path, monkeypatch, "binding_same")
    assert lib is not None and error == "", error


def test_swapped_fields_are_refused(addon, tmp_path, monkeypatch):
    """Same sizes everywhere, two uint32 fields in each other's place: only the
    offset check can see it."""
    _binding_copy(tmp_path, "binding_swapped",
                  lambda text: _swap_fields(text, "phos_render_settings", "global_photons", "caustic_photons"))
    copy, lib, error = _load_copy(tmp_path, monkeypatch, "binding_swapped")
    from phos import core
    assert copy.phos_render_settings.global_photons.offset == core.phos_render_settings.caustic_photons.offset
    assert [s.__name__ for s in copy.STRUCTS] == [s.__name__ for s in core.STRUCTS]
    for mine, theirs in zip(copy.STRUCTS, core.STRUCTS):
        assert ctypes.sizeof(mine) == ctypes.sizeof(theirs), mine.__name__
    assert lib is None, "a binding with swapped fields was accepted"
    assert "phos_render_settings.caustic_photons" in error or \
        "phos_render_settings.global_photons" in error, error
    assert "offset" in error and "different phos.h" in error, error


def test_binding_covers_the_library_structs(addon):
    """Every struct the library knows by name is mirrored, at its size."""
    from phos import core
    lib = core.lib()
    for struct in core.STRUCTS:
        assert lib.phos_struct_size(struct.__name__.encode()) == ctypes.sizeof(struct)
    assert lib.phos_struct_size(b"phos_no_such_struct") == 0


# ------------------------------------------------------ settings by table

def _rna():
    return bpy.types.Scene.bl_rna.properties["phos"].fixed_type.properties


def test_scene_properties_are_the_settings_table(scene):
    from phos import core, properties
    rna = _rna()
    user = [s for s in core.RENDER_SETTINGS if s.user]
    assert user and len(user) < len(core.RENDER_SETTINGS), "the table has user and host rows"
    for s in user:
        assert s.prop in rna, "scene.phos.%s missing" % s.prop
        p = rna[s.prop]
        assert p.name == s.label and p.description == s.description, s.prop
        if s.kind == "ENUM":
            items = properties.ENUM_ITEMS[s.enum]
            values = set(core.ENUMS[s.enum].values())
            assert all(item[3] in values and s.min <= item[3] <= s.max for item in items), s.prop
            assert {i.identifier: i.value for i in p.enum_items} == {i[0]: i[3] for i in items}, s.prop
            assert p.enum_items[p.default].value == s.default, s.prop
            continue
        if s.kind == "BOOLEAN":
            assert p.type == 'BOOLEAN' and p.default == bool(s.default) and (s.min, s.max) == (0, 1), s.prop
            continue
        assert p.default == pytest.approx(s.default), s.prop
        assert p.hard_min == pytest.approx(s.min), s.prop
        assert p.hard_max == pytest.approx(min(s.max, INT_MAX) if s.ctype != "float" else s.max), s.prop
        assert p.soft_max == pytest.approx(s.soft_max or p.hard_max), s.prop
        subtype = {"PIXELS": "PIXEL", "LENGTH": "DISTANCE", "FACTOR": "FACTOR",
                   "SECONDS": "TIME_ABSOLUTE"}.get(s.kind, "NONE")
        assert p.subtype == subtype, s.prop
    # Host rows are Blender's own settings, not scene.phos properties.
    for s in core.RENDER_SETTINGS:
        if not s.user:
            assert s.name not in rna, s.name
    assert rna["preview_samples"].hard_min == rna["samples"].hard_min


def test_table_defaults_are_the_library_defaults(addon):
    from phos import core
    rs = core.new_render_settings()
    for s in core.RENDER_SETTINGS:
        assert getattr(rs, s.name) == pytest.approx(s.default), s.name


def test_engine_copies_every_user_setting(scene, monkeypatch):
    """Each user setting set away from its default reaches the core's
    settings under its field name (the render is stopped at create)."""
    from phos import core, properties
    pt.add_plane(scene, "Floor", material=pt.diffuse("White", (0.5, 0.5, 0.5)))
    pt.add_camera(scene)
    pt.configure_output(scene, 16, 12)
    scene.render.engine = "PHOS"
    p = scene.phos
    expected = {}
    for s in properties.USER_SETTINGS:
        if s.kind == "ENUM":
            item = next(i for i in properties.ENUM_ITEMS[s.enum] if i[3] != s.default)
            setattr(p, s.prop, item[0])
            expected[s.name] = item[3]
        else:
            value = s.default + (1 if s.ctype != "float" else 0.25)
            if value > s.max:
                value = s.default - 1
            setattr(p, s.prop, value)
            expected[s.name] = value
    captured = []

    def spy(core_scene, settings):
        captured.append({s.name: getattr(settings, s.name) for s in core.RENDER_SETTINGS})
        raise core.PhosError("stopped on purpose")

    monkeypatch.setattr(core, "Render", spy)
    with pytest.raises(RuntimeError, match="stopped on purpose"):
        bpy.ops.render.render()
    assert len(captured) == 1
    got = captured[0]
    for name, value in expected.items():
        assert got[name] == pytest.approx(value), name
    assert (got["width"], got["height"]) == (16, 12)
    assert got["pass_mask"] == 1 << core.PHOS_PASS_COMBINED


# ------------------------------------------------------------------ stages

def test_stats_line_follows_the_core_plan(scene, monkeypatch):
    """Every stage of the core's plan is shown once, in order, named by the core."""
    from phos import core, engine
    pt.add_plane(scene, "Floor", material=pt.diffuse("White", (0.5, 0.5, 0.5)))
    pt.add_light(scene, "POINT", 100.0, location=(0, 0, 2))
    pt.add_camera(scene)
    pt.configure_output(scene, 16, 12)
    scene.render.engine = "PHOS"
    p = scene.phos
    p.integrator, p.photon_view, p.samples = "PHOTON", "FINAL_GATHER", 1
    p.global_photons, p.caustic_photons, p.final_gather_rays = 2000, 0, 2
    plans, lines = [], []
    original_stages = core.Render.stages

    def spy_stages(self):
        plan = original_stages(self)
        plans.append(plan)
        return plan

    monkeypatch.setattr(core.Render, "stages", spy_stages)
    original_stats = engine.PhosRenderEngine._stats

    def spy_stats(self, text, force=False):
        if force:  # shown whatever the rate limit
            lines.append(text)
        original_stats(self, text, force)

    monkeypatch.setattr(engine.PhosRenderEngine, "_stats", spy_stats)
    bpy.ops.render.render()
    assert len(plans) == 1
    names = [name for _id, name in plans[0]]
    assert names == ["Waiting", "Tracing photons", "Building kd-trees", "Precomputing radiance",
                     "Filling irradiance cache", "Rendering with photon maps", "Finished"], names
    shown = []
    for line in lines:
        for name in names:
            if line.startswith("Phos | " + name) and (not shown or shown[-1] != name):
                shown.append(name)
    assert shown[-1] == "Finished" and shown == [n for n in names if n in shown], lines
    assert all(name in shown for name in names[1:]), lines
