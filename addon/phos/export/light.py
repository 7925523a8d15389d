# SPDX-License-Identifier: GPL-3.0-or-later
"""Blender lights → core lights in physical units.

Blender's light units changed between versions; Phos matches the Cycles of
the Blender it runs in (measured against Cycles 3.4 renders, and read in the
Cycles sources for later versions; see docs/blender.md §1). With
S = colour × power:

  point/spot  intensity I = S/(4π) W/sr in every version. Before 4.0 a
              radius makes a disk facing the shading point with radiance
              S/(4π·πr²); 4.0 makes it a sphere of radiance S/(4π²r²), which
              is the same intensity (projected area πr²). 4.1's soft falloff
              (default on) is the disk again.
  spot        × the cone; before 3.5 Cycles also multiplies by the cosine to
              the spot axis.
  sun         irradiance E = S W/m² at normal incidence from 4.0, which
              spreads it as radiance S/(π·sin²(α/2)) over the cone. Before
              4.0 Cycles samples directions uniformly over a disc of radius
              r = tan(α/2) one unit away, each carrying S (pdf = eval):
              E = S·mean(cos) = S·2(√(1+r²) − 1)/r² (0.42 % less for 15°).
  area        radiance L = S/(4A) before 4.0, S/(πA) from 4.0, with A the
              world-space area (object scale included, ×π/4 for disk and
              ellipse); one-sided, emitting along the object's −Z.

From 4.5 (Cycles' light sync): S = colour × temperature colour (when
use_temperature) × power × 2^exposure, and with Normalize off the power
is not spread over the emitter: Cycles then multiplies it by the area it
would have divided by (4πr² for a point or spot, 4 for a radius of 0; the
world-space area of an area light; π sin²(α/2) for a sun of angle α).
"""

import math
import warnings

import numpy as np

from .. import core


def _normalized(v):
    n = float(np.linalg.norm(v))
    return v / n if n > 0.0 else v


def add_light(ob, matrix_world, ctx, is_instance=False):
    """Add one light instance (object + world matrix) to the core scene; its
    id (or None) is recorded for update_light."""
    light_id = _add_light(ob, matrix_world, ctx)
    ctx.light_ids.setdefault(ob.original.as_pointer(), []).append(None if is_instance else light_id)
    return light_id


def update_light(ob, ctx):
    """Replace an exported light in place (scene updates, phos.h). Returns
    False when that cannot stand for an export: the object is instanced or
    new, was not added (no light), becomes a portal or stops emitting."""
    ids = ctx.light_ids.get(ob.original.as_pointer())
    if ids is None or len(ids) != 1 or ids[0] is None:
        return False
    light = ob.data
    cycles = getattr(light, "cycles", None)
    if light.type == 'AREA' and cycles is not None and getattr(cycles, "is_portal", False):
        return False
    desc = light_desc(ob, np.array(ob.matrix_world, dtype=np.float64), ctx)
    if desc is None:
        return False
    try:
        ctx.core.update_light(ids[0], desc)
    except core.PhosError as ex:
        raise core.PhosError("light '%s': %s" % (ob.name, ex), ex.status) from None
    return True


def _add_light(ob, matrix_world, ctx):
    m = np.array(matrix_world, dtype=np.float64).reshape(4, 4)
    light = ob.data
    cycles = getattr(light, "cycles", None)
    if light.type == 'AREA' and cycles is not None and getattr(cycles, "is_portal", False):
        return add_portal(ob, light, m, ctx)
    desc = light_desc(ob, m, ctx)
    if desc is None:
        return None
    try:
        light_id = ctx.core.add_light(desc)
    except core.PhosError as ex:
        raise core.PhosError("light '%s': %s" % (ob.name, ex), ex.status) from None
    ctx.stats["lights"] += 1
    return light_id


def light_desc(ob, matrix_world, ctx):
    """The core description of a light (not a portal) at a world matrix, or
    None when it adds nothing (no light, zero area, an unknown type)."""
    light = ob.data
    m = np.array(matrix_world, dtype=np.float64).reshape(4, 4)
    strength = light_strength(light, m)
    if not np.any(strength):
        return None
    if not _neutral_node_tree(light):
        ctx.warn("Phos: light '%s': its shader nodes are not supported; rendered without them" % ob.name)

    desc = core.new_light()
    # Object > Visibility > Camera; off by default for lights, as in Cycles.
    desc.camera_visible = 1 if getattr(ob, "visible_camera", False) else 0
    desc.position[:] = [float(v) for v in m[:3, 3]]
    desc.direction[:] = [float(v) for v in _normalized(-m[:3, 2])]

    if light.type in {'POINT', 'SPOT'}:
        desc.type = core.PHOS_LIGHT_POINT if light.type == 'POINT' else core.PHOS_LIGHT_SPOT
        desc.color[:] = [float(v) for v in strength / (4.0 * math.pi)]
        desc.radius = max(light.shadow_soft_size, 0.0)
        desc.point_shape = _point_shape(light, ctx)
        if light.type == 'SPOT':
            desc.spot_angle = min(max(light.spot_size, 1e-4), math.pi)
            desc.spot_blend = min(max(light.spot_blend, 0.0), 1.0)
            desc.spot_cosine = 0 if ctx.at_least(3, 5) else 1
    elif light.type == 'SUN':
        desc.type = core.PHOS_LIGHT_SUN
        desc.sun_angle = min(max(light.angle, 0.0), math.pi - 1e-4)
        scale = 1.0 if ctx.at_least(4, 0) else sun_disc_mean_cosine(desc.sun_angle)
        desc.color[:] = [float(v) for v in strength * scale]
    elif light.type == 'AREA':
        desc.type = core.PHOS_LIGHT_AREA
        area = _area_shape(light, m, desc)
        if area <= 0.0:
            ctx.warn("Phos: light '%s' has zero area; skipped" % ob.name)
            return None
        denom = (math.pi if ctx.at_least(4, 0) else 4.0) * area
        desc.color[:] = [float(c) for c in strength / denom]
        spread = getattr(light, "spread", math.pi)
        if spread < math.pi - 1e-4:
            ctx.warn("Phos: light '%s': area light spread is not supported; using 180°" % ob.name)
    else:
        ctx.warn("Phos: light '%s' of type %s is not supported; skipped" % (ob.name, light.type))
        return None
    return desc


def _area_shape(light, m, desc):
    """An area light's edges and shape into desc; returns its area (m²)."""
    ellipse = light.shape in {'DISK', 'ELLIPSE'}
    size_v = light.size_y if light.shape in {'RECTANGLE', 'ELLIPSE'} else light.size
    u = m[:3, 0] * light.size
    v = m[:3, 1] * size_v
    area = float(np.linalg.norm(np.cross(u, v)))
    if ellipse:
        area *= math.pi / 4.0
    desc.axis_u[:] = [float(c) for c in u]
    desc.axis_v[:] = [float(c) for c in v]
    desc.area_shape = core.PHOS_AREA_ELLIPSE if ellipse else core.PHOS_AREA_RECTANGLE
    return area


def add_portal(ob, light, m, ctx):
    """An area light marked as a portal (Cycles' Portal): no light of its
    own, an opening the world's light samples are drawn through, facing
    into the interior as the lamp points."""
    desc = core.new_light()
    desc.type = core.PHOS_LIGHT_PORTAL
    desc.position[:] = [float(v) for v in m[:3, 3]]
    desc.direction[:] = [float(v) for v in _normalized(-m[:3, 2])]
    if _area_shape(light, m, desc) <= 0.0:
        ctx.warn("Phos: portal '%s' has zero area; skipped" % ob.name)
        return None
    try:
        light_id = ctx.core.add_light(desc)
    except core.PhosError as ex:
        raise core.PhosError("portal '%s': %s" % (ob.name, ex), ex.status) from None
    ctx.stats["portals"] += 1
    return light_id


def light_strength(light, m):
    """S = colour × power, as Cycles takes it from the light (RGB, W)."""
    color = np.array(light.color[:], dtype=np.float64)
    if getattr(light, "use_temperature", False):
        color = color * np.array(light.temperature_color[:], dtype=np.float64)
    strength = color * light.energy * 2.0 ** getattr(light, "exposure", 0.0)
    if not getattr(light, "normalize", True):
        strength = strength * unnormalized_area(light, m)
    return strength


def unnormalized_area(light, m):
    """The area Cycles divides a light's power by when Normalize is on."""
    if light.type in {'POINT', 'SPOT'}:
        r = max(light.shadow_soft_size, 0.0)
        return 4.0 * math.pi * r * r if r > 0.0 else 4.0
    if light.type == 'SUN':
        half = 0.5 * light.angle
        return math.pi * math.sin(half) ** 2 if half > 0.0 else 1.0
    if light.type == 'AREA':
        size_v = light.size_y if light.shape in {'RECTANGLE', 'ELLIPSE'} else light.size
        area = float(np.linalg.norm(m[:3, 0] * light.size) * np.linalg.norm(m[:3, 1] * size_v))
        return area * (math.pi / 4.0 if light.shape in {'DISK', 'ELLIPSE'} else 1.0)
    return 1.0


def _neutral_node_tree(light):
    """No node tree, or the one Blender 5.3 gives every new light: a white
    Emission of strength 1 into the Light Output, which changes nothing."""
    tree = getattr(light, "node_tree", None)
    with warnings.catch_warnings():
        # 5.x deprecates Light.use_nodes (its tree is then always used): read
        # it while it exists, without the warning in the user's console.
        warnings.simplefilter("ignore", DeprecationWarning)
        use_nodes = getattr(light, "use_nodes", True)
    if tree is None or not use_nodes:
        return True
    outputs = [n for n in tree.nodes if n.bl_idname == 'ShaderNodeOutputLight' and n.is_active_output]
    if not outputs or not outputs[0].inputs['Surface'].is_linked:
        return True
    source = outputs[0].inputs['Surface'].links[0].from_node
    if source.bl_idname != 'ShaderNodeEmission' or any(i.is_linked for i in source.inputs):
        return False
    color = tuple(source.inputs['Color'].default_value)[:3]
    return color == (1.0, 1.0, 1.0) and source.inputs['Strength'].default_value == 1.0


def sun_disc_mean_cosine(angle):
    """Mean cosine to the axis of directions uniform over a disc of radius
    r = tan(angle/2) one unit away: the irradiance of a Cycles < 4.0 sun of
    strength 1 at normal incidence."""
    r2 = math.tan(0.5 * angle) ** 2
    if r2 < 1e-6:
        return 1.0 - 0.25 * r2
    return 2.0 * (math.sqrt(1.0 + r2) - 1.0) / r2


def _point_shape(light, ctx):
    if not ctx.at_least(4, 0):
        return core.PHOS_POINT_DISK
    if ctx.at_least(4, 1) and getattr(light, "use_soft_falloff", True):
        return core.PHOS_POINT_DISK
    return core.PHOS_POINT_SPHERE
