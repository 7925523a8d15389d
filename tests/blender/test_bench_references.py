# SPDX-License-Identifier: GPL-3.0-or-later
"""The benchmark's references come only from methods that converge to the
exact image as their samples grow (bench/quality.py): Cycles, or Phos with
progressive caustics and path-traced gathers. A method is never its own
reference: fixed-k PHOTON with more photons would keep its own blur.
Also what the benchmark reads and reports from its renders: a light pass
on its own (--pass), and the defaults' ranking over scenes."""

import glob
import importlib
import os
import sys
import types

import pytest

REPO_DIR = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO_DIR, "bench"))
sys.path.insert(0, os.path.join(REPO_DIR, "scenes"))

import quality  # noqa: E402

SCENES = sorted(os.path.splitext(os.path.basename(p))[0]
                for p in glob.glob(os.path.join(REPO_DIR, "scenes", "*.py"))
                if not os.path.basename(p).startswith("_"))


@pytest.mark.parametrize("name", SCENES)
def test_scene_reference_is_consistent(name):
    recipe = quality.reference_recipe(importlib.import_module(name))
    assert recipe["engine"] in ("CYCLES", "PHOS"), recipe
    if recipe["engine"] == "PHOS":
        for setting, value in quality.CONSISTENT_PHOS_REFERENCE.items():
            assert recipe["settings"][setting] == value, (name, setting)


def test_fixed_photon_reference_is_refused():
    """The recipe cube_caustic had before: PHOTON's own estimate with more
    photons."""
    module = types.ModuleType("fixed_reference_scene")
    module.BENCH_REFERENCE = {"engine": "PHOS", "chunks": 8, "chunk_samples": 128,
                              "settings": {"global_photons": 2000000, "caustic_photons": 4000000}}
    with pytest.raises(SystemExit, match="converge"):
        quality.reference_recipe(module)


def test_phos_reference_file_is_not_an_older_recipes():
    """A cached Phos reference from before (named *_phos.npz) is not read as
    the consistent one."""
    path = quality.reference_path("/refs", "cube_caustic", (128, 128), "PHOS")
    assert path.endswith("_phos_ppm.npz")
    assert quality.reference_path("/refs", "cube_caustic", (128, 128)) == "/refs/cube_caustic_128x128.npz"


@pytest.mark.parametrize("name", ["metal_ring", "glass_sphere_caustic"])
def test_phos_reference_on_request_is_consistent(name):
    """--reference-engine PHOS on a scene whose own reference is Cycles."""
    recipe = quality.reference_recipe(importlib.import_module(name), "PHOS")
    assert recipe["engine"] == "PHOS" and "chunks" not in recipe
    for setting, value in quality.CONSISTENT_PHOS_REFERENCE.items():
        assert recipe["settings"][setting] == value, setting


def test_pass_reference_is_kept_apart():
    """A reference of one light pass (--pass) is never read as the image's."""
    path = quality.reference_path("/refs", "glass_sphere_focus", (128, 128), "PHOS", "Caustics")
    assert path == "/refs/glass_sphere_focus_128x128_phos_ppm_caustics.npz"


def test_pass_needs_a_phos_reference():
    """Cycles has no Caustics pass: scoring one against a Cycles reference
    is refused rather than compared with Cycles' whole image."""
    args = types.SimpleNamespace(pass_name="Caustics")
    with pytest.raises(SystemExit, match="Phos reference"):
        quality.check_pass(args, "CYCLES")
    quality.check_pass(args, "PHOS")
    quality.check_pass(types.SimpleNamespace(pass_name=None), "CYCLES")


def test_convergence_reads_a_cached_reference(tmp_path):
    """bench/convergence.py asks quality.py for its references with
    arguments of its own: a cached one is read, not rendered again. (It
    once lacked the --pass argument quality.py had gained, and `make
    bench` stopped there.)"""
    import numpy as np
    import convergence
    image = np.full((4, 4, 3), 0.5, dtype=np.float32)
    path = quality.reference_path(str(tmp_path), "cornell_box", (4, 4))
    quality.Reference(image * 2, image * image * 2, 2, 16, {"engine": "CYCLES"}).save(path)
    args = types.SimpleNamespace(resolution=(4, 4), reference_dir=str(tmp_path), ref_chunks=2, chunk_samples=16)
    ref = convergence.ensure_reference(args, "cornell_box")
    assert ref.chunks == 2 and np.allclose(ref.mean, image)


def test_render_reads_the_caustics_pass():
    """quality.render(scene, "Caustics") returns the caustic estimate alone:
    bright where the glass sphere focuses the lamp, nowhere above the image,
    and a small part of the image's light."""
    scene, module = quality.build_scene("glass_sphere_caustic")
    quality.configure(scene, module, "PHOS", (48, 48), 2, 0, "PHOTON",
                      {"global_photons": 20000, "caustic_photons": 50000, "final_gather_rays": 4})
    caustics, _ = quality.render(scene, "Caustics")
    image, _ = quality.render(scene)
    assert caustics.shape == image.shape == (48, 48, 3)
    assert caustics.max() > 1.0  # the focus
    assert (caustics <= image + 1e-4).all()
    assert 0.0 < caustics.sum() < 0.5 * image.sum()


def test_defaults_report_groups_rows_by_their_settings(tmp_path, capsys):
    """bench/defaults_report.py ranks a setting measured on every scene.
    The photon tracing time, its share and the photon yield are
    measurements, which differ on every row: taken for settings, they left
    no setting common to two scenes."""
    import defaults_report
    fields = ["scene", "engine", "integrator", "samples", "caustic_photons", "seconds", "fixed_seconds",
              "full_hd_seconds", "relative_mse", "reference_share", "mean_ratio", "tracing_seconds",
              "tracing_share", "photon_yield"]
    rows = [["cornell_box", "PHOS", "PHOTON", 16, 800000, 2.0, 1.0, 9.0, 0.01, 0.0, 1.0, 0.4, 0.2, 0.9],
            ["sunlit_room", "PHOS", "PHOTON", 16, 800000, 3.0, 1.5, 12.0, 0.02, 0.0, 1.0, 0.7, 0.23, 0.8]]
    path = tmp_path / "sweep.csv"
    path.write_text("\n".join(",".join(str(v) for v in r) for r in [fields] + rows) + "\n")
    argv = sys.argv
    sys.argv = ["defaults_report.py", str(path)]
    try:
        defaults_report.main()
    finally:
        sys.argv = argv
    out = capsys.readouterr().out
    assert "1 settings measured on all of them" in out
    assert "caustic_photons=800000 samples=16" in out
