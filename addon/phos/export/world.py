# SPDX-License-Identifier: GPL-3.0-or-later
"""The scene world → the core's background: a constant radiance, or a world
material whose program gives the radiance of each direction.

The world's node tree is walked like a material's (Mix/Add Shader, groups,
reroutes, every value node of the shader program): each Background node
becomes an EMISSION closure of colour × strength, in W/(m²·sr) as in
Cycles. When nothing in it varies with direction the core gets one colour,
which it samples cosine-weighted at no cost per ray; otherwise the closures
and their program go to the core as a material, which evaluates them as
Cycles evaluates a background shader (the point is the ray's direction) and
builds an importance-sampling map from them (docs/algorithms.md §11).
Environment Texture, Mapping, Texture Coordinate and Light Path's Is
Camera Ray work there as in Cycles. Without nodes the world's colour is
used; without a world the background is black.
"""

import numpy as np

from .. import core
from . import program as prog
from .material import NodeTreeWalker, active_output, closure_descs, uses_nodes


def world_closures(world, ctx):
    """(EMISSION closures, Program) of a world's node tree; ([], Program())
    when it sends no light."""
    owner = "world '%s'" % world.name
    out = active_output(world.node_tree, 'ShaderNodeOutputWorld')
    walker = NodeTreeWalker(ctx, owner, world=True)
    if out is None:
        ctx.warn("Phos: %s has no World Output node; the background is black" % owner)
        return [], walker.program
    closures = [c for c in walker.closures(out.inputs['Surface'])
                if c.type == core.PHOS_CLOSURE_EMISSION and not c.negligible()]
    volume = out.inputs.get('Volume')
    if volume is not None and volume.is_linked:
        ctx.warn("Phos: %s: the volume output is not supported; ignored" % owner)
    return closures[:core.PHOS_MAX_CLOSURES], walker.program


def _sum(closures):
    color = np.zeros(3, dtype=np.float32)
    for c in closures:
        color += np.asarray(c.weight, dtype=np.float32)
    return color


def world_color(world, ctx):
    """The world's constant radiance (float32[3]), or None when it varies
    with direction."""
    if world is None:
        return np.zeros(3, dtype=np.float32)
    if not uses_nodes(world):
        return np.array(world.color[:3], dtype=np.float32)
    closures, _ = world_closures(world, ctx)
    return None if any(prog.varies(c.weight) for c in closures) else _sum(closures)


def export_world(ctx):
    """Set the core scene's world from the scene's (the first export, or an
    edit of the world applied in place: a world material already added is
    replaced, never added again)."""
    desc = core.new_world()
    world = ctx.scene.world
    if world is None or not uses_nodes(world):
        color = world_color(world, ctx)
        closures, program = [], None
    else:
        closures, program = world_closures(world, ctx)
        color = None if any(prog.varies(c.weight) for c in closures) else _sum(closures)
    if color is not None:
        ctx.world_emits = bool(np.any(color > 0.0))
        desc.color[:] = [float(c) for c in color]
    else:
        if program.too_large():
            ctx.warn("Phos: world '%s': its shader program exceeds the core's limits; the background is black"
                     % world.name)
            closures = []
        descs = closure_descs(closures, program)
        program_desc = None if program.empty() else program.desc()
        try:
            if ctx.world_material is None:
                ctx.world_material = ctx.core.add_material(descs, program_desc)
            else:
                ctx.core.update_material(ctx.world_material, descs, program_desc)
        except core.PhosError as ex:
            raise core.PhosError("world '%s': %s" % (world.name, ex), ex.status) from None
        desc.material = ctx.world_material
        ctx.world_emits = bool(closures)
    ctx.core.set_world(desc)
