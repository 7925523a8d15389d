# SPDX-License-Identifier: GPL-3.0-or-later
"""Rendered viewport shading in Blender's GUI, under Xvfb with software
OpenGL (`make test-gui`; tools/test-gui.sh starts it):

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup --python tests/gui/test_viewport.py -- RESULT.json

1. A 3D view switched to Rendered with Phos shows Phos's image: the
   viewport's pixels, read from the X server's screen, are the session's film
   through the scene's display transform (Standard: the sRGB curve), mean
   within 3 %, and not black; the film equals a render of the same view
   and settings through the core, bit for bit (an F12 of that view).
2. A light moved: the image changes, with no new export.
3. With PHOTON, a view move renders from the photon maps already built
   (no photon stage in the new render's plan); an object moved (in place,
   no export) traces them again.
4. Pause (what Blender 5.x's viewport header calls, RenderEngine.view_pause;
   called here directly, as 3.4 and 4.x have no such button): no render
   runs or starts, even when the view moves, and the image stays on
   screen; resume renders the moved view.
5. Leaving Rendered shading frees the session.

The steps run from a timer and the outcome is written as JSON to
RESULT.json (tests/gui/guitest.py); the exit code is 0 only if every check
passed.
"""

import os
import sys
import time

import bpy
import mathutils
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import guitest  # noqa: E402
import xscreen  # noqa: E402
from guitest import check  # noqa: E402
import phostest as pt  # noqa: E402 (tests/blender, put on the path by guitest)

state = {}
SCREEN = xscreen.Screen()


def view3d():
    return guitest.area('VIEW_3D')


def session():
    from phos import viewport
    alive = [s for s in viewport.SESSIONS if s.scene is not None]
    return alive[0] if alive else None


def srgb(linear):
    c = np.clip(linear, 0.0, 1.0)
    return np.where(c <= 0.0031308, 12.92 * c, 1.055 * np.power(c, 1.0 / 2.4) - 0.055)


def inner(a):
    """The middle half of an image of the drawing region (rows bottom-up),
    away from the header and toolbar Blender draws over its edges."""
    h, w = a.shape[:2]
    return a[h // 4:h - h // 4, w // 4:w - w // 4]


def screen_mean():
    """Mean RGB (0..1) of the middle of the 3D view's drawing region, as the
    X server's screen shows it (xscreen.py)."""
    window, area, region = view3d()
    x, y, w, h = xscreen.region_rect(window, region)
    px = SCREEN.grab(x, y, w, h).astype(np.float32) / 255.0
    crop = inner(px[::-1])  # rows bottom-up, as the film's
    return float(crop.mean()), crop.shape


def setup():
    pt.reset_file()
    pt.enable_addon()
    scene = bpy.context.scene
    pt.add_plane(scene, "Floor", size=8.0, material=pt.diffuse("Floor", (0.6, 0.6, 0.6)))
    pt.add_cube(scene, "Box", size=1.0, location=(0, 0, 0.5), material=pt.diffuse("Box", (0.8, 0.3, 0.2)))
    pt.add_light(scene, "POINT", 800.0, location=(2, -2, 3), name="Lamp")
    cam = pt.add_camera(scene, location=(0, -6, 3), target=(0, 0, 0.5))
    cam.data.show_passepartout = False
    pt.set_world(scene, (0.1, 0.1, 0.1))
    scene.view_settings.view_transform = 'Standard'
    scene.view_settings.look = 'None'
    scene.view_settings.exposure, scene.view_settings.gamma = 0.0, 1.0
    scene.render.engine = "PHOS"
    scene.phos.preview_samples = 8
    window, area, region = view3d()
    space = area.spaces.active
    space.overlay.show_overlays = False
    space.show_gizmo = False
    space.region_3d.view_perspective = 'CAMERA'
    space.shading.type = 'RENDERED'


def wait_done(after=0):
    """Whether a render later than the `after`-th, at the view's full
    resolution, is done and drawn with all its samples."""
    s = session()
    return s is not None and s.render is not None and s.renders > after and s.divider == 1 and s.shows_final()


def step(n):
    """One step of the test (guitest.run): the next step's number."""
    if n == 0:
        setup()
        return 1
    if n == 1 and wait_done():
        s = session()
        state["exports"] = s.ctx
        shot, shape = screen_mean()
        film = inner(s.pixels.reshape(s.size[1], s.size[0], 4)[..., :3])
        expect = float(srgb(film).mean())
        check("the viewport is not black", shot > 0.02, "mean %.4f" % shot)
        check("the viewport shows the film through the display transform",
              abs(shot - expect) <= 0.03 * expect, "screen %.4f, film %.4f, %s" % (shot, expect, shape))
        # The film against a one-pass render of the same camera and
        # settings through the core: an F12 of this view.
        from phos import core
        rs = s._settings(bpy.context.scene, *s.size)
        rs.progressive = 0
        with core.Render(s.scene, rs) as r:
            r.start()
            r.wait(-1.0)
            ref = r.read(core.PHOS_PASS_COMBINED, 0, 0, s.size[0], s.size[1])
        check("the film is the F12 render of the view", np.array_equal(ref.reshape(-1, 4), s.pixels),
              "max difference %g" % float(np.abs(ref.reshape(-1, 4) - s.pixels).max()))
        check("the first image is at a reduced resolution", s.renders > 1 and s.first_image < s.full_image,
              "%d renders" % s.renders)
        print("GUI TIME: %dx%d px, first whole image %.2f s after the restart, at full resolution %.2f s "
              "(a draw later)" % (s.size[0], s.size[1], s.first_image or -1.0, s.full_image or -1.0),
              flush=True)
        state["first"], state["renders"] = shot, s.renders
        bpy.data.objects["Lamp"].location.x -= 3.0
        return 2
    if n == 2 and wait_done(state["renders"]):
        s = session()
        shot, _ = screen_mean()
        check("moving a light changes the image", abs(shot - state["first"]) > 0.005,
              "%.4f → %.4f" % (state["first"], shot))
        check("moving a light exports nothing", s.ctx is state["exports"])
        scene = bpy.context.scene
        scene.phos.global_photons, scene.phos.caustic_photons = 20000, 0
        scene.phos.integrator = 'PHOTON'
        state["renders"], state["traces"] = s.renders, s.photon_traces
        return 3
    if n == 3 and wait_done(state["renders"]):
        s = session()
        check("a PHOTON viewport traces its photon maps once", s.photon_traces == state["traces"] + 1,
              "%d traces" % (s.photon_traces - state["traces"]))
        window, area, region = view3d()
        r3d = area.spaces.active.region_3d
        r3d.view_perspective = 'PERSP'
        r3d.view_rotation.rotate(mathutils.Euler((0.0, 0.0, 0.3)))
        state["renders"], state["film"], state["traces"] = s.renders, s.pixels.copy(), s.photon_traces
        return 4
    if n == 4 and wait_done(state["renders"]):
        s = session()
        check("moving the view renders a new image", not np.array_equal(s.pixels, state["film"]))
        check("moving the view keeps the photon maps", s.photon_traces == state["traces"],
              "%d traces" % (s.photon_traces - state["traces"]))
        bpy.data.objects["Box"].location.x += 0.5
        state["renders"] = s.renders
        return 5
    if n == 5 and wait_done(state["renders"]):
        s = session()
        check("moving an object traces the photon maps again", s.photon_traces == state["traces"] + 1,
              "%d traces" % (s.photon_traces - state["traces"]))
        check("moving an object exports nothing", s.ctx is state["exports"])
        s.pause()
        window, area, region = view3d()
        area.spaces.active.region_3d.view_rotation.rotate(mathutils.Euler((0.0, 0.0, -0.2)))
        region.tag_redraw()
        state["renders"], state["paused_at"] = s.renders, time.monotonic()
        return 6
    if n == 6 and time.monotonic() - state["paused_at"] > 1.5:
        s = session()
        shot, _ = screen_mean()
        check("a paused viewport starts no render when the view moves", s.renders == state["renders"] and
              s.done(), "%d renders started, one running: %s" % (s.renders - state["renders"], not s.done()))
        check("a paused viewport keeps its image on screen", shot > 0.02, "mean %.4f" % shot)
        s.resume()
        view3d()[2].tag_redraw()
        return 7
    if n == 7 and wait_done(state["renders"]):
        window, area, region = view3d()
        check("resuming renders the moved view", session().renders > state["renders"])
        area.spaces.active.shading.type = 'SOLID'
        state["left"] = time.monotonic()
        return 8
    if n == 8:
        import gc
        gc.collect()
        if session() is None:
            check("leaving Rendered frees the session", True)
            return None
        if time.monotonic() - state["left"] > 10.0:
            check("leaving Rendered frees the session", False, "still alive after 10 s")
            return None
    return n


guitest.run(step)
