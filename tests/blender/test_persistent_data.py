# SPDX-License-Identifier: GPL-3.0-or-later
"""Persistent Data (Render Properties → Performance): Blender keeps the
engine between F12 renders, and Phos keeps its committed scene. An
unchanged scene, a camera move, and changes to lights and materials render
without a new export (the latter through the core's scene updates); other
changes export afresh. Either way the image is the one a render without
Persistent Data gives, bit for bit (the core is deterministic, and a scene
changed in place is the scene built afresh: tests/c/test_scene_updates.c)."""

import bpy
import numpy as np
import pytest

import exrread
import phostest as pt


def _render(scene, tmp_path, name=None):
    """F12 with write_still, read back without a new datablock: loading the
    file through bpy.data.images (phostest.render_array) adds an Image, and
    Blender 4.x then tags every object of the scene as changed at the next
    render (a relations update), which is a change Phos must take as one."""
    _render.count = getattr(_render, "count", 0) + 1
    path = str(tmp_path / ("%s.exr" % (name or "render_%d" % _render.count)))
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True, scene=scene.name)
    channels = exrread.read_channels(path)
    return np.stack([channels[c] for c in "RGBA"], axis=-1)


@pytest.fixture
def lit_scene(scene):
    pt.add_plane(scene, "Floor", size=6.0, material=pt.diffuse("Floor", (0.7, 0.7, 0.7)))
    pt.add_cube(scene, "Box", size=1.0, location=(0, 0, 0.5), material=pt.diffuse("Box", (0.8, 0.3, 0.2)))
    pt.add_light(scene, "POINT", 500.0, location=(2, -2, 3), name="Lamp")
    pt.add_camera(scene, location=(0, -5, 2), target=(0, 0, 0.5))
    pt.set_world(scene, (0.05, 0.05, 0.05))
    pt.configure_output(scene, 32, 24)
    pt.configure_phos(scene, 4, max_bounces=4, seed=3)
    scene.render.engine = "PHOS"
    pt.set_single_exr(scene.render.image_settings)
    scene.render.use_file_extension = False
    return scene


class _ExportCounter:
    """Counts the add-on's exports (phos.export.export_scene calls)."""

    def __init__(self):
        from phos import export
        self.module, self.count = export, 0

    def __enter__(self):
        original = self.original = self.module.export_scene

        def counted(*args, **kwargs):
            self.count += 1
            return original(*args, **kwargs)
        self.module.export_scene = counted
        return self

    def __exit__(self, *exc):
        self.module.export_scene = self.original
        return False


def _fresh(scene, tmp_path, name):
    """The image of a render without Persistent Data (exported afresh)."""
    scene.render.use_persistent_data = False
    image = _render(scene, tmp_path, name)
    scene.render.use_persistent_data = True
    return image


def test_persistent_data_reuses_the_scene(lit_scene, tmp_path):
    scene = lit_scene
    scene.render.use_persistent_data = True
    with _ExportCounter() as exports:
        first = _render(scene, tmp_path, name="first")
        again = _render(scene, tmp_path, name="again")
        assert exports.count == 1, "an unchanged scene was exported again"
        assert np.array_equal(first, again)

        # The camera alone: no export, the image of a fresh render.
        scene.camera.location.x += 0.4
        moved = _render(scene, tmp_path, name="camera_moved")
        assert exports.count == 1, "a camera move exported the scene again"
        assert not np.array_equal(moved, first)
        assert np.array_equal(moved, _fresh(scene, tmp_path, "camera_moved_fresh"))

        # A light's power, then its place, a material's colour and the
        # world's strength: changed in place (phos_scene_update_light,
        # _material, phos_scene_set_world), no export. Blender
        # 5.x tags the objects using an edited material for geometry as well,
        # which a modifier's edit also does: their meshes are replaced too.
        material_exports = 0
        lamp = bpy.data.objects["Lamp"]
        for name, change in (("energy", lambda: setattr(lamp.data, "energy", 900.0)),
                             ("light_moved", lambda: setattr(lamp, "location", (-2.0, -2.0, 3.0))),
                             ("material", lambda: pt.setup_node(
                                 bpy.data.materials["Box"].node_tree.nodes["Diffuse BSDF"],
                                 inputs={"Color": (0.2, 0.8, 0.3, 1.0)})),
                             ("world", lambda: setattr(
                                 scene.world.node_tree.nodes["Background"].inputs["Strength"],
                                 "default_value", 6.0))):
            before = _render(scene, tmp_path, name=name + "_before")
            count = exports.count
            change()
            changed = _render(scene, tmp_path, name=name)
            expected = count + (material_exports if name == "material" else 0)
            assert exports.count == expected, "%s: %d exports, expected %d" % (name, exports.count - count,
                                                                             expected - count)
            assert not np.array_equal(changed, before), "%s: the change did not reach the image" % name
            assert np.array_equal(changed, _fresh(scene, tmp_path, name + "_fresh")), name

        # A moved object and a mesh edit: changed in place
        # (phos_scene_update_instance, _mesh); a hidden object: exported
        # afresh. Blender 3.4 tags the object for geometry on a move too,
        # which replaces its mesh as well; still no export.
        box = bpy.data.objects["Box"]
        for name, change, expected in (
                ("moved", lambda: setattr(box, "location", (0.5, 0.2, 0.5)), 0),
                ("reshaped", lambda: box.data.vertices[0].co.__setitem__(2, 1.5), 0),
                ("hidden", lambda: setattr(box, "hide_render", True), 1)):
            before = _render(scene, tmp_path, name=name + "_before")
            count = exports.count
            change()
            box.data.update()
            changed = _render(scene, tmp_path, name=name)
            assert exports.count == count + expected, "%s: %d exports, expected %d" % (
                name, exports.count - count, expected)
            assert not np.array_equal(changed, before), "%s: the change did not reach the image" % name
            assert np.array_equal(changed, _fresh(scene, tmp_path, name + "_fresh")), name


def test_without_persistent_data_every_render_exports(lit_scene, tmp_path):
    scene = lit_scene
    scene.render.use_persistent_data = False
    with _ExportCounter() as exports:
        a = _render(scene, tmp_path, name="a")
        b = _render(scene, tmp_path, name="b")
    assert exports.count == 2
    assert np.array_equal(a, b)


def test_persistent_data_keeps_the_photon_maps(lit_scene, tmp_path):
    """A second F12 of an unchanged PHOTON scene reads the photon maps the
    first built (no photon stage in its plan) and renders the same image;
    a camera move (the world's photons are aimed at the view) and a light
    edit trace them again, and render what a fresh render does."""
    from phos import core, engine
    scene = lit_scene
    scene.phos.integrator = "PHOTON"
    scene.phos.global_photons, scene.phos.caustic_photons = 4000, 0
    scene.phos.ic_rays = 64
    scene.render.use_persistent_data = True

    def traced():
        return core.PHOS_STAGE_TRACING_PHOTONS in engine.last_render_seconds

    first = _render(scene, tmp_path, name="photons_first")
    assert traced()
    again = _render(scene, tmp_path, name="photons_again")
    assert not traced(), "an unchanged scene traced its photon maps again"
    assert np.array_equal(first, again)

    scene.camera.location.x += 0.4
    moved = _render(scene, tmp_path, name="photons_moved")
    assert traced(), "maps aimed at the old view were read by a final render"
    assert np.array_equal(moved, _fresh(scene, tmp_path, "photons_moved_fresh"))

    _render(scene, tmp_path, name="photons_before_light")  # keeps maps again (the fresh render exported)
    bpy.data.objects["Lamp"].data.energy = 900.0
    lit = _render(scene, tmp_path, name="photons_light")
    assert traced(), "a light edit kept the old photon maps"
    assert np.array_equal(lit, _fresh(scene, tmp_path, "photons_light_fresh"))


def test_edits_in_place_only_where_they_stand_for_an_export(lit_scene, tmp_path):
    """An edit is applied in place only where the kept scene can take it:
    a modifier added to one of two objects sharing a mesh (their core mesh
    is shared), a moved object that a collection instance also shows, and
    a moved object whose place a material reads (Texture Coordinate's
    Object) each export afresh, to the image a fresh render gives."""
    scene = lit_scene
    scene.render.use_persistent_data = True
    box = bpy.data.objects["Box"]
    twin = bpy.data.objects.new("Twin", box.data)   # a linked duplicate
    twin.location = (-1.5, 0.5, 0.5)
    scene.collection.objects.link(twin)
    shown = pt.add_cube(scene, "Shown", size=0.4, location=(1.5, 0.5, 0.2),
                        material=bpy.data.materials["Box"])
    group = bpy.data.collections.new("Group")
    group.objects.link(shown)
    holder = bpy.data.objects.new("Holder", None)
    holder.instance_type, holder.instance_collection = 'COLLECTION', group
    holder.location = (0.0, 1.5, 0.0)
    scene.collection.objects.link(holder)
    floor = bpy.data.materials["Floor"]
    nodes, links = floor.node_tree.nodes, floor.node_tree.links
    coords, checker = nodes.new("ShaderNodeTexCoord"), nodes.new("ShaderNodeTexChecker")
    coords.object = holder
    links.new(coords.outputs["Object"], checker.inputs["Vector"])
    links.new(checker.outputs["Color"], nodes["Diffuse BSDF"].inputs["Color"])

    def modifier():
        twin.modifiers.new("Bevel", 'BEVEL').width = 0.1

    with _ExportCounter() as exports:
        for name, change in (("modifier", modifier),
                             ("instanced_moved", lambda: setattr(shown, "location", (1.5, 0.5, 0.6))),
                             ("referenced_moved", lambda: setattr(holder, "location", (0.4, 1.5, 0.0)))):
            before = _render(scene, tmp_path, name=name + "_before")
            count = exports.count
            change()
            changed = _render(scene, tmp_path, name=name)
            assert exports.count == count + 1, "%s: applied in place" % name
            assert not np.array_equal(changed, before), "%s: the change did not reach the image" % name
            assert np.array_equal(changed, _fresh(scene, tmp_path, name + "_fresh")), name


def test_environment_edits_in_place(lit_scene, tmp_path):
    """A world lit by an HDR (a world material with a program): its
    strength and rotation changed in place (the world material replaced,
    not added again), and the image a fresh render gives."""
    scene = lit_scene
    scene.render.use_persistent_data = True
    pt.set_world_hdr(scene, strength=0.5)
    nodes = scene.world.node_tree.nodes
    mapping = next(n for n in nodes if n.type == 'MAPPING')
    with _ExportCounter() as exports:
        _render(scene, tmp_path, name="hdr_first")
        for name, change in (("strength", lambda: setattr(nodes["Background"].inputs["Strength"],
                                                          "default_value", 1.5)),
                             ("rotation", lambda: setattr(mapping.inputs["Rotation"], "default_value",
                                                          (0.0, 0.0, 1.0)))):
            before = _render(scene, tmp_path, name="hdr_%s_before" % name)
            count = exports.count
            change()
            changed = _render(scene, tmp_path, name="hdr_" + name)
            assert exports.count == count, "%s: exported again" % name
            assert not np.array_equal(changed, before), "%s: the change did not reach the image" % name
            assert np.array_equal(changed, _fresh(scene, tmp_path, "hdr_%s_fresh" % name)), name
