# SPDX-License-Identifier: GPL-3.0-or-later
"""A product shot under an HDR: glossy, metal and diffuse objects lit by a
captured environment alone.

    blender -b --factory-startup --python scenes/hdr_product.py -- --render out/hdr_product
    (options: see scenes/_common.py; the default integrator here is PHOTON)

How most product and character shots are lit: no lamps, one of the HDR
environments Blender ships (courtyard.exr, turned by a Mapping node) over a
pale table. On it a glazed ceramic ball (the Principled BSDF, roughness
0.2 over a blue base), a brushed steel can (GGX metal, roughness 0.3) and a
matte clay cube. Everything is lit through the environment light: its
importance-sampled map, its MIS with each BSDF, and its photons.
"""

import math
import os
import sys

import bmesh
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402
import _materials as m  # noqa: E402

HDR = "courtyard"
HDR_ROTATION_DEG = 40.0
MAX_BOUNCES = 12
DEFAULT_SAMPLES = 64
PHOTON_SETTINGS = {}


def build(scene):
    _common.clear_factory_scene()
    m.plane(scene, "Table", 6.0, 6.0, m.diffuse("Table", (0.8, 0.78, 0.74)))
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=64, v_segments=32, radius=0.35)
    m.mesh_object(scene, "Ball", bm, m.polished("Glazed Ceramic", (0.15, 0.3, 0.65), 0.2), smooth=True,
                  location=(-0.45, 0.1, 0.35))
    bm = bmesh.new()
    bmesh.ops.create_cone(bm, cap_ends=True, cap_tris=False, segments=64, radius1=0.22, radius2=0.22, depth=0.6)
    m.mesh_object(scene, "Can", bm, m.glossy("Brushed Steel", (0.8, 0.8, 0.82), 0.3), smooth=True,
                  location=(0.35, 0.35, 0.3))
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=0.4)
    m.mesh_object(scene, "Cube", bm, m.diffuse("Clay", (0.75, 0.45, 0.3)), location=(0.3, -0.35, 0.2),
                  rotation=(0.0, 0.0, math.radians(25.0)))
    m.camera(scene, (0.2, -2.6, 1.3), (0.0, 0.05, 0.25), lens=45.0)
    m.hdr_world(scene, HDR, strength=1.0, rotation_z_deg=HDR_ROTATION_DEG)
    return scene


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], MAX_BOUNCES, photon_settings=PHOTON_SETTINGS,
                      default_samples=DEFAULT_SAMPLES, default_integrator="PHOTON")
