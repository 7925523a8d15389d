# SPDX-License-Identifier: GPL-3.0-or-later
"""The viewport's camera (viewport.view_camera): from a 3D view's matrices
the core camera that an F12 render of the same view would use. A camera
object gives both: its projection (Object.calc_matrix_camera, what a
camera view's window matrix holds) and its world matrix, so the frame and
transform the viewport derives must equal the ones the F12 export sets
(export/camera.py). The drawing itself is tested under Xvfb
(tests/gui/test_viewport.py)."""

import bpy
import numpy as np
import pytest

import phostest as pt


class _View:
    """What view_camera reads of a RegionView3D and its SpaceView3D."""

    def __init__(self, cam_ob, depsgraph, width, height):
        self.view_matrix = cam_ob.matrix_world.inverted()
        self.window_matrix = cam_ob.calc_matrix_camera(depsgraph, x=width, y=height)
        self.is_perspective = cam_ob.data.type != 'ORTHO'
        self.clip_start, self.clip_end = cam_ob.data.clip_start, cam_ob.data.clip_end


@pytest.mark.parametrize("kind, shift", [("PERSP", (0.0, 0.0)), ("PERSP", (0.1, -0.05)), ("ORTHO", (0.0, 0.0)),
                                               ("ORTHO", (-0.2, 0.1))])
def test_view_camera_is_the_cameras(scene, kind, shift):
    from phos import core, viewport
    from phos.export import camera as camera_export
    from phos.export.context import ExportContext
    cam_ob = pt.add_camera(scene, location=(1, -4, 2), target=(0, 0, 0.5))
    cam_ob.data.type = kind
    cam_ob.data.shift_x, cam_ob.data.shift_y = shift
    pt.configure_output(scene, 160, 90)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    view = _View(cam_ob, depsgraph, 160, 90)

    expected = {}

    class Recorder:
        def set_camera(self, desc):
            expected["desc"] = desc
    ctx = ExportContext(scene, Recorder())
    camera_export.export_camera(cam_ob, cam_ob.matrix_world, ctx)
    want = expected["desc"]
    got = viewport.view_camera(None, view, view)
    assert got.type == want.type
    assert np.allclose(got.transform[:], want.transform[:], atol=1e-5), (got.transform[:], want.transform[:])
    assert np.allclose(got.frame_min[:], want.frame_min[:], rtol=1e-4, atol=1e-5), (got.frame_min[:],
                                                                                     want.frame_min[:])
    assert np.allclose(got.frame_max[:], want.frame_max[:], rtol=1e-4, atol=1e-5), (got.frame_max[:],
                                                                                     want.frame_max[:])


def test_start_resolution_steps():
    """The first render is at most Start Pixels on a side, in a power-of-two
    divider; each later step at least halves it, and skips to a finer one
    only when the last step's cost per pixel predicts that one within
    STEP_SECONDS; the last step is the full resolution."""
    from phos import viewport
    assert viewport.start_divider(1057, 667, 64) == 32      # 34 × 21 px
    assert viewport.start_divider(64, 10, 64) == 1
    assert viewport.start_divider(65, 10, 64) == 2
    slow, fast = 1e-3, 1e-9                                  # seconds per pixel
    assert viewport.next_divider(32, slow, 1057, 667) == 16
    assert viewport.next_divider(2, slow, 1057, 667) == 1
    assert viewport.next_divider(32, fast, 1057, 667) == 1
    # 4.4e-7 s a pixel: the full 1057 × 667 view is predicted at 0.31 s, a
    # half-resolution one at 0.078 s (under STEP_SECONDS).
    assert viewport.next_divider(32, 4.4e-7, 1057, 667) == 2
    divider, steps = viewport.start_divider(1057, 667, 64), 0
    while divider > 1:
        divider, steps = viewport.next_divider(divider, slow, 1057, 667), steps + 1
    assert steps == 5


def test_pause_and_resume_reach_the_session():
    """Blender 5.x calls RenderEngine.view_pause and view_resume from the
    viewport header's Pause; they pause and resume the view's session (the
    GUI test pauses a live one: tests/gui/test_viewport.py)."""
    from phos import engine, viewport

    class _Engine:
        redraws = 0

        def tag_redraw(self):
            self.redraws += 1

    fake = _Engine()
    session = fake._viewport = viewport.ViewportSession()
    session.scene = object()  # a scene to render: only the pause can hold the restart back
    engine.PhosRenderEngine.view_pause(fake, None)
    assert session.paused and session.status_text(16) == "Paused"
    assert session.restart_if_needed(None, None) is False  # never reads the (missing) view
    engine.PhosRenderEngine.view_resume(fake, None)
    assert not session.paused and fake.redraws == 1
    with pytest.raises(AttributeError):
        session.restart_if_needed(None, None)  # resumed, it reads the view to render it
    session.scene = None
    session.close()
