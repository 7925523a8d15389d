# SPDX-License-Identifier: GPL-3.0-or-later
"""Cancelling a render through the add-on's ctypes wrapper (phos.core).

Blender's test_break() is always False in background mode, so the engine's
cancel path cannot be driven from `blender -b`; the core's cancel is tested
directly, inside Blender's Python (same process, same libraries as a real
render). The spec bounds the latency: a cancelled render returns within
0.5 s. This is the only wall-clock assertion of the suite.
"""

import math
import threading
import time

import numpy as np
import pytest

CANCEL_LATENCY_S = 0.5


@pytest.fixture
def core(addon):
    from phos import core as c
    assert c.load() is not None, c.load_error()
    return c


def _sphere(n=48, m=24, r=0.5, centre=(0.0, 0.0, 0.5)):
    verts, tris = [], []
    for i in range(m + 1):
        th = math.pi * i / m
        for j in range(n):
            ph = 2 * math.pi * j / n
            verts.append((centre[0] + r * math.sin(th) * math.cos(ph),
                          centre[1] + r * math.sin(th) * math.sin(ph),
                          centre[2] + r * math.cos(th)))
    for i in range(m):
        for j in range(n):
            a, b = i * n + j, i * n + (j + 1) % n
            c, d = (i + 1) * n + j, (i + 1) * n + (j + 1) % n
            tris += [(a, c, b), (b, c, d)]
    return np.array(verts, np.float32), np.array(tris, np.uint32)


IDENTITY = (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0)


def build_scene(core):
    """Glass sphere on a diffuse floor, area light and world: expensive paths."""
    s = core.Scene()
    glass = core.new_closure()
    glass.type, glass.roughness, glass.ior = core.PHOS_CLOSURE_GLASS, 0.2, 1.5
    glass.weight[:] = (1, 1, 1)
    diffuse = core.new_closure()
    diffuse.type = core.PHOS_CLOSURE_DIFFUSE
    diffuse.weight[:] = (0.8, 0.8, 0.8)
    m_glass, m_diffuse = s.add_material([glass]), s.add_material([diffuse])
    v, t = _sphere()
    s.add_instance(s.add_mesh(v, t), IDENTITY, [m_glass])
    floor = np.array([(-4, -4, 0), (4, -4, 0), (4, 4, 0), (-4, 4, 0)], np.float32)
    s.add_instance(s.add_mesh(floor, np.array([(0, 1, 2), (0, 2, 3)], np.uint32)), IDENTITY, [m_diffuse])
    light = core.new_light()
    light.type = core.PHOS_LIGHT_AREA
    light.color[:] = (20, 20, 20)
    light.position[:] = (1.5, -1.5, 3.0)
    light.direction[:] = (0.0, 0.0, -1.0)
    light.axis_u[:] = (1.0, 0.0, 0.0)
    light.axis_v[:] = (0.0, 1.0, 0.0)
    s.add_light(light)
    world = core.new_world()
    world.color[:] = (0.3, 0.35, 0.4)
    s.set_world(world)
    cam = core.new_camera()
    cam.type = core.PHOS_CAMERA_PERSPECTIVE
    cam.transform[:] = (1, 0, 0, 0, 0, 0, -1, -4.2, 0, 1, 0, 0.5)  # at y=-4.2 looking +Y
    cam.frame_min[:] = (-0.36, -0.36)
    cam.frame_max[:] = (0.36, 0.36)
    s.set_camera(cam)
    s.commit()
    return s


def long_settings(core, threads=2, tile_size=64, samples=2048, size=2048):
    """A render of hours: 2048² pixels × 2048 samples (a few ms per pixel)."""
    rs = core.new_render_settings()
    rs.width, rs.height = size, size
    rs.samples = samples
    rs.max_bounces = 64
    rs.threads = threads
    rs.tile_size = tile_size
    rs.seed = 1
    return rs


def _wait_running(render, core, seconds=2.0):
    t_end = time.monotonic() + seconds
    while time.monotonic() < t_end:
        if render.progress().state == core.PHOS_STATE_RUNNING:
            return
        time.sleep(0.01)
    pytest.fail("the render never reached RUNNING: %r" % render.progress().state)


@pytest.mark.parametrize("threads,tile_size", [(2, 64), (1, 256), (2, 8)])
def test_cancel_returns_quickly(core, threads, tile_size):
    with build_scene(core) as scene, core.Render(scene, long_settings(core, threads, tile_size)) as r:
        r.start()
        _wait_running(r, core)
        time.sleep(0.3)  # workers deep inside their first tiles
        assert r.wait(0.0) == core.PHOS_ERROR_TIMEOUT, "the long render finished early"
        t0 = time.perf_counter()
        r.cancel()
        status = r.wait(-1.0)
        latency = time.perf_counter() - t0
        progress = r.progress()
        assert status == core.PHOS_ERROR_CANCELLED
        assert progress.state == core.PHOS_STATE_CANCELLED
        assert latency < CANCEL_LATENCY_S, "cancel took %.3f s" % latency
        # Finished tiles (if any) can still be read; unfinished read as zero.
        px = r.read(core.PHOS_PASS_COMBINED, 0, 0, 256, 256)
        assert np.all(np.isfinite(px))


def test_cancel_latency_independent_of_samples(core):
    """Even when one pixel takes seconds (2^20 samples), a cancel must not wait for
    the pixel to finish: the bound is on the render, not on a pixel's cost."""
    rs = long_settings(core, threads=2, tile_size=16, samples=1 << 20, size=64)
    with build_scene(core) as scene, core.Render(scene, rs) as r:
        r.start()
        _wait_running(r, core)
        time.sleep(0.3)
        t0 = time.perf_counter()
        r.cancel()
        status = r.wait(-1.0)
        latency = time.perf_counter() - t0
        assert status == core.PHOS_ERROR_CANCELLED
        assert latency < CANCEL_LATENCY_S, "cancel took %.3f s with 2^20 samples per pixel" % latency


def test_cancel_from_another_thread(core):
    """phos_render_cancel is safe from any thread: cancel from a Python thread while
    this one waits without limit."""
    with build_scene(core) as scene, core.Render(scene, long_settings(core)) as r:
        r.start()
        _wait_running(r, core)
        stamp = {}

        def canceller():
            time.sleep(0.2)
            stamp["t"] = time.perf_counter()
            r.cancel()
        th = threading.Thread(target=canceller)
        th.start()
        status = r.wait(-1.0)
        done = time.perf_counter()
        th.join()
        assert status == core.PHOS_ERROR_CANCELLED
        assert done - stamp["t"] < CANCEL_LATENCY_S


def test_close_while_running(core):
    """Closing (destroying) a running render cancels it and returns promptly."""
    scene = build_scene(core)
    try:
        r = core.Render(scene, long_settings(core))
        r.start()
        _wait_running(r, core)
        t0 = time.perf_counter()
        r.close()
        assert time.perf_counter() - t0 < CANCEL_LATENCY_S
    finally:
        scene.close()


def test_cancel_is_idempotent_and_harmless_after_done(core):
    with build_scene(core) as scene:
        rs = core.new_render_settings()
        rs.width, rs.height, rs.samples, rs.threads = 16, 16, 1, 2
        with core.Render(scene, rs) as r:
            r.cancel()  # before start: no effect on a later start? either way no crash
            r.start()
            status = r.wait(-1.0)
            assert status in (core.PHOS_OK, core.PHOS_ERROR_CANCELLED)
            r.cancel()
            r.cancel()
            assert r.wait(-1.0) == status
        with core.Render(scene, rs) as r:
            r.start()
            assert r.wait(-1.0) == core.PHOS_OK
            assert r.progress().state == core.PHOS_STATE_DONE
            r.cancel()  # after the end: stays DONE
            assert r.progress().state == core.PHOS_STATE_DONE
            assert r.wait(-1.0) == core.PHOS_OK
