# SPDX-License-Identifier: GPL-3.0-or-later
"""The Phos RenderEngine: export, start the core, poll, deliver tiles.

The engine is deliberately thin. render() exports the evaluated depsgraph
into a core scene (export/), starts the core's asynchronous render and then
polls it from this thread: finished tiles are copied into Blender's render
result, progress and stats are updated, and test_break() is honoured. The
core's worker threads never call into Python; every bpy call happens on the
thread running render(), and ctypes releases the GIL during C calls.

Whatever happens, one full-frame result is delivered if no tile was (a
render that produces no result crashes Blender 3.4.1 when the output is
EXR), and failures are reported with report({'ERROR'}) so that `blender -b`
exits non-zero.
"""

import time

import bpy
import numpy as np

from . import core, export
from .properties import INTEGRATORS

POLL_SECONDS = 0.03
STATS_SECONDS_BACKGROUND = 2.0

# Blender ≥ 4.1 takes a flat array in RenderPass.rect.foreach_set; 3.x needs
# (pixels, channels). Remember what worked so each tile tries once.
_flat_rect = None


def _write_rect(render_pass, pixels):
    """Write a (w*h, channels) float32 C-contiguous array into a render pass.

    Never pass a flat array of length w*h (one channel's worth): Blender 3.4
    then reads past the end of the buffer.
    """
    global _flat_rect
    if _flat_rect is not False and bpy.app.version >= (4, 1, 0):
        try:
            render_pass.rect.foreach_set(pixels.reshape(-1))
            _flat_rect = True
            return
        except TypeError:
            _flat_rect = False
    render_pass.rect.foreach_set(pixels)


class PhosRenderEngine(bpy.types.RenderEngine):
    bl_idname = "PHOS"
    bl_label = "Phos"
    bl_use_preview = True
    bl_use_shading_nodes_custom = False
    bl_use_eevee_viewport = True

    # ------------------------------------------------------------- geometry

    def _region(self, scene):
        """(x, y, width, height) of the rendered region in full-frame pixels.

        resolution_x/y include the percentage and stay full-frame with a
        border; the border rect is x0 = int(min_x·W), x1 = int(max_x·W),
        computed in single precision as Blender does (float border × int
        size, truncated): in double precision 0.7 × 180 gives 125 where
        Blender gets 126, and the last row would be missing.
        """
        width, height = self.resolution_x, self.resolution_y
        r = scene.render
        if r.use_border and not self.is_preview:
            f32 = np.float32
            x0, x1 = int(f32(r.border_min_x) * f32(width)), int(f32(r.border_max_x) * f32(width))
            y0, y1 = int(f32(r.border_min_y) * f32(height)), int(f32(r.border_max_y) * f32(height))
            x0, y0 = max(0, min(x0, width)), max(0, min(y0, height))
            x1, y1 = max(x0, min(x1, width)), max(y0, min(y1, height))
            if x1 > x0 and y1 > y0:
                return x0, y0, x1 - x0, y1 - y0
        return 0, 0, width, height

    # ---------------------------------------------------------------- render

    def render(self, depsgraph):
        scene = depsgraph.scene
        width, height = self.resolution_x, self.resolution_y
        region = self._region(scene)
        self._delivered = False
        # render() runs once per view layer: write into that layer only (an
        # empty name would give a result whose first layer is not this one).
        self._layer_name = depsgraph.view_layer.name
        self._stats_text, self._stats_time = "", 0.0
        self._region_origin = region[:2]
        try:
            self._render(depsgraph, scene, width, height, region)
        except core.PhosError as ex:
            self.report({'ERROR'}, "Phos: %s" % ex)
        except Exception as ex:  # a bug in the add-on must still end the frame cleanly
            import traceback
            traceback.print_exc()
            self.report({'ERROR'}, "Phos: unexpected error: %s: %s" % (type(ex).__name__, ex))
        finally:
            if not self._delivered:
                self._deliver_placeholder(region)

    def _render(self, depsgraph, scene, width, height, region):
        if core.load() is None:
            raise core.PhosError(core.load_error())
        settings = scene.phos
        camera_object = scene.camera
        if camera_object is None:
            raise core.PhosError("the scene has no active camera")

        self._stats("Phos | Exporting", force=True)
        t0 = time.perf_counter()
        with core.Scene() as core_scene:
            def progress(done, total):
                self._stats("Phos | Exporting | Object %d/%d" % (done, total), force=done == total)

            ctx = export.export_scene(
                depsgraph, core_scene, camera_object,
                self.camera_model_matrix(camera_object),
                is_preview=self.is_preview, progress=progress, cancelled=self.test_break)
            if not self.is_preview:
                for message in ctx.warnings:
                    self.report({'WARNING'}, message)
            if self.test_break():
                return
            self._stats("Phos | Building acceleration structures", force=True)
            core_scene.commit()
            if not self.is_preview:
                s = ctx.stats
                print("Phos: exported %d instances of %d meshes (%d triangles), %d lights, "
                      "%d materials, %d images in %.2f s"
                      % (s["instances"], s["meshes"], s["triangles"], s["lights"],
                         s["materials"], s["images"], time.perf_counter() - t0))

            rs = core.new_render_settings()
            rs.integrator = INTEGRATORS.get(settings.integrator, core.PHOS_INTEGRATOR_PATH)
            rs.width, rs.height = width, height
            rs.region_x, rs.region_y, rs.region_width, rs.region_height = region
            rs.samples = settings.preview_samples if self.is_preview else settings.samples
            rs.seed = settings.seed
            rs.max_bounces = settings.max_bounces
            # The effective thread count, whether threads_mode is AUTO or FIXED.
            rs.threads = scene.render.threads
            rs.tile_size = settings.tile_size
            rs.filter_width = settings.filter_width
            rs.transparent_background = 1 if scene.render.film_transparent else 0
            rs.pass_mask = 1 << core.PHOS_PASS_COMBINED

            with core.Render(core_scene, rs) as render:
                render.start()
                self._poll(render, rs)

    def _poll(self, render, rs):
        """Deliver tiles as they finish until the render ends or is cancelled."""
        cancelled = False
        buffer = None
        while True:
            progress = render.progress()
            while True:
                tile = render.next_tile()
                if tile is None:
                    break
                buffer = self._deliver_tile(render, tile, buffer)
            self._show_progress(progress, rs)
            if progress.state in (core.PHOS_STATE_DONE, core.PHOS_STATE_CANCELLED,
                                  core.PHOS_STATE_FAILED):
                break
            if not cancelled and self.test_break():
                render.cancel()
                cancelled = True
            time.sleep(POLL_SECONDS)

        # Tiles that finished between the last poll and the end.
        status = render.wait(-1.0)
        while True:
            tile = render.next_tile()
            if tile is None:
                break
            buffer = self._deliver_tile(render, tile, buffer)
        self._show_progress(render.progress(), rs, final=True)
        if status == core.PHOS_OK:
            self.update_progress(1.0)

    def _show_progress(self, progress, rs, final=False):
        """Progress bar and the stats line of the render."""
        self.update_progress(min(max(progress.fraction, 0.0), 1.0))
        stage = progress.stage.decode("utf-8", "replace") or "Rendering"
        self._stats("Phos | %s | Sample %d | Tile %d/%d" % (
            stage, progress.samples or rs.samples, progress.tiles_done, progress.tiles_total),
            force=final)

    def _stats(self, text, force=False):
        """update_stats with changed text only, and sparingly in background mode.

        `blender -b` prints every stats update as a line, so there it is
        limited to one line per STATS_SECONDS_BACKGROUND unless forced.
        """
        if text == self._stats_text:
            return
        now = time.monotonic()
        if bpy.app.background and not force and now - self._stats_time < STATS_SECONDS_BACKGROUND:
            return
        self._stats_text, self._stats_time = text, now
        self.update_stats("", text)

    def _deliver_tile(self, render, tile, buffer):
        """Copy one finished tile into a render result (relative to the border)."""
        n = tile.width * tile.height
        if buffer is None or buffer.shape[0] < n:
            buffer = np.empty((n, 4), dtype=np.float32)  # tiles share one buffer
        pixels = render.read(core.PHOS_PASS_COMBINED, tile.x, tile.y, tile.width, tile.height,
                             out=buffer[:n])
        ox, oy = self._region_origin
        result = self.begin_result(tile.x - ox, tile.y - oy, tile.width, tile.height,
                                   layer=self._layer_name)
        try:
            _write_rect(result.layers[0].passes["Combined"], pixels)
        except Exception:
            self.end_result(result, cancel=True)
            raise
        self.end_result(result)
        self._delivered = True
        return buffer

    def _deliver_placeholder(self, region):
        """A transparent black full-region result, so Blender never gets none."""
        _, _, w, h = region
        try:
            result = self.begin_result(0, 0, w, h, layer=self._layer_name)
            if result is None:
                return
            try:
                zeros = np.zeros((w * h, 4), dtype=np.float32)
                for render_pass in result.layers[0].passes:
                    if render_pass.channels == 4:
                        _write_rect(render_pass, zeros)
                    else:
                        _write_rect(render_pass, np.zeros((w * h, render_pass.channels),
                                                          dtype=np.float32))
            finally:
                self.end_result(result)
        except Exception as ex:
            print("Phos: could not deliver a placeholder result: %s" % ex)


classes = (PhosRenderEngine,)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)


def unregister():
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
