# SPDX-License-Identifier: GPL-3.0-or-later
"""Export of each datablock kind.

Two kinds of checks:
- through the add-on's export package (phos.export.export_scene and
  phos.export.material.material_closures): counts of instances, meshes,
  triangles and lights, closure lists, warnings;
- through renders: silhouettes compared with Cycles (emission-only scenes in
  a black world, so an image is just coverage), projected positions against
  Blender's own camera projection, output sizes, light produced.
"""

import math
import os

import bpy
import numpy as np
import pytest

import phostest as pt

SIL_RES = (64, 64)
SIL_SAMPLES = 64


# ----------------------------------------------------------------- helpers

def export(scene):
    """The add-on's ExportContext of a real (tiny) Phos render of the scene.

    The exporter must see the render depsgraph (hide_render, render
    visibility of instancers, particle render amounts), which Python cannot
    create in 3.4, so phos.export.export_scene is wrapped for one render and
    its context kept.
    """
    from phos import export as phos_export
    captured = []
    original = phos_export.export_scene

    def spy(*args, **kwargs):
        ctx = original(*args, **kwargs)
        captured.append(ctx)
        return ctx

    r = scene.render
    saved = (r.resolution_x, r.resolution_y, r.resolution_percentage, r.engine, scene.phos.samples)
    phos_export.export_scene = spy
    try:
        r.resolution_x, r.resolution_y, r.resolution_percentage = 8, 8, 100
        r.engine = "PHOS"
        scene.phos.samples = 1
        bpy.ops.render.render(scene=scene.name)
    finally:
        phos_export.export_scene = original
        (r.resolution_x, r.resolution_y, r.resolution_percentage, r.engine,
         scene.phos.samples) = saved
    assert len(captured) == 1, "the engine did not call phos.export.export_scene once"
    return captured[0]


def closures_of(scene, mat):
    from phos import core
    from phos.export import material as mexp
    from phos.export.context import ExportContext
    with core.Scene() as core_scene:
        ctx = ExportContext(scene, core_scene)
        closures = mexp.material_closures(mat, ctx)
        # The material must also be accepted by the core.
        mexp.add_material(mat, ctx)
    return closures, ctx.warnings


def ortho_top_camera(scene, scale=4.0):
    return pt.add_camera(scene, location=(0, 0, 10), target=(0, 0, 0), ortho_scale=scale)


def silhouettes(scene, tmp_path, res=SIL_RES, samples=SIL_SAMPLES):
    """Coverage masks (value > half the emission) of Phos and Cycles renders."""
    pt.configure_output(scene, *res)
    pt.configure_phos(scene, samples, max_bounces=0)
    pt.configure_cycles(scene, samples, max_bounces=0)
    p = pt.render_array(scene, tmp_path, "PHOS")
    c = pt.render_array(scene, tmp_path, "CYCLES")
    return p, c


def assert_same_silhouette(p, c, what=""):
    """Same covered area (sum of a unit emission = area in pixels, the filter
    preserves it) and the same shape (L1 difference small against the area).
    Returns the covered area in pixels."""
    gp, gc = p[..., 1].astype(np.float64), c[..., 1].astype(np.float64)
    area_p, area_c = gp.sum(), gc.sum()
    assert area_c > 10, "%s: the Cycles reference covers nothing" % what
    assert area_p == pytest.approx(area_c, rel=0.03), (
        "%s: covered area Phos %.1f px, Cycles %.1f px" % (what, area_p, area_c))
    l1 = np.abs(gp - gc).sum() / area_c
    assert l1 < 0.12, "%s: silhouettes differ: sum|P-C|/area = %.3f" % (what, l1)
    return area_c


def white_emission(name="White Emission"):
    return pt.emission(name, (1.0, 1.0, 1.0), 1.0)


# -------------------------------------------------------------- geometry

def test_mesh_modifier_exported(scene):
    ortho_top_camera(scene)
    cube = pt.add_cube(scene, size=1.0)
    mod = cube.modifiers.new("Subdivision", "SUBSURF")
    mod.levels = mod.render_levels = 2
    ctx = export(scene)
    assert ctx.stats["triangles"] == 6 * 16 * 2  # 96 quads after two Catmull-Clark levels
    assert ctx.stats["instances"] == 1 and ctx.stats["meshes"] == 1


def test_mesh_modifier_silhouette(scene, tmp_path):
    ortho_top_camera(scene, scale=4.0)
    pt.set_world(scene, (0, 0, 0))
    plane = pt.add_plane(scene, size=0.5, location=(-1.0, 0, 0), material=white_emission())
    arr = plane.modifiers.new("Array", "ARRAY")
    arr.count = 3
    arr.relative_offset_displace = (2.0, 0.0, 0.0)
    p, c = silhouettes(scene, tmp_path)
    covered = assert_same_silhouette(p, c, what="array modifier")
    # 3 copies of a 0.5 m square in a 4 m frame of 64 px: 3 × 8 × 8 px.
    assert covered == pytest.approx(192, rel=0.05)


def _instance_source(scene, name="Inst"):
    """A collection holding one small emissive cube, not linked to the scene."""
    coll = bpy.data.collections.new(name)
    me_ob = pt.add_cube(bpy.context.scene, "Src", size=0.4, material=white_emission())
    scene.collection.objects.unlink(me_ob)
    coll.objects.link(me_ob)
    return coll, me_ob


def test_collection_instances(scene, tmp_path):
    ortho_top_camera(scene)
    pt.set_world(scene, (0, 0, 0))
    coll, _ = _instance_source(scene)
    for i, x in enumerate((-1.2, 0.0, 1.2)):
        empty = bpy.data.objects.new("Instancer%d" % i, None)
        empty.instance_type = "COLLECTION"
        empty.instance_collection = coll
        empty.location = (x, 0.5 * i - 0.5, 0)
        scene.collection.objects.link(empty)
    ctx = export(scene)
    assert ctx.stats["instances"] == 3
    assert ctx.stats["meshes"] == 1, "collection instances should share one mesh"
    p, c = silhouettes(scene, tmp_path)
    covered = assert_same_silhouette(p, c, what="collection instances")
    assert covered == pytest.approx(3 * (0.4 * 16) ** 2, rel=0.05)


def _geometry_nodes_instancer(scene, count):
    """An object whose geometry nodes put `count` cubes on a mesh line (instances, not realized)."""
    base = pt.add_plane(scene, "GN", size=0.1)
    mod = base.modifiers.new("GN", "NODES")
    tree, gout = pt.geometry_node_group("Instancer")
    nodes, links = tree.nodes, tree.links
    line = nodes.new("GeometryNodeMeshLine")
    line.mode = "OFFSET"
    line.inputs["Count"].default_value = count
    line.inputs["Start Location"].default_value = (-1.5, 0.0, 0.0)
    line.inputs["Offset"].default_value = (3.0 / max(count - 1, 1), 0.0, 0.0)
    cube = nodes.new("GeometryNodeMeshCube")
    cube.inputs["Size"].default_value = (0.3, 0.3, 0.3)
    setmat = nodes.new("GeometryNodeSetMaterial")
    setmat.inputs["Material"].default_value = white_emission("GN Emission")
    iop = nodes.new("GeometryNodeInstanceOnPoints")
    links.new(cube.outputs["Mesh"], setmat.inputs["Geometry"])
    links.new(line.outputs["Mesh"], iop.inputs["Points"])
    links.new(setmat.outputs["Geometry"], iop.inputs["Instance"])
    links.new(iop.outputs["Instances"], gout.inputs[0])
    mod.node_group = tree
    return base


def test_geometry_nodes_instances(scene, tmp_path):
    ortho_top_camera(scene)
    pt.set_world(scene, (0, 0, 0))
    _geometry_nodes_instancer(scene, 5)
    ctx = export(scene)
    assert ctx.stats["instances"] == 5
    assert ctx.stats["meshes"] == 1, "geometry-nodes instances of one geometry should share a mesh"
    p, c = silhouettes(scene, tmp_path)
    covered = assert_same_silhouette(p, c, what="geometry-nodes instances")
    assert covered == pytest.approx(5 * (0.3 * 16) ** 2, rel=0.05)


def test_thousand_instances_in_one_call(scene, tmp_path):
    """A geometry-nodes scatter of 1000 cubes reaches the core in one
    phos_scene_add_instances call, none one by one, and renders as Cycles
    does."""
    from phos import core
    ortho_top_camera(scene)
    pt.set_world(scene, (0, 0, 0))
    _geometry_nodes_instancer(scene, 1000)
    calls = {"bulk": [], "single": 0}
    bulk, single = core.Scene.add_instances, core.Scene.add_instance

    def add_instances(self, mesh_ids, *args):
        calls["bulk"].append(len(mesh_ids))
        return bulk(self, mesh_ids, *args)

    def add_instance(self, *args, **kwargs):
        calls["single"] += 1
        return single(self, *args, **kwargs)
    core.Scene.add_instances, core.Scene.add_instance = add_instances, add_instance
    try:
        ctx = export(scene)
    finally:
        core.Scene.add_instances, core.Scene.add_instance = bulk, single
    assert calls == {"bulk": [1000], "single": 0}, calls
    assert ctx.stats["instances"] == 1000 and ctx.stats["meshes"] == 1
    p, c = silhouettes(scene, tmp_path)
    assert_same_silhouette(p, c, what="a thousand geometry-nodes instances")


def _particle_instancer(scene, count):
    target = pt.add_cube(scene, "Particle", size=0.15, location=(50, 50, 50),
                         material=white_emission("Particle Emission"))
    emitter = pt.add_plane(scene, "Emitter", size=3.0)
    emitter.modifiers.new("Particles", "PARTICLE_SYSTEM")
    ps = emitter.particle_systems[0].settings
    ps.count = count
    ps.frame_start = ps.frame_end = 1
    ps.lifetime = 1000
    ps.emit_from = "FACE"
    ps.physics_type = "NO"
    ps.render_type = "OBJECT"
    ps.instance_object = target
    ps.particle_size = 1.0
    ps.use_rotation_instance = False
    emitter.show_instancer_for_render = False
    return emitter, target


def test_particle_instances(scene, tmp_path):
    ortho_top_camera(scene)
    pt.set_world(scene, (0, 0, 0))
    scene.frame_set(1)
    _particle_instancer(scene, 12)
    ctx = export(scene)
    # 12 particles + the instanced object itself (far out of view); the
    # emitter is hidden by show_instancer_for_render.
    assert ctx.stats["instances"] == 13
    assert ctx.stats["meshes"] == 1
    p, c = silhouettes(scene, tmp_path)
    assert_same_silhouette(p, c, what="particle instances")


def test_hidden_objects_not_exported(scene):
    ortho_top_camera(scene)
    pt.add_cube(scene, "Shown")
    hidden = pt.add_cube(scene, "Hidden", location=(2, 0, 0))
    hidden.hide_render = True
    ctx = export(scene)
    assert ctx.stats["instances"] == 1


def test_material_slots(scene, tmp_path):
    """Two faces of one mesh with two materials render with their own colours."""
    ortho_top_camera(scene, scale=2.0)
    pt.set_world(scene, (0, 0, 0))
    me = bpy.data.meshes.new("TwoSlots")
    me.from_pydata([(-1, -1, 0), (0, -1, 0), (0, 1, 0), (-1, 1, 0), (1, -1, 0), (1, 1, 0)], [],
                   [(0, 1, 2, 3), (1, 4, 5, 2)])
    me.materials.append(pt.emission("Red", (1, 0, 0), 1.0))
    me.materials.append(pt.emission("Green", (0, 1, 0), 1.0))
    me.polygons[1].material_index = 1
    ob = bpy.data.objects.new("TwoSlots", me)
    scene.collection.objects.link(ob)
    pt.configure_output(scene, 32, 32)
    pt.configure_phos(scene, 8, max_bounces=0)
    img = pt.render_array(scene, tmp_path, "PHOS")
    left, right = img[8:24, 2:12, :3].mean(axis=(0, 1)), img[8:24, 20:30, :3].mean(axis=(0, 1))
    assert left == pytest.approx((1, 0, 0), abs=0.02)
    assert right == pytest.approx((0, 1, 0), abs=0.02)


# ----------------------------------------------------------------- camera

CAMERA_CASES = {
    # name: (resolution, camera data settings)
    "persp": ((64, 64), {}),
    "persp_shift": ((64, 64), {"shift_x": 0.15, "shift_y": -0.1}),
    "persp_fit_vertical_landscape": ((96, 48), {"sensor_fit": "VERTICAL", "sensor_height": 24.0}),
    "persp_fit_horizontal_portrait": ((48, 96), {"sensor_fit": "HORIZONTAL", "sensor_width": 30.0}),
    "persp_fit_auto_portrait": ((48, 96), {"sensor_fit": "AUTO"}),
    "ortho": ((64, 64), {"type": "ORTHO", "ortho_scale": 5.0}),
    "ortho_shift_landscape": ((96, 48), {"type": "ORTHO", "ortho_scale": 6.0, "shift_x": -0.1,
                                         "shift_y": 0.05}),
}


@pytest.mark.parametrize("case", list(CAMERA_CASES))
def test_camera_projection(case, scene, tmp_path):
    """A small emissive sphere appears where Blender's camera projection puts it."""
    (w, h), settings = CAMERA_CASES[case]
    cam = pt.add_camera(scene, location=(0.3, -6.0, 1.0), target=(0.0, 0.0, 0.3), lens=40.0)
    for k, v in settings.items():
        setattr(cam.data, k, v)
    pt.set_world(scene, (0, 0, 0))
    target = (0.7, 0.4, 0.8)
    pt.add_sphere(scene, "Dot", radius=0.08, location=target, material=white_emission(),
                  segments=24, rings=12)
    pt.configure_output(scene, w, h)
    pt.configure_phos(scene, 32, max_bounces=0)
    img = pt.render_array(scene, tmp_path, "PHOS")
    assert img.shape[:2] == (h, w)
    lum = img[..., :3].sum(axis=2)
    assert lum.sum() > 0, "the dot is not in the image"
    ys, xs = np.mgrid[0:h, 0:w]
    cx = (lum * (xs + 0.5)).sum() / lum.sum()
    cy = (lum * (ys + 0.5)).sum() / lum.sum()
    ex, ey = pt.project(scene, target)
    assert 2 < ex < w - 2 and 2 < ey < h - 2, "test setup: the dot should be inside the frame"
    assert (cx, cy) == pytest.approx((ex, ey), abs=0.25), (
        "dot centroid at (%.2f, %.2f), Blender projects it to (%.2f, %.2f)" % (cx, cy, ex, ey))


def test_resolution_percentage(scene, tmp_path):
    pt.add_camera(scene)
    pt.add_sphere(scene, material=white_emission())
    pt.configure_output(scene, 64, 48, percentage=50)
    pt.configure_phos(scene, 4, max_bounces=0)
    img = pt.render_array(scene, tmp_path, "PHOS")
    assert img.shape[:2] == (24, 32)
    assert img[..., :3].max() > 0.5


# ----------------------------------------------------------------- lights

LIGHT_CASES = {
    "point": ("POINT", 300.0, {"shadow_soft_size": 0.2}),
    "spot": ("SPOT", 600.0, {"spot_size": math.radians(60), "spot_blend": 0.2}),
    "sun": ("SUN", 3.0, {"angle": math.radians(5)}),
    "area_square": ("AREA", 200.0, {"shape": "SQUARE", "size": 1.0}),
    "area_rectangle": ("AREA", 200.0, {"shape": "RECTANGLE", "size": 1.0, "size_y": 0.4}),
    "area_disk": ("AREA", 200.0, {"shape": "DISK", "size": 1.0}),
    "area_ellipse": ("AREA", 200.0, {"shape": "ELLIPSE", "size": 1.0, "size_y": 0.4}),
}


@pytest.mark.parametrize("case", list(LIGHT_CASES))
def test_light_produces_light(case, scene, tmp_path):
    kind, energy, props = LIGHT_CASES[case]
    pt.add_camera(scene, location=(0, -4, 3), target=(0, 0, 0))
    pt.add_plane(scene, "Floor", size=6.0, material=pt.diffuse("Floor", (0.8, 0.8, 0.8)))
    pt.set_world(scene, (0, 0, 0))
    pt.add_light(scene, kind, energy, location=(0.5, -0.5, 3.0), target=(0, 0, 0), **props)
    ctx = export(scene)
    assert ctx.stats["lights"] == 1
    assert not ctx.warnings, ctx.warnings
    pt.configure_output(scene, 32, 32)
    pt.configure_phos(scene, 16, max_bounces=1)
    pt.configure_cycles(scene, 16, max_bounces=1)
    p = pt.render_array(scene, tmp_path, "PHOS")[..., :3].mean()
    c = pt.render_array(scene, tmp_path, "CYCLES")[..., :3].mean()
    assert p > 1e-3, "no light from a %s light" % case
    assert p == pytest.approx(c, rel=0.1), "Phos mean %.4f, Cycles %.4f" % (p, c)


@pytest.mark.parametrize("degrees", [0.0, 15.0, 90.0, 170.0])
def test_sun_disc_mean_cosine(degrees):
    """Cycles < 4.0 samples a sun of angle α uniformly over a disc of radius
    tan(α/2) one unit away, each direction carrying the full strength: its
    irradiance at normal incidence is the mean cosine over that disc (the
    add-on scales the sun by it on 3.x; 4.x spreads E = S over the cone)."""
    from phos.export import light as light_export
    angle = math.radians(degrees)
    r = math.tan(0.5 * angle)
    rho = (np.arange(200000) + 0.5) / 200000 * r   # midpoint rule over the disc's area
    numeric = float(np.sum(2.0 * rho / max(r * r, 1e-30) / np.sqrt(1.0 + rho * rho)) * r / 200000) \
        if r > 0 else 1.0
    assert light_export.sun_disc_mean_cosine(angle) == pytest.approx(numeric, rel=1e-6)


@pytest.mark.parametrize("visible", [False, True], ids=["hidden", "visible"])
@pytest.mark.parametrize("kind", ["AREA", "POINT", "SUN"])
def test_light_camera_visibility(kind, visible, scene, tmp_path):
    """Object > Visibility > Ray Visibility > Camera decides whether the camera sees a
    light (Cycles). Lights created from Python start with it off in 3.4."""
    pt.add_camera(scene, location=(0, 0, 0), target=(0, 0, 5))
    pt.set_world(scene, (0, 0, 0))
    props = {"AREA": {"size": 1.0}, "POINT": {"shadow_soft_size": 0.5}, "SUN": {"angle": 0.3}}[kind]
    light = pt.add_light(scene, kind, 5.0 if kind == "SUN" else 100.0, location=(0, 0, 5),
                         target=(0, 0, 0), **props)
    light.visible_camera = visible
    pt.configure_output(scene, 16, 16)
    pt.configure_phos(scene, 16, max_bounces=0)
    pt.configure_cycles(scene, 16, max_bounces=0)
    p = pt.render_array(scene, tmp_path, "PHOS")[..., :3].max()
    c = pt.render_array(scene, tmp_path, "CYCLES")[..., :3].max()
    assert (c > 0) == visible, "test setup: Cycles max %g" % c
    assert p == pytest.approx(c, rel=0.05, abs=1e-6), (
        "%s light, visible_camera=%s: brightest pixel Phos %g, Cycles %g" % (kind, visible, p, c))


def test_zero_energy_light_skipped(scene):
    pt.add_camera(scene)
    pt.add_light(scene, "POINT", 0.0)
    pt.add_light(scene, "POINT", 10.0, location=(1, 1, 1))
    assert export(scene).stats["lights"] == 1


# -------------------------------------------------------------- materials

def _closure_types(closures):
    return [c.type for c in closures]


def test_material_closures(scene):
    """Each supported node becomes the expected closures, without warnings."""
    from phos import core as C
    import parity_scenes as ps

    expected = {
        "diffuse": [C.PHOS_CLOSURE_DIFFUSE],
        "glossy_sharp": [C.PHOS_CLOSURE_REFLECTION],
        "glossy_ggx_r0.3": [C.PHOS_CLOSURE_REFLECTION],
        "glass_sharp": [C.PHOS_CLOSURE_GLASS],
        "glass_ggx": [C.PHOS_CLOSURE_GLASS],
        "refraction": [C.PHOS_CLOSURE_REFRACTION],
        "emission": [C.PHOS_CLOSURE_EMISSION],
        "transparent": [C.PHOS_CLOSURE_TRANSPARENT],
        "mix_0.3": [C.PHOS_CLOSURE_DIFFUSE, C.PHOS_CLOSURE_REFLECTION],
        "add": [C.PHOS_CLOSURE_DIFFUSE, C.PHOS_CLOSURE_REFLECTION],
        "image_texture": [C.PHOS_CLOSURE_DIFFUSE],
    }
    results = {}
    for name, types in expected.items():
        sc = pt.reset_file()
        ps.MATERIAL_SCENES[name](sc)
        mat = bpy.data.objects["Sphere"].active_material
        closures, warnings = closures_of(sc, mat)
        results[name] = closures
        assert _closure_types(closures) == types, name
        assert not warnings, "%s: %s" % (name, warnings)

    def only(name):
        return results[name][0]
    assert only("glossy_sharp").roughness == 0.0
    assert only("glossy_ggx_r0.3").roughness == pytest.approx(0.3)
    assert only("glass_sharp").ior == pytest.approx(1.5) and only("glass_sharp").roughness == 0.0
    assert only("glass_ggx").roughness == pytest.approx(0.2)
    assert only("refraction").ior == pytest.approx(1.45)
    assert tuple(only("emission").weight) == pytest.approx((3.0, 1.5, 0.6))  # colour × strength
    assert tuple(only("transparent").weight) == pytest.approx((0.7, 0.9, 0.7))
    mix = results["mix_0.3"]
    assert tuple(mix[0].weight) == pytest.approx(tuple(0.7 * np.array((0.8, 0.2, 0.2))))
    assert tuple(mix[1].weight) == pytest.approx(tuple(0.3 * np.array((0.9, 0.9, 0.9))))
    # The image is an instruction of the material's program, which sets the weight.
    from phos.export import program as prog
    assert prog.varies(results["image_texture"][0].weight)


def test_principled_closures(scene):
    from phos import core as C
    mat = pt.node_material("P", "ShaderNodeBsdfPrincipled")
    closures = closures_of(scene, mat)[0]
    types = _closure_types(closures)
    # Principled v1 (3.x): Burley diffuse beside the specular. Principled v2
    # (4.x): a Lambertian base under the specular layer.
    v4 = bpy.app.version >= (4, 0, 0)
    base_type = C.PHOS_CLOSURE_DIFFUSE if v4 else C.PHOS_CLOSURE_PRINCIPLED_DIFFUSE
    assert base_type in types
    spec = next(c for c in closures if c.type == C.PHOS_CLOSURE_REFLECTION_FRESNEL)
    base = next(c for c in closures if c.type == base_type)
    assert (base in (spec.layer_children or [])) == v4
    assert C.PHOS_CLOSURE_GLASS not in types
    # The default distribution: Multiscatter GGX from 4.0, GGX before.
    assert spec.microfacet == (C.PHOS_MICROFACET_GGX_MULTISCATTER if v4 else C.PHOS_MICROFACET_GGX_SEPARABLE)

    metal = pt.node_material("M", "ShaderNodeBsdfPrincipled",
                             {"Base Color": (0.9, 0.6, 0.3), "Metallic": 1.0})
    closures = closures_of(scene, metal)[0]
    assert base_type not in _closure_types(closures)
    # 4.x: an F82-tint metal; 3.x: the Fresnel-blended specular of f0 = base.
    metal_type = C.PHOS_CLOSURE_METAL if v4 else C.PHOS_CLOSURE_REFLECTION_FRESNEL
    spec = [c for c in closures if c.type == metal_type]
    assert spec and tuple(spec[0].specular_color) == pytest.approx((0.9, 0.6, 0.3), abs=1e-3)

    glass = pt.node_material("T", "ShaderNodeBsdfPrincipled",
                             {"Transmission": 1.0, "Base Color": (0.81, 0.49, 0.25)})
    closures = closures_of(scene, glass)[0]
    types = _closure_types(closures)
    assert C.PHOS_CLOSURE_GLASS in types
    assert base_type not in types
    # Each refraction is tinted by the base colour (3.x) or its square root (4.x).
    tint = next(c for c in closures if c.type == C.PHOS_CLOSURE_GLASS).transmission_tint
    expected = (0.9, 0.7, 0.5) if pt.BLENDER_4 else (0.81, 0.49, 0.25)
    assert tuple(tint) == pytest.approx(expected, abs=1e-6)


# Distributions of this Blender's nodes → (roughness Phos uses or None for the
# node's own, warned?). SHARP (3.x) is GGX roughness 0.
_DISTRIBUTIONS = {
    "SHARP": (0.0, False),
    "GGX": (None, False),
    "MULTI_GGX": (None, not pt.BLENDER_4),  # GGX with its energy compensation; 3.x: noted (a random walk there)
    "BECKMANN": (None, False),
    "ASHIKHMIN_SHIRLEY": (None, False),
}


@pytest.mark.parametrize("node_type", ["ShaderNodeBsdfGlossy", "ShaderNodeBsdfGlass",
                                       "ShaderNodeBsdfRefraction"])
def test_distributions(node_type, scene):
    """Every distribution this Blender offers maps to the core's (SHARP: GGX
    of roughness 0; Beckmann and Ashikhmin-Shirley their own, with the Smith
    G of the version); only those that render differently in Cycles are
    warned about, once, by their UI name."""
    from phos import core as C
    probe = bpy.data.materials.new("probe")
    pt.use_nodes(probe)
    items = probe.node_tree.nodes.new(node_type).bl_rna.properties["distribution"].enum_items
    assert {i.identifier for i in items} <= set(_DISTRIBUTIONS), "a distribution the add-on does not know"
    assert ("SHARP" in items) == (not pt.BLENDER_4)
    for item in items:
        roughness, warned = _DISTRIBUTIONS[item.identifier]
        mat = pt.node_material("D " + item.identifier, node_type, {"Roughness": 0.25},
                               {"distribution": item.identifier})
        closures, warnings = closures_of(scene, mat)
        assert len(closures) == 1 and closures[0].type != C.PHOS_CLOSURE_DIFFUSE, item.identifier
        expected = 0.25 if roughness is None else roughness
        assert closures[0].roughness == pytest.approx(expected), item.identifier
        multiscatter = item.identifier == "MULTI_GGX" and node_type != "ShaderNodeBsdfRefraction"
        assert (closures[0].microfacet == C.PHOS_MICROFACET_GGX_MULTISCATTER) == multiscatter, item.identifier
        beckmann = C.PHOS_MICROFACET_BECKMANN if pt.BLENDER_4 else C.PHOS_MICROFACET_BECKMANN_SEPARABLE
        assert (closures[0].microfacet == beckmann) == (item.identifier == "BECKMANN"), item.identifier
        assert ((closures[0].microfacet == C.PHOS_MICROFACET_ASHIKHMIN_SHIRLEY)
                == (item.identifier == "ASHIKHMIN_SHIRLEY")), item.identifier
        if warned:
            assert len(warnings) == 1 and item.name in warnings[0], (item.identifier, warnings)
        else:
            assert not warnings, (item.identifier, warnings)


@pytest.mark.parametrize("node_type", ["ShaderNodeBsdfGlossy", "ShaderNodeBsdfGlass"])
def test_ggx_roughness_zero_is_sharp(node_type, scene):
    """The 4.x way to make a sharp BSDF (GGX, roughness 0) reaches the core as
    roughness 0, which the core renders as a perfect mirror/refraction
    (alpha = roughness² < 1e-4); the same on 3.x, where SHARP also exists."""
    for dist in ("GGX", "MULTI_GGX") if pt.BLENDER_4 else ("GGX",):
        mat = pt.node_material("Sharp " + dist, node_type, {"Roughness": 0.0}, {"distribution": dist})
        closures, warnings = closures_of(scene, mat)
        assert [c.roughness for c in closures] == [0.0] and not warnings, (dist, warnings)
        assert closures[0].to_desc().roughness == 0.0


BLENDER_5 = bpy.app.version >= (5, 0, 0)
BLENDER_4 = bpy.app.version >= (4, 0, 0)


def test_material_without_nodes(scene):
    """Before 5.0, a material without nodes renders as a diffuse of its
    colour; 5.0 removed use_nodes (setting it False does nothing), and
    Cycles renders the node tree every new material has."""
    from phos import core as C
    mat = bpy.data.materials.new("Plain")
    mat.diffuse_color = (0.2, 0.4, 0.6, 1.0)
    if BLENDER_5:
        closures, warnings = closures_of(scene, mat)   # the default Principled BSDF
        assert C.PHOS_CLOSURE_DIFFUSE in _closure_types(closures)
        diffuse = next(c for c in closures if c.type == C.PHOS_CLOSURE_DIFFUSE)
        assert tuple(diffuse.weight) == pytest.approx((0.8, 0.8, 0.8), abs=1e-3)
        return
    mat.use_nodes = False
    closures, warnings = closures_of(scene, mat)
    assert _closure_types(closures) == [C.PHOS_CLOSURE_DIFFUSE]
    assert tuple(closures[0].weight) == pytest.approx((0.2, 0.4, 0.6))
    assert not warnings


@pytest.mark.parametrize("use_nodes", [True, False], ids=["nodes", "no_nodes"])
def test_world_background(use_nodes, scene, tmp_path):
    """The camera sees the world colour × strength (nodes) or world.color
    (no nodes, before 5.0; from 5.0 the node tree is always used)."""
    pt.add_camera(scene)
    world = pt.set_world(scene, (0.3, 0.4, 0.5), strength=2.0)
    if not BLENDER_5:
        world.use_nodes = use_nodes
    expected = (0.6, 0.8, 1.0) if use_nodes or BLENDER_5 else (0.3, 0.4, 0.5)
    pt.configure_output(scene, 8, 8)
    pt.configure_phos(scene, 2, max_bounces=0)
    pt.configure_cycles(scene, 2, max_bounces=0)
    p = pt.render_array(scene, tmp_path, "PHOS")[..., :3]
    c = pt.render_array(scene, tmp_path, "CYCLES")[..., :3]
    assert np.allclose(c, expected, atol=1e-5), "test setup: Cycles %s" % c[0, 0]
    assert np.allclose(p, expected, atol=1e-5), "Phos %s, expected %s" % (p[0, 0], expected)


@pytest.mark.parametrize("projection", ["EQUIRECTANGULAR", "MIRROR_BALL"])
def test_environment_texture_background(projection, scene, tmp_path):
    """The camera sees an HDR world as Cycles shows it, pixel by pixel: the
    image's direction convention, a Mapping rotation about Z and X, both
    projections (one of Blender's studio HDRs; no bounces)."""
    pt.add_camera(scene, location=(0, 0, 0), target=(1.0, -0.4, 0.3), lens=20.0)
    world = pt.set_world_hdr(scene, "forest", strength=1.5, rotation_z=math.radians(37.0), projection=projection)
    mapping = [n for n in world.node_tree.nodes if n.bl_idname == "ShaderNodeMapping"][0]
    mapping.inputs["Rotation"].default_value[0] = math.radians(10.0)
    pt.configure_output(scene, 48, 32)
    p, c = [], []
    for seed in (1, 2):
        pt.configure_phos(scene, 64, max_bounces=0, seed=seed)
        pt.configure_cycles(scene, 64, max_bounces=0, seed=seed)
        p.append(pt.render_array(scene, tmp_path, "PHOS", name="p%d" % seed)[..., :3])
        c.append(pt.render_array(scene, tmp_path, "CYCLES", name="c%d" % seed)[..., :3])
    # Against the pixels' own anti-aliasing noise: Cycles against itself.
    between = np.mean([np.abs(p[k] - c[k]).mean() for k in (0, 1)])
    noise = np.abs(c[0] - c[1]).mean()
    assert between < 1.5 * noise + 0.002 * c[0].mean(), (
        "Phos differs from Cycles by %.2g per pixel on the %s background, Cycles from itself by %.2g"
        % (between, projection, noise))


def test_portal_exports_its_opening_facing_in(scene):
    """An area light marked as a portal is a PORTAL of the lamp's shape,
    facing where the lamp points (into the room), and no light."""
    import parity_scenes
    from phos import core
    from phos.export import light as lexp
    from phos.export.context import ExportContext
    parity_scenes.LIGHT_SCENES["portal_interior"](scene)
    bpy.context.view_layer.update()
    ob = bpy.data.objects["Window"]
    with core.Scene() as core_scene:
        ctx = ExportContext(scene, core_scene)
        added = []
        real = ctx.core.add_light
        ctx.core.add_light = lambda desc: added.append(desc) or real(desc)
        lexp.add_light(ob, ob.matrix_world, ctx)
    assert len(added) == 1 and added[0].type == core.PHOS_LIGHT_PORTAL
    d = added[0]
    assert tuple(d.direction) == pytest.approx((0.0, -1.0, 0.0), abs=1e-6)
    assert np.linalg.norm(d.axis_u) == pytest.approx(1.6) and np.linalg.norm(d.axis_v) == pytest.approx(1.0)
    assert ctx.stats["portals"] == 1 and ctx.stats["lights"] == 0


def test_non_finite_hdr_pixels_count_as_black(scene):
    """NaN and infinite pixels of an HDR are black, with one warning that
    counts them, and the core accepts the world."""
    from phos import core
    from phos.export import world as wexp
    from phos.export.context import ExportContext
    img = bpy.data.images.new("Broken HDR", 16, 8, float_buffer=True)
    px = np.full((8, 16, 4), 0.5, np.float32)
    px[2, 3, :3] = np.nan
    px[5, 9, 0] = np.inf
    px[6, 1, 1] = -np.inf
    img.pixels.foreach_set(px.ravel())
    world = pt.set_world(scene, (0.0, 0.0, 0.0))
    env = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    env.image = img
    world.node_tree.links.new(env.outputs["Color"], world.node_tree.nodes["Background"].inputs["Color"])
    with core.Scene() as core_scene:
        ctx = ExportContext(scene, core_scene)
        wexp.export_world(ctx)
        assert ctx.world_emits
    ours = [w for w in ctx.warnings if "NaN or infinite" in w]
    assert len(ours) == 1 and "3 pixels" in ours[0], ctx.warnings


def test_mesh_without_uv_map_samples_texture_at_origin(scene, tmp_path):
    """Cycles reads UV (0, 0) on a mesh without a UV map: the texture's corner colour."""
    pt.add_camera(scene, location=(0, -4, 0), target=(0, 0, 0))
    pt.set_world(scene, (0, 0, 0))
    img = pt.checker_image(os.path.join(str(tmp_path), "chk.png"), size=16, squares=4,
                           colors=((1.0, 0.0, 0.0), (0.0, 0.0, 1.0)))
    mat, nt, out = pt.empty_material("Tex Emission")
    em = nt.nodes.new("ShaderNodeEmission")
    tex = nt.nodes.new("ShaderNodeTexImage")
    tex.image = img
    tex.interpolation = "Closest"
    nt.links.new(tex.outputs["Color"], em.inputs["Color"])
    nt.links.new(em.outputs[0], out.inputs["Surface"])
    pt.add_sphere(scene, "NoUV", radius=1.0, material=mat, uv=False)
    assert not bpy.data.objects["NoUV"].data.uv_layers
    pt.configure_output(scene, 32, 32)
    pt.configure_phos(scene, 8, max_bounces=0)
    pt.configure_cycles(scene, 8, max_bounces=0)
    p = pt.render_array(scene, tmp_path, "PHOS")[12:20, 12:20, :3].mean(axis=(0, 1))
    c = pt.render_array(scene, tmp_path, "CYCLES")[12:20, 12:20, :3].mean(axis=(0, 1))
    assert tuple(c) == pytest.approx((1.0, 0.0, 0.0), abs=0.02), "test setup: Cycles reference"
    assert tuple(p) == pytest.approx(tuple(c), abs=0.05), (
        "Phos %s, Cycles %s: a mesh without UV map must read UV (0,0)" % (p, c))


# --------------------------------------------------------------- warnings

UNSUPPORTED_SCRIPT = r'''
import bpy, phostest as pt
sc = pt.reset_file()
assert pt.addon_enabled()
pt.add_camera(sc)
mat = pt.node_material("Cartoon Paint", "ShaderNodeBsdfToon", {"Color": (0.2, 0.6, 0.2)})
mat.node_tree.nodes["Toon BSDF"].name = "My Toon Node"
pt.add_sphere(sc, "A", material=mat, location=(-0.6, 0, 0.5))
pt.add_sphere(sc, "B", material=mat, location=(0.6, 0, 0.5))   # same material twice
pt.add_plane(sc, "Floor", size=4, material=pt.diffuse("Fine", (0.5, 0.5, 0.5)))
pt.add_light(sc, "SUN", 3.0, location=(1, -1, 3))
pt.configure_output(sc, 16, 16)
pt.configure_phos(sc, 2)
sc.render.engine = "PHOS"
bpy.ops.render.render()
print("RENDER DONE")
'''


def test_unsupported_node_warns_once_in_export(scene):
    pt.add_camera(scene)
    mat = pt.node_material("Cartoon Paint", "ShaderNodeBsdfToon", {"Color": (0.2, 0.6, 0.2)})
    pt.add_sphere(scene, "A", material=mat, location=(-0.6, 0, 0))
    pt.add_sphere(scene, "B", material=mat, location=(0.6, 0, 0))
    pt.add_light(scene, "SUN", 3.0)  # else the scene's lack of light is a warning too
    warnings = export(scene).warnings
    assert len(warnings) == 1, warnings
    assert "Cartoon Paint" in warnings[0] and "Toon BSDF" in warnings[0]


def test_unsupported_node_report(tmp_path):
    """In a real render the warning reaches Blender's report exactly once."""
    rc, out = pt.run_script(UNSUPPORTED_SCRIPT, tmp_path)
    assert rc == 0, out[-3000:]
    assert "RENDER DONE" in out
    warning_lines = [line for line in out.splitlines() if line.startswith("Warning:")]
    ours = [line for line in warning_lines if "Cartoon Paint" in line]
    assert len(ours) == 1, "warnings naming the material: %s" % ours
    assert "My Toon Node" in ours[0], ours[0]
    assert not [line for line in out.splitlines() if line.startswith("Error:")], out[-3000:]


@pytest.mark.parametrize("node_type, inputs", [
    ("ShaderNodeBsdfToon", {"Color": (0.2, 0.6, 0.2)}),
    ("ShaderNodeSubsurfaceScattering", {"Color": (0.7, 0.3, 0.2)}),
], ids=["toon", "subsurface"])
def test_approximated_shader_nodes(node_type, inputs, scene):
    """Toon BSDF and Subsurface Scattering render as a diffuse of their
    colour, with one warning naming the material and the node."""
    from phos import core as C
    mat = pt.node_material("Approx", node_type, inputs)
    closures, warnings = closures_of(scene, mat)
    assert _closure_types(closures) == [C.PHOS_CLOSURE_DIFFUSE]
    assert tuple(closures[0].weight) == pytest.approx(inputs["Color"])
    ours = [w for w in warnings if "Approx" in w]
    assert len(ours) == 1 and "diffuse" in ours[0], warnings
    node_name = mat.node_tree.nodes[1].name
    assert node_name in ours[0], ours


def test_principled_subsurface_warns_once(scene):
    """Principled subsurface: its share renders as a diffuse, one warning."""
    from phos import core as C
    key = "Subsurface Weight" if BLENDER_4 else "Subsurface"
    mat = pt.node_material("Skin", "ShaderNodeBsdfPrincipled", {key: 0.5, "Base Color": (0.8, 0.5, 0.4)})
    closures, warnings = closures_of(scene, mat)
    diffuse_types = {C.PHOS_CLOSURE_DIFFUSE, C.PHOS_CLOSURE_PRINCIPLED_DIFFUSE, C.PHOS_CLOSURE_OREN_NAYAR}
    assert diffuse_types & set(_closure_types(closures)), _closure_types(closures)
    ours = [w for w in warnings if "Skin" in w]
    assert len(ours) == 1 and "Subsurface" in ours[0] and "diffuse" in ours[0], warnings


def test_translucent_and_holdout_closures(scene):
    """Translucent BSDF → TRANSLUCENT of its colour; a Holdout mixed in →
    HOLDOUT of the mix weight; neither warns."""
    from phos import core as C
    mat, nt, out = pt.empty_material("Leaf")
    mix = nt.nodes.new("ShaderNodeMixShader")
    mix.inputs[0].default_value = 0.3
    hold = nt.nodes.new("ShaderNodeHoldout")
    tr = nt.nodes.new("ShaderNodeBsdfTranslucent")
    tr.inputs["Color"].default_value = (0.2, 0.7, 0.1, 1.0)
    nt.links.new(tr.outputs[0], mix.inputs[1])
    nt.links.new(hold.outputs[0], mix.inputs[2])
    nt.links.new(mix.outputs[0], out.inputs["Surface"])
    closures, warnings = closures_of(scene, mat)
    assert _closure_types(closures) == [C.PHOS_CLOSURE_TRANSLUCENT, C.PHOS_CLOSURE_HOLDOUT]
    assert tuple(closures[0].weight) == pytest.approx((0.14, 0.49, 0.07))
    assert tuple(closures[1].weight) == pytest.approx((0.3, 0.3, 0.3))
    assert not [w for w in warnings if "Leaf" in w], warnings


# ------------------------------------------------------------ shader programs

def _chain_material(name, length, textured=True):
    """Diffuse whose colour is a chain of `length` Math nodes, fed by a
    texture coordinate (varying) or by a constant (folds away)."""
    mat, nt, out = pt.empty_material(name)
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    nt.links.new(bsdf.outputs[0], out.inputs["Surface"])
    value = nt.nodes.new("ShaderNodeValue")
    value.outputs[0].default_value = 0.3
    src = value.outputs[0]
    if textured:
        sep = nt.nodes.new("ShaderNodeSeparateXYZ")
        nt.links.new(nt.nodes.new("ShaderNodeTexCoord").outputs["UV"], sep.inputs[0])
        src = sep.outputs["X"]
    for k in range(length):
        m = nt.nodes.new("ShaderNodeMath")
        m.operation = ("ADD", "MULTIPLY", "SINE")[k % 3]
        m.inputs[1].default_value = 0.5 + 0.01 * k
        nt.links.new(src, m.inputs[0])
        src = m.outputs[0]
    nt.links.new(src, bsdf.inputs["Color"])
    return mat


def test_constant_node_chain_folds(scene):
    """Value nodes of constants compile to instructions of constants only,
    which the core folds into the closure's colour when the material is
    added (tests/c/test_shader_program.c shows the folding): nothing reads
    the shading point."""
    from phos import core
    from phos.export import material as mexp
    from phos.export.context import ExportContext
    mat = _chain_material("Folded", 12, textured=False)
    with core.Scene() as core_scene:
        ctx = ExportContext(scene, core_scene)
        closures, program = mexp.compile_material(mat, ctx)
    reads_point = {core.PHOS_OP_TEXTURE_COORDINATE, core.PHOS_OP_GEOMETRY, core.PHOS_OP_OBJECT_INFO,
                   core.PHOS_OP_FRESNEL, core.PHOS_OP_LAYER_WEIGHT, core.PHOS_OP_LIGHT_PATH,
                   core.PHOS_OP_BUMP_OFFSET, core.PHOS_OP_BUMP, core.PHOS_OP_NORMAL_MAP,
                   core.PHOS_OP_VECTOR_TRANSFORM}
    ops = [ins[0] for ins in program.instructions]
    assert len(ops) >= 12 and not set(ops) & reads_point, ops
    assert not ctx.warnings, ctx.warnings


def test_program_over_the_limit_warns(scene, monkeypatch):
    """A program beyond the core's limits is one warning naming the
    material; it renders without it."""
    from phos import core
    monkeypatch.setattr(core, "PHOS_SHADER_MAX_INSTRUCTIONS", 50)
    closures, warnings = closures_of(scene, _chain_material("Huge Graph", 80))
    assert any("Huge Graph" in w and "exceeds the core's limits" in w for w in warnings), warnings


def test_one_program_per_material(scene, tmp_path):
    """A thousand objects of one textured material share its program: the
    material is exported once."""
    mat = _chain_material("Shared", 6)
    for i in range(1000):
        pt.add_cube(scene, "Cube %d" % i, size=0.05, location=(i % 32 * 0.1, i // 32 * 0.1, 0.0), material=mat)
    ortho_top_camera(scene)
    ctx = export(scene)
    assert ctx.stats["instances"] == 1000
    assert ctx.stats["materials"] == 1


def _attribute_material(name, attribute):
    mat, nt, out = pt.empty_material(name)
    emission = nt.nodes.new("ShaderNodeEmission")
    nt.links.new(emission.outputs[0], out.inputs["Surface"])
    if attribute is not None:
        attr = nt.nodes.new("ShaderNodeAttribute")
        attr.attribute_name = attribute
        nt.links.new(attr.outputs["Color"], emission.inputs["Color"])
    return mat


def test_attributes_exported_only_when_read(scene, monkeypatch):
    """A mesh exports the attributes its materials read, and only those: the
    same mesh data under a material that reads none exports none. A name
    the mesh lacks is one warning naming the object and the attribute (it
    renders 0, as in Cycles: test_shader_nodes.py's "attribute missing")."""
    from phos import core
    exported = {}
    original = core.Scene.add_mesh

    def spy(self, *args, **kwargs):
        mesh_id = original(self, *args, **kwargs)
        exported[mesh_id] = [(a[0], a[1]) for a in kwargs.get("attributes", ())]
        return mesh_id

    monkeypatch.setattr(core.Scene, "add_mesh", spy)
    for i, attribute in enumerate(("Paint", None, "Nope")):
        ob = pt.add_plane(scene, "Plane %d" % i, size=1.0, location=(1.2 * i, 0.0, 0.0),
                          material=_attribute_material("Reads %s" % attribute, attribute))
        ob.data.color_attributes.new("Paint", 'FLOAT_COLOR', 'POINT')
        ob.data.attributes.new("Unread", 'FLOAT', 'FACE')
    ortho_top_camera(scene)
    ctx = export(scene)
    assert sorted(len(a) for a in exported.values()) == [0, 0, 1], exported
    (only,) = [a for a in exported.values() if a]
    assert only == [(ctx.attribute_ids[("name", "Paint")], core.PHOS_ATTRIBUTE_COLOR)]
    assert set(ctx.attribute_ids) == {("name", "Paint"), ("name", "Nope")}
    assert any("Plane 2" in w and "'Nope'" in w for w in ctx.warnings), ctx.warnings
    assert not any("Plane 0" in w or "Plane 1" in w for w in ctx.warnings), ctx.warnings


def test_object_attributes_split_shared_meshes(scene):
    """An Object attribute is a constant of each object, exported as a mesh
    attribute: objects sharing mesh data share one core mesh while their
    values agree, and get one each where they differ; a material that reads
    no Object attribute keeps the data shared whatever the properties."""
    mat = _attribute_material("Reads tint", None)
    attr = mat.node_tree.nodes.new("ShaderNodeAttribute")
    attr.attribute_type = 'OBJECT'
    attr.attribute_name = "tint"
    mat.node_tree.links.new(attr.outputs["Color"], mat.node_tree.nodes["Emission"].inputs["Color"])
    first = pt.add_plane(scene, "First", size=0.5, material=mat)
    for i, tint in enumerate((0.25, 0.25, 0.75)):
        ob = pt.link(scene, bpy.data.objects.new("Copy %d" % i, first.data))
        ob.location = (0.6 * (i + 1), 0.0, 0.0)
        ob["tint"] = tint
    first["tint"] = 0.25
    ortho_top_camera(scene)
    ctx = export(scene)
    assert ctx.stats["instances"] == 4 and ctx.stats["meshes"] == 2, ctx.stats


def test_shared_mesh_with_object_materials_reading_other_attributes(scene, monkeypatch):
    """Objects sharing mesh data whose object-linked materials read different
    attributes get a core mesh each, with the attribute its material reads;
    with the same material they share one."""
    from phos import core
    exported = []
    original = core.Scene.add_mesh

    def spy(self, *args, **kwargs):
        exported.append(sorted(a[0] for a in kwargs.get("attributes", ())))
        return original(self, *args, **kwargs)

    monkeypatch.setattr(core.Scene, "add_mesh", spy)
    first = pt.add_plane(scene, "First", size=0.5, material=_attribute_material("Reads A", "A"))
    first.data.attributes.new("A", 'FLOAT', 'POINT')
    first.data.attributes.new("B", 'FLOAT', 'POINT')
    for i, name in enumerate(("B", "A")):
        ob = pt.link(scene, bpy.data.objects.new("Copy %d" % i, first.data))
        ob.location = (0.6 * (i + 1), 0.0, 0.0)
        ob.material_slots[0].link = 'OBJECT'
        ob.material_slots[0].material = bpy.data.materials["Reads %s" % name] if name == "A" else \
            _attribute_material("Reads B", "B")
    ortho_top_camera(scene)
    ctx = export(scene)
    ids = ctx.attribute_ids
    assert ctx.stats["instances"] == 3
    assert sorted(exported) == sorted([[ids[("name", "A")]], [ids[("name", "B")]]]), exported


def test_normal_correction_per_version(scene):
    """Each closure's normal correction is the running Blender's (phos.h,
    docs/algorithms.md §8.1): before 4.0 every closure with a normal, by the
    two-root rule; from 4.0 the specular ones only, by the one-root rule,
    and none when the material's Bump Map Correction is off."""
    from phos import core
    from phos.export import material as mexp
    from phos.export.context import ExportContext
    mat = bpy.data.materials.new("Correction")
    with core.Scene() as core_scene:
        ctx = ExportContext(scene, core_scene)
        rule = {kind: mexp.normal_correction(kind, ctx, mat)
                for kind in (core.PHOS_CLOSURE_DIFFUSE, core.PHOS_CLOSURE_SHEEN, core.PHOS_CLOSURE_REFLECTION,
                             core.PHOS_CLOSURE_GLASS, core.PHOS_CLOSURE_TRANSLUCENT, core.PHOS_CLOSURE_EMISSION,
                             core.PHOS_CLOSURE_TRANSPARENT)}
        free = {core.PHOS_CLOSURE_EMISSION: 0, core.PHOS_CLOSURE_TRANSPARENT: 0}
        if not BLENDER_4:
            both = core.PHOS_NORMAL_CORRECTION_BOTH_ROOTS
            assert rule == {core.PHOS_CLOSURE_DIFFUSE: both, core.PHOS_CLOSURE_SHEEN: both,
                            core.PHOS_CLOSURE_REFLECTION: both, core.PHOS_CLOSURE_GLASS: both,
                            core.PHOS_CLOSURE_TRANSLUCENT: both, **free}
            return
        one = core.PHOS_NORMAL_CORRECTION_ONE_ROOT
        assert rule == {core.PHOS_CLOSURE_DIFFUSE: 0, core.PHOS_CLOSURE_SHEEN: 0, core.PHOS_CLOSURE_REFLECTION: one,
                        core.PHOS_CLOSURE_GLASS: one, core.PHOS_CLOSURE_TRANSLUCENT: one, **free}
        mat.cycles.use_bump_map_correction = False
        assert mexp.normal_correction(core.PHOS_CLOSURE_REFLECTION, ctx, mat) == 0


def test_converted_images_kept_between_exports(scene, tmp_path):
    """An image read from a file is converted once and reused by the next
    export (the next F12, without Persistent Data) while its file, its
    colour settings and its pixels in Blender are unchanged; a touched
    file, another colour space or an edited image is converted again. The
    image is the same either way."""
    import os
    import shutil
    from phos.export import image as image_cache
    cache = image_cache.CONVERTED
    cache.clear()
    hdr = str(tmp_path / "sky.exr")
    shutil.copy(pt.studio_hdr("forest"), hdr)
    pt.add_plane(scene, "Floor", size=4.0, material=pt.diffuse("Floor", (0.5, 0.5, 0.5)))
    pt.add_camera(scene, location=(0, -4, 2), target=(0, 0, 0))
    pt.set_world_hdr(scene)
    env = next(n for n in scene.world.node_tree.nodes if n.type == 'TEX_ENVIRONMENT')
    env.image = bpy.data.images.load(hdr)
    pt.configure_output(scene, 16, 12)
    pt.configure_phos(scene, 2)
    scene.render.engine = "PHOS"

    def render():
        before = cache.conversions
        image = pt.render_array(scene, tmp_path)
        return image, cache.conversions - before

    first, converted = render()
    assert converted == 1
    again, converted = render()
    assert converted == 0, "an unchanged image file was converted again"
    assert np.array_equal(first, again)

    stat = os.stat(hdr)
    os.utime(hdr, ns=(stat.st_atime_ns, stat.st_mtime_ns + 10**9))
    touched, converted = render()
    assert converted == 1, "a touched file was not converted again"
    assert np.array_equal(touched, first)

    env.image.colorspace_settings.name = "Non-Color"
    _, converted = render()
    assert converted == 1, "another colour space reused the old conversion"

    pixels = np.array(env.image.pixels[:], dtype=np.float32)
    env.image.pixels.foreach_set(pixels * 0.5)  # edited in Blender: is_dirty
    dimmer, converted = render()
    assert converted == 1 and dimmer.mean() < touched.mean()
    _, converted = render()
    assert converted == 1, "an edited image must be read every time"
