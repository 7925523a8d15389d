# SPDX-License-Identifier: GPL-3.0-or-later
"""The metal ring's caustic seen close up, at its cusp: where a fixed-k estimate's blur shows.

    blender -b --factory-startup --python scenes/metal_ring_cusp.py -- --render out/metal_ring_cusp
    (options: see scenes/_common.py; the default integrator here is PHOTON)

scenes/metal_ring.py with the camera's lens four times as long (160 mm)
and aimed at the nephroid's cusp, half the ring's radius from its centre
on the side away from the sun. A pixel here covers a sixteenth of the
floor it covers in the full view, so the disc of the k nearest caustic
photons spans several pixels across the cusp's bright lines: the fixed
estimate's error stops falling with samples, and progressive caustics,
whose radius shrinks, keep going (docs/benchmarks.md, "The ring's cusp
close up").
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402
import metal_ring  # noqa: E402

MAX_BOUNCES = metal_ring.MAX_BOUNCES
DEFAULT_SAMPLES = metal_ring.DEFAULT_SAMPLES
PHOTON_SETTINGS = metal_ring.PHOTON_SETTINGS
LENS_MM = 160.0
# The nephroid's cusp: about R/2 from the centre, away from the sun
# (azimuth 135° + 180°), rounded to the centimetre.
CUSP = (0.35, -0.35, 0.0)

BENCH_REFERENCE = _common.CLOSE_UP_REFERENCE


def build(scene):
    return _common.close_up(metal_ring.build(scene), LENS_MM, CUSP)


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], MAX_BOUNCES, photon_settings=PHOTON_SETTINGS,
                      default_samples=DEFAULT_SAMPLES, default_integrator="PHOTON")
