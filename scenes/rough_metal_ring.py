# SPDX-License-Identifier: GPL-3.0-or-later
"""The metal ring of metal_ring.py in brushed metal: a glossy caustic.

    blender -b --factory-startup --python scenes/rough_metal_ring.py -- --render out/rough_metal_ring
    (options: see scenes/_common.py; the default integrator here is PHOTON)

The same ring, floor and low sun as scenes/metal_ring.py, but the ring is
GGX gold of roughness 0.15 instead of a mirror. Its reflection still
focuses the sun into the cardioid, blurred by the lobe: a glossy caustic,
which Phos carries in its caustic map because the ring is smoother than
*Caustic Roughness* (0.3 by default; README, "Glossy caustics").
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402
import _materials as m  # noqa: E402
import metal_ring  # noqa: E402

RING_ROUGHNESS = 0.15
MAX_BOUNCES = metal_ring.MAX_BOUNCES
DEFAULT_SAMPLES = metal_ring.DEFAULT_SAMPLES
PHOTON_SETTINGS = metal_ring.PHOTON_SETTINGS


def build(scene):
    metal_ring.build(scene)
    scene.objects["Ring"].data.materials[0] = m.glossy("Brushed Gold", (1.0, 0.78, 0.34), RING_ROUGHNESS)
    return scene


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], MAX_BOUNCES,
                      photon_settings=PHOTON_SETTINGS, default_samples=DEFAULT_SAMPLES,
                      default_integrator="PHOTON")
