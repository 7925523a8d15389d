# SPDX-License-Identifier: GPL-3.0-or-later
"""Every kind of lamp at once: point, spot, area and sun over a few objects
on a floor, under a dim grey world.

    blender -b --factory-startup --python scenes/lamp_kinds.py -- --render out/lamp_kinds
    (options: see scenes/_common.py; the default integrator here is PATH)

Where next-event estimation decides the noise: which lamp a light sample
picks at each point, how each lamp is sampled (a point lamp and a spot with
a radius, a rectangular area lamp, a sun with an angle), and the world's
own sample (docs/algorithms.md §7). The objects are a Principled ball at
roughness 0.3, a matte cube and a rough metal cylinder, so that diffuse and
glossy lobes both meet every lamp. Strengths are in Cycles' units and
chosen so that no lamp dominates the image.
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
    bmesh.ops.create_uvsphere(bm, u_segments=48, v_segments=24, radius=0.4)
    m.mesh_object(scene, "Ball", bm, m.polished("Ball", (0.7, 0.25, 0.2), 0.3), smooth=True,
                  location=(-0.7, 0.2, 0.4))
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=0.6)
    m.mesh_object(scene, "Cube", bm, m.diffuse("Cube", (0.3, 0.5, 0.7)), location=(0.5, -0.3, 0.3),
                  rotation=(0.0, 0.0, math.radians(30.0)))
    bm = bmesh.new()
    bmesh.ops.create_cone(bm, cap_ends=True, cap_tris=False, segments=48, radius1=0.25, radius2=0.25, depth=0.9)
    m.mesh_object(scene, "Can", bm, m.glossy("Can", (0.85, 0.8, 0.7), 0.35), smooth=True,
                  location=(0.3, 0.8, 0.45))
    m.lamp(scene, "POINT", "Point", 120.0, (-2.0, -1.5, 2.5), (0, 0, 0), shadow_soft_size=0.1)
    m.lamp(scene, "SPOT", "Spot", 300.0, (2.5, 1.0, 3.0), (0.3, 0.5, 0.3), shadow_soft_size=0.1,
         spot_size=math.radians(45.0), spot_blend=0.15)
    m.lamp(scene, "AREA", "Area", 60.0, (0.0, -2.5, 2.0), (0, 0, 0.4), shape='RECTANGLE', size=1.0, size_y=0.5)
    m.lamp(scene, "SUN", "Sun", 1.0, (0, 0, 5), (1.0, 2.0, 0.0), angle=math.radians(2.0))
    m.camera(scene, (0.3, -4.2, 2.2), (0.0, 0.2, 0.35), lens=40.0)
    m.world(scene, (0.05, 0.05, 0.05))
    return scene


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], MAX_BOUNCES, photon_settings=PHOTON_SETTINGS,
                      default_samples=DEFAULT_SAMPLES, default_integrator="PATH")
