# SPDX-License-Identifier: GPL-3.0-or-later
"""A cognac glass on a table under an HDR: caustics from environment light.

    blender -b --factory-startup --python scenes/cognac_glass.py -- --render out/cognac_glass
    (options: see scenes/_common.py; the default integrator here is PHOTON)

The course's "Cognac Glass": a snifter, a profile revolved about the
vertical axis (a foot, a stem, a wide bowl narrowing to the rim, 2 mm
walls) of clear glass with a warm tint, stands on a pale table lit by one
of the HDR environments Blender ships (sunset.exr, its sun low). The bright
part of the sky refracts through the bowl into a caustic on the table;
the glass reflects the environment. Everything that lights it comes from
the HDR: the environment light's importance sampling, its photons aimed
at the glass, and its MIS with the glass's and the table's BSDFs.
"""

import math
import os
import sys

import bmesh
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402
import _materials as m  # noqa: E402

# The outer profile (radius, height) in metres, from the foot's edge up to
# the rim; the inner wall follows it WALL inside, from the rim down to the
# bowl's floor.
OUTER = [(0.040, 0.000), (0.040, 0.003), (0.006, 0.008), (0.005, 0.040), (0.012, 0.050), (0.040, 0.070),
         (0.052, 0.095), (0.050, 0.120), (0.040, 0.140), (0.034, 0.150)]
WALL = 0.002
SEGMENTS = 96
FOOT_GAP = 0.0005                 # m between the foot and the table
SHARP_ANGLE = math.radians(50.0)  # edges whose faces meet at more than this are not smoothed
HDR = "sunset"
HDR_ROTATION_DEG = 160.0           # turns the HDR's sun behind the glass, as seen from the camera
MAX_BOUNCES = 16
DEFAULT_SAMPLES = 64
PHOTON_SETTINGS = {
    "caustic_photons": 800000,
    "caustic_estimate_photons": 80,
    "max_radius": 0.01,
}


def profile():
    """The closed profile: outer wall up, the rim, inner wall down to the bowl."""
    inner = [(r - WALL, z) for r, z in OUTER[5:]]
    bowl_floor = (0.0, OUTER[4][1] + WALL)
    return OUTER + [(OUTER[-1][0] - WALL, OUTER[-1][1])] + list(reversed(inner[:-1])) + [bowl_floor]


def snifter():
    bm = bmesh.new()
    verts = [bm.verts.new((r, 0.0, z)) for r, z in profile()]
    verts = [bm.verts.new((0.0, 0.0, 0.0))] + verts
    edges = [bm.edges.new((verts[i], verts[i + 1])) for i in range(len(verts) - 1)]
    bmesh.ops.spin(bm, geom=verts + edges, cent=(0.0, 0.0, 0.0), axis=(0.0, 0.0, 1.0),
                   angle=2.0 * math.pi, steps=SEGMENTS, use_merge=True)
    bmesh.ops.remove_doubles(bm, verts=bm.verts, dist=1e-6)
    bmesh.ops.recalc_face_normals(bm, faces=bm.faces)
    # Smooth along the walls, sharp where the profile turns a corner (the
    # rim, the foot's edge), as Auto Smooth would: a shading normal
    # averaged across the 2 mm rim bends refraction there by up to 45°.
    sharp = [e for e in bm.edges if e.is_manifold and e.calc_face_angle(0.0) > SHARP_ANGLE]
    bmesh.ops.split_edges(bm, edges=sharp)
    return bm


def build(scene):
    _common.clear_factory_scene()
    m.plane(scene, "Table", 1.2, 1.2, m.diffuse("Table", (0.72, 0.66, 0.58)))
    # The foot stands 0.5 mm above the table: faces in one plane (the foot's
    # underside on the tabletop) are hit in whatever order each ray
    # tracer's BVH finds them, and Phos and Cycles then disagreed by 2 %.
    m.mesh_object(scene, "Snifter", snifter(), m.glass("Cognac Glass", 1.5, (1.0, 0.93, 0.82)), smooth=True,
                  location=(0.0, 0.0, FOOT_GAP))
    m.camera(scene, (0.0, -0.42, 0.20), (0.0, 0.02, 0.055), lens=55.0)
    m.hdr_world(scene, HDR, strength=1.0, rotation_z_deg=HDR_ROTATION_DEG)
    return scene


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], MAX_BOUNCES, photon_settings=PHOTON_SETTINGS,
                      default_samples=DEFAULT_SAMPLES, default_integrator="PHOTON")
