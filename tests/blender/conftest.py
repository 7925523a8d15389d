# SPDX-License-Identifier: GPL-3.0-or-later
"""Fixtures of the Blender tests (run inside Blender by run_tests.py).

- ``scene``: a clean file (factory settings, empty scene) with the add-on
  enabled; every test that uses it starts from the same state.
- ``render``: ``render(engine=None, name=None) -> float32 array (H, W, 4)``,
  linear RGBA, rows bottom-up; renders the current scene to an EXR in the
  test's tmp dir with write_still and loads it back.
- ``addon``: the enabled add-on module (skips nothing: a missing add-on fails).
- ``tmp_path`` (pytest's) for temporary files.
"""

import pytest

import phostest


def pytest_report_header(config):
    import bpy
    return "blender %s, add-on enabled: %s" % (bpy.app.version_string, phostest.addon_enabled())


@pytest.fixture
def addon():
    mod = phostest.enable_addon()
    assert mod is not None, "the Phos add-on could not be enabled from %s" % phostest.ADDON_DIR
    return mod


@pytest.fixture
def scene(addon):
    sc = phostest.reset_file()
    assert phostest.addon_enabled(), "the add-on was lost after read_factory_settings"
    return sc


@pytest.fixture
def render(scene, tmp_path):
    def _render(engine=None, name=None):
        import bpy
        return phostest.render_array(bpy.context.scene, tmp_path, engine=engine, name=name)
    return _render


def pytest_terminal_summary(terminalreporter):
    if phostest.PARITY_ROWS:
        import test_parity
        terminalreporter.section("Phos vs Cycles parity")
        terminalreporter.write_line(test_parity.format_table(phostest.PARITY_ROWS))
