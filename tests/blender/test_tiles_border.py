# SPDX-License-Identifier: GPL-3.0-or-later
"""Tiles, borders and threads: the core is deterministic (random numbers are
a hash of seed, pixel, sample and dimension), so every way of cutting the
work must give bit-identical pixels.

The scene is flat-shaded on purpose: Blender 3.4 computes smooth (vertex)
normals with multi-threaded accumulation, so each depsgraph evaluation of a
smooth mesh may differ in the last bits (26 of 39 evaluations of a UV sphere
differed; none with `blender -t 1`). That would change the input, not test
the core. Face normals are computed per face and are stable.
"""

import numpy as np
import pytest

import parity_scenes
import phostest as pt

# Not multiples of the tile sizes, so edge tiles are partial.
WIDTH, HEIGHT = 75, 50
SAMPLES = 8


@pytest.fixture
def glass_scene(scene):
    """Floor, rough glass sphere, area light and world: many random dimensions per path."""
    parity_scenes.MATERIAL_SCENES["glass_ggx"](scene)
    for ob in scene.objects:
        if ob.type == "MESH":
            for poly in ob.data.polygons:
                poly.use_smooth = False  # see the module docstring
    pt.configure_output(scene, WIDTH, HEIGHT)
    pt.configure_phos(scene, SAMPLES, max_bounces=6, seed=7, tile_size=32)
    pt.configure_threads(scene, 2)
    scene.render.engine = "PHOS"
    return scene


class _ReadSpy:
    """Records the rectangles the engine reads from the core (one per delivered tile)."""

    def __init__(self):
        from phos import core
        self.core = core
        self.rects = []

    def __enter__(self):
        original = self.original = self.core.Render.read
        rects = self.rects

        def read(render, pass_id, x, y, width, height, out=None):
            rects.append((x, y, width, height))
            return original(render, pass_id, x, y, width, height, out)
        self.core.Render.read = read
        return self

    def __exit__(self, *exc):
        self.core.Render.read = self.original
        return False


def test_small_tiles_stream_and_match_large_tiles(glass_scene, tmp_path):
    # One pass: each tile is delivered once (progressive refinement, below,
    # delivers it once per pass).
    glass_scene.phos.use_progressive_refine = False
    # One thread: the 1024 px setting is halved only until that thread has
    # 16 tiles (16 px here), so the two renders tile the frame differently.
    glass_scene.phos.tile_size = 1024
    glass_scene.render.threads_mode = 'FIXED'
    glass_scene.render.threads = 1
    with _ReadSpy() as big:
        large = pt.render_array(glass_scene, tmp_path, name="tiles_large")
    glass_scene.render.threads_mode = 'AUTO'
    glass_scene.phos.tile_size = 8
    with _ReadSpy() as small:
        tiled = pt.render_array(glass_scene, tmp_path, name="tiles_small")

    assert tiled.shape == (HEIGHT, WIDTH, 4)
    # Complete: the world is visible everywhere, so every pixel is opaque and lit.
    assert np.all(tiled[..., 3] == 1.0), "pixels missing: %d with alpha != 1" % np.sum(tiled[..., 3] != 1)
    assert np.all(tiled[..., :3].sum(axis=2) > 0)
    # Streamed: one read per 8 px tile, together covering the frame exactly once.
    n_tiles = -(-WIDTH // 8) * -(-HEIGHT // 8)
    assert len(small.rects) == n_tiles, "%d tiles delivered, %d expected" % (len(small.rects), n_tiles)
    assert all(w <= 8 and h <= 8 for _, _, w, h in small.rects)
    cover = np.zeros((HEIGHT, WIDTH), int)
    for x, y, w, h in small.rects:
        cover[y:y + h, x:x + w] += 1
    assert np.all(cover == 1), "tiles overlap or leave gaps"
    # The 1024 px setting is split (each thread gets tiles to choose from)
    # but stays coarser than 8 px, and covers the frame once.
    assert 1 < len(big.rects) < len(small.rects), (len(big.rects), len(small.rects))
    cover[:] = 0
    for x, y, w, h in big.rects:
        cover[y:y + h, x:x + w] += 1
    assert np.all(cover == 1), "large tiles overlap or leave gaps"
    # Deterministic whatever the tiling.
    diff = np.argwhere(np.any(tiled != large, axis=2))
    assert diff.size == 0, "%d pixels differ between 8 px tiles and 1024 px on one thread, first at (y, x) %s" % (
        len(diff), diff[:5].tolist())


def test_progressive_refinement_streams_passes_and_matches_one_pass(glass_scene, tmp_path):
    """F12 with progressive refinement (the default): the whole frame in one
    result after one sample a pixel, never the first pass tile by tile (a
    redraw then showed holes: tests/gui/test_final_render.py), then tiles
    as the passes of 1, 2, 4 more refine it (8 samples); the last image
    equals the one-pass render's bit for bit. How many of the later
    passes' tiles are read depends on how far the render got before the
    first pass was read: tiles finished by then are in that read."""
    glass_scene.phos.tile_size = 16
    assert glass_scene.phos.use_progressive_refine
    with _ReadSpy() as progressive:
        refined = pt.render_array(glass_scene, tmp_path, name="progressive")
    glass_scene.phos.use_progressive_refine = False
    with _ReadSpy() as single:
        one_pass = pt.render_array(glass_scene, tmp_path, name="one_pass")
    n_tiles = len(single.rects)
    passes = 4  # samples 1, 2, 4, 8
    assert progressive.rects[0] == (0, 0, WIDTH, HEIGHT), progressive.rects[:3]
    later = progressive.rects[1:]
    assert len(later) <= (passes - 1) * n_tiles
    assert set(later) <= set(single.rects), "a later read is not one of the tiles"
    diff = np.argwhere(np.any(refined != one_pass, axis=2))
    assert diff.size == 0, "%d pixels differ between progressive refinement and one pass, first at %s" % (
        len(diff), diff[:5].tolist())


def test_same_settings_same_image(glass_scene, tmp_path):
    a = pt.render_array(glass_scene, tmp_path)
    b = pt.render_array(glass_scene, tmp_path)
    assert np.array_equal(a, b)


def test_thread_counts_bit_identical(glass_scene, tmp_path):
    pt.configure_threads(glass_scene, 1)
    one = pt.render_array(glass_scene, tmp_path, name="threads_1")
    pt.configure_threads(glass_scene, 2)
    two = pt.render_array(glass_scene, tmp_path, name="threads_2")
    pt.configure_threads(glass_scene, None)
    auto = pt.render_array(glass_scene, tmp_path, name="threads_auto")
    assert np.array_equal(one, two), "%d pixels differ between 1 and 2 threads" % np.sum(
        np.any(one != two, axis=2))
    assert np.array_equal(one, auto)


def _blender_border_rect(scene):
    """The border's pixel rectangle as Blender computes it (float32 border × int size, truncated)."""
    r = scene.render
    w = r.resolution_x * r.resolution_percentage // 100
    h = r.resolution_y * r.resolution_percentage // 100
    f = np.float32
    return (int(f(r.border_min_x) * f(w)), int(f(r.border_min_y) * f(h)),
            int(f(r.border_max_x) * f(w)), int(f(r.border_max_y) * f(h)))


BORDERS = {
    "exact": (0.25, 0.625, 0.25, 0.75),   # binary fractions: no rounding question
    "awkward": (0.1, 0.84, 0.33, 0.58),   # 0.84 × 75 and 0.58 × 50 truncate differently in float32 and float64
}


@pytest.mark.parametrize("border", list(BORDERS))
def test_border_without_crop(border, glass_scene, tmp_path):
    full = pt.render_array(glass_scene, tmp_path, name="full")
    r = glass_scene.render
    r.use_border, r.use_crop_to_border = True, False
    r.border_min_x, r.border_max_x, r.border_min_y, r.border_max_y = BORDERS[border]
    x0, y0, x1, y1 = _blender_border_rect(glass_scene)
    img = pt.render_array(glass_scene, tmp_path, name="border")

    assert img.shape == full.shape, "without crop the image keeps the full size"
    inside = np.zeros(img.shape[:2], bool)
    inside[y0:y1, x0:x1] = True
    assert np.all(img[~inside] == 0.0), "pixels outside the border are not empty"
    assert np.all(img[inside][:, 3] == 1.0), (
        "pixels inside the border missing (alpha != 1): %d" % np.sum(img[inside][:, 3] != 1.0))
    # Determinism across regions: the border's pixels are the full frame's pixels.
    assert np.array_equal(img[y0:y1, x0:x1], full[y0:y1, x0:x1]), "%d border pixels differ" % np.sum(
        np.any(img[y0:y1, x0:x1] != full[y0:y1, x0:x1], axis=2))


@pytest.mark.parametrize("border", list(BORDERS))
def test_border_with_crop(border, glass_scene, tmp_path):
    full = pt.render_array(glass_scene, tmp_path, name="full")
    r = glass_scene.render
    r.use_border, r.use_crop_to_border = True, True
    r.border_min_x, r.border_max_x, r.border_min_y, r.border_max_y = BORDERS[border]
    x0, y0, x1, y1 = _blender_border_rect(glass_scene)
    img = pt.render_array(glass_scene, tmp_path, name="cropped")
    assert img.shape[:2] == (y1 - y0, x1 - x0)
    assert np.array_equal(img, full[y0:y1, x0:x1])


def test_border_with_small_tiles(glass_scene, tmp_path):
    """Tiles of a border start at the border's corner or on the frame grid: either way the pixels
    must be those of the full frame."""
    full = pt.render_array(glass_scene, tmp_path, name="full")
    r = glass_scene.render
    r.use_border, r.use_crop_to_border = True, True
    r.border_min_x, r.border_max_x, r.border_min_y, r.border_max_y = BORDERS["awkward"]
    glass_scene.phos.tile_size = 8
    x0, y0, x1, y1 = _blender_border_rect(glass_scene)
    img = pt.render_array(glass_scene, tmp_path, name="cropped_tiled")
    assert np.array_equal(img, full[y0:y1, x0:x1])


def test_resolution_percentage_border(glass_scene, tmp_path):
    """Border and percentage together: the border applies to the scaled frame."""
    r = glass_scene.render
    r.resolution_percentage = 50
    full = pt.render_array(glass_scene, tmp_path, name="half_full")
    assert full.shape[:2] == (HEIGHT // 2, WIDTH // 2)
    r.use_border, r.use_crop_to_border = True, True
    r.border_min_x, r.border_max_x, r.border_min_y, r.border_max_y = BORDERS["exact"]
    x0, y0, x1, y1 = _blender_border_rect(glass_scene)
    img = pt.render_array(glass_scene, tmp_path, name="half_cropped")
    assert np.array_equal(img, full[y0:y1, x0:x1])
