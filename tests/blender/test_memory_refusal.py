# SPDX-License-Identifier: GPL-3.0-or-later
"""A render that would exhaust memory is refused with a message, and the
next render works (docs/reliability.md, "Memory").

The core estimates what a render needs before it allocates anything
(core/src/render/memory.c) and refuses when that exceeds what the machine,
or the process's cgroup, has available; the estimate against fixed
amounts is tested in tests/c/test_api.c. Here: through Blender, 2²⁸
photons in each map (the settings' maximum), about 75 GiB, on a machine
that has less.
"""

import re

import bpy
import pytest

import phostest as pt


def small_scene(scene):
    pt.add_camera(scene, location=(0, -5, 2), target=(0, 0, 0.5))
    pt.add_plane(scene, "Floor", size=6, material=pt.diffuse("Floor", (0.8, 0.8, 0.8)))
    pt.add_sphere(scene, "Ball", location=(0, 0, 0.5))
    pt.add_light(scene, "POINT", 200.0, location=(1, -1, 3))
    pt.configure_output(scene, 16, 16)
    pt.configure_phos(scene, 2, max_bounces=4)
    scene.render.engine = "PHOS"
    scene.phos.integrator = "PHOTON"
    scene.phos.global_photons = scene.phos.caustic_photons = 2000
    return scene


def available_gib():
    with open("/proc/meminfo") as f:
        info = dict(line.split(":", 1) for line in f)
    kib = int(info["MemAvailable"].split()[0]) + int(info.get("SwapFree", "0 kB").split()[0])
    return kib / 2**20


def test_huge_photon_maps_are_refused_then_the_next_render_works(scene, tmp_path):
    if available_gib() > 60:
        pytest.skip("this machine has %.0f GiB available: 2^28 photons a map would fit" % available_gib())
    small_scene(scene)
    p = scene.phos
    p.global_photons = p.caustic_photons = 1 << 28
    with pytest.raises(RuntimeError) as err:
        pt.render_array(scene, tmp_path, name="refused")
    text = str(err.value)
    assert "needs about" in text and "photon maps" in text, text
    need = [float(x) for x in re.findall(r"([0-9.]+) GiB", text)]
    assert need and need[0] > 30.0, text
    # The placeholder result was delivered (Blender has an image), and the
    # next render with sane settings works in the same session.
    p.global_photons = p.caustic_photons = 2000
    px = pt.render_array(scene, tmp_path, name="after")
    assert px.shape == (16, 16, 4) and px[..., :3].mean() > 0.0
