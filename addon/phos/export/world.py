# SPDX-License-Identifier: GPL-3.0-or-later
"""The scene world → the core's constant background radiance.

The world's node tree is walked like a material's (Mix/Add Shader, groups,
reroutes): each Background node contributes colour × strength, and the sum
is the background radiance in W/(m²·sr), as in Cycles. Without nodes the
world's colour is used; without a world the background is black. Textures
(Environment, Sky) are not supported by the core yet: they render as the
colour their Background node would have unlinked, with a warning.
"""

import numpy as np

from .. import core
from .material import NodeTreeWalker, active_output, uses_nodes


def world_color(world, ctx):
    if world is None:
        return np.zeros(3, dtype=np.float32)
    if not uses_nodes(world):
        return np.array(world.color[:3], dtype=np.float32)
    out = active_output(world.node_tree, 'ShaderNodeOutputWorld')
    owner = "world '%s'" % world.name
    if out is None:
        ctx.warn("Phos: %s has no World Output node; the background is black" % owner)
        return np.zeros(3, dtype=np.float32)
    walker = NodeTreeWalker(ctx, owner, world=True)
    color = np.zeros(3, dtype=np.float32)
    for closure in walker.closures(out.inputs['Surface']):
        if closure.type == core.PHOS_CLOSURE_EMISSION:
            color += closure.weight
    volume = out.inputs.get('Volume')
    if volume is not None and volume.is_linked:
        ctx.warn("Phos: %s: the volume output is not supported; ignored" % owner)
    return color


def export_world(ctx):
    desc = core.new_world()
    color = world_color(ctx.scene.world, ctx)
    ctx.world_emits = bool(np.any(color > 0.0))
    desc.color[:] = [float(c) for c in color]
    ctx.core.set_world(desc)
