# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks of the test harness's own assumptions (no Phos involved)."""

import numpy as np
import pytest

import phostest as pt


@pytest.mark.parametrize("view", ["Filmic", "Standard"])
def test_exr_round_trip_is_linear(view, scene, tmp_path):
    """render_array reads scene-linear values whatever the view transform."""
    pt.add_camera(scene)
    pt.set_world(scene, (0.5, 0.25, 2.0))
    scene.view_settings.view_transform = view
    scene.view_settings.exposure = 1.0  # display-only: must not reach the EXR
    pt.configure_output(scene, 8, 8)
    pt.configure_cycles(scene, 1, max_bounces=0)
    img = pt.render_array(scene, tmp_path, "CYCLES")
    assert img.shape == (8, 8, 4)
    assert np.allclose(img[..., :3], (0.5, 0.25, 2.0), atol=1e-6)
    assert np.all(img[..., 3] == 1.0)


def test_blender_border_rect_formula(scene, tmp_path):
    """Blender truncates float32 border × size (0.7 × 180 → 126, not 125)."""
    pt.add_camera(scene)
    pt.set_world(scene, (1, 1, 1))
    pt.configure_output(scene, 180, 8)
    pt.configure_cycles(scene, 1, max_bounces=0)
    r = scene.render
    r.use_border, r.use_crop_to_border = True, True
    r.border_min_x, r.border_max_x, r.border_min_y, r.border_max_y = 0.1, 0.7, 0.0, 1.0
    img = pt.render_array(scene, tmp_path, "CYCLES")
    assert img.shape[1] == 126 - 18
