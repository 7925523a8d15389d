# SPDX-License-Identifier: GPL-3.0-or-later
"""A second F12 in Blender's GUI, under Xvfb (`make test-gui`;
tools/test-gui.sh): while it renders, the Image Editor never shows a hole;
and a third, without progressive refinement, ends whole.

Every pixel on screen is the previous render's or the new one's, never the
transparency of a tile not yet written, and the new render covers the whole
frame when it finishes. One moment is Blender's, not the engine's: between
the start of a render and its first tile, a redraw shows the new, still
empty result whole (Cycles does the same: 2 of 4 runs of this test with
Cycles showed it for 0.1-0.2 s). So screens before the new render's first
pixel may be wholly the old image or wholly empty; none may be partly empty.

A plane under a uniform world makes this checkable pixel by pixel: no
sample of it can be black, the first render's world is red and the
second's blue, so each pixel's hue tells which render it comes from even at
one sample per pixel. The screen is read from the X server by a process of
its own (xscreen.Watcher) while Blender renders.
"""

import os
import sys
import tempfile
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import guitest  # noqa: E402
import xscreen  # noqa: E402
from guitest import check  # noqa: E402
import phostest as pt  # noqa: E402 (tests/blender, put on the path by guitest)

SCREEN = xscreen.Screen()
GRAB_SECONDS = 0.02
RED, BLUE = (1.0, 0.15, 0.1), (0.1, 0.15, 1.0)
state = {"finished": 0}


@bpy.app.handlers.persistent
def _finished(*_args):
    state["finished"] += 1


def render_f12():
    window, area, region = guitest.area(state.get("editor", 'VIEW_3D'))
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.render.render('INVOKE_DEFAULT')


def image_rect():
    """The rendered image's rectangle in the Image Editor, on the screen:
    the box around the red pixels of the first render."""
    window, area, region = guitest.area('IMAGE_EDITOR')
    x, y, w, h = xscreen.region_rect(window, region)
    px = SCREEN.grab(x, y, w, h).astype(np.int32)
    red = px[..., 0] > px[..., 2] + 40
    rows, cols = np.nonzero(red)
    if rows.size == 0:
        return None
    # A pixel in from each edge: the border Blender draws around the image.
    top, bottom, left, right = rows.min() + 1, rows.max() - 1, cols.min() + 1, cols.max() - 1
    return x + left, y + top, right - left + 1, bottom - top + 1


def classify(frame):
    """Per pixel: red (first render), blue (second), or neither (a hole)."""
    px = frame.astype(np.int32)
    red = px[..., 0] > px[..., 2] + 40
    blue = px[..., 2] > px[..., 0] + 40
    return red, blue, ~(red | blue)


def step(n):
    if n == 0:
        pt.reset_file()
        pt.enable_addon()
        scene = bpy.context.scene
        scene.render.engine = "PHOS"
        pt.add_plane(scene, "Floor", size=40.0, material=pt.diffuse("Floor", (0.7, 0.7, 0.7)))
        cam = pt.add_camera(scene, location=(0, -6, 3), target=(0, 0, 0.5))
        cam.data.show_passepartout = False
        pt.set_world(scene, RED)
        scene.view_settings.view_transform = 'Standard'
        pt.configure_output(scene, 960, 540)
        scene.phos.samples = 1
        bpy.app.handlers.render_complete.append(_finished)
        bpy.context.preferences.view.render_display_type = 'AREA'  # the Image Editor in the 3D view's place
        render_f12()
        return 1
    if n == 1:
        if state["finished"] < 1 or bpy.app.is_job_running('RENDER'):
            return n
        state["editor"] = 'IMAGE_EDITOR'
        state["rect"] = image_rect()
        if state["rect"] is None:
            # The Image Editor draws the finished render a moment after
            # the render's end (its one result, with a single pass).
            state.setdefault("first_seen_wait", time.monotonic())
            if time.monotonic() - state["first_seen_wait"] < 10.0:
                return n
            check("the first render is on screen", False, "no red pixels in the Image Editor after 10 s")
            return None
        # The second render: blue, and long enough to be seen on its way.
        scene = bpy.context.scene
        scene.world.node_tree.nodes["Background"].inputs["Color"].default_value[:3] = BLUE
        scene.phos.samples = 16
        # One thread at 960x540: the first pass then lasts many of the
        # screen reader's reads, so tiles landing one by one are seen (an
        # engine that delivers the first pass tile by tile fails 3 runs of
        # 3; at 320x180 on two threads it failed 1 run in 8).
        scene.render.threads_mode = 'FIXED'
        scene.render.threads = 1
        state["frames_file"] = tempfile.NamedTemporaryFile(suffix=".rgb", delete=False).name
        state["watcher"] = xscreen.Watcher(state["rect"], state["frames_file"], GRAB_SECONDS)
        state["started"] = time.monotonic()
        render_f12()
        return 2
    if n == 2:
        if state["finished"] < 2:
            return n
        state["settled"] = time.monotonic()
        print("GUI TIME: the second render took %.1f s" % (state["settled"] - state["started"]), flush=True)
        return 3
    if n == 3:
        if time.monotonic() - state["settled"] < 1.0:  # the last draw
            return n
        state["watcher"].stop()
        frames = state["watcher"].frames()
        os.unlink(state["frames_file"])
        counts = [[int(m.sum()) for m in classify(f)] for f in frames]
        size = frames[0].shape[0] * frames[0].shape[1]
        first_new = next((i for i, c in enumerate(counts) if c[1] > 0), len(counts))
        empty = sum(c[2] == size for c in counts[:first_new])
        partial = [c[2] for c in counts[:first_new] if 0 < c[2] < size] + [c[2] for c in counts[first_new:] if c[2]]
        shown = sum(c[1] > 0 for c in counts)
        check("the second render was watched on its way", first_new >= 1 and shown >= 5,
              "%d screens, %d with the new render" % (len(frames), shown))
        check("no screen shows a hole", not partial,
              "%d screens with holes (most %d of %d pixels); %d wholly empty before the first image"
              % (len(partial), max(partial, default=0), size, empty))
        check("the new render ends whole", counts[-1][1] == size,
              "%d of %d pixels" % (counts[-1][1], size))
        # A third render without progressive refinement, whose tiles finish
        # one by one: Blender 5.2's Image Editor locked up its main thread
        # when results covering part of the frame arrived while it drew.
        scene = bpy.context.scene
        scene.phos.use_progressive_refine = False
        scene.world.node_tree.nodes["Background"].inputs["Color"].default_value[:3] = RED
        scene.phos.samples = 4
        render_f12()
        return 4
    if n == 4:
        if state["finished"] < 3:
            return n
        state["settled"] = time.monotonic()
        return 5
    if n == 5:
        if time.monotonic() - state["settled"] < 1.0:  # the last draw
            return n
        red, _, _ = classify(SCREEN.grab(*state["rect"]))
        check("a render without progressive refinement ends whole", red.all(),
              "%d of %d pixels" % (int(red.sum()), red.size))
        return None
    return n


guitest.run(step)
