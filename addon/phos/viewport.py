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
an edit of the scene does. As Cycles' viewport does, a restart first
renders one sample a pixel at a reduced resolution (at most Start Pixels
on a side), then at twice that until the full resolution, which then
refines progressively up to the Viewport samples. The core renders on its
own threads, so neither call waits for it: view_draw shows what the film
holds and asks for another redraw until the render is done.
"""

import time
import weakref

import bpy
import gpu
import numpy as np
from gpu_extras.presets import draw_texture_2d

from . import core, export, status
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


# The fewest photons a map of a reduced-resolution render holds (_start).
MIN_PREVIEW_PHOTONS = 2000


def start_divider(width, height, start_pixels):
    """The first render's divider: the smallest power of two that brings
    the view to at most start_pixels on each side (Cycles' viewport starts
    likewise; its resolution then doubles up to the full one)."""
    divider = 1
    while max(width, height) > start_pixels * divider:
        divider *= 2
    return divider


# A reduced-resolution step whose time, predicted from the last step's,
# stays under this is skipped for a finer one: each step costs a draw
# (tens of ms) beside its render, so on a fast scene halving six times
# would delay the full image for nothing.
STEP_SECONDS = 0.1


def next_divider(divider, seconds_per_pixel, width, height):
    """The divider after a reduced render at `divider`: the finest (down to
    1) whose render is predicted to take at most STEP_SECONDS at the last
    render's cost per pixel, and at least half the last one."""
    finer = divider // 2
    while finer > 1 and seconds_per_pixel * (-(-width // (finer // 2))) * (-(-height // (finer // 2))) \
            <= STEP_SECONDS:
        finer //= 2
    return finer


def _camera_key(desc):
    return (desc.type, tuple(desc.transform), tuple(desc.frame_min), tuple(desc.frame_max), desc.clip_start,
            desc.clip_end)


# The sessions alive, for the GUI test (tests/gui/test_viewport.py) to watch.
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
        self.photon_traces = 0     # of them, those that traced the full photon maps
        self.reduced_traces = 0    # and those that traced reduced ones (_start)
        self.keep_maps = True      # the running render's maps are worth keeping
        self.divider = 1           # the render running is at 1/divider of the view's resolution
        self.shown = (None, 0)     # the render whose film the texture holds, and its samples then
        self.size = self.render_size = (1, 1)  # the view's and the render's pixels
        # Seconds from the last restart (a view or scene change) to its
        # first whole image, and to the first at the view's full resolution.
        self.first_image = self.full_image = None
        self.paused = False        # the viewport's Pause (Blender 5.x): no render runs or starts

    # ---------------------------------------------------------- the scene

    def update(self, depsgraph, report):
        """view_update: export the scene the first time, then apply the
        changes Blender reports (in place where the core can, else a new
        export)."""
        changes = None
        if self.scene is not None:
            changes = scene_changes.changes_in_place(depsgraph, self.ctx, self.signature)
        if changes is not None and not changes:
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
        # The time limit and the noise filter are a final render's: the
        # viewport refines until its samples are in, then shows them as they are.
        rs.time_limit, rs.noise_filter = 0.0, core.PHOS_NOISE_FILTER_NONE
        return rs

    def restart_if_needed(self, context, depsgraph):
        """Start a new render when the view, its size, the settings or the
        scene changed since the one running, at the start resolution; when
        a reduced-resolution render is done, start the next one at twice
        its resolution. Returns whether a render runs."""
        if self.scene is None or self.paused:
            return False
        region, scene = context.region, depsgraph.scene
        width, height = max(region.width, 1), max(region.height, 1)
        camera = view_camera(region, context.region_data, context.space_data)
        rs = self._settings(scene, width, height)
        key = (_camera_key(camera), width, height, scene.phos.preview_start_resolution,
               tuple(getattr(rs, s.name) for s in core.RENDER_SETTINGS))
        if key != self.render_key or self.scene_changed:
            self.stop()
            self.scene.set_camera(camera)
            self.scene.commit()   # rebuilds nothing for the camera (phos_scene_changes)
            self.render_key, self.scene_changed = key, False
            self.divider = start_divider(width, height, scene.phos.preview_start_resolution)
            self.started = time.perf_counter()
            self.first_image = self.full_image = None
            self._start(rs, width, height)
        elif self.divider > 1 and self.done():
            self._take_image()  # done between two draws: show it while the next one renders
            self.divider = next_divider(self.divider, self._seconds_per_pixel(), width, height)
            self._end_render()
            self._start(rs, width, height)
        return True

    def _start(self, rs, width, height):
        """A render of the view at 1/divider of its resolution: one sample
        a pixel while reduced, else the viewport's samples, progressively.
        It reads the photon maps kept from the last render when the core
        finds they fit (only the view moved). Without such maps a reduced
        render traces maps of 1/divider² the photons (at least
        MIN_PREVIEW_PHOTONS), each of its pixels being divider² of the
        view's: its image comes in a fraction of the full maps' time, which
        only the full-resolution render waits for."""
        d = self.divider
        reduced = d > 1 and self.maps is None
        if d > 1:
            rs.width, rs.height = -(-width // d), -(-height // d)
            rs.samples, rs.progressive = 1, 0
        if reduced:
            rs.global_photons = min(rs.global_photons, max(MIN_PREVIEW_PHOTONS, rs.global_photons // (d * d)))
            rs.caustic_photons = min(rs.caustic_photons, max(MIN_PREVIEW_PHOTONS, rs.caustic_photons // (d * d)))
        self.render = core.Render(self.scene, rs)
        if self.maps is not None and not self.render.use_photon_maps(self.maps, any_view=True):
            self.drop_maps()  # other photon settings: trace them again
        if any(stage == core.PHOS_STAGE_TRACING_PHOTONS for stage, _ in self.render.stages()):
            if reduced:
                self.reduced_traces += 1
            else:
                self.photon_traces += 1
        self.keep_maps = not reduced
        self.render.start()
        self.renders += 1
        self.size, self.render_size = (width, height), (rs.width, rs.height)
        self.pixels = np.zeros((rs.width * rs.height, 4), dtype=np.float32)

    def _seconds_per_pixel(self):
        """What the finished render spent per pixel, its photon stages left
        out (the next render reads its maps)."""
        progress = self.render.progress()
        seconds = sum(progress.stage_seconds[i] for i in (core.PHOS_STAGE_FILLING_IRRADIANCE_CACHE,
                                                         core.PHOS_STAGE_RENDERING))
        return seconds / (self.render_size[0] * self.render_size[1])

    def _end_render(self):
        """Cancel and free the render; keep its photon maps if it got as far
        as building them (full ones only: reduced maps serve one render)."""
        if self.render is not None:
            if self.maps is None and self.keep_maps:
                self.maps = self.render.keep_photon_maps()
            self.render.cancel()
            self.render.wait(-1.0)
            self.render.close()
            self.render = None

    def stop(self):
        """End the render, so that the scene can change; the next draw
        starts another."""
        self._end_render()
        self.render_key = None

    def pause(self):
        """The viewport's Pause (RenderEngine.view_pause, Blender 5.x): the
        render stops and frees the CPU; its last whole image stays on
        screen, and edits wait until resume."""
        self.paused = True
        if self.render is not None and not self.done():
            self._take_image_if_gpu()
            self.stop()

    def resume(self):
        """Resume: the next draw renders again (afresh if the pause cut a
        render short, reading the photon maps kept from it)."""
        self.paused = False

    def _take_image_if_gpu(self):
        try:
            self._take_image()
        except Exception:  # no GPU context (a background caller): the texture stays as it was
            pass

    def shows_final(self):
        """Whether the texture holds the running render's last samples."""
        return self.render is not None and self.shown == (self.render, self.render.progress().samples) \
            and self.done()

    def done(self):
        return self.render is None or self.render.progress().state in (
            core.PHOS_STATE_DONE, core.PHOS_STATE_CANCELLED, core.PHOS_STATE_FAILED)

    # ---------------------------------------------------------- drawing

    def _take_image(self):
        """Upload the running render's film once it holds a whole image
        (every pixel has a sample); until then the last image stays on
        screen, so a restart or the next resolution never flashes black."""
        progress = self.render.progress() if self.render is not None else None
        if progress is None or progress.samples_done < 1:
            return
        while self.render.next_tile() is not None:
            pass  # the finished tiles are in the film; it is read whole below
        rw, rh = self.render_size
        self.render.read(core.PHOS_PASS_COMBINED, 0, 0, rw, rh, out=self.pixels)
        buffer = gpu.types.Buffer('FLOAT', rw * rh * 4, self.pixels.reshape(-1))
        self.texture = gpu.types.GPUTexture((rw, rh), format='RGBA16F', data=buffer)
        self.shown = (self.render, progress.samples_done)
        now = time.perf_counter() - self.started
        if self.first_image is None:
            self.first_image = now
        if self.full_image is None and self.divider == 1:
            self.full_image = now

    def draw(self, engine, scene):
        """Draw the last whole image, stretched over the view when reduced,
        through the scene's display transform (engine.bind_display_space_shader)."""
        self._take_image()
        if self.texture is None:
            return
        width, height = self.size
        gpu.state.blend_set('ALPHA_PREMULT')
        engine.bind_display_space_shader(scene)
        draw_texture_2d(self.texture, (0, 0), width, height)
        engine.unbind_display_space_shader()
        gpu.state.blend_set('NONE')

    def status_text(self, samples):
        """What the view's corner shows: the stage, the resolution while
        reduced, then the samples so far."""
        if self.paused:
            return "Paused"
        if self.render is None:
            return ""
        progress = self.render.progress()
        stage_id, name = self.render.stages()[progress.stage_index]
        if stage_id in (core.PHOS_STAGE_RENDERING, core.PHOS_STAGE_FINISHED):
            if self.divider > 1:
                return "Rendering at 1/%d resolution" % self.divider
            return "Sample %d/%d" % (progress.samples_done, samples)
        return status.stage_text(progress, stage_id, name, samples)

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
