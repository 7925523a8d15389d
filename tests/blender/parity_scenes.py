# SPDX-License-Identifier: GPL-3.0-or-later
"""Small scenes rendered by both Phos and Cycles in test_parity.py.

Two families, each a dict name -> builder(scene):

LIGHT_SCENES: one light of each kind over a diffuse floor and a diffuse
  sphere, in a black world (except the world-lighting scene); all kinds at
  once; and Blender's default cube with its lamp and grey world.
MATERIAL_SCENES: a sphere with the material under test on a diffuse floor,
  lit by a square area light and a uniform world.

Builders only create data; engine settings are applied by the test.
Inputs and properties are given as in Blender 3.x (Principled "Transmission",
distribution "SHARP"); phostest.setup_node translates them for 4.x.
"""

import math

import bpy

import phostest as pt

LIGHT_POS = (1.5, -1.5, 2.5)
SPHERE_CENTRE = (0.0, 0.0, 0.5)


def _stage(scene, sphere_material=None):
    """Camera, a 8 m diffuse floor and a r=0.5 sphere resting on it."""
    pt.add_camera(scene, location=(0.0, -4.2, 2.4), target=(0.0, 0.0, 0.45), lens=50.0)
    floor = pt.diffuse("Floor", (0.8, 0.8, 0.8))
    pt.add_plane(scene, "Floor", size=8.0, material=floor)
    if sphere_material is None:
        sphere_material = pt.diffuse("Sphere", (0.8, 0.55, 0.3))
    pt.add_sphere(scene, "Sphere", radius=0.5, location=SPHERE_CENTRE, material=sphere_material,
                  segments=48, rings=24)


# ------------------------------------------------------------------ lights

def _light_scene(kind, energy, location=LIGHT_POS, target=SPHERE_CENTRE, **props):
    def build(scene):
        _stage(scene)
        pt.set_world(scene, (0.0, 0.0, 0.0))
        pt.add_light(scene, kind, energy, location=location, target=target, **props)
    return build


def _emissive_mesh(scene):
    _stage(scene)
    pt.set_world(scene, (0.0, 0.0, 0.0))
    lamp = pt.add_plane(scene, "Lamp", size=1.0, location=LIGHT_POS,
                        material=pt.emission("Lamp", (1.0, 0.9, 0.8), 12.0))
    # Aims the plane's back (local −Z) at the sphere: both faces of an
    # emissive mesh emit the same radiance, so the side does not matter.
    pt.point_at(lamp, SPHERE_CENTRE)


def _world(scene):
    _stage(scene)
    pt.set_world(scene, (0.6, 0.7, 0.9), strength=1.0)


def _hdr_world(name, rotation_z=0.0, projection='EQUIRECTANGULAR', camera_color=None):
    """The stage under one of Blender's studio HDRs, turned about Z by a
    Mapping node, the sphere a glossy-coated Principled (issue 22: an
    HDR-lit diffuse and glossy scene; importance sampling and MIS)."""
    def build(scene):
        sphere = pt.node_material("Sphere", "ShaderNodeBsdfPrincipled",
                                  {"Base Color": (0.8, 0.55, 0.3, 1.0), "Roughness": 0.25})
        _stage(scene, sphere)
        pt.set_world_hdr(scene, name, strength=1.0, rotation_z=rotation_z, projection=projection,
                         camera_color=camera_color)
    return build


def _sky_world(model, glossy=True, **settings):
    """The stage under a Sky Texture (issue 22: a Sky Texture scene), the
    sphere glossy-coated as under the HDRs, or diffuse: the scattering
    models' sun is a light of its own (core/src/lights/sky_sun.c), the
    analytic models' sky is evaluated per direction."""
    def build(scene):
        sphere = None
        if glossy:
            sphere = pt.node_material("Sphere", "ShaderNodeBsdfPrincipled",
                                      {"Base Color": (0.8, 0.55, 0.3, 1.0), "Roughness": 0.25})
        _stage(scene, sphere)
        pt.set_world_sky(scene, model, **settings)
    return build


def _portal_interior(scene):
    """A closed 4 × 4 × 2.5 m room lit only through a window (1.6 × 1 m in
    the back wall) by a studio HDR, a portal filling the window and facing
    in (issue 22: a portal-lit interior). A diffuse sphere on the floor."""
    import bmesh
    bm = bmesh.new()
    quads = [
        [(-2, -2, 0), (2, -2, 0), (2, 2, 0), (-2, 2, 0)],                      # floor
        [(-2, -2, 2.5), (-2, 2, 2.5), (2, 2, 2.5), (2, -2, 2.5)],              # ceiling
        [(-2, -2, 0), (-2, 2, 0), (-2, 2, 2.5), (-2, -2, 2.5)],                # left
        [(2, -2, 0), (2, -2, 2.5), (2, 2, 2.5), (2, 2, 0)],                    # right
        [(-2, -2, 0), (-2, -2, 2.5), (2, -2, 2.5), (2, -2, 0)],                # front (behind the camera)
        [(-2, 2, 0), (-0.8, 2, 0), (-0.8, 2, 2.5), (-2, 2, 2.5)],              # back wall around the window
        [(0.8, 2, 0), (2, 2, 0), (2, 2, 2.5), (0.8, 2, 2.5)],
        [(-0.8, 2, 0), (0.8, 2, 0), (0.8, 2, 1.0), (-0.8, 2, 1.0)],
        [(-0.8, 2, 2.0), (0.8, 2, 2.0), (0.8, 2, 2.5), (-0.8, 2, 2.5)],
    ]
    for q in quads:
        bm.faces.new([bm.verts.new(v) for v in q])
    room = bpy.data.objects.new("Room", pt.mesh_from_bmesh("Room", bm))
    room.data.materials.append(pt.diffuse("Walls", (0.7, 0.7, 0.7)))
    pt.link(scene, room)
    pt.add_sphere(scene, "Sphere", radius=0.4, location=(0.3, 0.6, 0.4),
                  material=pt.diffuse("Sphere", (0.8, 0.55, 0.3)), segments=48, rings=24)
    pt.add_camera(scene, location=(-1.2, -1.7, 1.4), target=(0.3, 0.8, 0.5), lens=24.0)
    pt.set_world_hdr(scene, "courtyard", strength=1.0)
    portal = bpy.data.lights.new("Window", 'AREA')
    portal.shape = 'RECTANGLE'
    portal.size, portal.size_y = 1.6, 1.0
    portal.cycles.is_portal = True
    ob = bpy.data.objects.new("Window", portal)
    ob.location = (0.0, 2.0, 1.5)
    ob.rotation_euler = (math.radians(-90.0), 0.0, 0.0)  # its −Z (the lamp's direction) points into the room: −y
    pt.link(scene, ob)


def _default_cube(scene):
    """Blender's start-up scene: a 2 m cube, a 1000 W point lamp and the grey
    world (0.05), seen from a side the lamp does not reach, so that side is
    lit by the world alone (light picking per shading point, light_pick.c)."""
    pt.add_camera(scene, location=(-5.5, -6.0, 4.0), target=(0.0, 0.0, 0.0), lens=50.0)
    pt.add_cube(scene, "Cube", size=2.0, material=pt.diffuse("Cube", (0.8, 0.8, 0.8)))
    pt.add_plane(scene, "Floor", size=12.0, location=(0.0, 0.0, -1.0),
                 material=pt.diffuse("Floor", (0.8, 0.8, 0.8)))
    pt.set_world(scene, (0.05, 0.05, 0.05), strength=1.0)
    pt.add_light(scene, "POINT", 1000.0, location=(4.08, 1.0, 5.9), target=(0, 0, 0), shadow_soft_size=0.1)


def _mixed_lights(scene):
    """Every kind of light at once, each reaching part of the scene: MIS
    and per-point light picking must agree across light types."""
    _stage(scene)
    pt.set_world(scene, (0.1, 0.12, 0.15), strength=1.0)
    pt.add_light(scene, "POINT", 100.0, location=(-1.5, -1.0, 1.5), target=SPHERE_CENTRE, shadow_soft_size=0.2)
    pt.add_light(scene, "SPOT", 300.0, location=(1.2, -1.2, 3.0), target=(0.8, 0.5, 0.0), shadow_soft_size=0.1,
                 spot_size=math.radians(40.0), spot_blend=0.5)
    pt.add_light(scene, "AREA", 80.0, location=(0.0, 1.5, 2.0), target=SPHERE_CENTRE, shape="DISK", size=0.8)
    pt.add_light(scene, "SUN", 1.0, location=(2.0, 2.0, 4.0), target=(0, 0, 0), angle=math.radians(10.0))
    lamp = pt.add_plane(scene, "Lamp", size=0.5, location=(-1.2, 1.2, 1.2),
                        material=pt.emission("Lamp", (1.0, 0.8, 0.6), 8.0))
    pt.point_at(lamp, SPHERE_CENTRE)


def _sphere_lamp(kind, energy, **props):
    """A point or spot lamp as the sphere Blender 4.0+ makes it: soft falloff
    off (4.1+), so it is not the pre-4.0 disk facing each shading point."""
    def build(scene):
        _light_scene(kind, energy, **props)(scene)
        next(ob for ob in scene.objects if ob.type == 'LIGHT').data.use_soft_falloff = False
    return build


def _light_settings(kind, energy, settings, **props):
    """A light with Blender 4.5's exposure, colour temperature or Normalize
    (skipped where the light has no such settings)."""
    def build(scene):
        import pytest
        _light_scene(kind, energy, **props)(scene)
        light = next(ob for ob in scene.objects if ob.type == 'LIGHT').data
        for name, value in settings.items():
            if not hasattr(light, name):
                pytest.skip("Blender %s lights have no %s" % (bpy.app.version_string, name))
            setattr(light, name, value)
    return build


LIGHT_SCENES = {
    "point_r0": _light_scene("POINT", 200.0, shadow_soft_size=0.0),
    "point_r": _light_scene("POINT", 200.0, shadow_soft_size=0.4),
    "spot_blend": _light_scene("SPOT", 400.0, location=(1.2, -1.2, 3.0), shadow_soft_size=0.1,
                               spot_size=math.radians(50.0), spot_blend=0.4),
    "area_square": _light_scene("AREA", 150.0, shape="SQUARE", size=1.0),
    "area_rectangle": _light_scene("AREA", 150.0, shape="RECTANGLE", size=1.5, size_y=0.5),
    "area_disk": _light_scene("AREA", 150.0, shape="DISK", size=1.0),
    "area_ellipse": _light_scene("AREA", 150.0, shape="ELLIPSE", size=1.5, size_y=0.6),
    "sun_angle0": _light_scene("SUN", 3.0, location=(2.0, -2.0, 4.0), target=(0, 0, 0), angle=0.0),
    "sun_angle15": _light_scene("SUN", 3.0, location=(2.0, -2.0, 4.0), target=(0, 0, 0),
                                angle=math.radians(15.0)),
    "emissive_mesh": _emissive_mesh,
    "world": _world,
    "hdr_forest": _hdr_world("forest", rotation_z=math.radians(60.0)),
    "hdr_sunset_mirror_ball": _hdr_world("sunset", projection='MIRROR_BALL'),
    "portal_interior": _portal_interior,
    "hdr_city_camera_sees_grey": _hdr_world("city", rotation_z=math.radians(-120.0), camera_color=(0.2, 0.2, 0.2)),
    "sky_single_scattering": _sky_world("SINGLE_SCATTERING", sun_elevation=math.radians(25.0),
                                        sun_rotation=math.radians(40.0), altitude=100.0),
    "sky_multiple_scattering": _sky_world("MULTIPLE_SCATTERING", sun_elevation=math.radians(12.0),
                                          sun_rotation=math.radians(-60.0), sun_intensity=0.5),
    "sky_single_scattering_diffuse": _sky_world("SINGLE_SCATTERING", glossy=False, sun_elevation=math.radians(25.0),
                                                sun_rotation=math.radians(40.0), altitude=100.0),
    "sky_multiple_scattering_diffuse": _sky_world("MULTIPLE_SCATTERING", glossy=False,
                                                  sun_elevation=math.radians(12.0),
                                                  sun_rotation=math.radians(-60.0), sun_intensity=0.5),
    "sky_preetham": _sky_world("PREETHAM", sun_direction=(0.4, -0.6, 0.5), turbidity=3.0),
    "sky_hosek_wilkie": _sky_world("HOSEK_WILKIE", sun_direction=(-0.5, -0.5, 0.4), turbidity=4.0,
                                   ground_albedo=0.3),
    "default_cube": _default_cube,
    "mixed": _mixed_lights,
    "area_exposure_temperature": _light_settings(
        "AREA", 60.0, {"exposure": 1.0, "use_temperature": True, "temperature": 3500.0},
        shape="SQUARE", size=1.0),
    "area_unnormalized": _light_settings("AREA", 30.0, {"normalize": False}, shape="RECTANGLE",
                                         size=1.5, size_y=0.8),
    "point_unnormalized": _light_settings("POINT", 40.0, {"normalize": False, "exposure": -0.5},
                                          shadow_soft_size=0.3),
    "point_sphere": _sphere_lamp("POINT", 200.0, shadow_soft_size=0.4),
    "spot_sphere": _sphere_lamp("SPOT", 400.0, location=(1.2, -1.2, 3.0), shadow_soft_size=0.3,
                                spot_size=math.radians(50.0), spot_blend=0.4),
}


# --------------------------------------------------------------- materials

def _material_scene(make_material):
    def build(scene):
        _stage(scene, make_material(scene))
        pt.set_world(scene, (0.3, 0.35, 0.4), strength=1.0)
        pt.add_light(scene, "AREA", 200.0, location=(1.5, -1.5, 3.0), target=SPHERE_CENTRE,
                     shape="SQUARE", size=1.5)
    return build


def _one(node_type, inputs=None, props=None):
    return lambda scene: pt.node_material("Test " + node_type, node_type, inputs, props)


def _two(shader_node, a, b, fac=None):
    """Mix/Add shader of two single-node shaders a, b = (type, inputs, props)."""
    def make(scene):
        mat, nt, out = pt.empty_material("Test " + shader_node)
        mix = nt.nodes.new(shader_node)
        shaders = []
        for node_type, inputs, props in (a, b):
            shaders.append(pt.setup_node(nt.nodes.new(node_type), inputs, props))
        if fac is not None:
            mix.inputs["Fac"].default_value = fac
            nt.links.new(shaders[0].outputs[0], mix.inputs[1])
            nt.links.new(shaders[1].outputs[0], mix.inputs[2])
        else:
            nt.links.new(shaders[0].outputs[0], mix.inputs[0])
            nt.links.new(shaders[1].outputs[0], mix.inputs[1])
        nt.links.new(mix.outputs[0], out.inputs["Surface"])
        return mat
    return make


def _image_texture(scene):
    import os
    # Blender's session temp dir, removed when Blender exits.
    img = pt.checker_image(os.path.join(bpy.app.tempdir, "phos_checker.png"), size=16, squares=4)
    mat, nt, out = pt.empty_material("Test Image Texture")
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = img
    tex.interpolation = "Closest"  # no interpolation across the checker edges
    nt.links.new(tex.outputs["Color"], bsdf.inputs["Color"])
    nt.links.new(bsdf.outputs[0], out.inputs["Surface"])
    return mat


def _walnut(scene):
    """A material as artists build them (issue 21; scenes/procedural_materials.py):
    a Principled BSDF whose Base Color is wood grain in a node group through
    a Color Ramp, Roughness a Voronoi through Map Range, and a Bump."""
    import procedural_materials
    return procedural_materials.walnut()


def _mixed_by_texture(scene):
    """Diffuse and Glossy mixed by a checker times Layer Weight's Facing, the
    diffuse coloured by noise through Hue/Saturation/Value."""
    import procedural_materials
    return procedural_materials.glazed_ceramic()


def _texture_families(scene):
    """Every texture family lit (issue 21's lit sweep): six spheres whose
    colours, roughness and bump come from Noise, Voronoi, Wave, Magic,
    Gradient with Checker, and White Noise through Math and Vector Math,
    on the Brick floor, under the material scenes' area light and world."""
    import procedural_materials as pm
    pt.add_camera(scene, location=(0.0, -4.6, 3.4), target=(0.0, 0.15, 0.3), lens=42.0)
    pt.add_plane(scene, "Floor", size=8.0, material=pm.brick_floor())
    for i, make in enumerate((pm.marble, pm.rusted_metal, _wave_bumped, _magic, _gradient_checker,
                              _white_noise_cells)):
        location = (-1.1 + 1.1 * (i % 3), -0.45 + 1.0 * (i // 3), 0.4)
        pt.add_sphere(scene, "Sphere %d" % i, radius=0.4, location=location, material=make(),
                      segments=48, rings=24)
    pt.set_world(scene, (0.3, 0.35, 0.4), strength=1.0)
    pt.add_light(scene, "AREA", 250.0, location=(1.5, -1.8, 3.2), target=(0.0, 0.0, 0.3),
                 shape="SQUARE", size=1.5)


def _wave_bumped():
    """Wave rings distorted by noise into a Principled base colour, and a
    Bump of the same wave."""
    import procedural_materials as pm
    n = pm.Nodes("Wave bumped")
    bsdf = n.new("ShaderNodeBsdfPrincipled", Roughness=0.35)
    wave = n.new("ShaderNodeTexWave", Scale=3.0, Distortion=4.0, Detail=3.0)
    wave.wave_type = "RINGS"
    color = pm.ramp(n, [(0.0, (0.15, 0.3, 0.6)), (1.0, (0.9, 0.8, 0.5))])
    bump = n.new("ShaderNodeBump", Strength=0.3, Distance=0.05)
    n.link(wave.outputs["Fac"], color.inputs["Fac"])
    n.link(color.outputs["Color"], bsdf.inputs["Base Color"])
    n.link(wave.outputs["Fac"], bump.inputs["Height"])
    n.link(bump.outputs["Normal"], bsdf.inputs["Normal"])
    return n.surface(bsdf)


def _magic():
    import procedural_materials as pm
    n = pm.Nodes("Magic")
    bsdf = n.new("ShaderNodeBsdfDiffuse")
    magic = n.new("ShaderNodeTexMagic", Scale=2.5, Distortion=1.5)
    magic.turbulence_depth = 3
    n.link(magic.outputs["Color"], bsdf.inputs["Color"])
    return n.surface(bsdf)


def _gradient_checker():
    """A spherical Gradient times a Checker (Math), as the factor of a
    Diffuse-Glossy mix."""
    import procedural_materials as pm
    n = pm.Nodes("Gradient checker")
    mix = n.new("ShaderNodeMixShader")
    diffuse = n.new("ShaderNodeBsdfDiffuse", Color=(0.7, 0.25, 0.2))
    glossy = n.new("ShaderNodeBsdfGlossy", Roughness=0.2)
    glossy.distribution = "GGX"
    coords = n.new("ShaderNodeTexCoord")
    gradient = n.new("ShaderNodeTexGradient")
    gradient.gradient_type = "SPHERICAL"
    checker = n.new("ShaderNodeTexChecker", Scale=6.0)
    product = n.new("ShaderNodeMath")
    product.operation = "MULTIPLY"
    n.link(coords.outputs["Object"], gradient.inputs["Vector"])
    n.link(gradient.outputs["Fac"], product.inputs[0])
    n.link(checker.outputs["Fac"], product.inputs[1])
    n.link(product.outputs[0], mix.inputs["Fac"])
    n.link(diffuse.outputs[0], mix.inputs[1])
    n.link(glossy.outputs[0], mix.inputs[2])
    return n.surface(mix)


def _white_noise_cells():
    """White Noise of the position snapped to cells (Vector Math Snap), its
    colour as a Diffuse colour and its value as a Principled roughness."""
    import procedural_materials as pm
    n = pm.Nodes("White noise cells")
    bsdf = n.new("ShaderNodeBsdfPrincipled")
    coords = n.new("ShaderNodeTexCoord")
    snap = n.new("ShaderNodeVectorMath")
    snap.operation = "SNAP"
    snap.inputs[1].default_value = (0.2, 0.2, 0.2)
    noise = n.new("ShaderNodeTexWhiteNoise")
    noise.noise_dimensions = "3D"
    n.link(coords.outputs["Object"], snap.inputs[0])
    n.link(snap.outputs["Vector"], noise.inputs["Vector"])
    n.link(noise.outputs["Color"], bsdf.inputs["Base Color"])
    n.link(noise.outputs["Value"], bsdf.inputs["Roughness"])
    return n.surface(bsdf)


def _mix_two_bumps(scene):
    """Mix Shaders of two Diffuses, each under its own Bump (a coarse noise,
    wave ridges), and an unbumped Glossy: each closure shades about its own
    normal, as Cycles' closures carry their own N (a bumped Glossy:
    bumped_specular)."""
    mat, nt, out = pt.empty_material("Test Mix Two Bumps")
    outer, inner = nt.nodes.new("ShaderNodeMixShader"), nt.nodes.new("ShaderNodeMixShader")
    outer.inputs["Fac"].default_value = inner.inputs["Fac"].default_value = 0.5
    orange = pt.setup_node(nt.nodes.new("ShaderNodeBsdfDiffuse"), {"Color": (0.8, 0.4, 0.2)})
    blue = pt.setup_node(nt.nodes.new("ShaderNodeBsdfDiffuse"), {"Color": (0.2, 0.4, 0.9)})
    glossy = pt.setup_node(nt.nodes.new("ShaderNodeBsdfGlossy"), {"Color": (0.9, 0.9, 0.9), "Roughness": 0.25},
                           {"distribution": "GGX"})
    noise = pt.setup_node(nt.nodes.new("ShaderNodeTexNoise"), {"Scale": 4.0})
    wave = pt.setup_node(nt.nodes.new("ShaderNodeTexWave"), {"Scale": 3.0})
    for tex, strength, bsdf in ((noise, 0.8, orange), (wave, 0.6, blue)):
        bump = pt.setup_node(nt.nodes.new("ShaderNodeBump"), {"Strength": strength, "Distance": 0.1})
        nt.links.new(tex.outputs["Fac"], bump.inputs["Height"])
        nt.links.new(bump.outputs["Normal"], bsdf.inputs["Normal"])
    nt.links.new(blue.outputs[0], inner.inputs[1])
    nt.links.new(glossy.outputs[0], inner.inputs[2])
    nt.links.new(orange.outputs[0], outer.inputs[1])
    nt.links.new(inner.outputs[0], outer.inputs[2])
    nt.links.new(outer.outputs[0], out.inputs["Surface"])
    return mat


def _bumped_specular(scene):
    """A strong noise bump under both halves of a Mix Shader: a sharp-ish
    Glossy and a Principled BSDF with a clearcoat and sheen. Toward the
    silhouette many bent normals would mirror the viewer into the sphere;
    Cycles tilts them back (every closure's before 4.0, the specular
    closures' after), and from 4.2 lays the sheen's normal between the
    bumped one and the coat's (the surface's own here)."""
    mat, nt, out = pt.empty_material("Test Bumped Specular")
    mix = nt.nodes.new("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = 0.5
    glossy = pt.setup_node(nt.nodes.new("ShaderNodeBsdfGlossy"), {"Color": (0.9, 0.9, 0.9), "Roughness": 0.1},
                           {"distribution": "GGX"})
    principled = pt.setup_node(nt.nodes.new("ShaderNodeBsdfPrincipled"),
                               {"Base Color": (0.6, 0.1, 0.1), "Roughness": 0.4, "Clearcoat": 1.0,
                                "Clearcoat Roughness": 0.05, "Sheen": 1.0})
    noise = pt.setup_node(nt.nodes.new("ShaderNodeTexNoise"), {"Scale": 6.0})
    bump = pt.setup_node(nt.nodes.new("ShaderNodeBump"), {"Strength": 1.0, "Distance": 0.6})
    nt.links.new(noise.outputs["Fac"], bump.inputs["Height"])
    for bsdf in (glossy, principled):
        nt.links.new(bump.outputs["Normal"], bsdf.inputs["Normal"])
    nt.links.new(glossy.outputs[0], mix.inputs[1])
    nt.links.new(principled.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], out.inputs["Surface"])
    return mat


def _sheen_under_coat(scene):
    """A Principled BSDF (4.2+) that is mostly sheen under a coat, its
    Normal bumped hard by a noise, no Coat Normal: Cycles lays the sheen
    along normalize(mix(Normal, the surface's normal, Coat Weight)), here
    the smooth normal, so the bumps show in the coat only."""
    mat = pt.node_material("Test Sheen Under Coat", "ShaderNodeBsdfPrincipled",
                           {"Base Color": (0.02, 0.02, 0.02), "Specular IOR Level": 0.0, "Sheen Weight": 1.0,
                            "Sheen Roughness": 0.3, "Sheen Tint": (1.0, 0.9, 0.8), "Coat Weight": 1.0,
                            "Coat Roughness": 0.5})
    nt = mat.node_tree
    bsdf = next(n for n in nt.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    noise = pt.setup_node(nt.nodes.new("ShaderNodeTexNoise"), {"Scale": 6.0})
    bump = pt.setup_node(nt.nodes.new("ShaderNodeBump"), {"Strength": 1.0, "Distance": 0.6})
    nt.links.new(noise.outputs["Fac"], bump.inputs["Height"])
    nt.links.new(bump.outputs["Normal"], bsdf.inputs["Normal"])
    return mat


def _principled_coat_over_bump(scene):
    """A Principled BSDF (4.x) whose Normal is bumped by a noise and whose
    coat has no Coat Normal: Cycles 4.x lays the coat along the surface's own
    normal, so the bumped diffuse shows through a smooth coat. No specular
    (IOR Level 0): bumped_specular has the specular over a bump."""
    mat = pt.node_material("Test Principled Coat Over Bump", "ShaderNodeBsdfPrincipled",
                           {"Base Color": (0.7, 0.25, 0.1), "Roughness": 0.5, "Specular IOR Level": 0.0,
                            "Coat Weight": 1.0, "Coat Roughness": 0.1, "Coat IOR": 1.5})
    nt = mat.node_tree
    bsdf = next(n for n in nt.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    noise = pt.setup_node(nt.nodes.new("ShaderNodeTexNoise"), {"Scale": 4.0})
    bump = pt.setup_node(nt.nodes.new("ShaderNodeBump"), {"Strength": 0.8, "Distance": 0.1})
    nt.links.new(noise.outputs["Fac"], bump.inputs["Height"])
    nt.links.new(bump.outputs["Normal"], bsdf.inputs["Normal"])
    return mat


def _anisotropic_metal(scene):
    """A Principled metal (3.x and 4.x names alike) with Anisotropic 0.8 along
    the default tangent, its Anisotropic Rotation textured by a noise: the
    highlights follow Cycles' tangent field, turned point by point."""
    mat = pt.node_material("Test Anisotropic Metal", "ShaderNodeBsdfPrincipled",
                           {"Base Color": (0.9, 0.6, 0.3), "Metallic": 1.0, "Roughness": 0.4,
                            "Anisotropic": 0.8})
    nt = mat.node_tree
    bsdf = next(n for n in nt.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled")
    noise = pt.setup_node(nt.nodes.new("ShaderNodeTexNoise"), {"Scale": 3.0})
    nt.links.new(noise.outputs["Fac"], bsdf.inputs["Anisotropic Rotation"])
    return mat


def _principled(inputs, props=None):
    """A Principled BSDF with the given inputs (4.x names) and properties."""
    return _one("ShaderNodeBsdfPrincipled", inputs, props)


def _translucent_leaf(scene):
    """A leaf (a plane, Diffuse mixed with Translucent) between a lamp and
    the camera: most of what the camera sees of it is light that came
    through from the lamp's side; the floor behind it is lit through it."""
    pt.add_camera(scene, location=(0.0, -4.2, 1.6), target=(0.0, 0.0, 0.8), lens=50.0)
    pt.add_plane(scene, "Floor", size=8.0, material=pt.diffuse("Floor", (0.8, 0.8, 0.8)))
    mat, nt, out = pt.empty_material("Leaf")
    mix = nt.nodes.new("ShaderNodeMixShader")
    mix.inputs["Fac"].default_value = 0.6
    diffuse = pt.setup_node(nt.nodes.new("ShaderNodeBsdfDiffuse"), {"Color": (0.3, 0.6, 0.1)})
    translucent = pt.setup_node(nt.nodes.new("ShaderNodeBsdfTranslucent"), {"Color": (0.4, 0.8, 0.2)})
    nt.links.new(diffuse.outputs[0], mix.inputs[1])
    nt.links.new(translucent.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], out.inputs["Surface"])
    pt.add_plane(scene, "Leaf", size=1.4, location=(0.0, 0.0, 0.8), rotation=(math.radians(80), 0.0, 0.3),
                 material=mat)
    pt.set_world(scene, (0.05, 0.05, 0.06), strength=1.0)
    pt.add_light(scene, "AREA", 150.0, location=(0.4, 2.0, 2.2), target=(0.0, 0.0, 0.8), shape="SQUARE",
                 size=0.8)


def _depth_coloured(scene):
    """A sphere whose Diffuse colour is 0.9 − 0.7·min(depth, 1) per channel
    for Light Path's Diffuse, Glossy and Transmission Depth, on a floor
    that is half diffuse, half rough glossy: the floor's reflections of the
    sphere (diffuse or glossy depth 1) see it darker in that channel than
    the camera does (depth 0)."""
    mat, nt, out = pt.empty_material("Depths")
    lp = nt.nodes.new("ShaderNodeLightPath")
    combine = nt.nodes.new("ShaderNodeCombineRGB" if bpy.app.version < (3, 3, 0) else "ShaderNodeCombineColor")
    for k, output in enumerate(("Diffuse Depth", "Glossy Depth", "Transmission Depth")):
        low = nt.nodes.new("ShaderNodeMath")
        low.operation = "MINIMUM"
        low.inputs[1].default_value = 1.0
        nt.links.new(lp.outputs[output], low.inputs[0])
        value = nt.nodes.new("ShaderNodeMath")
        value.operation = "MULTIPLY_ADD"
        value.inputs[1].default_value = -0.7
        value.inputs[2].default_value = 0.9
        nt.links.new(low.outputs[0], value.inputs[0])
        nt.links.new(value.outputs[0], combine.inputs[k])
    diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
    nt.links.new(combine.outputs[0], diffuse.inputs["Color"])
    nt.links.new(diffuse.outputs[0], out.inputs["Surface"])
    _stage(scene, mat)
    floor = _two("ShaderNodeMixShader", ("ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.8, 0.8)}, None),
                 ("ShaderNodeBsdfGlossy", {"Color": (0.9, 0.9, 0.9), "Roughness": 0.2}, None), fac=0.5)(scene)
    scene.objects["Floor"].data.materials[0] = floor
    pt.set_world(scene, (0.3, 0.35, 0.4), strength=1.0)
    pt.add_light(scene, "AREA", 200.0, location=(1.5, -1.5, 3.0), target=SPHERE_CENTRE,
                 shape="SQUARE", size=1.5)


def _holdout(scene):
    """A transparent film: a sphere that is a whole holdout and one mixed
    half with a diffuse, in front of a diffuse cube (the RGBA test)."""
    pt.add_camera(scene, location=(0.0, -4.2, 1.2), target=(0.0, 0.0, 0.6), lens=50.0)
    pt.add_plane(scene, "Floor", size=8.0, material=pt.diffuse("Floor", (0.8, 0.8, 0.8)))
    pt.add_sphere(scene, "Back", radius=0.9, location=(0.0, 1.5, 0.9),
                  material=pt.diffuse("Back", (0.8, 0.5, 0.3)), segments=48, rings=24)
    hold = pt.node_material("Holdout", "ShaderNodeHoldout")
    pt.add_sphere(scene, "Whole", radius=0.35, location=(-0.5, 0.0, 0.6), material=hold,
                  segments=48, rings=24)
    half = _two("ShaderNodeMixShader", ("ShaderNodeBsdfDiffuse", {"Color": (0.2, 0.4, 0.8)}, None),
                ("ShaderNodeHoldout", None, None), fac=0.5)(scene)
    pt.add_sphere(scene, "Half", radius=0.35, location=(0.5, 0.0, 0.6), material=half,
                  segments=48, rings=24)
    pt.set_world(scene, (0.3, 0.35, 0.4), strength=1.0)
    pt.add_light(scene, "AREA", 200.0, location=(1.5, -1.5, 3.0), target=SPHERE_CENTRE,
                 shape="SQUARE", size=1.5)


MATERIAL_SCENES = {
    "translucent_leaf": _translucent_leaf,
    "light_path_depths": _depth_coloured,
    "diffuse": _material_scene(_one("ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.3, 0.2)})),
    "glossy_sharp": _material_scene(_one("ShaderNodeBsdfGlossy", {"Color": (0.9, 0.9, 0.9)},
                                         {"distribution": "SHARP"})),
    "glossy_ggx_r0.3": _material_scene(_one("ShaderNodeBsdfGlossy",
                                            {"Color": (0.8, 0.8, 0.8), "Roughness": 0.3},
                                            {"distribution": "GGX"})),
    "glass_sharp": _material_scene(_one("ShaderNodeBsdfGlass", {"IOR": 1.5},
                                        {"distribution": "SHARP"})),
    "glass_ggx": _material_scene(_one("ShaderNodeBsdfGlass", {"IOR": 1.5, "Roughness": 0.2},
                                      {"distribution": "GGX"})),
    "refraction": _material_scene(_one("ShaderNodeBsdfRefraction",
                                       {"IOR": 1.45, "Roughness": 0.1, "Color": (0.9, 0.9, 1.0)},
                                       {"distribution": "GGX"})),
    "emission": _material_scene(_one("ShaderNodeEmission",
                                     {"Color": (1.0, 0.5, 0.2), "Strength": 3.0})),
    "transparent": _material_scene(_one("ShaderNodeBsdfTransparent", {"Color": (0.7, 0.9, 0.7)})),
    "principled_default": _material_scene(_one("ShaderNodeBsdfPrincipled")),
    "principled_metallic": _material_scene(_one("ShaderNodeBsdfPrincipled",
                                                {"Base Color": (0.9, 0.6, 0.3), "Metallic": 1.0,
                                                 "Roughness": 0.3})),
    "principled_transmission": _material_scene(_one("ShaderNodeBsdfPrincipled",
                                                    {"Transmission": 1.0, "Roughness": 0.05,
                                                     "IOR": 1.45})),
    "principled_glass_tinted": _material_scene(_one("ShaderNodeBsdfPrincipled",
                                                    {"Base Color": (0.9, 0.5, 0.3), "Transmission": 1.0,
                                                     "Roughness": 0.2, "Transmission Roughness": 0.4,
                                                     "IOR": 1.5})),
    "mix_0.3": _material_scene(_two(
        "ShaderNodeMixShader",
        ("ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.2, 0.2)}, None),
        ("ShaderNodeBsdfGlossy", {"Color": (0.9, 0.9, 0.9), "Roughness": 0.2}, {"distribution": "GGX"}),
        fac=0.3)),
    "add": _material_scene(_two(
        "ShaderNodeAddShader",
        ("ShaderNodeBsdfDiffuse", {"Color": (0.2, 0.3, 0.5)}, None),
        ("ShaderNodeBsdfGlossy", {"Color": (0.4, 0.4, 0.4), "Roughness": 0.3}, {"distribution": "GGX"}))),
    "image_texture": _material_scene(_image_texture),
    "sheen_bsdf": _material_scene(_one("ShaderNodeBsdfSheen", {"Color": (0.9, 0.5, 0.6), "Roughness": 0.4},
                                       {"distribution": "MICROFIBER"})),
    "textured_walnut": _material_scene(_walnut),
    "textured_mix": _material_scene(_mixed_by_texture),
    "texture_families": _texture_families,
    "mix_two_bumps": _material_scene(_mix_two_bumps),
    "bumped_specular": _material_scene(_bumped_specular),
    "anisotropic_metal": _material_scene(_anisotropic_metal),
    "glossy_beckmann": _material_scene(_one("ShaderNodeBsdfGlossy", {"Color": (0.9, 0.8, 0.6), "Roughness": 0.35},
                                            {"distribution": "BECKMANN"})),
    "glossy_ashikhmin_shirley": _material_scene(_one(
        "ShaderNodeBsdfAnisotropic", {"Color": (0.8, 0.9, 0.9), "Roughness": 0.4, "Anisotropy": 0.5,
                                      "Rotation": 0.1}, {"distribution": "ASHIKHMIN_SHIRLEY"})),
    "glass_beckmann": _material_scene(_one("ShaderNodeBsdfGlass", {"IOR": 1.5, "Roughness": 0.3},
                                           {"distribution": "BECKMANN"})),
    # 3.x's Anisotropic BSDF, 4.x's Glossy: Anisotropy < 0 stretches across the tangent.
    "anisotropic_glossy": _material_scene(_one("ShaderNodeBsdfAnisotropic",
                                               {"Color": (0.9, 0.9, 0.9), "Roughness": 0.3, "Anisotropy": -0.6,
                                                "Rotation": 0.15}, {"distribution": "GGX"})),
}

# Multiscatter GGX at roughness 0.2, 0.5 and 1: a white Glossy (no Fresnel),
# a metal and a dielectric (Principled), and a rough glass.
for _r in (0.2, 0.5, 1.0):
    MATERIAL_SCENES["multiscatter_glossy_r%.1f" % _r] = _material_scene(_one(
        "ShaderNodeBsdfGlossy", {"Color": (0.9, 0.9, 0.9), "Roughness": _r}, {"distribution": "MULTI_GGX"}))
    MATERIAL_SCENES["multiscatter_metal_r%.1f" % _r] = _material_scene(_principled(
        {"Base Color": (0.95, 0.64, 0.54), "Metallic": 1.0, "Roughness": _r}, {"distribution": "MULTI_GGX"}))
    MATERIAL_SCENES["multiscatter_dielectric_r%.1f" % _r] = _material_scene(_principled(
        {"Base Color": (0.2, 0.35, 0.8), "Roughness": _r, "IOR": 1.5}, {"distribution": "MULTI_GGX"}))
MATERIAL_SCENES["multiscatter_glass_r0.5"] = _material_scene(_one(
    "ShaderNodeBsdfGlass", {"IOR": 1.5, "Roughness": 0.5}, {"distribution": "MULTI_GGX"}))

# Principled BSDF v2 (Blender 4.0+): each layer on its own.
MATERIAL_SCENES.update({
    "principled_coat": _material_scene(_principled(
        {"Base Color": (0.8, 0.1, 0.1), "Roughness": 0.6, "Coat Weight": 1.0, "Coat Roughness": 0.1,
         "Coat IOR": 1.6, "Coat Tint": (0.6, 0.8, 1.0)})),
    "principled_coat_over_bump": _material_scene(_principled_coat_over_bump),
    "sheen_under_coat": _material_scene(_sheen_under_coat),
    "principled_sheen": _material_scene(_principled(
        {"Base Color": (0.05, 0.1, 0.4), "Roughness": 0.7, "Sheen Weight": 1.0, "Sheen Roughness": 0.4,
         "Sheen Tint": (1.0, 0.9, 0.8)})),
    "principled_specular_tint": _material_scene(_principled(
        {"Base Color": (0.1, 0.1, 0.1), "Roughness": 0.25, "Specular IOR Level": 0.8,
         "Specular Tint": (1.0, 0.5, 0.2)})),
    "principled_metal_edge_tint": _material_scene(_principled(
        {"Base Color": (0.9, 0.9, 0.9), "Metallic": 1.0, "Roughness": 0.35,
         "Specular Tint": (0.4, 0.6, 1.0)})),
    "principled_thin_film": _material_scene(_principled(
        {"Base Color": (0.05, 0.05, 0.05), "Roughness": 0.15, "Thin Film Thickness": 500.0,
         "Thin Film IOR": 1.33})),
    "principled_diffuse_roughness": _material_scene(_principled(
        {"Base Color": (0.8, 0.5, 0.3), "Roughness": 0.5, "Diffuse Roughness": 1.0})),
    "metallic_anisotropic": _material_scene(_one(
        "ShaderNodeBsdfMetallic", {"Base Color": (0.8, 0.8, 0.85), "Roughness": 0.3, "Anisotropy": 0.6,
                                   "Rotation": 0.25})),
    "metallic_bsdf": _material_scene(_one(
        "ShaderNodeBsdfMetallic", {"Base Color": (0.9, 0.7, 0.4), "Edge Tint": (0.9, 0.9, 1.0), "Roughness": 0.4})),
    "diffuse_roughness": _material_scene(_one("ShaderNodeBsdfDiffuse", {"Color": (0.7, 0.7, 0.7), "Roughness": 0.8})),
})

# The Blender a scene needs (its nodes, inputs or light settings): older
# versions skip it.
# Compared in RGBA with a transparent film (test_parity.test_rgba).
RGBA_SCENES = {
    "holdout": _holdout,
}

MIN_VERSION = {
    # Cycles 3.x's Multiscatter GGX is a random walk between microfacets;
    # Phos renders 4.x's albedo scaling for it, which matches its brightness
    # (channel means within 0.5 %, the glass 1.2 %, on 3.4) but not the
    # shape of its highlights: parity per pixel is for 4.0 and later.
    **{name: (4, 0, 0) for name in MATERIAL_SCENES if name.startswith("multiscatter_")},
    "sky_multiple_scattering": (5, 0, 0),  # Blender 5's model
    "sky_multiple_scattering_diffuse": (5, 0, 0),
    "point_sphere": (4, 1, 0),
    "spot_sphere": (4, 1, 0),
    "principled_coat": (4, 0, 0),
    "principled_coat_over_bump": (4, 0, 0),
    "sheen_under_coat": (4, 2, 0),
    "principled_sheen": (4, 0, 0),
    "sheen_bsdf": (4, 0, 0),
    "principled_specular_tint": (4, 0, 0),
    "principled_metal_edge_tint": (4, 0, 0),
    "principled_thin_film": (4, 2, 0),
    "principled_diffuse_roughness": (4, 3, 0),
    "metallic_bsdf": (4, 3, 0),
    "metallic_anisotropic": (4, 3, 0),
    "diffuse_roughness": (4, 3, 0),
}
