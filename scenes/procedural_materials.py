# SPDX-License-Identifier: GPL-3.0-or-later
"""Procedural materials as artists build them, on spheres over a brick floor.

    blender -b --factory-startup --python scenes/procedural_materials.py -- --render out/procedural

(options: see scenes/_common.py; the default integrator here is PATH.)

Every material is a node tree of textures feeding a BSDF, the kind that
rendered in flat default colours before Phos compiled node trees into
shader programs (docs/architecture.md, "Shader programs"):

- walnut: a Principled BSDF whose Base Color is wood grain (a Wave texture
  distorted by noise, in a node group, through a Color Ramp), whose
  Roughness follows a Voronoi texture through Map Range, with a Bump of the
  grain;
- glazed ceramic: Diffuse and Glossy mixed by Layer Weight's Facing times a
  checker, the diffuse coloured by noise through Hue/Saturation/Value;
- marble: Noise through a Color Ramp into a Principled BSDF of low roughness;
- rusted metal: Metallic and rough Diffuse mixed by a noise mask through Map
  Range, the rust coloured by a Voronoi's cells;
- the floor: a Brick texture with a bump of its mortar.

An area light and a grey-blue world light them. `make bench` measures
`PATH`'s time per sample here against Cycles' (docs/benchmarks.md).
"""

import math
import os
import sys

import bmesh
import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import _common  # noqa: E402
import _materials as m  # noqa: E402

MAX_BOUNCES = 8
DEFAULT_SAMPLES = 64
SPHERE_RADIUS = 0.45


class Nodes:
    """A material's node tree with its output, and small wiring helpers."""

    def __init__(self, name):
        self.mat = bpy.data.materials.new(name)
        _common.use_nodes(self.mat)
        self.nt = self.mat.node_tree
        self.nt.nodes.clear()
        self.out = self.nt.nodes.new("ShaderNodeOutputMaterial")

    def new(self, kind, **inputs):
        node = self.nt.nodes.new(kind)
        for name, value in inputs.items():
            name = name.replace("_", " ")
            socket = next(s for s in node.inputs if s.name == name)
            if isinstance(value, tuple) and len(value) == 3 and socket.type == "RGBA":
                value = value + (1.0,)
            socket.default_value = value
        return node

    def link(self, a, b):
        self.nt.links.new(a, b)

    def surface(self, shader):
        self.link(shader.outputs[0], self.out.inputs["Surface"])
        return self.mat


def ramp(nodes, colors):
    """A Color Ramp through (position, RGB) stops."""
    r = nodes.new("ShaderNodeValToRGB")
    elements = r.color_ramp.elements
    elements[0].position, elements[0].color = colors[0][0], colors[0][1] + (1.0,)
    elements[1].position, elements[1].color = colors[-1][0], colors[-1][1] + (1.0,)
    for pos, col in colors[1:-1]:
        elements.new(pos).color = col + (1.0,)
    return r


def grain_group():
    """Wood grain in a node group: Wave bands distorted by noise."""
    group = bpy.data.node_groups.get("Grain")
    if group is not None:
        return group
    group = bpy.data.node_groups.new("Grain", "ShaderNodeTree")
    if hasattr(group, "interface"):  # 4.0+
        group.interface.new_socket("Vector", in_out="INPUT", socket_type="NodeSocketVector")
        group.interface.new_socket("Fac", in_out="OUTPUT", socket_type="NodeSocketFloat")
    else:
        group.inputs.new("NodeSocketVector", "Vector")
        group.outputs.new("NodeSocketFloat", "Fac")
    gin, gout = group.nodes.new("NodeGroupInput"), group.nodes.new("NodeGroupOutput")
    wave = group.nodes.new("ShaderNodeTexWave")
    wave.inputs["Scale"].default_value = 3.0
    wave.inputs["Distortion"].default_value = 4.0
    wave.inputs["Detail"].default_value = 2.0
    group.links.new(gin.outputs[0], wave.inputs["Vector"])
    group.links.new(wave.outputs["Fac"], gout.inputs[0])
    return group


def walnut():
    n = Nodes("Walnut")
    bsdf = n.new("ShaderNodeBsdfPrincipled")
    coords = n.new("ShaderNodeTexCoord")
    grain = n.new("ShaderNodeGroup")
    grain.node_tree = grain_group()
    n.link(coords.outputs["Object"], grain.inputs[0])
    color = ramp(n, [(0.0, (0.08, 0.035, 0.015)), (1.0, (0.35, 0.17, 0.07))])
    n.link(grain.outputs[0], color.inputs["Fac"])
    n.link(color.outputs["Color"], bsdf.inputs["Base Color"])
    voronoi = n.new("ShaderNodeTexVoronoi", Scale=6.0)
    n.link(coords.outputs["Object"], voronoi.inputs["Vector"])
    rough = n.new("ShaderNodeMapRange")
    rough.inputs[3].default_value, rough.inputs[4].default_value = 0.25, 0.6
    n.link(voronoi.outputs["Distance"], rough.inputs[0])
    n.link(rough.outputs[0], bsdf.inputs["Roughness"])
    bump = n.new("ShaderNodeBump", Strength=0.3, Distance=0.02)
    n.link(grain.outputs[0], bump.inputs["Height"])
    n.link(bump.outputs["Normal"], bsdf.inputs["Normal"])
    return n.surface(bsdf)


def glazed_ceramic():
    n = Nodes("Glazed Ceramic")
    mix = n.new("ShaderNodeMixShader")
    diffuse = n.new("ShaderNodeBsdfDiffuse")
    glossy = n.new("ShaderNodeBsdfGlossy", Roughness=0.25)
    glossy.distribution = "GGX"
    noise = n.new("ShaderNodeTexNoise", Scale=4.0)
    hsv = n.new("ShaderNodeHueSaturation", Saturation=1.6)
    n.link(noise.outputs["Color"], hsv.inputs["Color"])
    n.link(hsv.outputs["Color"], diffuse.inputs["Color"])
    checker = n.new("ShaderNodeTexChecker", Scale=4.0)
    weight = n.new("ShaderNodeLayerWeight", Blend=0.3)
    fac = n.new("ShaderNodeMath")
    fac.operation = "MULTIPLY"
    n.link(checker.outputs["Fac"], fac.inputs[0])
    n.link(weight.outputs["Facing"], fac.inputs[1])
    n.link(fac.outputs[0], mix.inputs["Fac"])
    n.link(diffuse.outputs[0], mix.inputs[1])
    n.link(glossy.outputs[0], mix.inputs[2])
    return n.surface(mix)


def marble():
    n = Nodes("Marble")
    bsdf = n.new("ShaderNodeBsdfPrincipled", Roughness=0.12)
    noise = n.new("ShaderNodeTexNoise", Scale=2.5, Detail=8.0, Distortion=2.0)
    color = ramp(n, [(0.35, (0.9, 0.88, 0.85)), (0.5, (0.25, 0.27, 0.3)), (0.65, (0.85, 0.83, 0.8))])
    n.link(noise.outputs["Fac"], color.inputs["Fac"])
    n.link(color.outputs["Color"], bsdf.inputs["Base Color"])
    return n.surface(bsdf)


def rusted_metal():
    n = Nodes("Rusted Metal")
    mix = n.new("ShaderNodeMixShader")
    metal = n.new("ShaderNodeBsdfPrincipled", Metallic=1.0, Roughness=0.3, Base_Color=(0.75, 0.76, 0.78))
    rust = n.new("ShaderNodeBsdfDiffuse")
    cells = n.new("ShaderNodeTexVoronoi", Scale=12.0)
    tint = ramp(n, [(0.0, (0.25, 0.07, 0.02)), (1.0, (0.55, 0.22, 0.06))])
    n.link(cells.outputs["Distance"], tint.inputs["Fac"])
    n.link(tint.outputs["Color"], rust.inputs["Color"])
    mask = n.new("ShaderNodeTexNoise", Scale=3.0, Detail=6.0)
    edge = n.new("ShaderNodeMapRange")
    edge.inputs[1].default_value, edge.inputs[2].default_value = 0.45, 0.55
    n.link(mask.outputs["Fac"], edge.inputs[0])
    n.link(edge.outputs[0], mix.inputs["Fac"])
    n.link(metal.outputs[0], mix.inputs[1])
    n.link(rust.outputs[0], mix.inputs[2])
    return n.surface(mix)


def brick_floor():
    n = Nodes("Brick Floor")
    bsdf = n.new("ShaderNodeBsdfDiffuse")
    bricks = n.new("ShaderNodeTexBrick", Color1=(0.45, 0.18, 0.1), Color2=(0.3, 0.12, 0.08),
                   Mortar=(0.6, 0.58, 0.55), Scale=2.0)
    n.link(bricks.outputs["Color"], bsdf.inputs["Color"])
    bump = n.new("ShaderNodeBump", Strength=0.4, Distance=0.05)
    n.link(bricks.outputs["Fac"], bump.inputs["Height"])
    n.link(bump.outputs["Normal"], bsdf.inputs["Normal"])
    return n.surface(bsdf)


def sphere(scene, name, material, location):
    bm = bmesh.new()
    bmesh.ops.create_uvsphere(bm, u_segments=48, v_segments=24, radius=SPHERE_RADIUS)
    return m.mesh_object(scene, name, bm, material, smooth=True, location=location)


def build(scene):
    _common.clear_factory_scene()
    m.plane(scene, "Floor", 8.0, 8.0, brick_floor())
    for i, (name, make) in enumerate((("Walnut", walnut), ("Ceramic", glazed_ceramic), ("Marble", marble),
                                      ("Rust", rusted_metal))):
        sphere(scene, name, make(), (-1.5 + 1.0 * i, 0.0, SPHERE_RADIUS))
    light = bpy.data.lights.new("Area", "AREA")
    light.energy = 300.0
    light.size = 1.5
    light_ob = bpy.data.objects.new("Area", light)
    light_ob.location = (1.5, -2.0, 3.0)
    light_ob.rotation_euler = _common.look_at_rotation(light_ob.location, (0.0, 0.0, 0.3))
    m.link(scene, light_ob)
    m.camera(scene, (0.0, -4.5, 2.2), (0.0, 0.0, 0.4), lens=40.0)
    m.world(scene, (0.3, 0.35, 0.4))
    return scene


if __name__ == "__main__":
    _common.run_scene(build, __doc__.splitlines()[0], MAX_BOUNCES, default_samples=DEFAULT_SAMPLES,
                      default_integrator="PATH")
