# SPDX-License-Identifier: GPL-3.0-or-later
"""Objects whose transform Embree cannot use render as nothing, and the
rest of the frame renders as without them (docs/reliability.md, "Bad
input").

An object scaled to zero on an axis is how animations often hide things;
its matrix has no inverse, and before the core left such instances out of
the BVH, the first ray into one reached Embree's validity assertion and
aborted Blender. Likewise an object translated beyond 10¹⁵.
"""

import numpy as np
import pytest

import phostest as pt


def build(scene, extra=None):
    pt.add_camera(scene, location=(0, -5, 2), target=(0, 0, 0.5))
    pt.add_plane(scene, "Floor", size=6, material=pt.diffuse("Floor", (0.8, 0.8, 0.8)))
    pt.add_cube(scene, "Box", location=(0.8, 0.5, 0.5))
    pt.add_light(scene, "POINT", 300.0, location=(1, -1, 3))
    pt.set_world(scene, (0.1, 0.1, 0.1))
    pt.configure_output(scene, 24, 16)
    pt.configure_phos(scene, 4, max_bounces=4)
    scene.render.engine = "PHOS"
    scene.phos.integrator = "PHOTON"
    scene.phos.global_photons = scene.phos.caustic_photons = 5000
    if extra:
        extra(scene)


def zero_scale(scene):
    ob = pt.add_cube(scene, "Hidden", location=(-0.8, 0, 0.5), material=pt.emission("Glow", (1, 1, 1), 50.0))
    ob.scale = (1.0, 0.0, 1.0)


def all_zero_scale(scene):
    ob = pt.add_cube(scene, "Gone", location=(-0.8, 0, 0.5))
    ob.scale = (0.0, 0.0, 0.0)


def far_away(scene):
    pt.add_cube(scene, "Far", location=(1e20, 0, 0))


@pytest.mark.parametrize("extra", [zero_scale, all_zero_scale, far_away])
def test_unusable_transforms_render_nothing(scene, tmp_path, extra):
    build(scene, extra)
    px = pt.render_array(scene, tmp_path, name="with")
    assert np.all(np.isfinite(px))
    pt.reset_file()
    import bpy
    scene = bpy.context.scene
    build(scene)
    reference = pt.render_array(scene, tmp_path, name="without")
    # The same image, bit for bit: the same seed, and nothing of the
    # unusable object reaches the BVH or the light table.
    assert np.array_equal(px, reference), np.abs(px - reference).max()
