# SPDX-License-Identifier: GPL-3.0-or-later
"""Digest of every pass of every test scene, for each integrator.

    make image-digests [DIGESTS=out/image-digests.txt] [DIGEST_SCENES=out/image-digest-scenes]

runs this inside Blender: each scene the tests render (the parity light and
material scenes, the photon-test scenes, the scenes/ scripts) is rendered at
a small size with PATH, PHOTON with final gathering and PHOTON with the
fast estimate, every pass enabled, and the SHA-256 of the float32 pixels of
all passes is printed, one line per scene and integrator.

A refactoring that must not change any image (docs/architecture.md,
"Changing the code without changing the images") is checked by running it
before and after and diffing the two files. The first run saves every
scene it builds into DIGEST_SCENES and later runs load them, so all runs
render the same data; PHOS_DIGEST_SCENES=regex limits a run to the scenes
whose names match. It is not a test: the digests
depend on the compiler, Embree's version and the CPU, so they are compared
on one machine, never stored.
"""

import hashlib
import importlib.util
import os
import re
import sys

import bpy

REPO_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TESTS_DIR = os.path.join(REPO_DIR, "tests", "blender")
SCENES_DIR = os.path.join(REPO_DIR, "scenes")
for d in (TESTS_DIR, SCENES_DIR):
    if d not in sys.path:
        sys.path.insert(0, d)

import parity_scenes  # noqa: E402
import phostest as pt  # noqa: E402

WIDTH, HEIGHT, SAMPLES = 40, 30, 4
INTEGRATORS = (("PATH", None), ("PHOTON", "FINAL_GATHER"), ("PHOTON", "FAST"))
PASS_PROPS = ("use_pass_emission", "use_pass_direct", "use_pass_specular", "use_pass_caustics",
              "use_pass_indirect", "use_pass_photon_map", "use_pass_caustic_map", "use_pass_photons")


def _module(name):
    spec = importlib.util.spec_from_file_location("digest_" + name, os.path.join(SCENES_DIR, name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _test_photon():
    spec = importlib.util.spec_from_file_location("digest_test_photon", os.path.join(TESTS_DIR, "test_photon.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


TEST_PHOTON = _test_photon()  # its scenes, and its render_passes (multilayer EXR, every pass)


def _photon_test_scenes():
    m = TEST_PHOTON
    return {"components": m.components_scene, "components_flat": lambda s: m.components_scene(s, True),
            "diffuse_room": m.diffuse_scene}


def scenes():
    out = {}
    out.update(("light/" + k, v) for k, v in parity_scenes.LIGHT_SCENES.items())
    out.update(("material/" + k, v) for k, v in parity_scenes.MATERIAL_SCENES.items())
    out.update(("photon/" + k, v) for k, v in _photon_test_scenes().items())
    for name in sorted(f[:-3] for f in os.listdir(SCENES_DIR) if f.endswith(".py") and not f.startswith("_")):
        out["scenes/" + name] = _module(name).build
    return out


def load_scene(name, build, blend_dir):
    """The scene as saved in blend_dir by the first run, built (and saved)
    if it is not there: two runs then render the same data. Building the
    parity scenes' UV spheres twice can order their faces differently, and
    with an emissive mesh that changes which triangle a light sample picks."""
    path = os.path.join(blend_dir, name.replace("/", "__") + ".blend")
    if os.path.isfile(path):
        bpy.ops.wm.open_mainfile(filepath=path)
        pt.enable_addon()
        return bpy.context.scene
    pt.reset_file()
    scene = bpy.context.scene
    build(scene)
    # Blender 3.4 sums smooth vertex normals in parallel, so two evaluations
    # of one smooth mesh can differ in the last bit: flat shading keeps the
    # digests a function of Phos' code alone.
    for mesh in bpy.data.meshes:
        for poly in mesh.polygons:
            poly.use_smooth = False
    scene.render.engine = "PHOS"
    bpy.ops.file.pack_all()  # the image-texture scene's checker lives in a temp folder
    bpy.ops.wm.save_as_mainfile(filepath=path, check_existing=False)
    return scene


def digest(name, build, integrator, view, tmp_dir, blend_dir):
    scene = load_scene(name, build, blend_dir)
    scene.render.engine = "PHOS"
    pt.configure_output(scene, WIDTH, HEIGHT)
    pt.configure_phos(scene, SAMPLES, max_bounces=8)
    pt.configure_threads(scene, 2)
    p = scene.phos
    p.integrator = integrator
    p.global_photons, p.caustic_photons = 20000, 5000
    p.final_gather_rays = 8
    p.max_photons_emitted = 1  # millions: scenes without glass never fill the caustic map
    if view:
        p.photon_view = view
    for prop in PASS_PROPS:
        setattr(scene.view_layers[0].phos, prop, True)
    passes = TEST_PHOTON.render_passes(scene, tmp_dir, "digest")
    h = hashlib.sha256()
    for name in sorted(passes):
        h.update(name.encode())
        h.update(passes[name].astype("<f4").tobytes())
    return h.hexdigest()


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    out_path = argv[0] if argv else os.path.join(REPO_DIR, "out", "image-digests.txt")
    blend_dir = argv[1] if len(argv) > 1 else os.path.join(REPO_DIR, "out", "image-digest-scenes")
    os.makedirs(os.path.dirname(os.path.abspath(out_path)), exist_ok=True)
    os.makedirs(blend_dir, exist_ok=True)
    tmp_dir = bpy.app.tempdir
    lines = []
    only = re.compile(os.environ.get("PHOS_DIGEST_SCENES", ""))
    for name, build in scenes().items():
        if not only.search(name):
            continue
        for integrator, view in INTEGRATORS:
            label = integrator + ("/" + view if view else "")
            lines.append("%-40s %-20s %s" % (name, label, digest(name, build, integrator, view, tmp_dir, blend_dir)))
            print(lines[-1], flush=True)
    with open(out_path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("wrote %d digests to %s" % (len(lines), out_path))


main()
