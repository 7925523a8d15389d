# SPDX-License-Identifier: GPL-3.0-or-later
"""A glass cube on a diffuse floor, lit from above at an angle: the cube caustic.

    blender -b --factory-startup --python scenes/cube_caustic.py -- --render out/cube_caustic
    (options: see scenes/_common.py; the default integrator here is PHOTON)

A glass cube (IOR 1.5, 0.8 m, flat faces, turned 30° about the vertical)
stands on a white Lambertian floor in front of a white back wall. A small
point light high up on the left shines into the top face: the flat faces
refract the light as a slab does, so the floor behind the cube catches the
light that went in through the top and out through a side (a bright
sheared patch in the cube's shadow), and the edges split it into sharp
lines — the cube caustic of the photon-mapping course, from the caustic
photon map.
"""

import math
import os
import sys

import bmesh
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402
import _materials as m  # noqa: E402

EDGE = 0.8
TURN_DEG = 30.0
LIGHT_LOCATION = (-2.2, 1.4, 2.0)
LIGHT_POWER_W = 400.0
LIGHT_RADIUS = 0.02
MAX_BOUNCES = 12
DEFAULT_SAMPLES = 16
PHOTON_SETTINGS = {
    "global_photons": 100000,
    "caustic_photons": 200000,
    "global_estimate_photons": 60,
    "caustic_estimate_photons": 80,
    "max_radius": 0.1,
    "final_gather_rays": 32,
}

# The benchmark's reference (bench/quality.py). Cycles finds this caustic
# only where a path from the floor happens to hit the small lamp through
# the specular object; after 8192 samples it is still fireflies, and its
# errors would be mostly its own. The reference is Phos with consistent
# methods only, bench/quality.py's PHOS_REFERENCE_SETTINGS: progressive
# caustics and path-traced gathers, no irradiance cache and no global map,
# in chunks of 2048 samples (docs/benchmarks.md, "Phos references,
# consistent methods only").
BENCH_REFERENCE = {"engine": "PHOS", "chunks": 8}


def build(scene):
    _common.clear_factory_scene()
    m.plane(scene, "Floor", 8.0, 8.0, m.diffuse("Floor White", (0.75, 0.75, 0.75)))
    m.plane(scene, "Back Wall", 8.0, 4.0, m.diffuse("Wall White", (0.7, 0.7, 0.7)),
            location=(0.0, 2.5, 2.0), rotation=(math.pi / 2, 0.0, 0.0))

    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=EDGE)
    m.mesh_object(scene, "Glass Cube", bm, m.glass("Glass", ior=1.5), smooth=False,
                  location=(0.0, 0.0, EDGE / 2), rotation=(0.0, 0.0, math.radians(TURN_DEG)))

    light = bpy.data.lights.new("Light", "POINT")
    light.energy = LIGHT_POWER_W
    light.shadow_soft_size = LIGHT_RADIUS
    light_ob = bpy.data.objects.new("Light", light)
    light_ob.location = LIGHT_LOCATION
    m.link(scene, light_ob)

    m.camera(scene, (1.2, -4.0, 2.4), (0.35, 0.2, 0.2), lens=45.0)
    m.world(scene, (0.0, 0.0, 0.0))
    return scene


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], MAX_BOUNCES, photon_settings=PHOTON_SETTINGS,
                      default_samples=DEFAULT_SAMPLES, default_integrator="PHOTON")
