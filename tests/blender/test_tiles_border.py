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

import time

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


class _Spy:
    """Records what the engine takes from the core: the rectangles it reads
    (`reads`, one per pass of each delivered result, with `read_samples`,
    the samples every pixel had then) and the finished tiles it is told of
    (`tiles`, from next_tile)."""

    def __init__(self):
        from phos import core
        self.core = core
        self.reads, self.read_samples, self.tiles = [], [], []

    def __enter__(self):
        self.original_read, self.original_next = self.core.Render.read, self.core.Render.next_tile
        original_read, original_next = self.original_read, self.original_next
        reads, read_samples, tiles = self.reads, self.read_samples, self.tiles

        def read(render, pass_id, x, y, width, height, out=None):
            reads.append((x, y, width, height))
            read_samples.append(render.progress().samples_done)
            return original_read(render, pass_id, x, y, width, height, out)

        def next_tile(render):
            t = original_next(render)
            if t is not None:
                tiles.append((t.x, t.y, t.width, t.height))
            return t
        self.core.Render.read, self.core.Render.next_tile = read, next_tile
        return self

    def __exit__(self, *exc):
        self.core.Render.read, self.core.Render.next_tile = self.original_read, self.original_next
        return False


def _whole_frame_reads_only(spy):
    """Every result the engine gave Blender covered the whole frame: Blender
    5.2 locks up on results of part of it (docs/blender.md §3)."""
    assert spy.reads, "nothing was delivered"
    assert set(spy.reads) == {(0, 0, WIDTH, HEIGHT)}, sorted(set(spy.reads))[:5]


def test_small_tiles_stream_and_match_large_tiles(glass_scene, tmp_path):
    # One pass: each tile finishes once (progressive refinement, below,
    # finishes it once per pass).
    glass_scene.phos.use_progressive_refine = False
    # One thread: the 1024 px setting is halved only until that thread has
    # 16 tiles (16 px here), so the two renders tile the frame differently.
    glass_scene.phos.tile_size = 1024
    glass_scene.render.threads_mode = 'FIXED'
    glass_scene.render.threads = 1
    with _Spy() as big:
        large = pt.render_array(glass_scene, tmp_path, name="tiles_large")
    glass_scene.render.threads_mode = 'AUTO'
    glass_scene.phos.tile_size = 8
    with _Spy() as small:
        tiled = pt.render_array(glass_scene, tmp_path, name="tiles_small")

    assert tiled.shape == (HEIGHT, WIDTH, 4)
    # Complete: the world is visible everywhere, so every pixel is opaque and lit.
    assert np.all(tiled[..., 3] == 1.0), "pixels missing: %d with alpha != 1" % np.sum(tiled[..., 3] != 1)
    assert np.all(tiled[..., :3].sum(axis=2) > 0)
    # The core finishes 8 px tiles, together covering the frame exactly once;
    # Blender gets the whole frame, once or a few times, never a tile.
    n_tiles = -(-WIDTH // 8) * -(-HEIGHT // 8)
    assert len(small.tiles) == n_tiles, "%d tiles finished, %d expected" % (len(small.tiles), n_tiles)
    assert all(w <= 8 and h <= 8 for _, _, w, h in small.tiles)
    cover = np.zeros((HEIGHT, WIDTH), int)
    for x, y, w, h in small.tiles:
        cover[y:y + h, x:x + w] += 1
    assert np.all(cover == 1), "tiles overlap or leave gaps"
    _whole_frame_reads_only(small)
    # The 1024 px setting is split (each thread gets tiles to choose from)
    # but stays coarser than 8 px, and covers the frame once.
    assert 1 < len(big.tiles) < len(small.tiles), (len(big.tiles), len(small.tiles))
    cover[:] = 0
    for x, y, w, h in big.tiles:
        cover[y:y + h, x:x + w] += 1
    assert np.all(cover == 1), "large tiles overlap or leave gaps"
    _whole_frame_reads_only(big)
    # Deterministic whatever the tiling.
    diff = np.argwhere(np.any(tiled != large, axis=2))
    assert diff.size == 0, "%d pixels differ between 8 px tiles and 1024 px on one thread, first at (y, x) %s" % (
        len(diff), diff[:5].tolist())


def test_progressive_refinement_streams_passes_and_matches_one_pass(glass_scene, tmp_path):
    """F12 with progressive refinement (the default): the core finishes each
    tile once per pass (1, 2, 4, 8 samples); Blender gets the whole frame,
    first once the first pass covers it (a result of part of the frame
    showed holes on a redraw: tests/gui/test_final_render.py), then at most
    every DISPLAY_SECONDS and at the end; the last image equals the
    one-pass render's bit for bit."""
    glass_scene.phos.tile_size = 16
    assert glass_scene.phos.use_progressive_refine
    with _Spy() as progressive:
        refined = pt.render_array(glass_scene, tmp_path, name="progressive")
    glass_scene.phos.use_progressive_refine = False
    with _Spy() as single:
        one_pass = pt.render_array(glass_scene, tmp_path, name="one_pass")
    passes = 4  # samples 1, 2, 4, 8
    assert len(progressive.tiles) == passes * len(single.tiles), (len(progressive.tiles), len(single.tiles))
    assert sorted(set(progressive.tiles)) == sorted(single.tiles)
    _whole_frame_reads_only(progressive)
    _whole_frame_reads_only(single)
    assert progressive.read_samples[0] >= 1, "the first read came before the first pass covered the frame"
    diff = np.argwhere(np.any(refined != one_pass, axis=2))
    assert diff.size == 0, "%d pixels differ between progressive refinement and one pass, first at %s" % (
        len(diff), diff[:5].tolist())


def test_display_refreshes_at_most_every_display_seconds(glass_scene, tmp_path, monkeypatch):
    """While a render runs, Blender gets the whole frame at most every
    DISPLAY_SECONDS (reading a large frame with many passes costs time the
    render needs), plus once at the end: a render of a few seconds on one
    thread, its deliveries timed. An engine that delivered at every poll
    (30 ms) or every tile would fail."""
    from phos import engine
    times = []
    original = engine.PhosRenderEngine._deliver_whole

    def timed(self, render, rs, buffers):
        times.append(time.monotonic())
        return original(self, render, rs, buffers)
    monkeypatch.setattr(engine.PhosRenderEngine, "_deliver_whole", timed)
    glass_scene.phos.samples = 1024  # about 4 s here: three deliveries need more than 1 s
    glass_scene.phos.tile_size = 8
    pt.configure_threads(glass_scene, 1)
    start = time.monotonic()
    pt.render_array(glass_scene, tmp_path, name="throttled")
    seconds = time.monotonic() - start
    assert len(times) >= 3, "%d deliveries in a %.1f s render" % (len(times), seconds)
    gaps = np.diff(times[:-1])  # the last delivery is the end's, whenever the render ends
    assert gaps.min() >= 0.95 * engine.DISPLAY_SECONDS, "deliveries %.3f s apart" % gaps.min()


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
