# SPDX-License-Identifier: GPL-3.0-or-later
"""An object on a floor under a spot, nothing else: the product shot's
simplest light.

    blender -b --factory-startup --python scenes/spot_on_floor.py -- --render out/spot_on_floor
    (options: see scenes/_common.py; the default integrator here is PHOTON)

A matte cube and a Principled ball on an 8 m floor under one spot of
45°, without a world. With `PHOTON` it shows what photon tracing costs
when every photon of the spot lands on the floor or the objects: the
global map's yield and its share of the render (docs/benchmarks.md,
"Lamps' photons aimed at what they can reach").
"""

import math
import os
import sys

import bmesh

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402
import _materials as m  # noqa: E402

MAX_BOUNCES = 12
DEFAULT_SAMPLES = 64
PHOTON_SETTINGS = {}


def build(scene):
    _common.clear_factory_scene()
    m.plane(scene, "Floor", 8.0, 8.0, m.diffuse("Floor", (0.6, 0.6, 0.6)))
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=0.6)
    m.mesh_object(scene, "Cube", bm, m.diffuse("Cube", (0.3, 0.5, 0.7)), location=(0.4, -0.2, 0.3),
                  rotation=(0.0, 0.0, math.radians(30.0)))
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=48, v_segments=24, radius=0.35)
    m.mesh_object(scene, "Ball", bm, m.polished("Ball", (0.7, 0.25, 0.2), 0.3), smooth=True,
                  location=(-0.5, 0.3, 0.35))
    m.lamp(scene, 'SPOT', "Spot", 400.0, (1.5, -1.0, 3.0), (0.0, 0.0, 0.3), shadow_soft_size=0.1,
           spot_size=math.radians(45.0), spot_blend=0.15)
    m.camera(scene, (0.3, -4.2, 2.2), (0.0, 0.1, 0.3), lens=40.0)
    m.world(scene, (0.0, 0.0, 0.0))
    return scene


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], MAX_BOUNCES, photon_settings=PHOTON_SETTINGS,
                      default_samples=DEFAULT_SAMPLES, default_integrator="PHOTON")
