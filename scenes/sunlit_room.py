# SPDX-License-Identifier: GPL-3.0-or-later
"""A closed room lit only by the sun through one small window.

    blender -b --factory-startup --python scenes/sunlit_room.py -- --render out/sunlit_room
    (options: see scenes/_common.py; the default integrator here is PHOTON)

The scene where the bias of a photon mapper lives: almost all the light the
camera sees is indirect, it arrives through an opening of 4 % of one wall,
and every wall-wall and wall-ceiling edge is in view. A room of 4 × 4 m and
2.5 m high with Lambertian walls, floor and ceiling (reflectance 0.6), a
window of 0.8 × 0.8 m in the far (+y) wall from 1.0 to 1.8 m above the
floor, and a diffuse ball (radius 0.5 m, the same white) on the floor. The
sun (30 W/m², angle 0.5°) shines down through the window onto the floor.
The camera stands inside by the near wall, looking at the window wall.

The same room as the C test suite's `sunlit_room_scene`
(tests/c/test_photon_map.c), so figures from the two can be compared; the
walls are one layer of quads, so sunlight also lands on their outer faces,
which the camera never sees: the photon passes must not spend their work
there (docs/algorithms.md, "Aiming sun photons").
"""

import math
import os
import sys

import bmesh
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402
import _materials as m  # noqa: E402

HALF = 2.0                     # m, half the room's width and depth
HEIGHT = 2.5                   # m
WINDOW_HALF_WIDTH = 0.4        # m
WINDOW_BOTTOM, WINDOW_TOP = 1.0, 1.8   # m above the floor
REFLECTANCE = 0.6
BALL_CENTRE, BALL_RADIUS = (-1.0, 0.6, 0.5), 0.5
SUN_DIRECTION = (0.35, -1.0, -0.9)     # where the sunlight travels (normalised below)
SUN_STRENGTH = 30.0            # W/m² (Blender's sun Strength)
SUN_ANGLE_DEG = 0.5
CAMERA_LOCATION = (0.0, -1.8, 1.3)
CAMERA_PITCH = 1.42            # rad from straight down: looking at the window wall
CAMERA_TAN_HALF_FOV = 0.8      # tan of half the field of view (square image)
MAX_BOUNCES = 12
DEFAULT_SAMPLES = 16
DEFAULT_RESOLUTION = (384, 384)
PHOTON_SETTINGS = {}           # the engine's defaults


def _room_quads():
    """The room's faces as quads whose winding gives an inward normal."""
    a, h = HALF, HEIGHT
    wx, z0, z1 = WINDOW_HALF_WIDTH, WINDOW_BOTTOM, WINDOW_TOP
    quads = [
        [(-a, -a, 0), (a, -a, 0), (a, a, 0), (-a, a, 0)],      # floor
        [(-a, -a, h), (-a, a, h), (a, a, h), (a, -a, h)],      # ceiling
        [(-a, -a, 0), (-a, a, 0), (-a, a, h), (-a, -a, h)],    # x = -a
        [(a, -a, 0), (a, -a, h), (a, a, h), (a, a, 0)],        # x = +a
        [(-a, -a, 0), (-a, -a, h), (a, -a, h), (a, -a, 0)],    # y = -a, behind the camera
    ]

    def window_wall(x0, x1, za, zb):  # part of the wall y = +a, facing -y
        return [(x0, a, za), (x1, a, za), (x1, a, zb), (x0, a, zb)]

    quads += [window_wall(-a, a, 0.0, z0), window_wall(-a, a, z1, h),
              window_wall(-a, -wx, z0, z1), window_wall(wx, a, z0, z1)]
    return quads


def build(scene):
    _common.clear_factory_scene()
    white = m.diffuse("Wall White", (REFLECTANCE,) * 3)
    bm = bmesh.new()
    for quad in _room_quads():
        bm.faces.new([bm.verts.new(v) for v in quad])
    m.mesh_object(scene, "Room", bm, white)

    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=48, v_segments=24, radius=BALL_RADIUS)
    m.mesh_object(scene, "Ball", bm, white, smooth=True, location=BALL_CENTRE)

    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = SUN_STRENGTH
    sun.angle = math.radians(SUN_ANGLE_DEG)
    sun_ob = bpy.data.objects.new("Sun", sun)
    norm = math.sqrt(sum(c * c for c in SUN_DIRECTION))
    d = tuple(c / norm for c in SUN_DIRECTION)
    sun_ob.location = (0.0, HALF + 3.0, HEIGHT + 3.0)
    sun_ob.rotation_euler = _common.look_at_rotation(
        sun_ob.location, tuple(p + c for p, c in zip(sun_ob.location, d)))
    m.link(scene, sun_ob)

    # The view direction: (0, 0, -1) turned by CAMERA_PITCH about +x.
    view = (0.0, math.sin(CAMERA_PITCH), -math.cos(CAMERA_PITCH))
    target = tuple(p + c for p, c in zip(CAMERA_LOCATION, view))
    lens = 36.0 / 2.0 / CAMERA_TAN_HALF_FOV    # mm, on a 36 mm sensor
    m.camera(scene, CAMERA_LOCATION, target, lens=lens)
    m.world(scene, (0.0, 0.0, 0.0))
    return scene


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], MAX_BOUNCES, photon_settings=PHOTON_SETTINGS,
                      default_samples=DEFAULT_SAMPLES, default_integrator="PHOTON",
                      default_resolution=DEFAULT_RESOLUTION)
