# SPDX-License-Identifier: GPL-3.0-or-later
"""The viewport's camera (viewport.view_camera): from a 3D view's matrices
the core camera that an F12 render of the same view would use. A camera
object gives both: its projection (Object.calc_matrix_camera, what a
camera view's window matrix holds) and its world matrix, so the frame and
transform the viewport derives must equal the ones the F12 export sets
(export/camera.py). The drawing itself is tested under Xvfb
(tests/gui/viewport.py)."""

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
