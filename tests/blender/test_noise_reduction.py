# SPDX-License-Identifier: GPL-3.0-or-later
"""Noise reduction as a user sets it in Blender (issue 24): the sampler,
adaptive sampling, the time limit and the noise filter, and their passes.

- Every setting is a scene.phos property drawn in the Sampling panel;
  each sampler renders, and two seeds of one sampler differ.
- Adaptive sampling writes a Sample Count pass whose counts differ across
  the image and stay between the minimum and the Samples setting.
- A time limit ends a render of a million samples a pixel by itself.
- Filtering the indirect irradiance leaves a checker texture's edges as
  sharp as unfiltered, while filtering everything (the slides' "everything
  is filtered") blurs them; both lower the noise between two seeds away
  from the edges. The Noisy Image pass keeps the unfiltered image.
"""

import bpy
import numpy as np
import pytest

import phostest as pt
import test_photon

SAMPLERS = ('RANDOM', 'STRATIFIED', 'HALTON', 'SOBOL')
FILTERS = ('NONE', 'LOWPASS', 'MEDIAN', 'ADAPTIVE_WIDTH', 'DIFFUSION', 'SPLATTING')


def _checker_room(scene):
    """A floor with a procedural checker (0.8 / 0.1 grey, squares of ~8
    pixels), a back wall and a side wall that light it indirectly, under an
    area lamp; the camera looks down at the floor."""
    mat, nt, out = pt.empty_material("Checker")
    checker = nt.nodes.new("ShaderNodeTexChecker")
    checker.inputs["Color1"].default_value = (0.8, 0.8, 0.8, 1.0)
    checker.inputs["Color2"].default_value = (0.1, 0.1, 0.1, 1.0)
    checker.inputs["Scale"].default_value = 6.0
    bsdf = nt.nodes.new("ShaderNodeBsdfDiffuse")
    nt.links.new(checker.outputs["Color"], bsdf.inputs["Color"])
    nt.links.new(bsdf.outputs[0], out.inputs["Surface"])
    pt.add_plane(scene, "Floor", size=4.0, material=mat)
    wall = pt.diffuse("Wall", (0.8, 0.6, 0.4))
    pt.add_plane(scene, "Back", size=4.0, location=(0, 2, 2), rotation=(pt.angle(90), 0, 0), material=wall)
    pt.add_plane(scene, "Side", size=4.0, location=(-2, 0, 2), rotation=(0, pt.angle(90), 0), material=wall)
    pt.add_light(scene, 'AREA', 300.0, location=(1.0, -0.5, 2.5), target=(0, 0, 0), size=0.5)
    pt.set_world(scene, (0, 0, 0), 0.0)
    pt.add_camera(scene, location=(0, -2.2, 3.2), target=(0, 0.3, 0), lens=30.0)
    pt.configure_output(scene, 96, 72)


def _render(scene, tmp_path, name):
    return test_photon.render_passes(scene, tmp_path, name)


def test_settings_in_the_sampling_panel():
    phos = bpy.context.scene.phos
    assert phos.sampler == 'SOBOL'
    assert {i.identifier for i in phos.bl_rna.properties["sampler"].enum_items} == set(SAMPLERS)
    assert {i.identifier for i in phos.bl_rna.properties["filter"].enum_items} == set(FILTERS)
    assert phos.filter == 'NONE' and phos.filter_target == 'INDIRECT_IRRADIANCE'
    assert not phos.use_adaptive_sampling and phos.time_limit == 0.0
    assert hasattr(bpy.types, "PHOS_RENDER_PT_sampling_adaptive")
    assert hasattr(bpy.types, "PHOS_RENDER_PT_sampling_filter")


@pytest.mark.parametrize("sampler", SAMPLERS)
def test_each_sampler_renders(scene, tmp_path, sampler):
    _checker_room(scene)
    pt.configure_phos(scene, 4, max_bounces=3, seed=1)
    scene.render.engine = 'PHOS'
    scene.phos.sampler = sampler
    a = _render(scene, tmp_path, "a")["Combined"][..., :3]
    scene.phos.seed = 2
    b = _render(scene, tmp_path, "b")["Combined"][..., :3]
    assert np.all(np.isfinite(a)) and a.mean() > 0.01
    assert not np.array_equal(a, b), "another seed gave the same image"
    # Same brightness within the two images' noise.
    assert abs(a.mean() - b.mean()) < 0.05 * a.mean()


def test_adaptive_sampling_sample_count(scene, tmp_path):
    _checker_room(scene)
    pt.configure_phos(scene, 256, max_bounces=3, seed=1)
    scene.render.engine = 'PHOS'
    phos = scene.phos
    phos.use_adaptive_sampling = True
    phos.adaptive_threshold = 0.05
    phos.adaptive_min_samples = 8
    scene.view_layers[0].phos.use_pass_sample_count = True
    passes = _render(scene, tmp_path, "adaptive")
    assert "Sample Count" in passes, sorted(passes)
    n = passes["Sample Count"][..., 0] * 256
    assert n.min() >= 8 - 1e-3 and n.max() <= 256 + 1e-3
    assert n.min() < n.max(), "every pixel took the same samples"
    assert np.allclose(n, np.round(n), atol=1e-3)
    print("\nadaptive: %.0f..%.0f samples, mean %.1f" % (n.min(), n.max(), n.mean()))


def test_time_limit_ends_the_render(scene, tmp_path):
    _checker_room(scene)
    pt.configure_phos(scene, 1 << 20, max_bounces=3, seed=1)
    scene.render.engine = 'PHOS'
    scene.phos.time_limit = 0.5
    scene.view_layers[0].phos.use_pass_sample_count = True
    passes = _render(scene, tmp_path, "limited")
    n = passes["Sample Count"][..., 0] * (1 << 20)
    assert n.min() >= 1 - 1e-3 and n.max() < (1 << 20)
    assert np.all(np.isfinite(passes["Combined"]))


def _edges_and_noise(scene, tmp_path, filter_kind, target):
    """Edge contrast (mean |step| across the checker's edges, found in the
    albedo pass) and noise (variance of the difference of two seeds, away
    from the edges) of the Combined pass."""
    phos = scene.phos
    phos.filter, phos.filter_target = filter_kind, target
    images = []
    for seed in (1, 2):
        phos.seed = seed
        p = _render(scene, tmp_path, "%s_%s_%d" % (filter_kind, target, seed))
        images.append((p["Combined"][..., :3].astype(np.float64), p))
    albedo = images[0][1]["Denoising Albedo"][..., 0]
    step_x = np.abs(np.diff(albedo, axis=1)) > 0.3
    edge = np.zeros(albedo.shape, bool)
    edge[:, 1:] |= step_x
    edge[:, :-1] |= step_x
    flat = ~edge
    for _ in range(2):  # two pixels away from any edge (the lowpass reaches one)
        grown = flat.copy()
        grown[1:, :] &= flat[:-1, :]
        grown[:-1, :] &= flat[1:, :]
        grown[:, 1:] &= flat[:, :-1]
        grown[:, :-1] &= flat[:, 1:]
        flat = grown
    mean = 0.5 * (images[0][0] + images[1][0])
    contrast = float(np.mean(np.abs(np.diff(mean, axis=1))[step_x]))
    noise = float(np.var((images[0][0] - images[1][0])[flat]))
    return contrast, noise, images[0][1]


def test_filtering_indirect_irradiance_keeps_texture_edges(scene, tmp_path):
    _checker_room(scene)
    pt.configure_phos(scene, 4, max_bounces=4, seed=1)
    scene.render.engine = 'PHOS'
    scene.phos.integrator = 'PATH'
    vl = scene.view_layers[0].phos
    vl.use_pass_denoising_albedo = True
    vl.use_pass_noisy_image = True
    raw = _edges_and_noise(scene, tmp_path, 'NONE', 'INDIRECT_IRRADIANCE')
    everything = _edges_and_noise(scene, tmp_path, 'LOWPASS', 'ALL')
    irradiance = _edges_and_noise(scene, tmp_path, 'LOWPASS', 'INDIRECT_IRRADIANCE')
    print("\nedge contrast / noise: unfiltered %.4f / %.3g, everything %.4f / %.3g, indirect irradiance %.4f / %.3g"
          % (raw[0], raw[1], everything[0], everything[1], irradiance[0], irradiance[1]))
    assert everything[0] < 0.8 * raw[0], "filtering everything should blur the checker's edges"
    assert irradiance[0] > 0.9 * raw[0], "filtering the indirect irradiance blurred the checker's edges"
    assert everything[1] < 0.7 * raw[1] and irradiance[1] < 0.9 * raw[1], "the filter lowered no noise"
    # The Noisy Image pass holds the unfiltered image.
    passes = irradiance[2]
    assert "Noisy Image" in passes
    assert not np.array_equal(passes["Noisy Image"], passes["Combined"])
