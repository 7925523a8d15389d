# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender's default scene: the cube, its point lamp and the grey world.

    blender -b --factory-startup --python scenes/default_scene.py -- --render out/default_scene
    (options: see scenes/_common.py; the default integrator here is PATH)

What every new user renders first, as the factory startup file of the
running Blender makes it: the cube's Principled BSDF at its defaults
(roughness 0.5), the 1000 W point lamp of radius 0.1 m and the world's
0.05 grey. Nothing here is built; the scene checks that the factory objects
are there. Its light is direct light from a small lamp plus a dim world
seen through a glossy lobe: where next-event estimation decides the noise
(docs/algorithms.md §7, docs/benchmarks.md).
"""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402

MAX_BOUNCES = 12
DEFAULT_SAMPLES = 64
PHOTON_SETTINGS = {}


def build(scene):
    missing = [name for name in ("Cube", "Light", "Camera") if name not in bpy.data.objects]
    if missing or scene.world is None:
        raise RuntimeError("default_scene.py needs Blender's factory startup scene (--factory-startup); "
                           "missing: %s" % (", ".join(missing) or "the world"))
    scene.camera = bpy.data.objects["Camera"]
    return scene


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], MAX_BOUNCES, photon_settings=PHOTON_SETTINGS,
                      default_samples=DEFAULT_SAMPLES, default_integrator="PATH")
