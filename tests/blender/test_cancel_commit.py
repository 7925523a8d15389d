# SPDX-License-Identifier: GPL-3.0-or-later
"""Cancelling the BVH build (the scene's commit) through the add-on's wrapper.

The engine commits with `Scene.commit(cancelled=self.test_break)`: the
build runs on a worker thread while Blender's thread asks test_break and
calls phos_scene_cancel. test_break() is always False in background mode,
so the callable is driven by the test; the bound is the one of
test_cancel.py (0.5 s from the request to the return).
"""

import time

import numpy as np
import pytest

CANCEL_LATENCY_S = 0.5


@pytest.fixture
def core(addon):
    from phos import core as c
    assert c.load() is not None, c.load_error()
    return c


def triangle_soup(core, triangles, seed=1):
    """Small random triangles in a 10 m cube: seconds of BVH build."""
    rng = np.random.default_rng(seed)
    centres = rng.uniform(0.0, 10.0, (triangles, 1, 3))
    corners = (centres + rng.uniform(0.0, 0.05, (triangles, 3, 3))).astype(np.float32)
    s = core.Scene()
    diffuse = core.new_closure()
    diffuse.type = core.PHOS_CLOSURE_DIFFUSE
    diffuse.weight[:] = (0.5, 0.5, 0.5)
    mat = s.add_material([diffuse])
    mesh = s.add_mesh(corners.reshape(-1), np.arange(triangles * 3, dtype=np.uint32))
    s.add_instance(mesh, (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0), [mat])
    cam = core.new_camera()
    cam.transform[:] = (1, 0, 0, 5, 0, 0, -1, -20, 0, 1, 0, 5)
    s.set_camera(cam)
    return s


def test_commit_cancel_returns_quickly(core):
    s = triangle_soup(core, 1_500_000)  # as tests/c/test_cancel.c: Embree answers sooner
    asked = {}

    def cancelled():
        if time.monotonic() - start > 0.1:
            asked.setdefault("at", time.monotonic())
            return True
        return False

    start = time.monotonic()
    done = s.commit(cancelled=cancelled)
    returned = time.monotonic()
    assert "at" in asked, "the commit finished in %.2f s before the cancel: make the soup larger" % (
        returned - start)
    assert done is False
    latency = returned - asked["at"]
    assert latency < CANCEL_LATENCY_S, "the commit's cancel took %.3f s" % latency
    # The scene is uncommitted again: a render is refused with a message.
    with pytest.raises(core.PhosError):
        core.Render(s, core.new_render_settings())
    s.close()


def test_commit_with_callable_that_never_cancels(core):
    s = triangle_soup(core, 20_000)
    calls = []
    assert s.commit(cancelled=lambda: calls.append(1) or False) is True
    rs = core.new_render_settings()
    rs.width, rs.height, rs.samples = 8, 8, 1
    with core.Render(s, rs) as r:
        r.start()
        assert r.wait(-1.0) == core.PHOS_OK
    s.close()
