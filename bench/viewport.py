# SPDX-License-Identifier: GPL-3.0-or-later
"""The viewport's latency against Cycles' viewport, measured in Blender's
GUI on a virtual X server (make bench; tools/bench-viewport.sh starts it):

    xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup \\
        --python bench/viewport.py -- --csv FILE

The Cornell box of scenes/cornell_box.py, seen through its camera in a 3D
view in Rendered shading, at 16 viewport samples, for Cycles (CPU) and for
Phos with each integrator. What is timed is what a user sees: a thread
copies the middle of the view from the X server's screen every 5 ms
(XGetImage), and

- first image: from switching the view to Rendered to the first draw that
  is not the empty view;
- each edit (the camera moved, a light's power, a light moved, a
  material's colour, an object moved, a mesh edited): from the edit, made
  once the image is still, to the first draw that differs from the image
  before it; the median of REPEATS edits.

Both engines pay the same drawing costs (tens of ms a draw under software
OpenGL) and the copy's 5 ms granularity, so the ratios are fairer than the
absolute times. The
ratios are Phos's time over Cycles'; docs/benchmarks.md keeps a run.
"""

import argparse
import csv
import os
import sys
import threading
import time
import traceback

import bpy
import numpy as np

REPO_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO_DIR, "scenes"))
sys.path.insert(0, os.path.join(REPO_DIR, "tests", "blender"))
sys.path.insert(0, os.path.join(REPO_DIR, "tests", "gui"))
import cornell_box  # noqa: E402
import phostest  # noqa: E402
import xscreen  # noqa: E402

SAMPLES = 16
STILL_SECONDS = 2.5      # the screen unchanged this long: the image is still
REPEATS = 3              # each edit made this many times; the median is reported
TIMEOUT_SECONDS = 120.0  # per measurement
CONFIGS = [("CYCLES", None), ("PHOS", "PATH"), ("PHOS", "PHOTON")]


def _edits():
    """(name, edit) in order; each changes what the camera sees."""
    def camera_move():
        # The view looks through the camera: moving it moves the view.
        bpy.data.objects["Camera"].location.x += 0.02 * _size()

    def light_power():
        bpy.data.lights["Ceiling Light"].energy *= 1.5

    def light_move():
        bpy.data.objects["Ceiling Light"].location.x += 0.05 * _size()

    def material():
        tree = bpy.data.materials["Cornell White"].node_tree
        bsdf = next(n for n in tree.nodes if n.type in ('BSDF_DIFFUSE', 'BSDF_PRINCIPLED'))
        socket = bsdf.inputs["Color" if "Color" in bsdf.inputs else "Base Color"]
        warm = abs(socket.default_value[0] - 0.9) < 1e-3
        socket.default_value = (0.8, 0.8, 0.8, 1.0) if warm else (0.9, 0.8, 0.5, 1.0)

    def object_move():
        bpy.data.objects["Mirror Sphere"].location.x += 0.05 * _size()

    def mesh_edit():
        me = bpy.data.objects["Glass Sphere"].data
        co = np.empty(len(me.vertices) * 3, np.float32)
        me.vertices.foreach_get("co", co)
        me.vertices.foreach_set("co", co * np.float32(1.15))
        me.update()

    return [("camera moved", camera_move), ("light power", light_power), ("light moved", light_move),
            ("material colour", material), ("object moved", object_move), ("mesh edited", mesh_edit)]


def _size():
    return bpy.data.objects["Floor"].dimensions.x or 1.0


def _view():
    window = bpy.context.window_manager.windows[0]
    area = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
    return window, area, next(r for r in area.regions if r.type == 'WINDOW')


class Frames(threading.Thread):
    """What the screen shows: a thread with its own connection to the X
    server copies the middle half of the 3D view from the screen every
    POLL_SECONDS (XGetImage: what was drawn and swapped, whatever drew it),
    and keeps the time it last changed and its pixels."""

    POLL_SECONDS = 0.005

    def __init__(self):
        super().__init__(daemon=True)
        self.screen = xscreen.Screen()
        self.rect = None                    # (x, y, w, h) on the screen, top-left origin
        self.time, self.pixels = 0.0, None  # when the pixels last changed, and them
        self.lock = threading.Lock()

    def watch(self):
        """Watch the middle half of the 3D view's drawing region."""
        window, area, region = _view()
        x, y, w, h = xscreen.region_rect(window, region)
        self.rect = (x + w // 4, y + h // 4, w // 2, h // 2)

    def run(self):
        while True:
            rect = self.rect
            pixels = self.screen.grab(*rect) if rect is not None else None
            if pixels is not None:
                now = time.perf_counter()
                with self.lock:
                    if self.pixels is None or not np.array_equal(pixels, self.pixels):
                        self.pixels, self.time = pixels, now
            time.sleep(self.POLL_SECONDS)

    def latest(self):
        with self.lock:
            return self.time, self.pixels


def _phos_restarted(t0):
    """When the Phos viewport last restarted after t0 (its session's start),
    or t0 for Cycles; infinity while it has not."""
    if bpy.context.scene.render.engine != "PHOS":
        return t0
    from phos import viewport
    starts = [session.started for session in viewport.SESSIONS if session.started > t0]
    return min(starts) if starts else float("inf")


def _differs(a, b):
    """Whether two screen copies differ by more than the last bit here and there."""
    if a is None or b is None or a.shape != b.shape:
        return a is not b
    return float(np.abs(a.astype(np.int16) - b).mean()) > 0.05


class Bench:
    def __init__(self, csv_path):
        self.csv_path, self.rows = csv_path, []
        self.frames = Frames()
        self.configs = list(CONFIGS)
        self.steps = self._steps()
        self.redraw = False  # ask for one redraw at the next tick

    def _setup(self, engine, integrator):
        bpy.ops.wm.read_factory_settings(use_empty=False)
        if engine == "PHOS":
            phostest.enable_addon()
        scene = bpy.context.scene
        cornell_box.build(scene)
        scene.render.engine = engine
        if engine == "CYCLES":
            scene.cycles.device = 'CPU'
            scene.cycles.preview_samples = SAMPLES
            scene.cycles.use_preview_denoising = False
            if hasattr(scene.cycles, "use_preview_adaptive_sampling"):
                scene.cycles.use_preview_adaptive_sampling = False
        else:
            scene.phos.integrator = integrator
            scene.phos.preview_samples = SAMPLES
        for ob in scene.objects:
            ob.select_set(False)
        window, area, region = _view()
        space = area.spaces.active
        overlay = space.overlay
        for name in ("show_floor", "show_axis_x", "show_axis_y", "show_cursor", "show_object_origins",
                     "show_extras", "show_outline_selected", "show_relationship_lines", "show_text",
                     "show_stats"):
            if hasattr(overlay, name):
                setattr(overlay, name, False)
        space.show_gizmo = False
        space.region_3d.view_perspective = 'CAMERA'
        space.region_3d.view_camera_zoom = 30.0  # the camera's frame fills the view

    def _still(self, since):
        """Whether an edit may be made: for Phos, once its session renders
        at the full resolution (an edit cancels that render, and _changed
        waits for an image of the restarted one, so a later pass of the old
        one cannot be taken for the edit's effect); for Cycles, which says
        nothing, once the screen has not changed for STILL_SECONDS since
        `since` (its 16 passes at this size take well under that)."""
        if bpy.context.scene.render.engine == "PHOS":
            from phos import viewport
            return all(session.divider == 1 and session.first_image is not None for session in viewport.SESSIONS)
        return self._quiet(since)

    def _quiet(self, since):
        """Whether the screen has not changed for STILL_SECONDS since `since`."""
        changed, pixels = self.frames.latest()
        return pixels is not None and time.perf_counter() - max(changed, since) > STILL_SECONDS

    def _changed(self, t0, before, label, what):
        """Wait (yielding) for the screen to differ from `before` after t0;
        the seconds it took."""
        while True:
            changed, pixels = self.frames.latest()
            # An image, not the empty view: the box has structure; for Phos,
            # one of the render the change started (not a pass of the last).
            if changed > t0 and _differs(pixels, before) and float(pixels.std()) > 8.0 and \
                    changed > _phos_restarted(t0):
                return changed - t0
            if time.perf_counter() - t0 > TIMEOUT_SECONDS:
                raise RuntimeError("%s: %s: nothing on the screen changed in %.0f s" % (label, what, TIMEOUT_SECONDS))
            yield

    def _steps(self):
        """A generator: each next() is one timer tick."""
        self.frames.start()
        while self.configs:
            engine, integrator = self.configs.pop(0)
            label = engine.lower() if integrator is None else "phos %s" % integrator.lower()
            self._setup(engine, integrator)
            self.redraw = True
            self.frames.watch()
            start = time.perf_counter()
            while not self._quiet(start):  # the Solid view drawn, and copied
                yield
            window, area, region = _view()
            _, before = self.frames.latest()
            t0 = time.perf_counter()
            area.spaces.active.shading.type = 'RENDERED'
            self.redraw = True
            seconds = yield from self._changed(t0, before, label, "first image")
            self._row(label, "first image", seconds)
            for name, edit in _edits():
                times = []
                for _ in range(REPEATS):
                    start = time.perf_counter()
                    while not self._still(start):
                        if time.perf_counter() - start > TIMEOUT_SECONDS:
                            raise RuntimeError("%s: the image never settles" % label)
                        yield
                    _, before = self.frames.latest()
                    t0 = time.perf_counter()
                    edit()
                    self.redraw = True
                    times.append((yield from self._changed(t0, before, label, name)))
                self._row(label, name, float(np.median(times)))
            area.spaces.active.shading.type = 'SOLID'
            self.frames.rect = None
            yield

    def _row(self, label, what, seconds):
        print("VIEWPORT %-12s %-16s %.3f s" % (label, what, seconds), flush=True)
        self.rows.append((label, what, seconds))

    def report(self):
        cycles = {what: s for label, what, s in self.rows if label == "cycles"}
        print("\nViewport latency (s; Phos / Cycles):")
        labels = sorted({label for label, _, _ in self.rows if label != "cycles"})
        print("%-16s %8s " % ("", "cycles") + " ".join("%16s" % label for label in labels))
        for what in cycles:
            cells = []
            for label in labels:
                s = next((s for l, w, s in self.rows if l == label and w == what), None)
                cells.append("%7.3f (%5.2fx)" % (s, s / cycles[what]) if s is not None else "%16s" % "-")
            print("%-16s %8.3f " % (what, cycles[what]) + " ".join(cells))
        if self.csv_path:
            os.makedirs(os.path.dirname(os.path.abspath(self.csv_path)), exist_ok=True)
            with open(self.csv_path, "w", newline="") as f:
                out = csv.writer(f)
                out.writerow(["engine", "what", "seconds", "ratio_to_cycles"])
                for label, what, s in self.rows:
                    out.writerow([label, what, "%.4f" % s, "%.3f" % (s / cycles[what]) if what in cycles else ""])

    def tick(self):
        try:
            next(self.steps)
            if self.redraw:
                # Once after an edit; the engines ask for their own redraws
                # while they render, and idle views are not redrawn.
                _view()[1].tag_redraw()
                self.redraw = False
            return 0.02
        except StopIteration:
            self.report()
            os._exit(0)
        except Exception:
            traceback.print_exc()
            os._exit(1)


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--csv")
    args = parser.parse_args(argv)
    bench = Bench(args.csv)
    bpy.app.timers.register(bench.tick, first_interval=1.0, persistent=True)


main()
