# SPDX-License-Identifier: GPL-3.0-or-later
"""Scene export against Cycles' sync, measured in one Blender process.

    blender -b --factory-startup --python bench/export.py -- [--instances N] [--csv FILE]

A geometry-nodes scatter of N cubes (default a million) on a diffuse
material, rendered at 16 × 16 pixels with one sample, so that the time
from Blender's render_pre to render_post is the export (Phos: export and
BVH build; Cycles: its sync and BVH build). Each engine renders it three
times with Persistent Data on: the first F12, the same again, and again
after the camera moved. The ratios are Phos's time over Cycles'.
docs/benchmarks.md keeps the results.
"""

import argparse
import csv
import os
import sys
import time

import bpy

REPO_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO_DIR, "scenes"))
import _common  # noqa: E402
import _materials as m  # noqa: E402


def build(scene, count):
    """The scatter: a line of `count` cubes as geometry-nodes instances."""
    _common.clear_factory_scene()
    base = m.plane(scene, "Base", 0.1, 0.1, m.diffuse("Grey", (0.5, 0.5, 0.5)))
    tree, out = _common.geometry_node_group("Scatter")
    nodes, links = tree.nodes, tree.links
    line = nodes.new("GeometryNodeMeshLine")
    line.mode = "OFFSET"
    line.inputs["Count"].default_value = count
    line.inputs["Offset"].default_value = (3.0 / max(count - 1, 1), 0.0, 0.0)
    cube = nodes.new("GeometryNodeMeshCube")
    cube.inputs["Size"].default_value = (0.002, 0.002, 0.002)
    material = nodes.new("GeometryNodeSetMaterial")
    material.inputs["Material"].default_value = base.data.materials[0]
    instance = nodes.new("GeometryNodeInstanceOnPoints")
    links.new(cube.outputs["Mesh"], material.inputs["Geometry"])
    links.new(line.outputs["Mesh"], instance.inputs["Points"])
    links.new(material.outputs["Geometry"], instance.inputs["Instance"])
    links.new(instance.outputs["Instances"], out.inputs[0])
    base.modifiers.new("Scatter", "NODES").node_group = tree
    m.camera(scene, (1.5, -3.0, 1.0), (1.5, 0.0, 0.0), lens=35.0)
    scene.world = bpy.data.worlds.new("World")
    scene.world.color = (0.5, 0.5, 0.5)
    _common.configure_output(scene, (16, 16))
    _common.configure_cycles(scene, 1, 4)
    _common.configure_phos(scene, 1, 4)
    scene.render.use_persistent_data = True


def seconds(scene):
    """render_pre to render_post of one F12."""
    marks = {}
    pre = lambda *_: marks.__setitem__("pre", time.perf_counter())    # noqa: E731
    post = lambda *_: marks.__setitem__("post", time.perf_counter())  # noqa: E731
    bpy.app.handlers.render_pre.append(pre)
    bpy.app.handlers.render_post.append(post)
    try:
        bpy.ops.render.render()
    finally:
        bpy.app.handlers.render_pre.remove(pre)
        bpy.app.handlers.render_post.remove(post)
    return marks["post"] - marks["pre"]


def main():
    p = argparse.ArgumentParser(prog="export.py", description=__doc__.splitlines()[0])
    p.add_argument("--instances", type=int, default=1000000)
    p.add_argument("--csv", default=os.path.join(REPO_DIR, "out", "bench", "export.csv"))
    args = p.parse_args(_common.script_argv())
    _common.enable_addon()
    scene = bpy.context.scene
    rows = []
    for engine in ("PHOS", "CYCLES"):
        build(scene, args.instances)
        scene.render.engine = engine
        times = [seconds(scene), seconds(scene)]
        scene.camera.location.x += 0.1
        times.append(seconds(scene))
        rows.append({"engine": engine, "instances": args.instances, "first": times[0], "again": times[1],
                     "camera_moved": times[2]})
        _common.log("%s: first F12 %.2f s, again %.2f s, after a camera move %.2f s" % (engine, *times))
    phos, cycles = rows
    for key in ("first", "again", "camera_moved"):
        _common.log("Phos / Cycles, %s: %.2f" % (key, phos[key] / cycles[key]))
    os.makedirs(os.path.dirname(os.path.abspath(args.csv)), exist_ok=True)
    with open(args.csv, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)


main()
