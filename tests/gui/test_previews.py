# SPDX-License-Identifier: GPL-3.0-or-later
"""Material and light previews rendered by Phos in Blender's GUI, under
Xvfb (`make test-gui`; tools/test-gui.sh):

1. A material's preview (the Properties editor's Preview panel) is a Phos
   render at engine.PREVIEW_SAMPLES in Blender's preview scene, and it
   shows that scene's checker floor (a Checker Texture, read by the shader
   program) under the sphere in the material's hue.
2. A light's preview is a Phos render that is not blank.
3. While a final render runs, a preview renders on one thread (it never
   competes with an F12 for the cores).

The Preview panels are closed by default; the test adds open ones of its
own for the datablocks it shows.
"""

import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import guitest  # noqa: E402
from guitest import check  # noqa: E402
import phostest as pt  # noqa: E402 (tests/blender, put on the path by guitest)

state = {"renders": []}


class TEST_PT_material_preview(bpy.types.Panel):
    bl_label = "Test Preview"
    bl_space_type, bl_region_type, bl_context = 'PROPERTIES', 'WINDOW', "material"
    bl_order = -1000

    def draw(self, context):
        self.layout.template_preview(context.material)


class TEST_PT_light_preview(bpy.types.Panel):
    bl_label = "Test Preview"
    bl_space_type, bl_region_type, bl_context = 'PROPERTIES', 'WINDOW', "data"
    bl_order = -1000

    @classmethod
    def poll(cls, context):
        return context.light is not None

    def draw(self, context):
        self.layout.template_preview(context.light)


def record_renders():
    """Keep each preview render's settings and its whole Combined image
    (the core.Render reads of its results, put together)."""
    from phos import core
    original = core.Render.read

    def read(self, pass_id, x, y, width, height, out=None):
        pixels = original(self, pass_id, x, y, width, height, out)
        rs = self.settings
        if pass_id == core.PHOS_PASS_COMBINED and rs.width > 48:  # not the 32-pixel icons
            record = next((r for r in state["renders"] if r["render"] is self), None)
            if record is None:
                record = {"render": self, "samples": rs.samples, "threads": rs.threads,
                          "image": np.zeros((rs.height, rs.width, 4), np.float32)}
                state["renders"].append(record)
            record["image"][y:y + height, x:x + width] = pixels.reshape(height, width, -1)
        return pixels
    core.Render.read = read


def show(context_name, ob):
    bpy.context.view_layer.objects.active = ob
    window, props, _ = guitest.area('PROPERTIES')
    props.spaces.active.context = context_name
    state["seen"] = len(state["renders"])


def new_render_done():
    """The last preview render started since show() has finished."""
    renders = state["renders"][state["seen"]:]
    if not renders:
        return None
    from phos import core
    last = renders[-1]
    handle = last["render"]._handle
    done = handle is None or last["render"].progress().state == core.PHOS_STATE_DONE
    return last if done else None


def step(n):
    if n == 0:
        scene = pt.reset_file()  # enables the add-on
        bpy.utils.register_class(TEST_PT_material_preview)
        bpy.utils.register_class(TEST_PT_light_preview)
        scene.render.engine = "PHOS"
        record_renders()
        cube = pt.add_cube(scene, "Cube", material=pt.diffuse("Red", (0.8, 0.1, 0.05)))
        show('MATERIAL', cube)
        return 1
    from phos import engine
    if n == 1:
        r = new_render_done()
        if r is None:
            return n
        check("a material preview is a Phos render", r["samples"] == engine.PREVIEW_SAMPLES,
              "%d samples" % r["samples"])
        img = r["image"]
        h = img.shape[0]
        lum = img[..., :3].mean(axis=2)
        floor = lum[: h // 8].reshape(-1)           # rows bottom-up: the floor under the sphere
        low, high = np.percentile(floor, 10), np.percentile(floor, 90)
        check("the preview shows the checker floor", high > 4.0 * low and high > 0.02,
              "floor 10th/90th percentile %.3f / %.3f" % (low, high))
        middle = img[h // 2 - 3:h // 2 + 3, img.shape[1] // 2 - 3:img.shape[1] // 2 + 3, :3].mean(axis=(0, 1))
        check("the sphere has the material's hue", middle[0] > 2.0 * middle[1] > 0.0,
              "RGB %.3f %.3f %.3f" % tuple(middle))
        lamp = pt.add_light(bpy.context.scene, "POINT", 100.0, location=(0, 0, 3), name="Lamp")
        show('DATA', lamp)
        return 2
    if n == 2:
        r = new_render_done()
        if r is None:
            return n
        check("a light preview is a Phos render and not blank", r["image"][..., :3].max() > 0.01,
              "max %.3f" % r["image"][..., :3].max())
        # A final render running: the next preview takes one thread.
        engine._final_renders += 1
        state["seen"] = len(state["renders"])
        bpy.data.objects["Lamp"].data.energy = 300.0  # an edit renders the preview again
        return 3
    if n == 3:
        r = new_render_done()
        if r is None:
            return n
        engine._final_renders -= 1
        check("beside a final render a preview renders on one thread", r["threads"] == 1,
              "%d threads" % r["threads"])
        return None
    return n


guitest.run(step)
