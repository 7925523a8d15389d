# SPDX-License-Identifier: GPL-3.0-or-later
"""How Phos's and Cycles' costs grow with the triangle count, in one Blender
process (`make bench`; docs/benchmarks.md).

    blender -b --factory-startup --python bench/scaling.py -- [--triangles N ...] [--csv FILE]

The scene: a rippled grid of N triangles (a bmesh grid with a sine
displacement, so the BVH is not trivially flat) under a sun, seen from
above, shaded flat and shaded smooth (most production meshes are smooth;
their vertex normals cost the export more, docs/reliability.md). Per
engine, shading and size:

- sync_seconds: Phos's export and BVH build (the add-on's "export"
  stage); Cycles' time to its first sample, the render time of 1 sample
  less the time of one more sample;
- seconds_per_sample: (time at 9 samples − time at 1) / 8, at 256 × 256;
  for Phos the growth of its own rendering stage, which leaves out the
  export's run-to-run spread;
- peak_bytes: the largest resident memory the render added, from
  /proc/self/status (VmHWM after the render, reset before it through
  /proc/self/clear_refs, less VmRSS before it), and per triangle.
"""

import argparse
import csv
import math
import os
import sys
import time

import bmesh
import bpy

REPO_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO_DIR, "scenes"))
import _common  # noqa: E402


def log(msg):
    print("[bench] %s" % msg, flush=True)


def status_bytes(key):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(key):
                return int(line.split()[1]) * 1024
    return -1


def reset_peak():
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")  # resets VmHWM to the current RSS
        return True
    except OSError:
        return False


def build(triangles, smooth=False):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    side = max(2, int(math.sqrt(triangles / 2.0)))
    bm = bmesh.new()
    bmesh.ops.create_grid(bm, x_segments=side, y_segments=side, size=2.0)
    for v in bm.verts:
        v.co.z = 0.05 * math.sin(9.0 * v.co.x) * math.cos(7.0 * v.co.y)
    mesh = bpy.data.meshes.new("Grid")
    bm.to_mesh(mesh)
    bm.free()
    if smooth:
        mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
    ob = bpy.data.objects.new("Grid", mesh)
    scene.collection.objects.link(ob)
    sun = bpy.data.lights.new("Sun", "SUN")
    sun.energy = 3.0
    sun_ob = bpy.data.objects.new("Sun", sun)
    sun_ob.rotation_euler = (0.6, 0.2, 0.0)
    scene.collection.objects.link(sun_ob)
    cam = bpy.data.cameras.new("Camera")
    cam_ob = bpy.data.objects.new("Camera", cam)
    cam_ob.location = (0.0, -3.0, 3.0)
    cam_ob.rotation_euler = (math.radians(45.0), 0.0, 0.0)
    scene.collection.objects.link(cam_ob)
    scene.camera = cam_ob
    world = bpy.data.worlds.new("World")
    scene.world = world
    if not _common.enable_addon():
        raise RuntimeError("the Phos add-on could not be enabled")
    return scene, len(mesh.polygons) * 2


def timed_render(scene):
    t = {}
    handlers = bpy.app.handlers
    pre = lambda *_a: t.__setitem__("start", time.perf_counter())  # noqa: E731
    post = lambda *_a: t.__setitem__("end", time.perf_counter())  # noqa: E731
    handlers.render_pre.append(pre)
    handlers.render_post.append(post)
    reset = reset_peak()
    before = status_bytes("VmRSS:")
    try:
        bpy.ops.render.render()
    finally:
        handlers.render_pre.remove(pre)
        handlers.render_post.remove(post)
    peak = status_bytes("VmHWM:") - before if reset else -1
    return t["end"] - t["start"], peak


def phos_stage_seconds():
    """The stage times of Phos's last render ({"export": s, stage id: s})."""
    eng = sys.modules.get(_common.ADDON_NAME + ".engine")
    return getattr(eng, "last_render_seconds", {})


def measure(scene, engine, samples):
    _common.configure_output(scene, (256, 256))
    _common.configure_cycles(scene, samples, 4)
    _common.configure_phos(scene, samples, 4, integrator="PATH")
    scene.render.engine = engine
    return timed_render(scene)


def main():
    p = argparse.ArgumentParser(prog="scaling.py")
    p.add_argument("--triangles", type=int, nargs="+", default=[10000, 100000, 1000000, 5000000])
    p.add_argument("--shading", nargs="+", choices=("flat", "smooth"), default=["flat", "smooth"])
    p.add_argument("--csv", default=os.path.join(REPO_DIR, "out", "bench", "scaling.csv"))
    args = p.parse_args(_common.script_argv())
    rows = []
    for n, shading in [(n, sh) for n in args.triangles for sh in args.shading]:
        scene, count = build(n, smooth=shading == "smooth")
        for engine in ("PHOS", "CYCLES"):
            one, peak = measure(scene, engine, 1)
            phos_one = dict(phos_stage_seconds())
            nine, peak9 = measure(scene, engine, 9)
            if engine == "PHOS":
                # Phos reports its own stages: the rendering stage's growth
                # from 1 to 9 samples, free of the export's run-to-run
                # spread (at 10⁶ triangles that spread exceeds 8 samples).
                phos_nine = phos_stage_seconds()
                rendering = sys.modules[_common.ADDON_NAME + ".core"].PHOS_STAGE_RENDERING
                per_sample = max(phos_nine.get(rendering, 0.0) - phos_one.get(rendering, 0.0), 0.0) / 8.0
                sync = phos_nine.get("export", float("nan"))
            else:
                per_sample = max(nine - one, 0.0) / 8.0
                sync = one - per_sample
            peak = max(peak, peak9)
            row = {"engine": engine, "shading": shading, "triangles": count, "sync_seconds": round(sync, 4),
                   "seconds_per_sample": round(per_sample, 5), "peak_bytes": peak,
                   "bytes_per_triangle": round(peak / count, 1) if peak > 0 else ""}
            log(" ".join("%s=%s" % kv for kv in row.items()))
            rows.append(row)
        os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    try:
        main()
    except Exception:
        import traceback
        traceback.print_exc()
        sys.exit(1)
