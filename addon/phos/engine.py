# SPDX-License-Identifier: GPL-3.0-or-later
"""The Phos RenderEngine: export, start the core, poll, deliver the image.

The engine is deliberately thin. render() exports the evaluated depsgraph
into a core scene (export/), starts the core's asynchronous render and then
polls it from this thread: as tiles finish, the render region is copied
whole into Blender's render result (_poll says when and why whole),
progress and stats are updated, and test_break() is honoured. The
settings are copied by the core's settings table (properties.USER_SETTINGS);
the stats line names the stages of the core's plan (Render.stages()). The
core's worker threads never call into Python; every bpy call happens on the
thread running render(), and ctypes releases the GIL during C calls.

Passes: the view layer's toggles (`view_layer.phos`, properties.PASSES)
become the core's pass_mask and are registered in update_render_passes;
Blender merges every registered pass of a result whether it was written or
not, so every result (and the placeholder) writes every pass of it.

Whatever happens, one full-frame result is delivered if none was (a
render that produces no result crashes Blender 3.4.1 when the output is
EXR), and failures are reported with report({'ERROR'}) so that `blender -b`
exits non-zero.
"""

import time

import bpy
import numpy as np

from . import core, export
from . import status, viewport
from .export import camera, changes as scene_changes, image as image_cache
from .properties import PASSES, cache_files, enabled_passes, render_settings

# How often a final render's progress, tiles and cancel are looked at; the
# wait between looks ends early when the render does.
POLL_SECONDS = 0.03
# The image shown while a final render runs is refreshed at most every
# DISPLAY_SECONDS, and its reading may take at most 1/DISPLAY_COST_RATIO of
# the render's time (_poll).
DISPLAY_SECONDS = 0.5
DISPLAY_COST_RATIO = 20.0

# Material, world and light previews: Blender renders them in its own
# preview scene, which holds none of the user's Phos settings (its
# scene.phos has the defaults), so their sample count is set here: enough
# for a clean 200-pixel preview in about a second on two cores, shown
# after 1, 2, 4 … samples (progressive refinement) as it refines.
PREVIEW_SAMPLES = 64

# Final renders running now (render() of a non-preview engine): a preview
# then renders on one thread, so that it never competes with an F12 for
# the cores.
_final_renders = 0
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


# Render pass name → core pass, for every pass Phos can deliver.
PASS_IDS = {"Combined": core.PHOS_PASS_COMBINED}
PASS_IDS.update((p.name, p.pass_id) for p in PASSES)

# How Blender is told what a pass holds (channel names, type), by kind.
PASS_REGISTRATION = {core.PHOS_PASS_KIND_COLOR: ("RGB", 'COLOR'), core.PHOS_PASS_KIND_VECTOR: ("XYZ", 'VECTOR'),
                     core.PHOS_PASS_KIND_VALUE: ("X", 'VALUE')}


# Wall time (s) of the last final render: "export" (export and BVH build)
# and each stage it ran, by enum phos_stage; with the tiles' ray count
# ("rays") and the irradiance cache's records and share of lookups
# interpolated. `blender -b` prints them at the end of a render, and
# scripts that measure Phos read them here (bench/quality.py).
last_render_seconds = {}

# A render farm's cache job (farm/blender_task.py) sets this around one
# final render: that render traces the photon maps and fills the
# irradiance cache for the scene's camera and these further views (core
# cameras, export/camera.py camera_desc), saves them as the scene's cache
# file settings say, and renders no pixel (phos_render_add_view,
# caches_only).
cache_job_views = None

# Why a final render failed: a render in the background reports only to
# its log, and a farm task must fail with the reason. Set on failure, never
# cleared here (render() runs once per view layer: a later layer's success
# must not hide an earlier one's failure); the farm task clears it first.
last_render_error = None


def _timing(plan, progress, export_seconds):
    """({"export": s, stage id: s, ...}, 'exporting and building the BVH 0.05 s, ...')."""
    seconds, parts = {"export": export_seconds}, [("exporting and building the BVH", export_seconds)]
    for stage_id, name in plan:
        if stage_id not in (core.PHOS_STAGE_WAITING, core.PHOS_STAGE_FINISHED):
            seconds[stage_id] = progress.stage_seconds[stage_id]
            parts.append((name.lower(), seconds[stage_id]))
    text = ", ".join("%s %.2f s" % part for part in parts)
    tiles = progress.stage_seconds[core.PHOS_STAGE_RENDERING]
    seconds["rays"] = progress.rays_traced
    seconds["cache_records"] = progress.cache_records
    seconds["cache_interpolated"] = (progress.cache_interpolated / progress.cache_lookups
                                     if progress.cache_lookups else 0.0)
    # Photon paths emitted and photons kept (both maps): their ratio is the
    # yield, the share of tracing work that is stored (docs/benchmarks.md).
    seconds["photons_emitted"] = progress.photons_emitted
    seconds["photons_stored"] = progress.photons_stored
    if progress.rays_traced and tiles > 0.0:
        text += "; %.1f M rays, %.2f M rays/s" % (progress.rays_traced * 1e-6, progress.rays_traced * 1e-6 / tiles)
    text += status.cache_text(progress).replace(" | ", "; ", 1)
    return seconds, text


def border_rect(width, height, min_x, max_x, min_y, max_y):
    """(x, y, width, height) in pixels of a render border of a width ×
    height frame (y from the bottom): the whole frame if it is empty.

    The rect is x0 = int(min_x·W), x1 = int(max_x·W), computed in single
    precision as Blender does (float border × int size, truncated): in
    double precision 0.7 × 180 gives 125 where Blender gets 126, and the
    last row would be missing. A farm's stitch (farm/blender_task.py)
    places each region by it.
    """
    f32 = np.float32
    x0, x1 = int(f32(min_x) * f32(width)), int(f32(max_x) * f32(width))
    y0, y1 = int(f32(min_y) * f32(height)), int(f32(max_y) * f32(height))
    x0, y0 = max(0, min(x0, width)), max(0, min(y0, height))
    x1, y1 = max(x0, min(x1, width)), max(y0, min(y1, height))
    if x1 > x0 and y1 > y0:
        return x0, y0, x1 - x0, y1 - y0
    return 0, 0, width, height


class PhosRenderEngine(bpy.types.RenderEngine):
    bl_idname = "PHOS"
    bl_label = "Phos"
    bl_use_preview = True
    bl_use_shading_nodes_custom = False
    bl_use_eevee_viewport = True

    # ---------------------------------------------------------------- passes

    def update_render_passes(self, scene=None, renderlayer=None):
        """Declare the passes of a view layer (Blender calls this for renders
        and for the compositor's Render Layers node)."""
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", 'COLOR')
        for p in enabled_passes(renderlayer):
            chan_id, kind = PASS_REGISTRATION[p.kind]
            chan_id = "RGBA" if p.channels == 4 else chan_id  # the Noisy Image keeps Combined's alpha
            self.register_pass(scene, renderlayer, p.name, p.channels, chan_id, kind)

    # ------------------------------------------------------------- geometry

    def _region(self, scene):
        """(x, y, width, height) of the rendered region in full-frame pixels
        (resolution_x/y include the percentage and stay full-frame with a
        border)."""
        r = scene.render
        if r.use_border and not self.is_preview:
            return border_rect(self.resolution_x, self.resolution_y, r.border_min_x, r.border_max_x,
                               r.border_min_y, r.border_max_y)
        return 0, 0, self.resolution_x, self.resolution_y

    # -------------------------------------------------------------- viewport

    def view_update(self, context, depsgraph):
        """Rendered viewport shading: the scene, exported once and then
        changed in place as Blender edits it (viewport.py)."""
        if core.load() is None:
            return
        session = getattr(self, "_viewport", None)
        if session is None:
            session = self._viewport = viewport.ViewportSession()
        try:
            session.update(depsgraph, lambda message: self.report({'WARNING'}, message))
        except core.PhosError as ex:
            self.report({'ERROR'}, "Phos: %s" % ex)
            session.close_scene()

    def view_draw(self, context, depsgraph):
        session = getattr(self, "_viewport", None)
        if session is None:
            return
        try:
            session.restart_if_needed(context, depsgraph)
        except core.PhosError as ex:
            self.report({'ERROR'}, "Phos: %s" % ex)
            session.close_scene()
            return
        session.draw(self, depsgraph.scene)
        self.update_stats("", session.status_text(max(1, depsgraph.scene.phos.preview_samples)))
        if not session.paused and (not session.done() or session.divider > 1):
            self.tag_redraw()  # the render goes on, or the next resolution: draw again soon

    def view_pause(self, context):
        """The viewport header's Pause (Blender 5.x calls it; older
        versions have no such button)."""
        session = getattr(self, "_viewport", None)
        if session is not None:
            session.pause()

    def view_resume(self, context):
        session = getattr(self, "_viewport", None)
        if session is not None:
            session.resume()
            self.tag_redraw()

    def __del__(self):
        # Blender frees a viewport's engine when the view leaves Rendered
        # shading, the engine changes or the view closes (RenderEngine has
        # no __del__ of its own in Blender 3.4).
        session = getattr(self, "_viewport", None)
        if session is not None:
            session.close()

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
        self._plan, self._last_stage = [], None  # the core's stages, the index of the one shown
        global _final_renders, last_render_error
        if not self.is_preview:
            _final_renders += 1
        try:
            self._render(depsgraph, scene, width, height, region)
        except core.PhosError as ex:
            self.report({'ERROR'}, "Phos: %s" % ex)
            if not self.is_preview:
                last_render_error = str(ex)
        except Exception as ex:  # a bug in the add-on must still end the frame cleanly
            import traceback
            traceback.print_exc()
            self.report({'ERROR'}, "Phos: unexpected error: %s: %s" % (type(ex).__name__, ex))
            if not self.is_preview:
                last_render_error = "unexpected error: %s: %s" % (type(ex).__name__, ex)
        finally:
            if not self.is_preview:
                _final_renders -= 1
            if not self._delivered:
                self._deliver_placeholder(region)

    def _render(self, depsgraph, scene, width, height, region):
        if core.load() is None:
            raise core.PhosError(core.load_error())
        settings = scene.phos
        # The evaluated camera: an original object's matrix_world is only
        # kept up to date by the depsgraph of the view layer in the window,
        # not by a render's own (a material preview's camera there is the
        # identity; an animation's camera would be one frame behind).
        camera_object = depsgraph.scene_eval.camera
        if camera_object is None:
            raise core.PhosError("the scene has no active camera")

        t0 = time.perf_counter()
        core_scene = self._scene_for(depsgraph, scene, camera_object)
        if core_scene is None:
            return
        try:
            rs = render_settings(scene, width, height)
            if self.is_preview:
                rs.samples, rs.progressive = PREVIEW_SAMPLES, 1
                rs.time_limit, rs.noise_filter = 0.0, core.PHOS_NOISE_FILTER_NONE
                if _final_renders:
                    rs.threads = 1
            rs.region_x, rs.region_y, rs.region_width, rs.region_height = region
            if not self.is_preview:
                for p in enabled_passes(depsgraph.view_layer):
                    rs.pass_mask |= 1 << p.pass_id
            views = cache_job_views if not self.is_preview else None
            if views is not None:
                rs.caches_only = 1

            export_seconds = time.perf_counter() - t0
            with core.Render(core_scene, rs) as render:
                files = cache_files(settings) if not self.is_preview else []
                for kind, path, mode in files:
                    render.set_cache_file(kind, bpy.path.abspath(path), mode)
                for view in views or ():
                    render.add_view(view)
                self._use_kept_maps(render, depsgraph, scene, files)
                self._plan = render.stages()
                render.start()
                self._poll(render, rs)
                self._keep_maps(render, depsgraph, scene)
                if not self.is_preview:
                    seconds, text = _timing(self._plan, render.progress(), export_seconds)
                    last_render_seconds.clear()
                    last_render_seconds.update(seconds)
                    print("Phos: " + text)
        finally:
            if not self._keeps(scene):
                core_scene.close()

    # ------------------------------------------------------- the core scene

    def _keeps(self, scene):
        """Whether this render's core scene is kept for the next one:
        Blender's Persistent Data (Render Properties → Performance), which
        keeps this engine between F12 renders; never for previews."""
        return scene.render.use_persistent_data and not self.is_preview

    def _scene_for(self, depsgraph, scene, camera_object):
        """The committed core scene of this view layer, or None if the export
        or the BVH build was cancelled.

        With Persistent Data the last render's scene is reused when the
        depsgraph reports no change that the export reads, but to the camera
        (set again every render; a camera change rebuilds nothing at commit,
        phos_scene_changes); any other change exports afresh. Blender's own
        record of what changed (depsgraph.updates, empty for an unchanged
        scene) decides it."""
        kept = getattr(self, "_kept_scenes", None)
        if kept is None:
            kept = self._kept_scenes = {}
        layer = depsgraph.view_layer.name
        entry = kept.pop(layer, None)
        signature = scene_changes.signature(depsgraph)
        matrix = self.camera_model_matrix(camera_object)
        changes = scene_changes.changes_in_place(depsgraph, entry[1], entry[2]) if entry is not None else None
        if changes is not None and self._keeps(scene) and self._apply(entry[1], depsgraph, changes):
            core_scene, ctx = entry[0], entry[1]
            camera.export_camera(camera_object, matrix, ctx)
            self._stats("Phos | Reusing the scene (Persistent Data)", force=True)
            print("Phos: reused the scene of the last render (Persistent Data); changed in place: "
                  + changes.summary())
        else:
            if entry is not None:
                entry[0].close()
            core_scene, ctx = self._export(depsgraph, camera_object, matrix)
            if ctx is None:
                core_scene.close()
                return None
        # Committed again after the camera set on a kept scene: that
        # rebuilds nothing (phos_scene_commit).
        self._stats("Phos | Building acceleration structures", force=True)
        if not core_scene.commit(cancelled=self.test_break):
            core_scene.close()
            return None
        if self._keeps(scene):
            kept[layer] = (core_scene, ctx, signature)
        return core_scene

    def _use_kept_maps(self, render, depsgraph, scene, files):
        """With Persistent Data, give the render the photon maps the last
        render of this view layer built, if the core finds they still fit:
        the same scene unchanged but for a camera that aimed nothing, the
        same photon settings (phos_render_use_photon_maps, never from
        another view, so the image is the one tracing them gives)."""
        maps = getattr(self, "_kept_maps", {}).pop(depsgraph.view_layer.name, None)
        if maps is None:
            return
        with maps:
            if not self._keeps(scene) or any(kind == core.PHOS_CACHE_PHOTON_MAPS for kind, _, _ in files):
                return
            if render.use_photon_maps(maps):
                print("Phos: reusing the photon maps of the last render (Persistent Data)")

    def _keep_maps(self, render, depsgraph, scene):
        """With Persistent Data, keep the finished render's photon maps for
        the next F12 of this view layer (released with the engine)."""
        if not self._keeps(scene) or render.progress().state != core.PHOS_STATE_DONE:
            return
        maps = render.keep_photon_maps()
        if maps is not None:
            if not hasattr(self, "_kept_maps"):
                self._kept_maps = {}
            self._kept_maps[depsgraph.view_layer.name] = maps

    def _apply(self, ctx, depsgraph, changes):
        """Apply the changed lights and materials to a kept scene
        (export/changes.py); False if the scene must be exported afresh."""
        if not scene_changes.apply_changes(depsgraph, ctx, changes):
            return False
        for message in ctx.warnings:
            self.report({'WARNING'}, message)
        return True

    def _export(self, depsgraph, camera_object, matrix):
        """A new core scene filled from the depsgraph, not committed; its
        ExportContext, or None if the export was cancelled."""
        self._stats("Phos | Exporting", force=True)
        t0 = time.perf_counter()
        core_scene = core.Scene()

        def progress(done, total):
            self._stats("Phos | Exporting | Object %d/%d" % (done, total), force=done == total)

        try:
            ctx = export.export_scene(depsgraph, core_scene, camera_object, matrix, is_preview=self.is_preview,
                                      progress=progress, cancelled=self.test_break)
        except BaseException:
            core_scene.close()
            raise
        if not self.is_preview:
            for message in ctx.warnings:
                self.report({'WARNING'}, message)
            s = ctx.stats
            print("Phos: exported %d instances of %d meshes (%d triangles), %d lights, "
                  "%d materials, %d images in %.2f s"
                  % (s["instances"], s["meshes"], s["triangles"], s["lights"],
                     s["materials"], s["images"], time.perf_counter() - t0))
        if self.test_break():
            return core_scene, None
        return core_scene, ctx

    def _poll(self, render, rs):
        """Deliver the image as tiles finish until the render ends or is cancelled.

        The image goes to Blender whole (the render region), never tile by
        tile:
        - under the tiles of a progressive render's first pass Blender's new
          result is still empty, so a redraw would show holes;
        - Blender 5.2's Image Editor locks up its own main thread when a
          result covering part of the frame arrives while it draws (found
          by tests/gui/test_final_render.py; whole-frame results, as
          Cycles sends, never did: docs/blender.md).
        It is delivered when the first pass covers it (a render without
        progressive refinement: when its first tile is done), then while
        tiles finish at most every DISPLAY_SECONDS, or rarer when reading
        it takes long (a large frame with many passes), and at the end.
        """
        cancelled = False
        buffers = None
        pending = False
        next_delivery = 0.0
        while True:
            progress = render.progress()
            while render.next_tile() is not None:
                pending = True
            shown_whole = not rs.progressive or progress.samples_done > 0
            if pending and shown_whole and time.monotonic() >= next_delivery:
                started = time.monotonic()
                buffers = self._deliver_whole(render, rs, buffers)
                pending = False
                took = time.monotonic() - started
                next_delivery = started + max(DISPLAY_SECONDS, DISPLAY_COST_RATIO * took)
            self._show_progress(progress, rs)
            if progress.state in (core.PHOS_STATE_DONE, core.PHOS_STATE_CANCELLED,
                                  core.PHOS_STATE_FAILED):
                break
            if not cancelled and self.test_break():
                render.cancel()
                cancelled = True
            # Waits on the render, not a fixed sleep: a poll period slept in
            # full after the last tile cost every render up to 30 ms, a
            # tenth of a 0.3 s render (docs/benchmarks.md). A failure
            # raises here as it would after the loop.
            render.wait(POLL_SECONDS)

        # Tiles that finished between the last poll and the end. The state is
        # final here, so this wait only joins workers that are done; the loop
        # above ends because the core reaches a final state, and after a
        # cancel it does so within 0.5 s (tests/blender/test_cancel.py).
        outcome = render.wait(-1.0)
        while render.next_tile() is not None:
            pending = True
        if pending:
            buffers = self._deliver_whole(render, rs, buffers)
        final = render.progress()
        self._show_progress(final, rs, final=True)
        if not self.is_preview:
            for message in status.short_map_warnings(final, rs):
                self.report({'WARNING'}, message)
        if outcome == core.PHOS_OK:
            self.update_progress(1.0)

    def _show_progress(self, progress, rs, final=False):
        """Progress bar and the stats line of the render.

        A new stage is always shown (in background mode too, where the lines
        are otherwise rate-limited), so `blender -b` prints each of them.
        """
        self.update_progress(min(max(progress.fraction, 0.0), 1.0))
        index = progress.stage_index
        new_stage = index != self._last_stage
        if new_stage and self._last_stage is not None:
            # Stages that began and ended between two polls (a small photon
            # map is traced and built in milliseconds) are still logged, in
            # the plan's order, so the stats line and `blender -b` show every
            # stage.
            for stage_id, name in self._plan[self._last_stage + 1:index]:
                self._stats("Phos | " + status.stage_text(progress, stage_id, name, rs.samples), force=True)
        self._last_stage = index
        stage_id, name = self._plan[index]
        self._stats("Phos | " + status.stage_text(progress, stage_id, name, rs.samples), force=final or new_stage)

    def _stats(self, text, force=False):
        """update_stats with changed text only, and sparingly in background mode.

        `blender -b` prints every stats update as a line (Blender 5: Phos
        prints it), so there it is limited to one line per
        STATS_SECONDS_BACKGROUND unless forced.
        """
        if text == self._stats_text:
            return
        now = time.monotonic()
        if bpy.app.background and not force and now - self._stats_time < STATS_SECONDS_BACKGROUND:
            return
        self._stats_text, self._stats_time = text, now
        self.update_stats("", text)
        if bpy.app.background and bpy.app.version >= (5, 0, 0):
            # Blender 5 prints stats lines only with its render log on;
            # a farm's log should still show each stage.
            print(text, flush=True)

    def _deliver_whole(self, render, rs, buffers):
        """The whole render region in one result (_poll says when): the
        tiles finished so far are dropped from the queue first, so any that
        finish during the read are delivered again after it."""
        while render.next_tile() is not None:
            pass
        whole = core.phos_tile()
        whole.x, whole.y = rs.region_x, rs.region_y
        whole.width, whole.height = rs.region_width, rs.region_height
        return self._deliver_rect(render, whole, buffers)

    def _deliver_rect(self, render, tile, buffers):
        """Copy a rectangle of the film into a render result (relative to the border).

        Every pass of the result is written: the ones the core rendered from
        the core, any other (a pass Phos does not know, or one enabled after
        the render started) with zeros, since Blender merges them all.
        `buffers` (pass → float32 array) is reused from result to result.
        """
        if buffers is None:
            buffers = {}
        n = tile.width * tile.height
        ox, oy = self._region_origin
        result = self.begin_result(tile.x - ox, tile.y - oy, tile.width, tile.height,
                                   layer=self._layer_name)
        try:
            enabled = render.settings.pass_mask
            for render_pass in result.layers[0].passes:
                pass_id = PASS_IDS.get(render_pass.name)
                channels = render_pass.channels
                key = (pass_id, channels) if pass_id is not None and enabled & (1 << pass_id) \
                    else (None, channels)
                buffer = buffers.get(key)
                if buffer is None or buffer.shape[0] < n:
                    buffer = buffers[key] = np.empty((n, channels), dtype=np.float32)
                pixels = buffer[:n]
                if key[0] is None:
                    pixels[:] = 0.0
                elif render.channels(pass_id) == channels:
                    render.read(pass_id, tile.x, tile.y, tile.width, tile.height, out=pixels)
                else:  # never expected: Blender gave the pass another channel count
                    data = render.read(pass_id, tile.x, tile.y, tile.width, tile.height)
                    c = min(channels, data.shape[1])
                    pixels[:] = 0.0
                    pixels[:, :c] = data[:, :c]
                _write_rect(render_pass, pixels)
        except Exception:
            self.end_result(result, cancel=True)
            raise
        self.end_result(result)
        self._delivered = True
        return buffers

    def _deliver_placeholder(self, region):
        """A transparent black full-region result, so Blender never gets none."""
        _, _, w, h = region
        try:
            result = self.begin_result(0, 0, w, h, layer=self._layer_name)
            if result is None:
                return
            try:
                # Every pass (Combined and the enabled Phos passes alike).
                zeros = {}
                for render_pass in result.layers[0].passes:
                    ch = render_pass.channels
                    if ch not in zeros:
                        zeros[ch] = np.zeros((w * h, ch), dtype=np.float32)
                    _write_rect(render_pass, zeros[ch])
            finally:
                self.end_result(result)
        except Exception as ex:
            print("Phos: could not deliver a placeholder result: %s" % ex)


classes = (PhosRenderEngine,)


@bpy.app.handlers.persistent
def _forget_converted_images(*_args):
    """Another file is loaded: its images are others (export/image.py's cache)."""
    image_cache.CONVERTED.clear()


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.app.handlers.load_pre.append(_forget_converted_images)


def unregister():
    if _forget_converted_images in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.remove(_forget_converted_images)
    image_cache.CONVERTED.clear()
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
