# SPDX-License-Identifier: GPL-3.0-or-later
"""Rendered viewport shading: a Phos render of the 3D view, refined
progressively and drawn through Blender's display transform.

One ViewportSession per viewport engine (Blender makes an engine per 3D
view in Rendered mode and frees it when the view leaves that mode, the
engine changes or the view closes). The session keeps the core scene it
exported; view_update applies what the depsgraph reports changed through
the core's scene updates (lights and materials in place, the rest by a new
export), and view_draw starts a new render whenever the scene, the view or
the viewport's size changed since the one running. A render that only
follows the view reads the photon maps the last one built (the core's kept
maps, taken from any view): moving the view never traces photons again;
an edit of the scene does. The core renders on its
own threads (progressive refinement: the whole view at one sample a pixel
first), so neither call waits for it: view_draw shows what the film holds
and asks for another redraw until the render is done.
"""

import time
import weakref

import bpy
import gpu
import numpy as np
from gpu_extras.presets import draw_texture_2d

from . import core, export
from .export import changes as scene_changes
from .properties import render_settings


def view_camera(region, rv3d, space):
    """The core camera of a 3D view: its view matrix inverted, and the frame
    on the image plane from its projection matrix (perspective: the plane
    z = −1; orthographic: scene units), which holds the lens, the zoom and
    the camera view's offset as Blender draws them."""
    desc = core.new_camera()
    view_to_world = np.linalg.inv(np.array(rv3d.view_matrix, dtype=np.float64))
    desc.transform[:] = core.matrix_to_3x4(view_to_world)
    p = np.array(rv3d.window_matrix, dtype=np.float64)
    # x_ndc = p00·x/(−z) − p02 (perspective, clip w = −z) or p00·x + p03
    # (orthographic): the frame is where x_ndc = ±1.
    perspective = rv3d.is_perspective
    offset_x, offset_y = (p[0, 2], p[1, 2]) if perspective else (-p[0, 3], -p[1, 3])
    desc.type = core.PHOS_CAMERA_PERSPECTIVE if perspective else core.PHOS_CAMERA_ORTHOGRAPHIC
    desc.frame_min[:] = ((-1.0 + offset_x) / p[0, 0], (-1.0 + offset_y) / p[1, 1])
    desc.frame_max[:] = ((1.0 + offset_x) / p[0, 0], (1.0 + offset_y) / p[1, 1])
    if perspective:
        desc.clip_start, desc.clip_end = space.clip_start, space.clip_end
    else:
        # An orthographic view is drawn from far in front of what it shows.
        desc.clip_start, desc.clip_end = 0.0, 2.0 * space.clip_end
    return desc


def _camera_key(desc):
    return (desc.type, tuple(desc.transform), tuple(desc.frame_min), tuple(desc.frame_max), desc.clip_start,
            desc.clip_end)


# The sessions alive, for the GUI test (tests/gui/viewport.py) to watch.
SESSIONS = weakref.WeakSet()


class ViewportSession:
    """The core scene and the render of one viewport (module docstring)."""

    def __init__(self):
        SESSIONS.add(self)
        self.scene = None          # core.Scene, committed between renders
        self.ctx = None            # its ExportContext
        self.signature = None      # export/changes.py's signature of what it was exported from
        self.render = None         # the core.Render running or done
        self.render_key = None     # (camera, size, settings) the render was started with
        self.maps = None           # core.PhotonMaps kept from the last render that built them
        self.scene_changed = True  # the scene changed since the render started
        self.texture = None
        self.pixels = None
        self.started = 0.0
        self.renders = 0           # renders started so far
        self.first_image = None    # seconds from the last start to its first whole image

    # ---------------------------------------------------------- the scene

    def update(self, depsgraph, report):
        """view_update: export the scene the first time, then apply the
        changes Blender reports (in place where the core can, else a new
        export)."""
        changes = None
        if self.scene is not None:
            changes = scene_changes.changes_in_place(depsgraph, self.ctx, self.signature)
        if changes is not None and not changes[0] and not changes[1]:
            return  # cameras and the scene's settings only: view_draw sees those
        self.stop()  # the core changes no scene a render holds
        self.drop_maps()  # made for the scene before this change
        if changes is not None and scene_changes.apply_changes(depsgraph, self.ctx, changes):
            self.scene_changed = True
            return
        self.close_scene()
        scene = core.Scene()
        try:
            ctx = export.export_scene(depsgraph, scene, None, None, is_preview=False)
        except BaseException:
            scene.close()
            raise
        for message in ctx.warnings:
            report(message)
        self.scene, self.ctx, self.scene_changed = scene, ctx, True
        self.signature = scene_changes.signature(depsgraph)

    # ---------------------------------------------------------- the render

    def _settings(self, scene, width, height):
        rs = render_settings(scene, width, height)
        rs.samples = max(1, scene.phos.preview_samples)
        rs.progressive = 1
        return rs

    def restart_if_needed(self, context, depsgraph):
        """Start a new render when the view, its size, the settings or the
        scene changed since the one running. Returns whether one runs."""
        if self.scene is None:
            return False
        region, scene = context.region, depsgraph.scene
        width, height = max(region.width, 1), max(region.height, 1)
        camera = view_camera(region, context.region_data, context.space_data)
        rs = self._settings(scene, width, height)
        key = (_camera_key(camera), width, height,
               tuple(getattr(rs, s.name) for s in core.RENDER_SETTINGS))
        if key == self.render_key and not self.scene_changed:
            return True
        self.stop()
        self.scene.set_camera(camera)
        self.scene.commit()   # rebuilds nothing for the camera (phos_scene_changes)
        self.render = core.Render(self.scene, rs)
        if self.maps is not None and not self.render.use_photon_maps(self.maps, any_view=True):
            self.drop_maps()  # other photon settings: trace them again
        self.render.start()
        self.renders += 1
        self.render_key, self.scene_changed = key, False
        self.pixels = np.zeros((width * height, 4), dtype=np.float32)
        self.size = (width, height)
        self.started = time.perf_counter()
        self.first_image = None
        return True

    def stop(self):
        """Cancel and free the render, so that the scene can change; keep
        its photon maps if it got as far as building them."""
        if self.render is not None:
            if self.maps is None:
                self.maps = self.render.keep_photon_maps()
            self.render.cancel()
            self.render.wait(-1.0)
            self.render.close()
            self.render = None
            self.render_key = None

    def done(self):
        return self.render is None or self.render.progress().state in (
            core.PHOS_STATE_DONE, core.PHOS_STATE_CANCELLED, core.PHOS_STATE_FAILED)

    # ---------------------------------------------------------- drawing

    def draw(self, engine, scene):
        """Draw the film as it is now, through the scene's display
        transform (engine.bind_display_space_shader)."""
        if self.render is None:
            return
        width, height = self.size
        if self.first_image is None and self.render.progress().samples_done >= 1:
            self.first_image = time.perf_counter() - self.started
        while self.render.next_tile() is not None:
            pass  # the finished tiles are in the film; it is read whole below
        self.render.read(core.PHOS_PASS_COMBINED, 0, 0, width, height, out=self.pixels)
        buffer = gpu.types.Buffer('FLOAT', width * height * 4, self.pixels.reshape(-1))
        self.texture = gpu.types.GPUTexture((width, height), format='RGBA16F', data=buffer)
        gpu.state.blend_set('ALPHA_PREMULT')
        engine.bind_display_space_shader(scene)
        draw_texture_2d(self.texture, (0, 0), width, height)
        engine.unbind_display_space_shader()
        gpu.state.blend_set('NONE')

    # ---------------------------------------------------------- cleanup

    def drop_maps(self):
        if self.maps is not None:
            self.maps.close()
            self.maps = None

    def close_scene(self):
        self.stop()
        self.drop_maps()
        if self.scene is not None:
            self.scene.close()
        self.scene, self.ctx = None, None

    def close(self):
        self.close_scene()
        self.texture = None
