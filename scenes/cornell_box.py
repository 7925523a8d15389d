# SPDX-License-Identifier: GPL-3.0-or-later
"""The Cornell box, with a glass and a mirror sphere in place of the blocks.

    blender -b --factory-startup --python scenes/cornell_box.py -- --render out/cornell_box
    blender -b --factory-startup --python scenes/cornell_box.py -- --save cornell_box.blend
    (options: see scenes/_common.py; --real-size builds the box at its true 0.55 m;
    the default integrator is PHOTON at 64 samples, --integrator PATH renders
    the path-traced reference at 256)

Geometry: the published vertex coordinates of the Cornell Program of Computer
Graphics ("Cornell Box Data", www.graphics.cornell.edu/online/box/data.html),
in millimetres, Y up, camera at (278, 273, −800) looking along +Z. Blender is
Z up: a Cornell point (x, y, z) goes to ((278 − x), (z − 279.6), y) × SCALE,
a proper rotation (no mirroring: the red wall stays on the left) that puts the
floor centre at the origin.

SCALE is 0.01 m per published millimetre by default: a box about 5.5 m tall,
so that a light of a familiar 100-300 W gives a sensible exposure. With
--real-size the box has its true size (0.55 m) and the light power is divided
by 100, which gives the same image (area-light radiance is power / area and
the irradiance a surface receives depends only on radiance and solid angle).

Materials: the walls are Lambertian with RGB approximations of the published
reflectance spectra: white 0.73, red (0.63, 0.065, 0.05), green
(0.14, 0.45, 0.091). These are the approximations commonly used by renderers
(e.g. Mitsuba's and pbrt's Cornell box scenes), not a spectral conversion
done here.

The blocks are replaced by a glass sphere (Glass BSDF, sharp, IOR 1.5) where
the short block stands and a mirror sphere (Glossy BSDF, sharp, white) where
the tall block stands. The published light patch (130 × 105 mm) becomes a
Blender area light of that rectangle, 1 mm (published units) below the
ceiling, facing down. The camera uses the published 35 mm lens on a
25 mm × 25 mm film.
"""

import math
import os
import sys

import bmesh
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402

# ------------------------------------------------------- published data (mm)

FLOOR = [(552.8, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 559.2), (549.6, 0.0, 559.2)]
CEILING = [(556.0, 548.8, 0.0), (556.0, 548.8, 559.2), (0.0, 548.8, 559.2), (0.0, 548.8, 0.0)]
BACK_WALL = [(549.6, 0.0, 559.2), (0.0, 0.0, 559.2), (0.0, 548.8, 559.2), (556.0, 548.8, 559.2)]
RIGHT_WALL = [(0.0, 0.0, 559.2), (0.0, 0.0, 0.0), (0.0, 548.8, 0.0), (0.0, 548.8, 559.2)]  # green
LEFT_WALL = [(552.8, 0.0, 0.0), (549.6, 0.0, 559.2), (556.0, 548.8, 559.2), (556.0, 548.8, 0.0)]  # red
LIGHT = [(343.0, 548.8, 227.0), (343.0, 548.8, 332.0), (213.0, 548.8, 332.0), (213.0, 548.8, 227.0)]
CAMERA_POSITION = (278.0, 273.0, -800.0)   # looking along +Z, up +Y
CAMERA_FOCAL_LENGTH_MM = 35.0              # published 0.035 m
CAMERA_FILM_MM = 25.0                      # published 0.025 m × 0.025 m

# Where the blocks stand (centres of their published footprints).
SHORT_BLOCK_CENTRE = (185.5, 168.5)        # (x, z)
TALL_BLOCK_CENTRE = (368.5, 351.25)

# ------------------------------------------------------------------- choices

WHITE = (0.73, 0.73, 0.73)
RED = (0.63, 0.065, 0.05)
GREEN = (0.14, 0.45, 0.091)
SPHERE_RADIUS_MM = 100.0
LIGHT_DROP_MM = 1.0                        # the light sits this far below the ceiling
LIGHT_POWER_W = 200.0                      # at the default 5.5 m scale
MAX_BOUNCES = 12
# The demo renders with PHOTON (`make render`); --integrator PATH renders
# the path-traced reference. Samples per pixel unless --samples is given:
# PHOTON half its default of 128 (4 gather rays each), for a demo of about
# two minutes on two cores; PATH twice the default, for a reference as
# clean as PHOTON's image.
DEMO_SAMPLES = {"PHOTON": 64, "PATH": 256}
DEFAULT_SCALE = 0.01                       # metres per published millimetre: a 5.5 m box
REAL_SCALE = 0.001


def to_blender(p, scale):
    """Cornell (x, y, z), Y up, mm → Blender metres, Z up."""
    x, y, z = p
    return ((278.0 - x) * scale, (z - 279.6) * scale, y * scale)


# ---------------------------------------------------------------- building

def diffuse_material(name, color):
    mat = bpy.data.materials.new(name)
    _common.use_nodes(mat)
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.0
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    mat.diffuse_color = (*color, 1.0)
    return mat


def glass_material(name, ior=1.5):
    mat = bpy.data.materials.new(name)
    _common.use_nodes(mat)
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    bsdf = nt.nodes.new("ShaderNodeBsdfGlass")
    _common.set_sharp(bsdf)
    bsdf.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bsdf.inputs["IOR"].default_value = ior
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return mat


def mirror_material(name):
    mat = bpy.data.materials.new(name)
    _common.use_nodes(mat)
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    bsdf = nt.nodes.new("ShaderNodeBsdfGlossy")
    _common.set_sharp(bsdf)
    bsdf.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    nt.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return mat


def quad_object(scene, name, corners_mm, material, scale):
    """A wall from its four published corners, as the two triangles (0,1,2), (0,2,3)."""
    me = bpy.data.meshes.new(name)
    verts = [to_blender(p, scale) for p in corners_mm]
    me.from_pydata(verts, [], [(0, 1, 2), (0, 2, 3)])
    me.materials.append(material)
    me.update()
    ob = bpy.data.objects.new(name, me)
    scene.collection.objects.link(ob)
    return ob


def sphere_object(scene, name, centre_xz_mm, material, scale):
    me = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=64, v_segments=32,
                              radius=SPHERE_RADIUS_MM * scale)
    bm.to_mesh(me)
    bm.free()
    for poly in me.polygons:
        poly.use_smooth = True
    me.materials.append(material)
    ob = bpy.data.objects.new(name, me)
    x, z = centre_xz_mm
    ob.location = to_blender((x, SPHERE_RADIUS_MM, z), scale)
    scene.collection.objects.link(ob)
    return ob


def build(scene, scale=DEFAULT_SCALE):
    _common.clear_factory_scene()

    white = diffuse_material("Cornell White", WHITE)
    red = diffuse_material("Cornell Red", RED)
    green = diffuse_material("Cornell Green", GREEN)
    quad_object(scene, "Floor", FLOOR, white, scale)
    quad_object(scene, "Ceiling", CEILING, white, scale)
    quad_object(scene, "Back Wall", BACK_WALL, white, scale)
    quad_object(scene, "Left Wall (red)", LEFT_WALL, red, scale)
    quad_object(scene, "Right Wall (green)", RIGHT_WALL, green, scale)

    sphere_object(scene, "Glass Sphere", SHORT_BLOCK_CENTRE, glass_material("Glass"), scale)
    sphere_object(scene, "Mirror Sphere", TALL_BLOCK_CENTRE, mirror_material("Mirror"), scale)

    # Ceiling light: the published patch, a little below the ceiling, facing
    # down (an area light emits along its local −Z, which is world −Z here).
    xs = [p[0] for p in LIGHT]
    zs = [p[2] for p in LIGHT]
    light = bpy.data.lights.new("Ceiling Light", "AREA")
    light.shape = "RECTANGLE"
    light.size = (max(xs) - min(xs)) * scale      # along Blender X (Cornell x)
    light.size_y = (max(zs) - min(zs)) * scale    # along Blender Y (Cornell z)
    light.energy = LIGHT_POWER_W * (scale / DEFAULT_SCALE) ** 2
    light.color = (1.0, 1.0, 1.0)
    light_ob = bpy.data.objects.new("Ceiling Light", light)
    # The patch is seen by the camera, as in the photographs. (A light object
    # made from Python is invisible to camera rays by default in 3.4.)
    light_ob.visible_camera = True
    light_ob.location = to_blender(((max(xs) + min(xs)) / 2, LIGHT[0][1] - LIGHT_DROP_MM,
                                    (max(zs) + min(zs)) / 2), scale)
    scene.collection.objects.link(light_ob)

    cam = bpy.data.cameras.new("Camera")
    cam.type = "PERSP"
    cam.lens_unit = "MILLIMETERS"
    cam.lens = CAMERA_FOCAL_LENGTH_MM
    cam.sensor_fit = "AUTO"
    cam.sensor_width = CAMERA_FILM_MM
    cam.sensor_height = CAMERA_FILM_MM
    cam.clip_start = 0.01 * scale / DEFAULT_SCALE
    cam.clip_end = 100.0 * scale / DEFAULT_SCALE
    cam_ob = bpy.data.objects.new("Camera", cam)
    cam_ob.location = to_blender(CAMERA_POSITION, scale)
    # Local −Z to world +Y (Cornell +Z), local +Y to world +Z (Cornell +Y).
    cam_ob.rotation_euler = (math.pi / 2, 0.0, 0.0)
    scene.collection.objects.link(cam_ob)
    scene.camera = cam_ob

    # Nothing outside the box: a black world.
    world = bpy.data.worlds.new("Black")
    world.color = (0.0, 0.0, 0.0)
    _common.use_nodes(world)
    bg = world.node_tree.nodes.get("Background")
    bg.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    scene.world = world
    return scene


def main():
    argv = _common.script_argv()
    real_size = "--real-size" in argv
    args = _common.parse_args(__doc__.splitlines()[0],
                              argv=["--"] + [a for a in argv if a != "--real-size"],
                              default_integrator="PHOTON")
    if "--samples" not in argv:
        args.samples = DEMO_SAMPLES.get(args.integrator, args.samples)
    if args.extra:
        _common.log("error: unknown arguments %s" % args.extra)
        return 2
    scene = bpy.context.scene
    build(scene, REAL_SCALE if real_size else DEFAULT_SCALE)
    return _common.finish(scene, args, MAX_BOUNCES)


if __name__ == "__main__":
    rc = main()
    if rc:
        sys.exit(rc)
