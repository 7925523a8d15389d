#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes the seed corpus of tests/fuzz/fuzz_api.c into tests/fuzz/corpus/.

Each seed is a scene and render in the byte stream fuzz_api.c reads (its
reader: counts as bytes, numbers through take_float / take_u32), one per
kind of bad input the fuzzer must survive, plus valid scenes for every
integrator so that mutations start from renders that reach every stage.
Inputs that once crashed are among them as regress_* scenes. The seeds
are committed; run this again after changing the stream format (it
removes the corpus's old files first):

    python3 tests/fuzz/make_seeds.py
"""

import math
import os
import re
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
PHOS_H = os.path.join(HERE, "..", "..", "core", "include", "phos.h")

# take_float's table (selector bytes 0xE0 + index), and take_u32's (0x40 + index).
FLOAT_SPECIAL = ["nan", "inf", "-inf", "flt_max", "-flt_max", 1e30, -1e30, 1e-30, 1.4e-45, "-0", 1e6, -1e6,
                 1e-6, 65536.0, 3.14159265, 0.999999, 1.000001, 1e12, 4096.0, 0.01, 100.0, 1e-3, 2.0, 0.5,
                 1e38, -1e-38, 8192.0, 0.25, 1.5, 10.0, 1000.0]
U32_SPECIAL = [0, 1, 2, 3, 7, 8, 9, 15, 16, 17, 31, 32, 33, 63, 64, 65, 255, 256, 1000, 1023, 1024, 1025, 4096,
               8192, 8193, 10000, 10001, 20000, 65535, 65536, 65537, 1 << 20, 1 << 24, (1 << 24) + 1, 1 << 26,
               1 << 28, (1 << 28) + 1, 1 << 31, 2**32 - 2, 2**32 - 1]


def setting_names():
    """The render settings' field names in struct order, from phos.h's table."""
    text = open(PHOS_H).read()
    table = text[text.index("#define PHOS_RENDER_SETTINGS"):text.index("#define PHOS_SETTING_FIELD_")]
    return re.findall(r"(?:USER|HOST)\(\s*(?:uint32_t|float)\s*,\s*(\w+)", table)


SETTINGS = setting_names()


class Stream:
    def __init__(self):
        self.b = bytearray()

    def u8(self, v):
        self.b.append(v & 0xFF)

    def f(self, v):
        if isinstance(v, str):
            self.u8(0xE0 + FLOAT_SPECIAL.index(v))
            return
        sel = v * 8 + 112
        if sel == int(sel) and 0 <= sel < 0xE0:
            self.u8(int(sel))
        elif v in FLOAT_SPECIAL:
            self.u8(0xE0 + FLOAT_SPECIAL.index(v))
        else:
            self.u8(0xFF)
            self.b += struct.pack("<f", v)

    def fs(self, values):
        for v in values:
            self.f(v)

    def u32(self, v):
        if v < 0x40:
            self.u8(v)
        elif v in U32_SPECIAL:
            self.u8(0x40 + U32_SPECIAL.index(v))
        else:
            self.u8(0xC0)
            self.b += struct.pack("<I", v)


def closure(s, kind=0, weight=(0.75, 0.75, 0.75), roughness=0.5, ior=1.5, microfacet=0, film=0.0,
            layer_span=0, normal_correction=0):
    s.u8(kind)
    s.fs(weight)
    s.f(roughness)
    s.f(ior)
    s.u8(0)                    # no specular colour
    s.u8(0)                    # glass_fresnel
    s.u8(0)                    # no transmission tint
    s.f(-1.0)                  # transmission_roughness
    s.u8(microfacet)           # enum phos_microfacet
    s.u8(0)                    # no multiscatter Fresnel (white)
    s.u8(0)                    # no specular tint (white)
    s.f(film)                  # thin film thickness, nm
    s.f(1.33)                  # thin film IOR
    s.u8(layer_span)           # closures under this one
    s.u8(0)                    # layer weight 1
    s.u8(0)                    # no layer tint
    s.f(0.0)                   # layer tint weight
    s.u8(0)                    # isotropic
    s.u8(normal_correction)    # enum phos_normal_correction


def materials(s, mats, programs=None):
    s.u8(len(mats))
    for i, closures in enumerate(mats):
        s.u8(len(closures))
        for c in closures:
            closure(s, *c)
        s.u8(0)                # closures not NULL
        program = (programs or {}).get(i)
        if program is None:
            s.u8(0)            # no shader program
        else:
            s.u8(1)
            program(s)


NO = 0xFF  # no register


def noise_program(s):
    """A shader program: Texture Coordinate → Noise Texture (3D, normalized)
    → the closure's weight; registers 0-2 hold (0.25, 2, 0.5)."""
    s.u8(22 - 1)               # registers
    s.u8(3)                    # constants
    s.fs((0.25, 2.0, 0.5))
    s.u8(2)                    # instructions
    s.u8(32)                   # PHOS_OP_TEXTURE_COORDINATE
    s.u32(0), s.u32(0), s.u32(0), s.fs((0.0, 0.0, 0.0, 0.0))
    for _ in range(12):
        s.u8(NO)
    for k in range(5):
        s.u8(3 + 3 * k)        # generated, normal, uv, object, camera at 3..17
    s.u8(23)                   # PHOS_OP_TEX_NOISE
    s.u32(0), s.u32(3 | 8), s.u32(0), s.fs((0.0, 0.0, 0.0, 0.0))
    for reg in (3, 0, 1, 1, 2, 1, 0, 1, 0):
        s.u8(reg)              # vector, w, scale, detail, roughness, lacunarity, offset, gain, distortion
    for _ in range(3):
        s.u8(NO)
    for reg in (18, 19, NO, NO, NO):
        s.u8(reg)              # fac, colour
    s.u8(0)                    # instructions not NULL
    s.u8(0)                    # no table
    s.u8(1)                    # one binding: the colour sets closure 0's weight
    s.u8(0), s.u8(0), s.u8(19)


def mesh(s, positions, tris, slots=None, attributes=None):
    """attributes: (id, type, 12 floats per triangle) each (fuzz_api.c, take_attributes)."""
    s.u8(len(positions))
    s.u8(len(tris))
    for p in positions:
        s.fs(p)
    for t in tris:
        for i in t:
            s.u8(i)
    s.u8((4 if slots else 0) | (32 if attributes is not None else 0))
    if slots:
        for k in slots:
            s.u8(k)
    if attributes is not None:
        s.u8(len(attributes))
        for attr_id, kind, values in attributes:
            s.u8(attr_id)
            s.u8(kind)
            s.fs(values)


def instance(s, mesh_id, mats, transform=None):
    s.u8(mesh_id)
    s.u8(1 if transform else 0)
    if transform:
        s.fs(transform)
    s.u8(len(mats))
    for m in mats:
        s.u8(m)


def light(s, kind=2, color=(10, 10, 10), position=(0, 0, 1.5), direction=(0, 0, -1), u=(0.5, 0, 0),
          v=(0, 0.5, 0), radius=0.0, spot_angle=1.0, sun_angle=0.0):
    s.u8(kind)
    s.fs(color)
    s.fs(position)
    s.fs(direction)
    s.fs(u)
    s.fs(v)
    s.u8(0)                    # area shape
    s.f(radius)
    s.u8(0)                    # point shape
    s.f(spot_angle)
    s.f(0.25)                  # spot blend
    s.u8(0)                    # spot cosine
    s.f(sun_angle)
    s.u8(0)                    # camera visible


# The camera looks down −Z from z = 5 (identity transform, shifted up).
CAMERA_TRANSFORM = (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 5)
BOX = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0), (-1, -1, 2), (1, -1, 2), (1, 1, 2), (-1, 1, 2)]
BOX_TRIS = [(0, 1, 2), (0, 2, 3), (4, 6, 5), (4, 7, 6), (0, 4, 5), (0, 5, 1), (1, 5, 6), (1, 6, 2),
            (2, 6, 7), (2, 7, 3), (3, 7, 4), (3, 4, 0)]


def world_and_camera(s, world=None, camera=True, world_material=0xFF):
    if world is None:
        s.u8(0)
    else:
        s.u8(1)
        s.fs(world)
        s.u8(world_material)   # 0xFF: the colour; else that material as the world
    if not camera:
        s.u8(0xFF)
        return
    s.u8(0)
    s.u8(0)                    # perspective
    s.u8(1)
    s.fs(CAMERA_TRANSFORM)
    s.u8(0)                    # default frame
    s.u8(0)                    # pinhole
    s.u8(0)                    # default clipping


def settings(s, **overrides):
    s.u8(len(overrides))
    for name, value in overrides.items():
        s.u8(SETTINGS.index(name))
        if isinstance(value, float) or (isinstance(value, str)):
            s.f(value)
        else:
            s.u32(value)


def render_tail(s, renders):
    """commit, then each render's settings, stage query, cache-file byte, the
    byte that gives it the photon maps kept from an earlier render (present
    only when an earlier render of the input built maps: a third element),
    and read."""
    s.u8(0)                    # commit
    s.u8(len(renders) - 1)
    for overrides, file_byte, *use_maps in renders:
        settings(s, **overrides)
        s.u8(PHOS_STAGE_COUNT)
        s.u8(file_byte)
        for byte in use_maps:
            s.u8(byte)         # bit 0: use them; bit 1: from any view
        for _ in range(6):     # the fuzzed read: x, y, w, h, pass, count
            s.u8(1)


PHOS_STAGE_COUNT = 7


def scene(mats=None, meshes=None, instances=None, lights=None, world=None, camera=True,
          renders=(({}, 0),), vertex_normals=None, programs=None, world_material=0xFF, bulk_instances=None):
    s = Stream()
    s.u8(0)                    # no images
    materials(s, mats if mats is not None else [[(0, (0.75, 0.75, 0.75))]], programs)
    meshes = meshes if meshes is not None else [(BOX, BOX_TRIS, None)]
    s.u8(len(meshes))
    for m in meshes:
        mesh(s, *m)
    instances = instances if instances is not None else [(0, [0])]
    s.u8(len(instances))
    for i in instances:
        instance(s, *i)
    if bulk_instances is not None:
        s.u8(0x5C)
        s.u8(len(bulk_instances))
        s.u8(0)                # offsets start at 0
        for k, (mesh_id, transform) in enumerate(bulk_instances):
            s.u8(mesh_id)
            s.fs(transform)
            s.u8(k + 1)        # one material each
            s.f(0.5)           # random
        for _ in range(8):
            s.u8(0)            # material 0
        s.u8(0)                # no NULL arrays
    elif vertex_normals is None:
        s.u8(0)
    else:
        s.u8(0x5A)
        positions, polygons, loops = vertex_normals
        s.u8(len(positions))
        s.u8(len(polygons))
        s.u8(len(loops))
        for p in positions:
            s.fs(p)
        for start, total, normal in polygons:
            s.u8(start)
            s.u8(total)
            s.fs(normal)
        for v in loops:
            s.u8(v)
    lights = lights if lights is not None else [{}]
    s.u8(len(lights))
    for kw in lights:
        light(s, **kw)
    world_and_camera(s, world, camera, world_material)
    render_tail(s, list(renders))
    return bytes(s.b)


def updates_tail(overrides, use_maps=None):
    """After a scene's renders: changed (a light and an instance replaced by
    id, nothing added), committed again, rendered once more (given the kept
    photon maps with the use_maps byte, if an earlier render built them)."""
    s = Stream()
    s.u8(0x5B)
    s.u8(2)
    s.u8(0)                    # a light
    s.u8(0)                    # id 0
    light(s, color=(20, 10, 5), position=(0.5, 0, 1.5))
    s.u8(1)                    # an instance
    s.u8(0)                    # id 0
    s.u8(0)                    # of mesh 0
    s.fs((1, 0, 0, 0.25, 0, 1, 0, 0, 0, 0, 1, 0))
    s.u8(0)                    # no meshes added
    s.u8(0)                    # no instances added
    s.u8(0)                    # no lights added
    s.u8(0)                    # the world as it was
    s.u8(0xFF)                 # the camera as it was
    settings(s, **overrides)
    s.u8(PHOS_STAGE_COUNT)
    s.u8(0)
    if use_maps is not None:
        s.u8(use_maps)
    for _ in range(6):
        s.u8(1)
    return bytes(s.b)


PHOTON = {"integrator": 1}
SEEDS = {
    "valid_path": scene(),
    "valid_photon": scene(renders=[(PHOTON, 0)]),
    "valid_photon_cache_always": scene(renders=[({"irradiance_cache": 2, "ic_rays": 16}, 0)]),
    "world_light_photon": scene(world=(0.2, 0.2, 0.2), renders=[(PHOTON, 0)]),
    "world_material_photon": scene(world=(0.2, 0.2, 0.2), world_material=0, renders=[(PHOTON, 0)]),
    "portal_photon": scene(world=(0.5, 0.5, 0.5), lights=[{"kind": 4, "position": (0, 0, 2)}],
                           renders=[(PHOTON, 0)]),
    "valid_two_renders": scene(renders=[(PHOTON, 0), ({"photon_view": 2, **PHOTON}, 0, 0)]),
    # The maps kept from the first render, taken by the second (the same
    # scene and settings), then refused after a change (the third).
    "photon_maps_kept": scene(renders=[(PHOTON, 0), (PHOTON, 0, 1)]) +
    updates_tail(PHOTON, use_maps=3),
    "scene_updated": scene(renders=[(PHOTON, 0)]) + updates_tail(PHOTON, use_maps=0),
    "bulk_instances": scene(bulk_instances=[(0, (1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0)),
                                            (0, (0.5, 0, 0, -0.5, 0, 0.5, 0, 0, 0, 0, 0.5, 0))]),
    "glass_and_mirror": scene(mats=[[(0, (0.75, 0.75, 0.75), 0.5, 1.5, 0, 0.0, 0, 1)], [(5, (1, 1, 1), 0.0, 1.5)],
                                    [(2, (1, 1, 1), 0.0, 1.5, 0, 0.0, 0, 1)]],
                              instances=[(0, [0, 1, 2])],
                              meshes=[(BOX, BOX_TRIS, [0, 0, 1, 1, 2, 2, 0, 0, 0, 0, 0, 0])],
                              renders=[(PHOTON, 0)]),
    # Cycles 4's closures: a coat layered over an F82 metal and Oren-Nayar,
    # sheen, a Multiscatter glass with a thin film; every pass, the
    # denoising ones included.
    "cycles4_closures": scene(mats=[[(3, (1, 1, 1), 0.1, 1.5, 2, 0.0, 2, 2),
                                     (8, (0.5, 0.5, 0.5), 0.3, 1.5, 2, 0.0, 0, 2),
                                     (9, (0.5, 0.4, 0.3), 0.5, 1.5)],
                                    [(10, (1, 1, 1), 0.5, 1.5), (5, (1, 1, 1), 0.3, 1.5, 2, 400.0, 0, 2)]],
                              instances=[(0, [0, 1])],
                              meshes=[(BOX, BOX_TRIS, [0] * 6 + [1] * 6)],
                              renders=[({"pass_mask": (1 << 10) | (1 << 11), **PHOTON}, 0), ({"pass_mask": 4095}, 0, 1)]),
    "shader_program_noise": scene(programs={0: noise_program}, renders=[(PHOTON, 0)]),
    "world_program_photon": scene(programs={0: noise_program}, world=(0.2, 0.2, 0.2), world_material=0,
                                  renders=[(PHOTON, 0)]),
    "nan_vertex": scene(meshes=[([(0, 0, 0), ("nan", 0, 0), (0, 1, 0)], [(0, 1, 2)], None),
                                (BOX, BOX_TRIS, None)], instances=[(1, [0]), (0, [0])]),
    "inf_and_huge_vertices": scene(meshes=[([(0, 0, 0), ("inf", 0, 0), (0, 1e30, 0), (1e38, 1e38, 1e38)],
                                            [(0, 1, 2), (0, 2, 3)], None)], instances=[(0, [0])]),
    "degenerate_triangles": scene(meshes=[([(0, 0, 0), (0, 0, 0), (0, 0, 0), (1, 0, 0), (2, 0, 0)],
                                           [(0, 1, 2), (0, 3, 4), (1, 1, 1)], None)], renders=[(PHOTON, 0)]),
    "bad_indices": scene(meshes=[([(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1, 4)], None)]),
    "bad_material_ids": scene(instances=[(0, [3, 4])]),
    "bad_material_slots": scene(meshes=[(BOX, BOX_TRIS, [5] * 12)], renders=[(PHOTON, 0)]),
    "bad_mesh_id": scene(instances=[(4, [0])]),
    "empty_mesh": scene(meshes=[([], [], None)], renders=[(PHOTON, 0)]),
    # Per-corner attributes: a colour and a float, valid; then a duplicate id
    # and, after a valid one, a non-finite value, each refused.
    "mesh_attributes": scene(meshes=[(BOX, BOX_TRIS, None, [(1, 3, [0.5, 0.25, 1, 1] * 36),
                                                            (2, 0, [0.125] * 144)]),
                                     (BOX, BOX_TRIS, None, [(1, 0, [0] * 144), (1, 2, [0] * 144)]),
                                     (BOX, BOX_TRIS, None, [(1, 1, ["nan"] + [0] * 143), (0, 0x80, [0] * 144)])],
                             instances=[(0, [0])]),
    "no_geometry": scene(meshes=[], instances=[], renders=[(PHOTON, 0)]),
    "zero_light_power": scene(lights=[{"color": (0, 0, 0)}], renders=[(PHOTON, 0)]),
    "negative_light_power": scene(lights=[{"color": (-10, 10, 10)}]),
    "no_lights_photon": scene(lights=[], renders=[(PHOTON, 0)]),
    "point_spot_sun_lights": scene(lights=[{"kind": 0, "radius": 0.1}, {"kind": 1, "spot_angle": 0.5},
                                           {"kind": 3, "sun_angle": 0.1}], renders=[(PHOTON, 0)]),
    "no_camera": scene(camera=False),
    "photons_zero": scene(renders=[({"global_photons": 0, "caustic_photons": 0, **PHOTON}, 0)]),
    "photons_2_31": scene(renders=[({"global_photons": 1 << 31, **PHOTON}, 0)]),
    "photons_2_28": scene(renders=[({"global_photons": 1 << 28, "caustic_photons": 1 << 28, **PHOTON}, 0)]),
    "k_zero": scene(renders=[({"global_estimate_photons": 0, "caustic_estimate_photons": 0, **PHOTON}, 0)]),
    "radius_zero_and_negative": scene(renders=[({"max_radius": -1.0, **PHOTON}, 0), ({"max_radius": 1e-30,
                                                                                       **PHOTON}, 0)]),
    "resolution_0x0": scene(renders=[({"width": 0, "height": 0}, 0)]),
    "resolution_1x1": scene(renders=[({"width": 1, "height": 1, **PHOTON}, 0)]),
    "resolution_huge": scene(renders=[({"width": 65536, "height": 65536, "pass_mask": 1023}, 0)]),
    "samples_absurd": scene(renders=[({"samples": 1 << 31}, 0), ({"samples": 1 << 24, "width": 1,
                                                                  "height": 1}, 0)]),
    "region_outside": scene(renders=[({"region_x": 7, "region_y": 7, "region_width": 2,
                                       "region_height": 2}, 0)]),
    "settings_nan": scene(renders=[({"filter_width": "nan", "ic_accuracy": "inf"}, 0)]),
    "vertex_normals_cube": scene(vertex_normals=(BOX, [(4 * i, 4, (0, 0, 1)) for i in range(4)],
                                                 [0, 1, 2, 3, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5])),
    "vertex_normals_bad": scene(vertex_normals=(BOX[:3], [(0, 2, (0, 0, 1)), (20, 3, ("nan", 0, 1))],
                                                [0, 1, 9, 2])),
    # Inputs that once crashed, as scenes (docs/reliability.md, "The fuzzer").
    "regress_rank_one_instance": scene(instances=[(0, [0], (-13.875, -13.875, -13.875, -14, -14, -14, -14, -14,
                                                             -14, -14, -14, -14))]),
    "regress_zero_scale_instance": scene(instances=[(0, [0], (1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0)),
                                                    (0, [0])]),
    "regress_far_instance": scene(instances=[(0, [0], (1, 0, 0, 1e20, 0, 1, 0, 0, 0, 0, 1, 0))]),
    # A 10 GB film that fits this machine: allocated lazily, cancelled, freed.
    # Maps so small that no class needs a split plane: the kd-tree build
    # added an offset to the NULL split array (UBSan, 2026-12-05).
    "regress_tiny_photon_map": scene(renders=[({"global_photons": 5, "caustic_photons": 3, **PHOTON}, 0)]),
    "regress_large_film": scene(renders=[({"width": 65536, "height": 10001, "pass_mask": 1023}, 0)]),
    "cache_file_garbage": scene(renders=[({"irradiance_cache": 2}, 1 | (2 << 1) | (0 << 3))]) + b"PHOSIRC\0garbage",
    "photon_file_garbage": scene(renders=[(PHOTON, 1 | (2 << 1) | (1 << 3))]) + b"PHOSPMF\0\x01\x00",
}


def main():
    out = os.path.join(HERE, "corpus")
    os.makedirs(out, exist_ok=True)
    for name in os.listdir(out):
        os.remove(os.path.join(out, name))
    for name, data in SEEDS.items():
        with open(os.path.join(out, name), "wb") as f:
            f.write(data)
    print("wrote %d seeds to %s" % (len(SEEDS), out))


if __name__ == "__main__":
    main()
