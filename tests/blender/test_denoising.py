# SPDX-License-Identifier: GPL-3.0-or-later
"""The Denoising Albedo and Denoising Normal passes, and a Phos render
through the compositor's Denoise node.

- The passes as Cycles defines them: on a scene of diffuse, mirror and
  glass objects under a lamp and a world, Phos's passes against Cycles' own
  (view_layer.cycles.denoising_store_passes): channel means within 2 %,
  and the same pixels per 8 × 8 block (both engines average each pixel's
  samples, so only the sampling noise of edges differs).
- Denoising works: the denoised PHOTON image of the Cornell box at a few
  samples has a lower relative MSE against a converged Cycles reference
  than the raw one (needs OpenImageDenoise, which the official builds
  have and Debian's Blender does not).
"""

import os

import bpy
import numpy as np
import pytest

import exrread
import phostest as pt
import test_photon


def _with_oidn():
    try:
        import _cycles
    except ImportError:
        return False
    return bool(getattr(_cycles, "with_openimagedenoise", False))


def _enable_features(scene):
    vl = scene.view_layers[0]
    vl.phos.use_pass_denoising_albedo = True
    vl.phos.use_pass_denoising_normal = True
    vl.cycles.denoising_store_passes = True


def _render_passes(scene, tmp_path, engine, name):
    scene.render.engine = engine
    return test_photon.render_passes(scene, tmp_path, name)


def test_passes_match_cycles(scene, tmp_path):
    test_photon.components_scene(scene)
    pt.configure_output(scene, 64, 48)
    pt.configure_phos(scene, 32, max_bounces=8, seed=1)
    pt.configure_cycles(scene, 32, max_bounces=8, seed=1)
    scene.cycles.use_denoising = False
    _enable_features(scene)
    phos = _render_passes(scene, tmp_path, "PHOS", "phos")
    cycles = _render_passes(scene, tmp_path, "CYCLES", "cycles")
    for name in ("Denoising Albedo", "Denoising Normal"):
        assert name in phos, "Phos wrote no %s pass: %s" % (name, sorted(phos))
        assert name in cycles, "test setup: Cycles wrote no %s pass: %s" % (name, sorted(cycles))
        p, c = phos[name][..., :3], cycles[name][..., :3]
        assert np.all(np.isfinite(p)), name
        mp, mc = p.reshape(-1, 3).mean(axis=0), c.reshape(-1, 3).mean(axis=0)
        scale = np.abs(c).reshape(-1, 3).mean(axis=0).max()
        assert np.all(np.abs(mp - mc) < 0.02 * scale + 1e-3), "%s means: Phos %s, Cycles %s" % (name, mp, mc)
        blocks_p, blocks_c = test_photon.box_down(p, 8), test_photon.box_down(c, 8)
        worst = float(np.abs(blocks_p - blocks_c).max())
        assert worst < 0.05 * scale + 0.01, "%s: an 8x8 block differs by %.4f (Phos %s, Cycles %s)" % (
            name, worst, blocks_p.reshape(-1, 3)[np.abs(blocks_p - blocks_c).reshape(-1, 3).max(axis=1).argmax()],
            blocks_c.reshape(-1, 3)[np.abs(blocks_p - blocks_c).reshape(-1, 3).max(axis=1).argmax()])
    # Normals are unit where a surface was found (the mean of a pixel's
    # samples, shorter on edges).
    n = phos["Denoising Normal"]
    lengths = np.linalg.norm(n, axis=-1)
    assert np.median(lengths) > 0.99, np.median(lengths)


def _relmse(img, ref):
    return float(np.mean((img - ref) ** 2 / (ref ** 2 + 1e-2)))


@pytest.mark.skipif(not _with_oidn(), reason="this Blender has no OpenImageDenoise (Debian's builds)")
def test_denoise_node_lowers_the_error(scene, tmp_path):
    import importlib
    import sys
    scenes_dir = os.path.join(pt.REPO_DIR, "scenes")
    if scenes_dir not in sys.path:
        sys.path.insert(0, scenes_dir)
    importlib.import_module("cornell_box").build(scene)
    pt.configure_output(scene, 96, 96)
    pt.configure_cycles(scene, 2048, max_bounces=8, seed=7)
    scene.cycles.use_denoising = False
    reference = pt.render_array(scene, tmp_path, engine="CYCLES", name="reference")[..., :3]

    pt.configure_phos(scene, 8, max_bounces=8, seed=1)
    scene.phos.integrator = "PHOTON"
    _enable_features(scene)
    raw = pt.render_array(scene, tmp_path, engine="PHOS", name="raw")[..., :3]

    tree = pt.compositor_tree(scene)
    layers = tree.nodes.new("CompositorNodeRLayers")
    denoise = tree.nodes.new("CompositorNodeDenoise")
    tree.links.new(layers.outputs["Image"], denoise.inputs["Image"])
    tree.links.new(layers.outputs["Denoising Albedo"], denoise.inputs["Albedo"])
    tree.links.new(layers.outputs["Denoising Normal"], denoise.inputs["Normal"])
    tree.links.new(denoise.outputs["Image"], pt.compositor_output(tree))
    scene.render.use_compositing = True
    denoised = pt.render_array(scene, tmp_path, engine="PHOS", name="denoised")[..., :3]

    e_raw, e_den = _relmse(raw, reference), _relmse(denoised, reference)
    print("\nCornell box, PHOTON 8 spp: relMSE raw %.5f, denoised %.5f (%.1fx lower)"
          % (e_raw, e_den, e_raw / max(e_den, 1e-12)))
    assert not np.array_equal(raw, denoised), "the compositor did not run"
    assert e_den < e_raw, "denoising raised the error: raw %.5f, denoised %.5f" % (e_raw, e_den)
