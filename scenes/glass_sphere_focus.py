# SPDX-License-Identifier: GPL-3.0-or-later
"""The glass sphere's caustic seen close up, at its focus: where a fixed-k estimate's blur shows.

    blender -b --factory-startup --python scenes/glass_sphere_focus.py -- --render out/glass_sphere_focus
    (options: see scenes/_common.py; the default integrator here is PHOTON)

scenes/glass_sphere_caustic.py with the camera's lens four times as long
(180 mm) and aimed at the focus of the ball lens on the floor: where the
ray from the lamp through the sphere's centre meets the floor. A pixel
here covers a sixteenth of the floor it covers in the full view, so the
disc of the k nearest caustic photons spans pixels across the focus
(docs/benchmarks.md, "The ring's cusp close up").
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402
import glass_sphere_caustic  # noqa: E402

MAX_BOUNCES = glass_sphere_caustic.MAX_BOUNCES
DEFAULT_SAMPLES = glass_sphere_caustic.DEFAULT_SAMPLES
PHOTON_SETTINGS = glass_sphere_caustic.PHOTON_SETTINGS
LENS_MM = 180.0
# The lamp (-1.6, 1.2, 2.6) through the centre (0, 0, 0.5) meets the floor
# at about (0.38, -0.29, 0).
FOCUS = (0.38, -0.29, 0.0)

BENCH_REFERENCE = _common.CLOSE_UP_REFERENCE


def build(scene):
    return _common.close_up(glass_sphere_caustic.build(scene), LENS_MM, FOCUS)


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], MAX_BOUNCES, photon_settings=PHOTON_SETTINGS,
                      default_samples=DEFAULT_SAMPLES, default_integrator="PHOTON")
