# SPDX-License-Identifier: GPL-3.0-or-later
"""Photon mapping through Blender: settings, passes, stages, consistency
with PATH, determinism.

Passes are read from multilayer EXRs written by real renders (exrread.py),
so what is checked is what Blender received from the engine, after its
merging of tiles, not what the engine meant to write.

Consistency (test_cornell_photon_converges_to_path): scenes/cornell_box.py at
64 × 64, a PATH reference of 2048 samples, then PHOTON with final gathering
at growing photon counts and estimate sizes. The error is the relative RMSE
of the Combined RGB after a 4 × 4 box downsample (which averages away most
of the pixel noise of both renders and keeps the photon map's low-frequency
error). 4 × 4 blocks that contain a pixel brighter than BRIGHT in the
reference are left out: they hold the light patch and its images in the
two spheres, 100 × brighter than the walls and only partly covering a
pixel, so their value is decided by how many of a pixel's samples hit the
tiny light — noise that has nothing to do with photons and that, at 16-32
samples, moves the image mean by ±3 % from seed to seed.
"""

import os

import re

import bpy
import numpy as np
import pytest

import exrread
import phostest as pt

SCENES_DIR = os.path.join(pt.REPO_DIR, "scenes")

LIGHT_PASSES = ("Emission", "Direct", "Specular", "Caustics", "Indirect")
DEBUG_PASSES = ("Photon Map", "Caustic Map", "Photons")
PASS_PROPS = {
    "Emission": "use_pass_emission", "Direct": "use_pass_direct",
    "Specular": "use_pass_specular", "Caustics": "use_pass_caustics",
    "Indirect": "use_pass_indirect", "Photon Map": "use_pass_photon_map",
    "Caustic Map": "use_pass_caustic_map", "Photons": "use_pass_photons",
}


# ------------------------------------------------------------------ helpers

def enable_passes(scene, names=LIGHT_PASSES + DEBUG_PASSES, on=True):
    settings = scene.view_layers[0].phos
    for name in names:
        setattr(settings, PASS_PROPS[name], on)


def configure_photons(scene, global_photons, caustic_photons, k_global=50, k_caustic=80,
                      gather_rays=16, view="FINAL_GATHER", max_radius=0.0):
    p = scene.phos
    p.integrator = "PHOTON"
    p.global_photons, p.caustic_photons = global_photons, caustic_photons
    p.global_estimate_photons, p.caustic_estimate_photons = k_global, k_caustic
    p.final_gather_rays = gather_rays
    p.photon_view = view
    p.max_radius = max_radius


def render_passes(scene, out_dir, name):
    """Render to a multilayer EXR (32-bit float, lossless) and read every pass back."""
    path = os.path.join(str(out_dir), name + ".exr")
    if os.path.exists(path):
        os.remove(path)
    r = scene.render
    r.filepath, r.use_file_extension = path, False
    pt.set_multilayer_exr(r.image_settings)
    bpy.ops.render.render(write_still=True, scene=scene.name)
    assert os.path.isfile(path), "the render wrote no %s" % path
    return exrread.read_passes(path)


def box_down(a, f):
    h, w = a.shape[:2]
    return a[:h - h % f, :w - w % f].reshape(h // f, f, w // f, f, *a.shape[2:]).mean(axis=(1, 3))


def glass_material(name="Glass"):
    return pt.node_material(name, "ShaderNodeBsdfGlass", {"IOR": 1.5, "Color": (1, 1, 1)},
                            {"distribution": "SHARP"})


def mirror_material(name="Mirror"):
    return pt.node_material(name, "ShaderNodeBsdfGlossy", {"Color": (0.9, 0.9, 0.9)},
                            {"distribution": "SHARP"})


def components_scene(scene, flat=False):
    """Every light component at once: a visible emitter and world (Emission),
    a point light on diffuse floor and wall (Direct, Indirect), a glass and a
    mirror sphere (Specular) whose light lands on the floor (Caustics)."""
    pt.add_plane(scene, "Floor", size=6.0, material=pt.diffuse("Floor", (0.7, 0.7, 0.7)))
    pt.add_plane(scene, "Wall", size=6.0, location=(0, 1.5, 3.0), rotation=(pt.angle(90), 0, 0),
                 material=pt.diffuse("Wall", (0.6, 0.65, 0.7)))
    pt.add_sphere(scene, "Glass Sphere", radius=0.5, location=(-0.5, 0.0, 0.5), material=glass_material(),
                  smooth=not flat)
    pt.add_sphere(scene, "Mirror Sphere", radius=0.3, location=(0.8, 0.4, 0.3),
                  material=mirror_material(), smooth=not flat)
    pt.add_plane(scene, "Panel", size=0.5, location=(1.0, 1.49, 1.2), rotation=(pt.angle(90), 0, 0),
                 material=pt.emission("Panel", (1.0, 0.8, 0.6), 4.0))
    pt.add_light(scene, "POINT", 300.0, location=(-1.6, -0.6, 2.6), shadow_soft_size=0.05)
    pt.add_camera(scene, location=(0.3, -4.2, 1.9), target=(0.0, 0.3, 0.5))
    pt.set_world(scene, (0.05, 0.06, 0.08))
    scene.render.engine = "PHOS"
    return scene


def diffuse_scene(scene):
    """Diffuse surfaces only, lit by an area light the camera does not see."""
    white = pt.diffuse("White", (0.7, 0.7, 0.7))
    pt.add_plane(scene, "Floor", size=4.0, material=white)
    pt.add_plane(scene, "Back", size=4.0, location=(0, 2.0, 2.0), rotation=(pt.angle(90), 0, 0),
                 material=white)
    pt.add_plane(scene, "Left", size=4.0, location=(-2.0, 0, 2.0), rotation=(0, pt.angle(90), 0),
                 material=pt.diffuse("Red", (0.6, 0.1, 0.1)))
    pt.add_cube(scene, "Block", size=0.8, location=(0.3, 0.3, 0.4),
                material=pt.diffuse("Blue", (0.2, 0.3, 0.6)))
    pt.add_light(scene, "AREA", 150.0, location=(0.0, 0.0, 3.0), target=(0, 0, 0), size=1.0)
    pt.add_camera(scene, location=(0.8, -5.0, 2.2), target=(0.0, 0.5, 0.8))
    pt.set_world(scene, (0.0, 0.0, 0.0))
    scene.render.engine = "PHOS"
    return scene


# ---------------------------------------------------------------- settings

def test_photon_settings_and_defaults(scene):
    p = scene.phos
    props = type(p).bl_rna.properties
    expected = {"global_photons": 200000, "caustic_photons": 800000, "global_estimate_photons": 50,
                "caustic_estimate_photons": 20, "max_radius": 0.0, "final_gather_rays": 4,
                "photon_view": "FINAL_GATHER"}
    for name, value in expected.items():
        assert getattr(p, name) == value, name
    for name in ("global_photons", "caustic_photons", "max_radius"):
        assert props[name].hard_min == 0, name
    for name in ("global_estimate_photons", "caustic_estimate_photons", "final_gather_rays"):
        assert props[name].hard_min == 1, name
    assert props["max_radius"].subtype == "DISTANCE" and props["max_radius"].unit == "LENGTH"
    integrators = props["integrator"].enum_items
    assert integrators["PATH"].value == 0 and integrators["PHOTON"].value == 1
    views = props["photon_view"].enum_items
    assert views["FINAL_GATHER"].value == 0 and views["FAST"].value == 1
    assert views["PATH_TRACED"].value == 2
    assert p.integrator == "PATH", "PATH stays the default integrator"


def test_view_layer_pass_toggles(scene):
    settings = scene.view_layers[0].phos
    for prop in PASS_PROPS.values():
        assert getattr(settings, prop) is False, prop
    # A second view layer has its own toggles.
    other = scene.view_layers.new("Other")
    settings.use_pass_caustics = True
    assert other.phos.use_pass_caustics is False


def test_passes_registered_for_compositor(scene):
    """Toggling a pass re-registers the view layer's passes: the compositor's
    Render Layers node offers exactly the enabled ones."""
    scene.render.engine = "PHOS"
    node = pt.compositor_tree(scene).nodes.new("CompositorNodeRLayers")
    enable_passes(scene, ("Caustics", "Photons"))

    def offered(name):
        socket = node.outputs.get(name)
        return socket is not None and socket.enabled

    assert offered("Image")
    assert offered("Caustics") and offered("Photons")
    assert not offered("Direct") and not offered("Photon Map")
    enable_passes(scene, ("Caustics",), on=False)
    assert not offered("Caustics") and offered("Photons")


def test_panels_registered(addon):
    panels = {name: getattr(bpy.types, name, None) for name in (
        "PHOS_RENDER_PT_photon_mapping", "PHOS_VIEW_LAYER_PT_passes",
        "PHOS_VIEW_LAYER_PT_passes_light", "PHOS_VIEW_LAYER_PT_passes_photon_debug")}
    assert all(panels.values()), "missing panels: %s" % [n for n, p in panels.items() if p is None]
    assert panels["PHOS_RENDER_PT_photon_mapping"].bl_context == "render"
    for name in ("PHOS_VIEW_LAYER_PT_passes", "PHOS_VIEW_LAYER_PT_passes_light",
                 "PHOS_VIEW_LAYER_PT_passes_photon_debug"):
        assert panels[name].bl_context == "view_layer"
        assert panels[name].COMPAT_ENGINES == {"PHOS"}
    assert panels["PHOS_VIEW_LAYER_PT_passes_light"].bl_label == "Light"
    assert panels["PHOS_VIEW_LAYER_PT_passes_photon_debug"].bl_label == "Photon Map Debug"


# ------------------------------------------------------------------- passes

def test_exr_reader_matches_blender(scene, tmp_path):
    """The test's EXR reader agrees with Blender's own loader, ZIP and uncompressed."""
    components_scene(scene)
    pt.configure_output(scene, 40, 30)
    pt.configure_phos(scene, 2)
    for codec in ("ZIP", "NONE"):
        scene.render.image_settings.exr_codec = codec
        path = os.path.join(str(tmp_path), "reader_%s.exr" % codec)
        scene.render.filepath, scene.render.use_file_extension = path, False
        bpy.ops.render.render(write_still=True)
        ours = exrread.read_channels(path)
        theirs = pt.load_image_array(path)
        mine = np.stack([ours[c] for c in "RGBA"], axis=-1)
        assert np.array_equal(mine, theirs), codec


@pytest.mark.parametrize("integrator", ["PHOTON", "PATH"])
def test_light_passes_sum_to_combined(integrator, scene, tmp_path):
    components_scene(scene)
    pt.configure_output(scene, 64, 48)
    pt.configure_phos(scene, 8, max_bounces=8)
    configure_photons(scene, 20000, 20000, gather_rays=8)
    scene.phos.integrator = integrator
    enable_passes(scene)
    passes = render_passes(scene, tmp_path, "components_" + integrator)

    assert set(passes) == {"Combined"} | set(LIGHT_PASSES) | set(DEBUG_PASSES), sorted(passes)
    assert passes["Combined"].shape == (48, 64, 4)
    for name in LIGHT_PASSES + DEBUG_PASSES:
        assert passes[name].shape == (48, 64, 3), name
    combined = passes["Combined"][..., :3].astype(np.float64)
    total = sum(passes[name].astype(np.float64) for name in LIGHT_PASSES)
    bad = np.abs(combined - total) > 1e-5 * np.abs(combined) + 1e-7
    assert not bad.any(), "%d channel values where Combined != sum of the light passes, worst %g" % (
        bad.sum(), np.max(np.abs(combined - total)))
    # Each component is really there (this scene has all five).
    means = {name: float(passes[name].mean()) for name in LIGHT_PASSES}
    print("%s component means: %s" % (integrator, {k: round(v, 5) for k, v in means.items()}))
    for name in LIGHT_PASSES:
        assert means[name] > 0.0, name
    assert means["Direct"] > means["Indirect"] > 0.0
    # The photon debug passes build the maps for either integrator.
    photons = passes["Photons"]
    dots = photons.max(axis=-1) > 0
    assert 0.02 < dots.mean() < 0.95, "photon dots cover %.1f %% of the image" % (100 * dots.mean())
    assert photons.min() >= 0.0 and photons.max() <= 1.0
    # Each dot is a photon's power normalised to its largest channel.
    np.testing.assert_allclose(photons[dots].max(axis=-1), 1.0, rtol=1e-6)
    assert passes["Photon Map"].mean() > 0.0
    caustic_map = passes["Caustic Map"]
    assert caustic_map.max() > 0.0, "the caustic map pass is black"
    # The caustic map's light lies on the floor behind the glass sphere, in
    # its shadow, where it is brighter than anywhere the direct light falls
    # except that caustic (the sphere focuses it).
    assert caustic_map.max() > np.percentile(passes["Direct"], 50)


def _assert_same_in_expectation(a, b, what, block=8, z=4.5):
    """a and b (H×W×3) are independent renders of the same quantity: every
    block×block mean of a − b is zero within z standard errors, each from
    the spread of a − b inside the block (its pixels are independent
    estimates of zero)."""
    d = (a - b).astype(np.float64).mean(axis=-1)
    h, w = d.shape
    blocks = d[:h - h % block, :w - w % block].reshape(h // block, block, w // block, block)
    blocks = blocks.transpose(0, 2, 1, 3).reshape(h // block, w // block, block * block)
    mean = blocks.mean(axis=-1)
    se = blocks.std(axis=-1, ddof=1) / np.sqrt(block * block)
    scale = np.abs(b).mean() * 1e-6  # blocks where both are exactly equal
    worst = np.max(np.abs(mean) / (se + scale))
    total_se = d.std(ddof=1) / np.sqrt(d.size)
    print("%s: image means %.5f vs %.5f (± %.5f), worst block %.2f standard errors" % (
        what, float(a.mean()), float(b.mean()), total_se, worst))
    assert abs(d.mean()) < 4.0 * total_se + scale, what
    assert worst < z, "%s: a %d×%d block differs by %.1f standard errors" % (what, block, block, worst)


def test_light_passes_against_independent_renders(scene, tmp_path):
    """Combined = the sum of the passes holds by construction (the film adds
    each sample to both), so each pass is checked against something
    computed apart from it:
    - Emission: the panel's radiance, 4 × (1, 0.8, 0.6) W/(m²·sr), where
      the camera sees only the panel, and that colour scaled elsewhere;
    - Emission + Direct of `PATH`: the Combined of another `PATH` render,
      another seed, with Max Bounces 0 (light that scattered once only);
    - Emission + Direct of `PHOTON`: the same sum of `PATH` (both
      integrators file light that scattered once the same way for every
      material; README "What the passes mean")."""
    components_scene(scene)
    pt.configure_output(scene, 64, 48)
    pt.configure_phos(scene, 16, max_bounces=8, seed=1)
    enable_passes(scene, LIGHT_PASSES)
    full = render_passes(scene, tmp_path, "independent_path")
    emission = full["Emission"]
    red = emission[..., 0]
    panel = red > 3.99
    print("Emission: %d pixels see only the panel, %d part of it" % (panel.sum(), ((red > 0) & ~panel).sum()))
    assert panel.sum() >= 4
    np.testing.assert_allclose(emission[panel], np.broadcast_to([4.0, 3.2, 2.4], emission[panel].shape),
                               rtol=1e-5)
    # Elsewhere the camera sees the panel over part of a pixel, or no
    # emitter at all (it sees no world either): the panel's colour, scaled.
    assert red.max() <= 4.0 * (1 + 1e-5)
    np.testing.assert_allclose(emission[..., 1], 0.8 * red, rtol=1e-5, atol=1e-7)
    np.testing.assert_allclose(emission[..., 2], 0.6 * red, rtol=1e-5, atol=1e-7)
    once = full["Emission"] + full["Direct"]

    pt.configure_phos(scene, 16, max_bounces=0, seed=2)
    enable_passes(scene, LIGHT_PASSES, on=False)
    direct_only = render_passes(scene, tmp_path, "independent_path_b0")["Combined"][..., :3]
    _assert_same_in_expectation(direct_only, once, "PATH max bounces 0 vs Emission + Direct")

    pt.configure_phos(scene, 16, max_bounces=8, seed=3)
    configure_photons(scene, 20000, 20000, gather_rays=4)
    enable_passes(scene, LIGHT_PASSES)
    photon = render_passes(scene, tmp_path, "independent_photon")
    _assert_same_in_expectation(photon["Emission"] + photon["Direct"], once,
                                "PHOTON vs PATH Emission + Direct")


def test_photon_map_pass_matches_combined_on_diffuse_scene(scene, tmp_path):
    """Global map read at the first hit ≈ the converged image, for diffuse surfaces only."""
    diffuse_scene(scene)
    pt.configure_output(scene, 64, 48)
    pt.configure_phos(scene, 64, max_bounces=8)
    scene.phos.integrator = "PATH"
    scene.phos.global_photons, scene.phos.caustic_photons = 200000, 1000
    scene.phos.global_estimate_photons = 100
    enable_passes(scene, ("Photon Map", "Emission"))
    passes = render_passes(scene, tmp_path, "diffuse")
    combined = passes["Combined"][..., :3]
    photon_map = passes["Photon Map"]
    assert passes["Emission"].max() == 0.0, "the camera sees no emitter in this scene"
    ratio = photon_map.mean() / combined.mean()
    blocks_c = box_down(combined, 8).mean(axis=-1)
    blocks_p = box_down(photon_map, 8).mean(axis=-1)
    lit = blocks_c > 0.1 * blocks_c.mean()
    block_dev = np.median(np.abs(blocks_p[lit] / blocks_c[lit] - 1.0))
    print("photon map / combined: mean ratio %.4f, median 8x8 block deviation %.4f" % (ratio, block_dev))
    assert abs(ratio - 1.0) < 0.10
    assert block_dev < 0.10


# ------------------------------------------------------------ consistency

def _load_cornell_box():
    import importlib.util
    import sys
    if SCENES_DIR not in sys.path:
        sys.path.insert(0, SCENES_DIR)
    spec = importlib.util.spec_from_file_location("cornell_box_scene",
                                                  os.path.join(SCENES_DIR, "cornell_box.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


CORNELL_SIZE = 64
CORNELL_REFERENCE_SAMPLES = 2048
CORNELL_PHOTON_SAMPLES = 32
BRIGHT = 2.0  # W/(m²·sr); the walls are below 1, the light patch about 37
# (global photons, k) — the caustic map gets half the photons and the same k.
CORNELL_SIZES = ((2500, 15), (10000, 35), (40000, 70))
CORNELL_MEAN_SEEDS = 6   # renders at the largest count whose image means give the mean's noise
CORNELL_MEAN_T = 6.0


def test_cornell_photon_converges_to_path(scene, tmp_path):
    cornell = _load_cornell_box()
    cornell.build(scene)
    pt.configure_output(scene, CORNELL_SIZE, CORNELL_SIZE)
    pt.configure_phos(scene, CORNELL_REFERENCE_SAMPLES, max_bounces=cornell.MAX_BOUNCES)
    scene.render.engine = "PHOS"
    reference = pt.render_array(scene, tmp_path, name="cornell_path")[..., :3].astype(np.float64)

    f = 4
    ref_blocks = box_down(reference, f)
    keep = ~box_down((reference.max(axis=-1) > BRIGHT).astype(np.float64), f).astype(bool)
    assert keep.mean() > 0.85, "too few blocks left to compare: %.2f" % keep.mean()
    ref_kept = ref_blocks[keep]

    scene.phos.samples = CORNELL_PHOTON_SAMPLES
    rows = []
    for global_photons, k in CORNELL_SIZES:
        configure_photons(scene, global_photons, global_photons // 2, k_global=k, k_caustic=k,
                          gather_rays=32)
        image = pt.render_array(scene, tmp_path, name="cornell_photon_%d" % global_photons)
        blocks = box_down(image[..., :3].astype(np.float64), f)[keep]
        rmse = np.sqrt(np.mean((blocks - ref_kept) ** 2)) / np.sqrt(np.mean(ref_kept ** 2))
        mean_ratio = blocks.mean() / ref_kept.mean()
        rows.append((global_photons, k, rmse, mean_ratio, blocks))
    # The noise of one PHOTON render at these samples, from more seeds at
    # the largest photon count. Per block, from the second seed:
    # Var(a − b) = 2σ². Of the image mean, from the spread of the means of
    # all seeds: a photon map's error is shared by every pixel of a render,
    # so pixel or block differences, taken as independent, understate it
    # (on 4.3 they gave 0.0012 where the seeds' means spread by 0.006).
    last = rows[-1][4]
    seed_means = [rows[-1][3]]
    for seed in range(1, CORNELL_MEAN_SEEDS):
        scene.phos.seed = seed
        image = pt.render_array(scene, tmp_path, name="cornell_photon_seed%d" % seed)
        blocks = box_down(image[..., :3].astype(np.float64), f)[keep]
        seed_means.append(blocks.mean() / ref_kept.mean())
        if seed == 1:
            other = blocks
    scene.phos.seed = 0
    noise = np.sqrt(np.mean((last - other) ** 2) / 2.0) / np.sqrt(np.mean(ref_kept ** 2))
    mean_ratio = float(np.mean(seed_means))
    mean_se = float(np.std(seed_means, ddof=1) / np.sqrt(len(seed_means)))
    print("\nCornell box %d² PHOTON (%d spp, 32 gather rays) vs PATH (%d spp), %d×%d blocks, "
          "%.0f %% of them compared; PHOTON's own noise %.4f; at %d photons, mean ratio over %d seeds "
          "%.4f ± %.4f (seeds: %s):" % (
              CORNELL_SIZE, CORNELL_PHOTON_SAMPLES, CORNELL_REFERENCE_SAMPLES, f, f, 100 * keep.mean(),
              noise, rows[-1][0], len(seed_means), mean_ratio, mean_se,
              " ".join("%.4f" % m for m in seed_means)))
    for g, k, e, m, _ in rows:
        bias = np.sqrt(max(e * e - noise * noise, 0.0))
        print("  global %6d  caustic %6d  k %3d   rel. RMSE %.4f (beyond the noise %.4f)   mean ratio %.4f" % (
            g, g // 2, k, e, bias, m))
    # Consistent: the error left beyond PHOTON's own noise falls with every
    # step (by a tenth at least) until it is below that noise, and the mean
    # over the seeds at the largest count is within MEAN_T standard errors
    # (Student's t with CORNELL_MEAN_SEEDS − 1 degrees of freedom: P(|t| >
    # 6) ≈ 0.2 %). Measured on 3.4 while gather hits read direct light from
    # the global map: mean errors 6.5 %, 3.2 %, 2.0 %; since they take it
    # from a light sample: RMSE 0.041, 0.036, 0.034 at PHOTON's own noise,
    # mean ratios 0.999, 0.999, 0.998 (seed 0).
    for (g0, _, e0, _, _), (g1, _, e1, _, _) in zip(rows, rows[1:]):
        b0 = np.sqrt(max(e0 * e0 - noise * noise, 0.0))
        b1 = np.sqrt(max(e1 * e1 - noise * noise, 0.0))
        assert b1 < 0.9 * b0 or b1 < noise, \
            "error beyond the noise did not fall from %d to %d photons: %.4f -> %.4f (noise %.4f)" % (
                g0, g1, b0, b1, noise)
    assert rows[-1][2] < 1.5 * noise, "error %.4f at %d photons, noise %.4f" % (rows[-1][2], rows[-1][0], noise)
    assert abs(mean_ratio - 1.0) < CORNELL_MEAN_T * mean_se, "mean ratio %.4f at %d photons (%.0f SE %.4f)" % (
        mean_ratio, rows[-1][0], CORNELL_MEAN_T, CORNELL_MEAN_T * mean_se)


# ------------------------------------------------------------------ stages

STAGES_SCRIPT = r"""
import bpy
import phostest as pt
sc = pt.reset_file()
import test_photon
test_photon.components_scene(sc)
pt.configure_output(sc, 48, 32)
pt.configure_phos(sc, 2)
test_photon.configure_photons(sc, 50000, 20000, gather_rays=4)
bpy.ops.render.render()
print("STAGES-SCRIPT-DONE")
"""


def test_background_render_prints_stages(tmp_path):
    """`blender -b` prints the engine's stats lines: every stage shows, in
    order (Blender up to 4.x prints them; 5.x prints them only when its
    render log is on, so Phos prints its own there)."""
    rc, out = pt.run_script(STAGES_SCRIPT, tmp_path, timeout=120)
    assert rc == 0 and "STAGES-SCRIPT-DONE" in out, out[-3000:]
    lines = [line for line in out.splitlines() if "Phos | " in line]
    stages = ["Tracing photons", "Building kd-trees", "Precomputing radiance", "Rendering", "Finished"]
    positions = []
    for stage in stages:
        found = [i for i, line in enumerate(lines) if "Phos | %s" % stage in line]
        assert found, "no '%s' line in:\n%s" % (stage, "\n".join(lines))
        positions.append(found[0])
    assert positions == sorted(positions), "stages out of order:\n%s" % "\n".join(lines)
    tracing = next(line for line in lines if "Tracing photons" in line)
    assert " stored" in tracing
    finished = next(line for line in lines if "Phos | Finished" in line)
    # The last line keeps the render's time beside its photons and records.
    assert re.search(r"Phos \| Finished in \d+\.\d\d s \|", finished), finished
    # A map stops after the path that fills it, which may store a photon at
    # each of its surfaces (at most max_bounces + 1).
    m = re.search(r"photons ([\d,]+) global, ([\d,]+) caustic", finished)
    assert m, finished
    stored = [int(g.replace(",", "")) for g in m.groups()]
    max_bounces = 8  # configure_phos's default, used by STAGES_SCRIPT
    assert 50000 <= stored[0] <= 50000 + max_bounces + 1, finished
    assert 20000 <= stored[1] <= 20000 + max_bounces + 1, finished


SHORT_MAP_SCRIPT = r"""
import bpy
import phostest as pt
sc = pt.reset_file()
grey = pt.diffuse("Grey", (0.6, 0.6, 0.6))
pt.add_cube(sc, "Cube", size=1.0, material=grey)
# A floor the cube's gathers reach: without anything to read it, the
# global map would not be traced at all (docs/algorithms.md §3.1).
pt.add_plane(sc, "Floor", size=10.0, location=(0, 0, -0.5), material=grey)
pt.add_light(sc, 'SPOT', 500.0, location=(2, -1, 3), target=(4, -2, 6), spot_size=0.8)
pt.set_world(sc, (0, 0, 0), 0.0)
pt.add_camera(sc)
pt.configure_output(sc, 32, 24)
pt.configure_phos(sc, 1)
sc.phos.integrator = 'PHOTON'
sc.render.engine = 'PHOS'
bpy.ops.render.render()
print("SHORT-MAP-SCRIPT-DONE")
"""


def test_short_map_is_reported(tmp_path):
    """A spot turned away from the cube and its floor lights nothing: the
    global pass stops at its probe of 1 M paths instead of emitting the
    50 M the cap allows, and the render says so in a warning naming the
    map."""
    rc, out = pt.run_script(SHORT_MAP_SCRIPT, tmp_path, timeout=120)
    assert rc == 0 and "SHORT-MAP-SCRIPT-DONE" in out, out[-3000:]
    assert re.search(r"the global photon map holds 0 of 200,000 photons", out), out[-3000:]
    emitted = re.findall(r"([\d,]+) emitted", out)
    assert emitted and int(emitted[-1].replace(",", "")) <= 2000000, emitted[-3:]


FAINT_CAUSTIC_SCRIPT = r"""
import bpy
import phostest as pt
sc = pt.reset_file()
pt.add_plane(sc, "Floor", size=10.0, material=pt.diffuse("Grey", (0.6, 0.6, 0.6)))
# A coat that reflects 4 % sharply over a 90 % diffuse base: aimed caustic
# paths mostly leave it by the diffuse part, which ends them.
mat, nt, out = pt.empty_material("Coat")
base = pt.setup_node(nt.nodes.new("ShaderNodeBsdfDiffuse"), {"Color": (0.9, 0.9, 0.9)})
mirror = pt.setup_node(nt.nodes.new("ShaderNodeBsdfGlossy"), {"Color": (1.0, 1.0, 1.0)}, {"distribution": "SHARP"})
mix = pt.setup_node(nt.nodes.new("ShaderNodeMixShader"), {"Fac": 0.04})
nt.links.new(base.outputs[0], mix.inputs[1])
nt.links.new(mirror.outputs[0], mix.inputs[2])
nt.links.new(mix.outputs[0], out.inputs["Surface"])
pt.add_sphere(sc, "Ball", radius=0.5, location=(0, 0, 0.5), material=mat)
pt.add_light(sc, 'POINT', 500.0, location=(1, -1, 3))
pt.set_world(sc, (0, 0, 0), 0.0)
pt.add_camera(sc)
pt.configure_output(sc, 32, 24)
pt.configure_phos(sc, 1)
sc.phos.integrator = 'PHOTON'
sc.phos.caustic_photons = 20000
sc.render.engine = 'PHOS'
bpy.ops.render.render()
print("FAINT-CAUSTIC-SCRIPT-DONE")
"""


def test_faint_caustic_short_map_is_reported(tmp_path):
    """A faint caustic stops at ten paths a caustic photon asked for
    (docs/algorithms.md §3.2): the render warns that the caustic map is
    short and gives that reason, not the global map's."""
    rc, out = pt.run_script(FAINT_CAUSTIC_SCRIPT, tmp_path, timeout=120)
    assert rc == 0 and "FAINT-CAUSTIC-SCRIPT-DONE" in out, out[-3000:]
    m = re.search(r"the caustic photon map holds ([\d,]+) of 20,000 photons: few of its lights' paths", out)
    assert m, out[-3000:]
    assert 0 < int(m.group(1).replace(",", "")) < 20000, m.group(0)
    assert "global photon map holds" not in out, out[-3000:]


# ------------------------------------------------------------ determinism

def test_photon_render_thread_count_bit_identical(scene, tmp_path):
    """The maps are assembled in path order: 1 and 2 threads give the same
    pixels in every pass (flat shading: see test_tiles_border.py)."""
    components_scene(scene, flat=True)
    pt.configure_output(scene, 48, 32)
    pt.configure_phos(scene, 4, tile_size=16)
    configure_photons(scene, 20000, 20000, gather_rays=8)
    enable_passes(scene)
    pt.configure_threads(scene, 1)
    one = render_passes(scene, tmp_path, "threads_1")
    pt.configure_threads(scene, 2)
    two = render_passes(scene, tmp_path, "threads_2")
    assert set(one) == set(two) == {"Combined"} | set(LIGHT_PASSES) | set(DEBUG_PASSES)
    for name in one:
        differ = np.any(one[name] != two[name], axis=-1)
        assert not differ.any(), "%s: %d pixels differ between 1 and 2 threads" % (name, differ.sum())
    assert one["Caustics"].max() > 0 and one["Photons"].max() > 0


# ------------------------------------------------------------ placeholder

def test_failed_render_writes_every_pass(scene, monkeypatch):
    """When the export fails, the placeholder result still writes every
    registered pass (zeros), as Blender would merge unwritten ones anyway."""
    from phos import core, engine, export
    components_scene(scene)
    pt.configure_output(scene, 32, 24)
    enable_passes(scene)

    def failing_export(*args, **kwargs):
        raise core.PhosError("export failed on purpose")

    written = []
    original_write = engine._write_rect

    def spy_write(render_pass, pixels):
        written.append((render_pass.name, pixels.shape, float(np.abs(pixels).max())))
        original_write(render_pass, pixels)

    monkeypatch.setattr(export, "export_scene", failing_export)
    monkeypatch.setattr(engine, "_write_rect", spy_write)
    with pytest.raises(RuntimeError, match="export failed on purpose"):
        bpy.ops.render.render()
    names = {name for name, _, _ in written}
    assert names == {"Combined"} | set(LIGHT_PASSES) | set(DEBUG_PASSES), sorted(names)
    for name, shape, peak in written:
        assert shape == (32 * 24, 4 if name == "Combined" else 3), (name, shape)
        assert peak == 0.0, name


def test_render_reports_stage_times_and_rays(scene):
    """After an F12 the add-on keeps what each stage took and how many rays
    the tiles cast (bench/quality.py reads them; Blender's console shows
    them): every stage of the plan, and at least one camera ray a sample."""
    from phos import core, engine
    components_scene(scene)
    pt.configure_output(scene, 32, 24)
    pt.configure_phos(scene, 4, max_bounces=4)
    configure_photons(scene, 2000, 2000, gather_rays=2)
    bpy.ops.render.render()
    seconds = engine.last_render_seconds
    print("last render: %s" % seconds)
    assert seconds["export"] > 0.0
    for stage in (core.PHOS_STAGE_TRACING_PHOTONS, core.PHOS_STAGE_BUILDING_KDTREES, core.PHOS_STAGE_RENDERING):
        assert seconds[stage] > 0.0, stage
    assert seconds["rays"] >= 32 * 24 * 4


# ------------------------------------------------------------ translucency

LEAF_SIZE = 64
LEAF_REFERENCE_SAMPLES = 512
LEAF_PHOTON_SAMPLES = 16
LEAF_SEEDS = 4
LEAF_MEAN_T = 6.0


@pytest.mark.parametrize("cache", ["PHOTON", "OFF"], ids=["irradiance_cache", "final_gather"])
def test_translucent_leaf_photon_matches_path(cache, scene, tmp_path):
    """A leaf (Diffuse + Translucent) lit from behind (parity_scenes, whose
    PATH render matches Cycles): PHOTON must carry the light through it —
    the camera path traces on through the translucent closure, gathers read
    the photons that reached its back side — to the mean PATH gives. The
    tolerance is LEAF_MEAN_T standard errors of the ratio: the spread of
    PHOTON's image means over seeds (a photon map's error is shared by
    every pixel of a render; Student's t with LEAF_SEEDS − 1 degrees of
    freedom, P(|t| > 6) ≈ 1 %) with the PATH reference's own. With the
    irradiance cache and with a final gather at every sample. Measured on
    3.4 when gathers did not read the photons on the leaf's back side: 0.9946
    and 0.9931, 0.5 % and 0.7 % dark."""
    import parity_scenes
    parity_scenes._translucent_leaf(scene)
    pt.configure_output(scene, LEAF_SIZE, LEAF_SIZE)
    pt.configure_phos(scene, LEAF_REFERENCE_SAMPLES // 2)
    scene.render.engine = "PHOS"
    paths = []
    for seed in (1, 2):
        scene.phos.seed = seed
        paths.append(pt.render_array(scene, tmp_path, name="leaf_path_%d" % seed)[..., :3].astype(np.float64))
    reference = 0.5 * (paths[0] + paths[1])
    # PATH's pixels are independent: the standard error of the reference's
    # mean from the two seeds' per-pixel differences, Var = (P1 − P2)²/2.
    se_reference = float(np.sqrt(np.sum((paths[0] - paths[1]) ** 2)) / (2.0 * paths[0].size)) / reference.mean()
    scene.phos.samples = LEAF_PHOTON_SAMPLES
    configure_photons(scene, 200000, 20000, k_global=100, k_caustic=50, gather_rays=32)
    scene.phos.irradiance_cache = cache
    means = []
    for seed in range(LEAF_SEEDS):
        scene.phos.seed = seed
        image = pt.render_array(scene, tmp_path, name="leaf_photon_%d" % seed)
        means.append(float(image[..., :3].astype(np.float64).mean()))
    scene.phos.seed = 0
    ratio = np.array(means) / reference.mean()
    se = float(np.sqrt(np.var(ratio, ddof=1) / len(ratio) + se_reference ** 2))
    print("\ntranslucent leaf PHOTON (irradiance cache %s) / PATH image mean over %d seeds: %.4f ± %.4f "
          "(PATH's own %.4f; seeds %s)" % (cache, LEAF_SEEDS, ratio.mean(), se, se_reference,
                                           " ".join("%.4f" % r for r in ratio)))
    assert abs(ratio.mean() - 1.0) < LEAF_MEAN_T * se, \
        "PHOTON/PATH %.4f (tolerance %.4f)" % (ratio.mean(), LEAF_MEAN_T * se)
