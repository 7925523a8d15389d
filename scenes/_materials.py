# SPDX-License-Identifier: GPL-3.0-or-later
"""Materials and meshes shared by the photon-mapping scenes in scenes/.

Each material is one shader node into the Material Output, the way the
course's scenes are described (a Lambertian floor, a glass sphere, a mirror
ring), so Phos and Cycles render exactly the same BSDF.
"""

import math
import os

import bmesh
import bpy

import _common


def _single_node_material(name, node_type):
    mat = bpy.data.materials.new(name)
    _common.use_nodes(mat)
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    node = nt.nodes.new(node_type)
    nt.links.new(node.outputs["BSDF"], out.inputs["Surface"])
    return mat, node


def diffuse(name, color):
    """Lambertian (Diffuse BSDF, roughness 0)."""
    mat, bsdf = _single_node_material(name, "ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.0
    mat.diffuse_color = (*color, 1.0)
    return mat


def glass(name, ior=1.5, color=(1.0, 1.0, 1.0)):
    """Smooth dielectric (Glass BSDF, sharp)."""
    mat, bsdf = _single_node_material(name, "ShaderNodeBsdfGlass")
    _common.set_sharp(bsdf)
    bsdf.inputs["Color"].default_value = (*color, 1.0)
    bsdf.inputs["IOR"].default_value = ior
    return mat


def mirror(name, color=(1.0, 1.0, 1.0)):
    """Perfect specular reflector (Glossy BSDF, sharp): a polished metal of that colour."""
    mat, bsdf = _single_node_material(name, "ShaderNodeBsdfGlossy")
    _common.set_sharp(bsdf)
    bsdf.inputs["Color"].default_value = (*color, 1.0)
    mat.diffuse_color = (*color, 1.0)
    return mat


def link(scene, ob):
    scene.collection.objects.link(ob)
    return ob


def lamp(scene, kind, name, energy, location, target, **props):
    """A lamp of Blender's `kind` ('POINT', 'SPOT', 'AREA', 'SUN') at
    `location`, aimed at `target`, with its light's other settings."""
    light = bpy.data.lights.new(name, kind)
    light.energy = energy
    for key, value in props.items():
        setattr(light, key, value)
    ob = bpy.data.objects.new(name, light)
    ob.location = location
    ob.rotation_euler = _common.look_at_rotation(location, target)
    return link(scene, ob)


def mesh_object(scene, name, bm, material, smooth=False, location=(0.0, 0.0, 0.0),
                rotation=(0.0, 0.0, 0.0)):
    """An object from a bmesh (which is freed)."""
    me = bpy.data.meshes.new(name)
    bm.to_mesh(me)
    bm.free()
    for poly in me.polygons:
        poly.use_smooth = smooth
    me.materials.append(material)
    ob = bpy.data.objects.new(name, me)
    ob.location = location
    ob.rotation_euler = rotation
    return link(scene, ob)


def plane(scene, name, size_x, size_y, material, location=(0.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.0)):
    bm = bmesh.new()
    hx, hy = size_x / 2.0, size_y / 2.0
    verts = [bm.verts.new(co) for co in ((-hx, -hy, 0.0), (hx, -hy, 0.0), (hx, hy, 0.0), (-hx, hy, 0.0))]
    bm.faces.new(verts)
    return mesh_object(scene, name, bm, material, location=location, rotation=rotation)


def camera(scene, location, target, lens=50.0, name="Camera"):
    cam = bpy.data.cameras.new(name)
    cam.lens = lens
    cam.sensor_fit = "AUTO"
    cam.sensor_width = 36.0
    cam.clip_start = 0.01
    cam.clip_end = 100.0
    ob = bpy.data.objects.new(name, cam)
    ob.location = location
    ob.rotation_euler = _common.look_at_rotation(location, target)
    link(scene, ob)
    scene.camera = ob
    return ob


def world(scene, color=(0.0, 0.0, 0.0), strength=1.0, name="World"):
    w = bpy.data.worlds.new(name)
    w.color = color
    _common.use_nodes(w)
    bg = w.node_tree.nodes.get("Background")
    bg.inputs["Color"].default_value = (*color, 1.0)
    bg.inputs["Strength"].default_value = strength
    scene.world = w
    return w


def glossy(name, color=(1.0, 1.0, 1.0), roughness=0.2):
    """Rough metal (Glossy BSDF, GGX) of that colour and Blender roughness."""
    mat, bsdf = _single_node_material(name, "ShaderNodeBsdfGlossy")
    bsdf.distribution = "GGX"
    bsdf.inputs["Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    mat.diffuse_color = (*color, 1.0)
    return mat


def polished(name, color=(0.8, 0.8, 0.8), roughness=0.2):
    """A varnished surface: the Principled BSDF (dielectric, specular 0.5)
    over a diffuse base of that colour, at that roughness."""
    mat, bsdf = _single_node_material(name, "ShaderNodeBsdfPrincipled")
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    mat.diffuse_color = (*color, 1.0)
    return mat


def studio_hdr_path(name):
    """One of the HDR environments Blender ships with its data files
    (studiolights/world/NAME.exr): real captured light on every machine
    with Blender, so the scenes need no download."""
    path = os.path.join(bpy.utils.system_resource('DATAFILES', path="studiolights/world"), name + ".exr")
    if not os.path.exists(path):
        raise FileNotFoundError("Blender's data files have no studio light %r (%s)" % (name, path))
    return path


def hdr_world(scene, name, strength=1.0, rotation_z_deg=0.0):
    """A world lit by a studio HDR: Texture Coordinate → Mapping (turned
    about Z) → Environment Texture → Background."""
    w = bpy.data.worlds.new("World " + name)
    _common.use_nodes(w)
    nodes, links = w.node_tree.nodes, w.node_tree.links
    bg = nodes["Background"]
    bg.inputs["Strength"].default_value = strength
    env = nodes.new("ShaderNodeTexEnvironment")
    env.image = bpy.data.images.load(studio_hdr_path(name), check_existing=True)
    coords = nodes.new("ShaderNodeTexCoord")
    mapping = nodes.new("ShaderNodeMapping")
    mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(rotation_z_deg))
    links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], env.inputs["Vector"])
    links.new(env.outputs["Color"], bg.inputs["Color"])
    scene.world = w
    return w
