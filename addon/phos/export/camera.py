# SPDX-License-Identifier: GPL-3.0-or-later
"""The scene camera → core camera.

The image plane comes from `Camera.view_frame(scene=...)`, which already
applies sensor fit, aspect ratio and lens shift exactly as Blender draws the
camera frame; perspective corners are projected onto the z = −1 plane
(tangents of the half angles), orthographic corners are used as they are.
Depth of field follows Cycles' camera sync (blender/camera.cpp): the lens
radius is focal_length / (2·f-stop) with the focal length in metres, and the
focus distance is measured along the view axis.
"""

import numpy as np

from .. import core


def _clear_scale(m):
    """The camera transform without scale (Cycles ignores camera object scale)."""
    m = np.array(m, dtype=np.float64).reshape(4, 4)
    for c in range(3):
        n = np.linalg.norm(m[:3, c])
        if n > 0.0:
            m[:3, c] /= n
    return m


def _focus_distance(cam, matrix):
    dof = cam.dof
    target = dof.focus_object
    if target is None:
        return max(dof.focus_distance, 1e-4)
    target_pos = np.array(target.matrix_world.translation[:], dtype=np.float64)
    view_dir = matrix[:3, 2]
    return max(abs(float(np.dot(view_dir, matrix[:3, 3] - target_pos))), 1e-4)


def export_camera(cam_ob, matrix_world, ctx):
    """Set the core camera from a camera object and its model matrix.

    `matrix_world` is RenderEngine.camera_model_matrix(cam_ob) (the world
    matrix, with the stereo eye offset when rendering multi-view).
    """
    desc = camera_desc(cam_ob, matrix_world, ctx.scene, ctx.warn)
    try:
        ctx.core.set_camera(desc)
    except core.PhosError as ex:
        raise core.PhosError("camera '%s': %s" % (cam_ob.name, ex), ex.status) from None


def camera_desc(cam_ob, matrix_world, scene, warn):
    """The core camera of a camera object with this model matrix, in
    `scene` (its render size and aspect); `warn(message)` hears what is
    rendered otherwise than Blender shows it."""
    desc = core.new_camera()
    matrix = _clear_scale(matrix_world)
    desc.transform[:] = core.matrix_to_3x4(matrix)

    cam = cam_ob.data if cam_ob.type == 'CAMERA' else None
    if cam is None:
        # Blender lets any object be the active camera; look through it with a 50 mm lens.
        warn("Phos: the active camera '%s' is not a camera; using a 50 mm lens" % cam_ob.name)
        aspect = scene.render.resolution_y / max(scene.render.resolution_x, 1)
        half = 18.0 / 50.0
        desc.type = core.PHOS_CAMERA_PERSPECTIVE
        desc.frame_min[:] = (-half, -half * aspect)
        desc.frame_max[:] = (half, half * aspect)
        return desc

    if cam.type == 'ORTHO':
        desc.type = core.PHOS_CAMERA_ORTHOGRAPHIC
    else:
        if cam.type != 'PERSP':
            warn("Phos: camera '%s': %s cameras are not supported; rendering as perspective"
                     % (cam.name, cam.type.title()))
        desc.type = core.PHOS_CAMERA_PERSPECTIVE

    corners = np.array([v[:] for v in cam.view_frame(scene=scene)], dtype=np.float64)
    if desc.type == core.PHOS_CAMERA_PERSPECTIVE:
        xy = corners[:, :2] / -corners[:, 2:3]
    else:
        xy = corners[:, :2]
    desc.frame_min[:] = [float(v) for v in xy.min(axis=0)]
    desc.frame_max[:] = [float(v) for v in xy.max(axis=0)]

    desc.clip_start = cam.clip_start
    desc.clip_end = cam.clip_end

    if cam.dof.use_dof:
        fstop = max(cam.dof.aperture_fstop, 1e-5)
        if desc.type == core.PHOS_CAMERA_PERSPECTIVE:
            desc.aperture_radius = (cam.lens * 1e-3) / (2.0 * fstop)
            desc.focus_distance = _focus_distance(cam, matrix)
            if cam.dof.aperture_blades >= 3 or abs(cam.dof.aperture_ratio - 1.0) > 1e-6:
                warn("Phos: camera '%s': aperture blades and ratio are not supported; "
                         "using a round aperture" % cam.name)
        else:
            warn("Phos: camera '%s': depth of field of orthographic cameras is not supported"
                     % cam.name)
    return desc
