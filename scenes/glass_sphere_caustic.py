# SPDX-License-Identifier: GPL-3.0-or-later
"""A glass sphere on a diffuse floor: the classic refraction caustic.

    blender -b --factory-startup --python scenes/glass_sphere_caustic.py -- --render out/glass_sphere_caustic
    (options: see scenes/_common.py; the default integrator here is PHOTON)

A sphere of glass (IOR 1.5, radius 0.5 m) rests on a large white Lambertian
floor in front of a white back wall. A small point light (radius 2 cm) high
up on the left shines through the sphere: a ball lens of index n has its
focus n·R / (2(n − 1)) = 1.5 R from its centre, so the floor, about 1.4 R
from the centre along the light's direction, catches a bright, nearly focused
spot inside the sphere's shadow — the caustic of Jensen's photon-mapping
course images, which the caustic photon map renders sharply and a path
tracer only as noise.
"""

import math
import os
import sys

import bmesh
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402
import _materials as m  # noqa: E402

RADIUS = 0.5
LIGHT_LOCATION = (-1.6, 1.2, 2.6)
LIGHT_POWER_W = 400.0
LIGHT_RADIUS = 0.02
MAX_BOUNCES = 12
DEFAULT_SAMPLES = 16
# About one minute at 512 × 512 and 16 samples on two cores.
PHOTON_SETTINGS = {
    "global_photons": 100000,
    "caustic_photons": 200000,
    "global_estimate_photons": 60,
    "caustic_estimate_photons": 100,
    "max_radius": 0.1,
    "final_gather_rays": 32,
}

# The benchmark's reference (bench/quality.py): Cycles, 65 536 samples in
# 256 chunks. Cycles finds this caustic only where a path from the floor
# happens to hit the small light through the specular object, so even
# there its caustic is noisy; the chunks' spread measures that noise, which
# the tables take out of every score and report as the reference's own
# error (docs/benchmarks.md). A PHOTON reference would be Phos judging
# itself: its own blur of the caustic would never count.
BENCH_REFERENCE = {"engine": "CYCLES", "chunks": 256, "chunk_samples": 256, "settings": {}}


def build(scene):
    _common.clear_factory_scene()
    white = m.diffuse("Floor White", (0.75, 0.75, 0.75))
    m.plane(scene, "Floor", 8.0, 8.0, white)
    m.plane(scene, "Back Wall", 8.0, 4.0, m.diffuse("Wall White", (0.7, 0.7, 0.7)),
            location=(0.0, 2.5, 2.0), rotation=(math.pi / 2, 0.0, 0.0))

    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=96, v_segments=48, radius=RADIUS)
    m.mesh_object(scene, "Glass Sphere", bm, m.glass("Glass", ior=1.5), smooth=True,
                  location=(0.0, 0.0, RADIUS))

    light = bpy.data.lights.new("Light", "POINT")
    light.energy = LIGHT_POWER_W
    light.shadow_soft_size = LIGHT_RADIUS
    light_ob = bpy.data.objects.new("Light", light)
    light_ob.location = LIGHT_LOCATION
    m.link(scene, light_ob)

    m.camera(scene, (0.9, -4.2, 2.2), (0.35, 0.1, 0.25), lens=45.0)
    m.world(scene, (0.0, 0.0, 0.0))
    return scene


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], MAX_BOUNCES, photon_settings=PHOTON_SETTINGS,
                      default_samples=DEFAULT_SAMPLES, default_integrator="PHOTON")
