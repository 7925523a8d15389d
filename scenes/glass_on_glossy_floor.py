# SPDX-License-Identifier: GPL-3.0-or-later
"""A glass sphere on a varnished floor: a caustic on a glossy surface.

    blender -b --factory-startup --python scenes/glass_on_glossy_floor.py -- --render out/glass_on_glossy_floor
    (options: see scenes/_common.py; the default integrator here is PHOTON)

The glass sphere, lamp and wall of glass_sphere_caustic.py, on a floor of
varnished wood instead of white paper: the Principled BSDF, a diffuse
base under a dielectric coat of roughness 0.25. The sphere's caustic falls
on the floor's diffuse base, read from the caustic map, and its glossy
coat reflects the sphere and the lamp; the course's "Caustics On Glossy
Surfaces". The floor's coat, a glossy dielectric layer, stores photons
like its base (README, "Glossy caustics"), and its reflections of the
caustic are path traced from the camera.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402
import _materials as m  # noqa: E402
import glass_sphere_caustic  # noqa: E402

FLOOR_COLOR = (0.45, 0.28, 0.16)
FLOOR_ROUGHNESS = 0.25


def build(scene):
    glass_sphere_caustic.build(scene)
    scene.objects["Floor"].data.materials[0] = m.polished("Varnished Wood", FLOOR_COLOR, FLOOR_ROUGHNESS)
    return scene


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], glass_sphere_caustic.MAX_BOUNCES,
                      photon_settings=glass_sphere_caustic.PHOTON_SETTINGS,
                      default_samples=glass_sphere_caustic.DEFAULT_SAMPLES, default_integrator="PHOTON")
