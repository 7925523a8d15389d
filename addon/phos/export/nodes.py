# SPDX-License-Identifier: GPL-3.0-or-later
"""Cycles' value nodes → shader-program instructions (docs/architecture.md,
"Shader programs").

`NodeCompiler.input(node, names, width)` gives the Value feeding a node's
input: the socket's default when unlinked (or, for the sockets Cycles links
implicitly, the texture coordinate or normal it reads), else the compiled
output of the node behind reroutes, muted nodes and groups. Each node type
has a handler returning its outputs; handlers are memoised per (node, group
stack, bump offset), so a node used twice is computed once.

A Bump node's Height is compiled three times: at the point and at two
points moved along the surface (BUMP_OFFSET), as Cycles evaluates it; the
texture coordinates inside those copies come from the moved points. The
moves are the pixel's footprint times the version's filter width
(_bump_filter_width).

Anything without a handler gives one warning naming the material and node,
and the input it feeds takes its own unlinked value (the closest match).
"""

import math

import numpy as np

from .. import core
from .mesh_attributes import attribute_id
from .program import Value, constant, is_const

_GENERATED, _NORMAL, _UV, _OBJECT, _CAMERA = range(5)


def _socket_default(socket, width):
    value = getattr(socket, "default_value", None)
    if value is None:
        return constant(np.zeros(width))
    try:
        v = [float(x) for x in value[:3]]
        if width == 1:
            return constant(float(np.dot([0.2126, 0.7152, 0.0722], v)) if len(v) == 3 else v[0])
        return constant(v if len(v) == 3 else [v[0]] * 3)
    except TypeError:
        return constant(float(value) if width == 1 else [float(value)] * 3)


def _enum(prefix, identifier):
    return getattr(core, prefix + identifier, None)


def _mode_of(nc, node, prefix, identifier):
    value = _enum(prefix, identifier)
    if value is None:
        nc.walker.note(node, "its setting %s is unknown to Phos; the first choice is used" % identifier)
        return 0
    return value


def _dims(s):
    return {'1D': 1, '2D': 2, '3D': 3, '4D': 4}.get(s, 3)


class NodeCompiler:
    def __init__(self, walker, program):
        from .material import find_input, _resolve  # the walker's plumbing
        self._find_input, self._resolve = find_input, _resolve
        self.walker = walker
        self.ctx = walker.ctx
        self.p = program
        self.bump = 0             # 0, or 1/2 while compiling a Bump's moved heights
        self.bump_width = 0.0     # the filter width of those moves (BUMP_OFFSET's param[0])
        self._memo = {}
        self._active = set()

    # ---------------------------------------------------------------- plumbing

    def input(self, node, names, width, stack=None, implicit=None):
        """The Value of a node's input (first of `names` that exists), or the
        constant 0 when the node has none of them."""
        names = (names,) if isinstance(names, str) else names
        socket = self._find_input(node, *names)
        if socket is None:
            return constant(np.zeros(width)) if width == 3 else constant(0.0)
        return self.socket(socket, width, self.walker.stack if stack is None else stack, implicit)

    def socket(self, socket, width, stack, implicit=None):
        src = self._resolve(socket, stack)
        if src.node is None:
            if implicit is not None and not socket.is_linked:
                return self.p.convert(implicit(), width)
            return self.p.convert(_socket_default(src.socket if src.socket is not None else socket, width), width)
        outputs = self.node_outputs(src.node, src.stack)
        value = outputs.get(src.output.identifier)
        if value is None:
            # An unsupported node or output, a missing image: the input
            # takes its own unlinked value (the node has warned).
            value = _socket_default(socket, width)
        return self.p.convert(value, width)

    def node_outputs(self, node, stack):
        key = (node.as_pointer(), tuple(g.as_pointer() for g in stack), self.bump, self.bump_width)
        if key in self._memo:
            return self._memo[key]
        if key in self._active:
            self.ctx.warn("Phos: %s: the node tree has a cycle through node '%s'; the cycle is cut there"
                          % (self.walker.owner, node.name))
            return {}
        handler = _HANDLERS.get(node.bl_idname)
        self._active.add(key)
        outer = self.walker.stack
        self.walker.stack = stack
        try:
            if handler is None:
                self.walker.unsupported(node)
                outputs = {}
            else:
                outputs = handler(self, node, stack)
        finally:
            self.walker.stack = outer
            self._active.discard(key)
        self._memo[key] = outputs
        return outputs

    def value_node_linked(self, socket, stack):
        """Whether a socket is fed by a node this compiler evaluates."""
        src = self._resolve(socket, stack)
        return src.node is not None

    # ------------------------------------------------------ implicit inputs

    def coordinates(self):
        """Texture Coordinate's outputs at the point (or at the bump's moved point)."""
        if self.bump:
            pos, gen, uv, obj, _ = self.p.emit(core.PHOS_OP_BUMP_OFFSET, [], [3, 3, 3, 3, 3], mode=self.bump,
                                               param=(self.bump_width,))
            base = self.p.emit(core.PHOS_OP_TEXTURE_COORDINATE, [], [3, 3, 3, 3, 3], mode=0)
            return [gen, base[1], uv, obj, base[4]], pos
        base = self.p.emit(core.PHOS_OP_TEXTURE_COORDINATE, [], [3, 3, 3, 3, 3], mode=0)
        geometry = self.p.emit(core.PHOS_OP_GEOMETRY, [], [3, 3, 3, 3, 1])
        return base, geometry[0]

    def generated(self):
        return self.coordinates()[0][_GENERATED]

    def uv(self):
        return self.coordinates()[0][_UV]

    def normal(self):
        return self.p.emit(core.PHOS_OP_GEOMETRY, [], [3, 3, 3, 3, 1])[1]

    def attribute(self, key, flags=0):
        """Color, Vector, Fac and Alpha of a mesh attribute (mesh_attributes.py),
        at the point or at a Bump's moved point;
        the program remembers the key, so the meshes of its material export it.
        flags 1: a missing attribute's alpha is 0 (the Color Attribute node)."""
        self.p.attributes.add(key)
        return self.p.emit(core.PHOS_OP_ATTRIBUTE, [], [3, 3, 1, 1], mode=self.bump, flags=flags,
                           table=attribute_id(self.ctx, key), param=(self.bump_width if self.bump else 0.0,))

    def vector_math(self, operation, a, b=None):
        """The vector output of a Vector Math operation on Values."""
        zero = constant((0.0, 0.0, 0.0))
        return self.p.emit(core.PHOS_OP_VECTOR_MATH, [a, zero if b is None else b, zero, constant(1.0)], [3, 1],
                           mode=getattr(core, "PHOS_VECTOR_MATH_" + operation), flags=self.version_flags())[0]

    def mode(self, node, prefix, identifier):
        """The core enum of a node setting (PHOS_<prefix><identifier>), or 0
        with a warning for one a newer Blender added."""
        return _mode_of(self, node, prefix, identifier)

    def version_flags(self):
        """Flags of MATH, VECTOR_MATH and HUE_SATURATION for the running
        Blender's definitions (shading/nodes/node_util.h)."""
        flags = 0
        if not self.ctx.at_least(5, 0):
            flags |= 32
        if not self.ctx.at_least(4, 3):
            flags |= 16
        return flags

    def legacy_texture_flag(self):
        """Value 16 in the texture ops' flags: Blender 3.x's definitions."""
        return 0 if self.ctx.at_least(4, 0) else 16

    def check_texture_mapping(self, node):
        mapping = getattr(node, "texture_mapping", None)
        if mapping is None:
            return
        identity = (tuple(mapping.translation) == (0.0, 0.0, 0.0) and tuple(mapping.rotation) == (0.0, 0.0, 0.0)
                    and tuple(mapping.scale) == (1.0, 1.0, 1.0) and not mapping.use_min and not mapping.use_max)
        if not identity:
            self.walker.note(node, "its Texture Mapping panel is not supported; ignored (use a Mapping node)")


# ---------------------------------------------------------------- converters

def _math(nc, node, stack):
    op = nc.mode(node, "PHOS_MATH_", node.operation)
    a, b, c = (nc.socket(node.inputs[k], 1, stack) for k in range(3))
    flags = (1 if node.use_clamp else 0) | nc.version_flags()
    return {"Value": nc.p.emit(core.PHOS_OP_MATH, [a, b, c], [1], mode=op, flags=flags)[0]}


def _vector_math(nc, node, stack):
    op = nc.mode(node, "PHOS_VECTOR_MATH_", node.operation)
    a, b, c = (nc.socket(node.inputs[k], 3, stack) for k in range(3))
    scale = nc.socket(node.inputs[3], 1, stack)
    vec, val = nc.p.emit(core.PHOS_OP_VECTOR_MATH, [a, b, c, scale], [3, 1], mode=op, flags=nc.version_flags())
    return {"Vector": vec, "Value": val}


def _map_range(nc, node, stack):
    mode = nc.mode(node, "PHOS_MAP_RANGE_", node.interpolation_type)
    flags = 1 if node.clamp else 0
    if getattr(node, "data_type", 'FLOAT') == 'FLOAT_VECTOR':
        ins = [nc.socket(node.inputs[k], 3, stack) for k in (6, 7, 8, 9, 10, 11)]
        return {"Vector": nc.p.emit(core.PHOS_OP_MAP_RANGE_VECTOR, ins, [3], mode=mode, flags=flags)[0]}
    ins = [nc.socket(node.inputs[k], 1, stack) for k in range(6)]
    return {"Result": nc.p.emit(core.PHOS_OP_MAP_RANGE, ins, [1], mode=mode, flags=flags)[0]}


def _clamp_node(nc, node, stack):
    ins = [nc.socket(node.inputs[k], 1, stack) for k in range(3)]
    mode = nc.mode(node, "PHOS_CLAMP_", node.clamp_type)
    return {"Result": nc.p.emit(core.PHOS_OP_CLAMP, ins, [1], mode=mode)[0]}


def _combine_xyz(nc, node, stack):
    ins = [nc.socket(node.inputs[k], 1, stack) for k in range(3)]
    return {"Vector": nc.p.emit(core.PHOS_OP_COMBINE_XYZ, ins, [3])[0]}


def _separate(nc, value, names):
    """Components of a 3-wide Value as three float Values."""
    if value.is_const:
        return {n: constant(float(value.const[k])) for k, n in enumerate(names)}
    p = nc.p
    out = {}
    for k, n in enumerate(names):
        out[n] = Value(1, ref=(value.ref[0], value.ref[1] + k), program=p)
    return out


def _separate_xyz(nc, node, stack):
    return _separate(nc, nc.socket(node.inputs[0], 3, stack), ("X", "Y", "Z"))


def _math_value(nc, node, stack):
    return {"Value": constant(float(node.outputs[0].default_value))}


def _rgb(nc, node, stack):
    return {"Color": constant([float(x) for x in node.outputs[0].default_value[:3]])}


def _rgb_to_bw(nc, node, stack):
    return {"Val": nc.p.convert(nc.socket(node.inputs[0], 3, stack), 1)}


def _blackbody(nc, node, stack):
    return {"Color": nc.p.emit(core.PHOS_OP_BLACKBODY, [nc.socket(node.inputs[0], 1, stack)], [3])[0]}


def _wavelength(nc, node, stack):
    return {"Color": nc.p.emit(core.PHOS_OP_WAVELENGTH, [nc.socket(node.inputs[0], 1, stack)], [3])[0]}


# --------------------------------------------------------------------- colour

def _mix(nc, node, stack):
    """The Mix node (3.4+): float, vector or colour, uniform or per-axis factor."""
    dt = node.data_type
    sockets = {s.identifier: s for s in node.inputs}
    clamp_factor = 2 if node.clamp_factor else 0
    if dt == 'FLOAT':
        fac, a, b = (nc.socket(sockets[k], 1, stack) for k in ("Factor_Float", "A_Float", "B_Float"))
        return {"Result_Float": nc.p.emit(core.PHOS_OP_MIX_FLOAT, [fac, a, b], [1], flags=clamp_factor)[0]}
    if dt == 'VECTOR':
        uniform = getattr(node, "factor_mode", 'UNIFORM') == 'UNIFORM'
        fac = nc.socket(sockets["Factor_Float" if uniform else "Factor_Vector"], 1 if uniform else 3, stack)
        a, b = (nc.socket(sockets[k], 3, stack) for k in ("A_Vector", "B_Vector"))
        flags = clamp_factor | (0 if uniform else 4)
        return {"Result_Vector": nc.p.emit(core.PHOS_OP_MIX_VECTOR, [fac, a, b], [3], flags=flags,
                                           in_widths=[1 if uniform else 3, 3, 3])[0]}
    if dt != 'RGBA':
        nc.walker.unsupported(node, "its %s data type is not supported; using its default" % dt)
        return {}
    fac = nc.socket(sockets["Factor_Float"], 1, stack)
    a, b = (nc.socket(sockets[k], 3, stack) for k in ("A_Color", "B_Color"))
    mode = nc.mode(node, "PHOS_BLEND_", node.blend_type)
    flags = clamp_factor | (1 if node.clamp_result else 0)
    return {"Result_Color": nc.p.emit(core.PHOS_OP_MIX_COLOR, [fac, a, b], [3], mode=mode, flags=flags)[0]}


def _mix_rgb(nc, node, stack):
    """The legacy MixRGB node: its factor is always clamped (Cycles)."""
    fac = nc.socket(node.inputs[0], 1, stack)
    a, b = nc.socket(node.inputs[1], 3, stack), nc.socket(node.inputs[2], 3, stack)
    mode = nc.mode(node, "PHOS_BLEND_", node.blend_type)
    flags = 2 | (1 if node.use_clamp else 0)
    return {"Color": nc.p.emit(core.PHOS_OP_MIX_COLOR, [fac, a, b], [3], mode=mode, flags=flags)[0]}


RAMP_TABLE_SIZE = 256  # Cycles bakes ramps and curves into this many entries


def _color_ramp(nc, node, stack):
    ramp = node.color_ramp
    if ramp.color_mode != 'RGB' and ramp.interpolation not in {'CONSTANT', 'LINEAR'}:
        pass  # evaluate() already blends in the ramp's colour mode
    table = []
    for i in range(RAMP_TABLE_SIZE):
        table.extend(float(x) for x in ramp.evaluate(i / (RAMP_TABLE_SIZE - 1)))
    offset = nc.p.add_table(table)
    flags = 8 if ramp.interpolation == 'CONSTANT' else 0
    fac = nc.socket(node.inputs[0], 1, stack)
    color, alpha = nc.p.emit(core.PHOS_OP_RAMP, [fac], [3, 1], mode=RAMP_TABLE_SIZE, flags=flags, table=offset)
    return {"Color": color, "Alpha": alpha}


def _curve_range(mapping, curves):
    """The x range a curve table spans: from the leftmost to the rightmost
    point of the curves (Cycles bakes the same range)."""
    xs = [point.location[0] for curve in curves for point in curve.points]
    if not xs or max(xs) <= min(xs):
        return 0.0, 1.0
    return min(xs), max(xs)


def _extrapolate(mapping):
    return 1 if getattr(mapping, "extend", 'EXTRAPOLATED') == 'EXTRAPOLATED' else 0


def _curve_node(nc, node, stack, op, used, entry, width, output):
    """A curve node baked as Cycles bakes it: RAMP_TABLE_SIZE entries of
    entry(mapping, curves, t) (four floats) over the x range of the `used`
    curves (one more from Blender 4.0, which samples the range's end too,
    as Blender's own curve table does: the extrapolated slope comes from
    the last step), then one instruction reading Fac and the input (width
    wide)."""
    mapping = node.mapping
    mapping.update()
    curves = mapping.curves
    lo, hi = _curve_range(mapping, curves[:used])
    size = RAMP_TABLE_SIZE + 1 if nc.ctx.at_least(4, 0) else RAMP_TABLE_SIZE
    table = []
    for i in range(size):
        table.extend(entry(mapping, curves, lo + i / (size - 1) * (hi - lo)))
    offset = nc.p.add_table(table)
    fac, value = nc.socket(node.inputs[0], 1, stack), nc.socket(node.inputs[1], width, stack)
    return {output: nc.p.emit(op, [fac, value], [width], mode=size, table=offset, param=(lo, hi),
                              flags=_extrapolate(mapping))[0]}


def _rgb_entry(mapping, curves, t):
    c = mapping.evaluate(curves[3], t)  # the combined curve first, then R, G, B
    return [mapping.evaluate(curves[0], c), mapping.evaluate(curves[1], c), mapping.evaluate(curves[2], c), 0.0]


def _rgb_curves(nc, node, stack):
    return _curve_node(nc, node, stack, core.PHOS_OP_CURVES_RGB, 4, _rgb_entry, 3, "Color")


def _vector_curves(nc, node, stack):
    return _curve_node(nc, node, stack, core.PHOS_OP_CURVES_VECTOR, 3,
                       lambda m, c, t: [m.evaluate(c[0], t), m.evaluate(c[1], t), m.evaluate(c[2], t), 0.0],
                       3, "Vector")


def _float_curve(nc, node, stack):
    return _curve_node(nc, node, stack, core.PHOS_OP_CURVE_FLOAT, 1,
                       lambda m, c, t: [m.evaluate(c[0], t), 0.0, 0.0, 0.0], 1, "Value")


def _hue_saturation(nc, node, stack):
    ins = [nc.socket(node.inputs[k], 1, stack) for k in range(4)] + [nc.socket(node.inputs[4], 3, stack)]
    return {"Color": nc.p.emit(core.PHOS_OP_HUE_SATURATION, ins, [3], flags=nc.version_flags())[0]}


def _bright_contrast(nc, node, stack):
    ins = [nc.socket(node.inputs[0], 3, stack), nc.socket(node.inputs[1], 1, stack),
           nc.socket(node.inputs[2], 1, stack)]
    return {"Color": nc.p.emit(core.PHOS_OP_BRIGHT_CONTRAST, ins, [3])[0]}


def _gamma(nc, node, stack):
    ins = [nc.socket(node.inputs[0], 3, stack), nc.socket(node.inputs[1], 1, stack)]
    return {"Color": nc.p.emit(core.PHOS_OP_GAMMA, ins, [3])[0]}


def _invert(nc, node, stack):
    ins = [nc.socket(node.inputs[0], 1, stack), nc.socket(node.inputs[1], 3, stack)]
    return {"Color": nc.p.emit(core.PHOS_OP_INVERT, ins, [3])[0]}


def _separate_color(nc, node, stack):
    mode = nc.mode(node, "PHOS_COLOR_MODEL_", getattr(node, "mode", 'RGB'))
    out = nc.p.emit(core.PHOS_OP_SEPARATE_COLOR, [nc.socket(node.inputs[0], 3, stack)], [3], mode=mode)[0]
    return _separate(nc, out, ("Red", "Green", "Blue"))


def _combine_color(nc, node, stack):
    mode = nc.mode(node, "PHOS_COLOR_MODEL_", getattr(node, "mode", 'RGB'))
    ins = [nc.socket(node.inputs[k], 1, stack) for k in range(3)]
    return {"Color": nc.p.emit(core.PHOS_OP_COMBINE_COLOR, ins, [3], mode=mode)[0]}


def _separate_rgb(nc, node, stack):
    return _separate(nc, nc.socket(node.inputs[0], 3, stack), ("R", "G", "B"))


def _combine_rgb(nc, node, stack):
    ins = [nc.socket(node.inputs[k], 1, stack) for k in range(3)]
    return {"Image": nc.p.emit(core.PHOS_OP_COMBINE_COLOR, ins, [3], mode=core.PHOS_COLOR_MODEL_RGB)[0]}


def _separate_hsv(nc, node, stack):
    out = nc.p.emit(core.PHOS_OP_SEPARATE_COLOR, [nc.socket(node.inputs[0], 3, stack)], [3],
                    mode=core.PHOS_COLOR_MODEL_HSV)[0]
    return _separate(nc, out, ("H", "S", "V"))


def _combine_hsv(nc, node, stack):
    ins = [nc.socket(node.inputs[k], 1, stack) for k in range(3)]
    return {"Color": nc.p.emit(core.PHOS_OP_COMBINE_COLOR, ins, [3], mode=core.PHOS_COLOR_MODEL_HSV)[0]}


# ------------------------------------------------------------------- textures

def _texture_vector(nc, node, stack, implicit):
    nc.check_texture_mapping(node)
    return nc.input(node, "Vector", 3, stack, implicit=implicit)


def _tex_image(nc, node, stack):
    from . import image as image_export
    image_id = image_export.add_image(node, nc.ctx, nc.walker.owner)
    if image_id is None:
        # Cycles' missing-image colour is magenta; Phos renders as unlinked.
        return {}
    vec = _texture_vector(nc, node, stack, nc.uv)
    interp = {'Closest': core.PHOS_IMAGE_CLOSEST, 'Cubic': core.PHOS_IMAGE_CUBIC,
              'Smart': core.PHOS_IMAGE_CUBIC}.get(node.interpolation, core.PHOS_IMAGE_LINEAR)
    ext = {'EXTEND': core.PHOS_IMAGE_EXTEND, 'CLIP': core.PHOS_IMAGE_CLIP,
           'MIRROR': core.PHOS_IMAGE_MIRROR}.get(node.extension, core.PHOS_IMAGE_REPEAT)
    flags = interp | ext
    alpha_linked = any(l.is_valid for l in node.outputs["Alpha"].links) if "Alpha" in node.outputs else False
    alpha_mode = getattr(node.image, "alpha_mode", 'STRAIGHT')
    if alpha_linked or alpha_mode in {'CHANNEL_PACKED', 'NONE'} or node.image.colorspace_settings.is_data:
        flags |= core.PHOS_IMAGE_UNASSOCIATE
    mode = nc.mode(node, "PHOS_PROJECTION_", node.projection)
    color, alpha = nc.p.emit(core.PHOS_OP_TEX_IMAGE, [vec], [3, 1], mode=mode, flags=flags, table=image_id,
                             param=(getattr(node, "projection_blend", 0.0),))
    return {"Color": color, "Alpha": alpha}


def _tex_environment(nc, node, stack):
    """The Environment Texture: the image looked up by a direction, its
    Vector unlinked the shading point's position (Cycles' LINK_POSITION),
    which for the world is the ray's direction."""
    from . import image as image_export
    image_id = image_export.add_image(node, nc.ctx, nc.walker.owner)
    if image_id is None:
        return {}
    vec = _texture_vector(nc, node, stack, lambda: nc.coordinates()[1])
    interp = {'Closest': core.PHOS_IMAGE_CLOSEST, 'Cubic': core.PHOS_IMAGE_CUBIC,
              'Smart': core.PHOS_IMAGE_CUBIC}.get(node.interpolation, core.PHOS_IMAGE_LINEAR)
    flags = interp | core.PHOS_IMAGE_REPEAT
    if node.image.colorspace_settings.is_data:
        flags |= core.PHOS_IMAGE_UNASSOCIATE
    mode = nc.mode(node, "PHOS_PROJECTION_", node.projection)
    color, alpha = nc.p.emit(core.PHOS_OP_TEX_IMAGE, [vec], [3, 1], mode=mode, flags=flags, table=image_id)
    return {"Color": color, "Alpha": alpha}


# Blender's names of the Sky Texture's models: "Nishita" until 4.5 is
# 5.0's "Single Scattering".
_SKY_MODELS = {'NISHITA': core.PHOS_SKY_SINGLE_SCATTERING, 'SINGLE_SCATTERING': core.PHOS_SKY_SINGLE_SCATTERING,
               'MULTIPLE_SCATTERING': core.PHOS_SKY_MULTIPLE_SCATTERING, 'PREETHAM': core.PHOS_SKY_PREETHAM,
               'HOSEK_WILKIE': core.PHOS_SKY_HOSEK_WILKIE}
# The models computed into a texture (the rest are evaluated per direction).
SKY_TEXTURED = {core.PHOS_SKY_SINGLE_SCATTERING, core.PHOS_SKY_MULTIPLE_SCATTERING}


def _tex_sky(nc, node, stack):
    """The Sky Texture (docs/algorithms.md §11.1): the model computed once
    by the core, its texture added as an image; the instruction looks it up
    by direction. The Vector unlinked is Generated, which for the world is
    the ray's direction: the core may then render the sun's disc as a sun
    light (flags 1)."""
    from . import image as image_export
    model = _SKY_MODELS.get(node.sky_type)
    if model is None:  # a model a newer Blender added
        nc.walker.note(node, "the %s sky model is not supported; the node is treated as unlinked"
                       % node.sky_type.replace('_', ' ').title())
        return {}
    found = image_export.add_sky(node, model, nc.ctx, nc.walker.owner)
    if found is None:
        return {}
    image_id, data = found
    data = list(data)
    if image_id is not None:
        data[core.PHOS_SKY_DATA_IMAGE] = float(image_id)
    socket = nc._find_input(node, "Vector")
    if socket is not None and not socket.enabled:
        socket = None  # 3.x's scattering sky ignores it (unavailable); 4.x's node has none
    if socket is None:
        nc.check_texture_mapping(node)
        vec = nc.p.convert(nc.generated(), 3)
    else:
        vec = _texture_vector(nc, node, stack, nc.generated)
    direction = nc.walker.world and (socket is None or not socket.is_linked)
    flags = 1 if direction and model in SKY_TEXTURED else 0
    color = nc.p.emit(core.PHOS_OP_TEX_SKY, [vec], [3], mode=model, flags=flags, table=nc.p.add_table(data))[0]
    return {"Color": color}


def _tex_noise(nc, node, stack):
    vec = _texture_vector(nc, node, stack, nc.generated)
    names = ("W", "Scale", "Detail", "Roughness", "Lacunarity", "Offset", "Gain", "Distortion")
    defaults = {"Lacunarity": 2.0, "Gain": 1.0}
    ins = [vec] + [nc.input(node, n, 1, stack) if nc._find_input(node, n) is not None
                   else constant(defaults.get(n, 0.0)) for n in names]
    mode = nc.mode(node, "PHOS_NOISE_", getattr(node, "noise_type", 'FBM'))
    flags = _dims(node.noise_dimensions) | (8 if getattr(node, "normalize", True) else 0) | nc.legacy_texture_flag()
    fac, color = nc.p.emit(core.PHOS_OP_TEX_NOISE, ins, [1, 3], mode=mode, flags=flags)
    return {"Fac": fac, "Color": color}


def _tex_musgrave(nc, node, stack):
    vec = _texture_vector(nc, node, stack, nc.generated)
    names = ("W", "Scale", "Detail", "Dimension", "Lacunarity", "Offset", "Gain")
    ins = [vec] + [nc.input(node, n, 1, stack) for n in names]
    mode = nc.mode(node, "PHOS_NOISE_", node.musgrave_type)
    fac = nc.p.emit(core.PHOS_OP_TEX_MUSGRAVE, ins, [1], mode=mode, flags=_dims(node.musgrave_dimensions))[0]
    return {"Fac": fac, "Height": fac}


def _tex_white_noise(nc, node, stack):
    vec = _texture_vector(nc, node, stack, nc.generated)
    value, color = nc.p.emit(core.PHOS_OP_TEX_WHITE_NOISE, [vec, nc.input(node, "W", 1, stack)], [1, 3],
                             flags=_dims(node.noise_dimensions))
    return {"Value": value, "Color": color}


def _tex_voronoi(nc, node, stack):
    vec = _texture_vector(nc, node, stack, nc.generated)
    names = ("W", "Scale", "Detail", "Roughness", "Lacunarity", "Smoothness", "Exponent", "Randomness")
    defaults = {"Roughness": 0.5, "Lacunarity": 2.0}
    ins = [vec] + [nc.input(node, n, 1, stack) if nc._find_input(node, n) is not None
                   else constant(defaults.get(n, 0.0)) for n in names]
    mode = nc.mode(node, "PHOS_VORONOI_", node.feature)
    metric = nc.mode(node, "PHOS_VORONOI_", node.distance)
    flags = (_dims(node.voronoi_dimensions) | (metric << 5) | (8 if getattr(node, "normalize", False) else 0)
             | nc.legacy_texture_flag() | (128 if nc.ctx.at_least(5, 0) else 0))
    dist, color, pos, w, radius = nc.p.emit(core.PHOS_OP_TEX_VORONOI, ins, [1, 3, 3, 1, 1], mode=mode, flags=flags)
    return {"Distance": dist, "Color": color, "Position": pos, "W": w, "Radius": radius}


def _tex_wave(nc, node, stack):
    vec = _texture_vector(nc, node, stack, nc.generated)
    names = ("Scale", "Distortion", "Detail", "Detail Scale", "Detail Roughness", "Phase Offset")
    ins = [vec] + [nc.input(node, n, 1, stack) for n in names]
    mode = nc.mode(node, "PHOS_WAVE_", node.wave_type)
    bands = {'X': 0, 'Y': 1, 'Z': 2, 'DIAGONAL': 3}.get(getattr(node, "bands_direction", 'X'), 0)
    rings = {'X': 0, 'Y': 1, 'Z': 2, 'SPHERICAL': 3}.get(getattr(node, "rings_direction", 'X'), 0)
    profile = {'SIN': 0, 'SAW': 1, 'TRI': 2}.get(node.wave_profile, 0)
    flags = bands | (rings << 4) | (profile << 8) | (nc.legacy_texture_flag() << 8)
    color, fac = nc.p.emit(core.PHOS_OP_TEX_WAVE, ins, [3, 1], mode=mode, flags=flags)
    return {"Color": color, "Fac": fac}


def _tex_brick(nc, node, stack):
    vec = _texture_vector(nc, node, stack, nc.generated)
    ins = [vec] + [nc.input(node, n, 3, stack) for n in ("Color1", "Color2", "Mortar")] + \
        [nc.input(node, n, 1, stack) for n in ("Scale", "Mortar Size", "Mortar Smooth", "Bias", "Brick Width",
                                               "Row Height")]
    param = (node.offset, float(node.offset_frequency), node.squash, float(node.squash_frequency))
    flags = 0 if nc.ctx.at_least(4, 0) else 1  # 3.x's mortar smoothing (phos.h)
    color, fac = nc.p.emit(core.PHOS_OP_TEX_BRICK, ins, [3, 1], param=param, flags=flags)
    return {"Color": color, "Fac": fac}


def _tex_checker(nc, node, stack):
    vec = _texture_vector(nc, node, stack, nc.generated)
    ins = [vec, nc.input(node, "Color1", 3, stack), nc.input(node, "Color2", 3, stack),
           nc.input(node, "Scale", 1, stack)]
    color, fac = nc.p.emit(core.PHOS_OP_TEX_CHECKER, ins, [3, 1])
    return {"Color": color, "Fac": fac}


def _tex_magic(nc, node, stack):
    vec = _texture_vector(nc, node, stack, nc.generated)
    ins = [vec, nc.input(node, "Scale", 1, stack), nc.input(node, "Distortion", 1, stack)]
    color, fac = nc.p.emit(core.PHOS_OP_TEX_MAGIC, ins, [3, 1], mode=int(node.turbulence_depth),
                           flags=1 if nc.ctx.at_least(5, 3) else 0)
    return {"Color": color, "Fac": fac}


def _tex_gradient(nc, node, stack):
    vec = _texture_vector(nc, node, stack, nc.generated)
    mode = nc.mode(node, "PHOS_GRADIENT_", node.gradient_type)
    color, fac = nc.p.emit(core.PHOS_OP_TEX_GRADIENT, [vec], [3, 1], mode=mode)
    return {"Color": color, "Fac": fac}


# --------------------------------------------------------------------- inputs

def _affine(nc, matrix, point):
    """A constant affine map of a point Value: rows of the 3x4 matrix as dot
    products, then the translation."""
    rows = [nc.p.emit(core.PHOS_OP_VECTOR_MATH, [point, constant(tuple(matrix[r][:3])), constant((0.0,) * 3),
                                                 constant(1.0)], [3, 1], mode=core.PHOS_VECTOR_MATH_DOT_PRODUCT,
                      flags=nc.version_flags())[1] for r in range(3)]
    combined = nc.p.emit(core.PHOS_OP_COMBINE_XYZ, rows, [3])[0]
    return combined + constant(tuple(matrix[r][3] for r in range(3)))


def _tex_coord(nc, node, stack):
    (gen, normal, uv, obj, cam), pos = nc.coordinates()
    other = getattr(node, "object", None)
    if other is not None:
        # Cycles: the world position in the named object's space (its
        # inverse world matrix, a constant of the render).
        inverse = other.matrix_world.inverted_safe()
        nc.ctx.referenced_objects.add(other.original.as_pointer())  # its move changes this material
        obj = _affine(nc, [list(inverse[r]) for r in range(3)], pos)
    if getattr(node, "from_instancer", False):
        nc.walker.note(node, "'From Instancer' is not supported; the instance's own coordinates are used")
    window, reflection = nc.p.emit(core.PHOS_OP_TEXTURE_COORDINATE, [], [3, 3], mode=1)
    return {"Generated": gen, "Normal": normal, "UV": uv, "Object": obj, "Camera": cam, "Window": window,
            "Reflection": reflection}


def _uv_map(nc, node, stack):
    if getattr(node, "from_instancer", False):
        nc.walker.note(node, "'From Instancer' is not supported; the mesh's own UV map is used")
    name = getattr(node, "uv_map", "")
    if not name:
        return {"UV": nc.uv()}
    return {"UV": nc.attribute(("name", name))[1]}


def _rgba_outputs(rgba):
    """The Attribute node's outputs of a constant RGBA, as Cycles converts a
    colour: Fac the mean of RGB, Alpha the fourth number."""
    rgb = constant(rgba[:3])
    return {"Color": rgb, "Vector": rgb, "Fac": constant(sum(rgba[:3]) / 3.0), "Alpha": constant(rgba[3])}


def _attribute(nc, node, stack):
    """The Attribute node: Geometry attributes by name, Object properties
    (a constant mesh attribute per object), View Layer properties (a
    constant of the render); Instancer ones read the object's, with a
    warning."""
    kind = getattr(node, "attribute_type", 'GEOMETRY')
    name = node.attribute_name
    if not name:
        return _rgba_outputs((0.0, 0.0, 0.0, 1.0))
    if kind == 'VIEW_LAYER':
        from .mesh_attributes import view_layer_rgba
        value = view_layer_rgba(nc.ctx, name)
        if value is None:
            nc.walker.note(node, "no view layer, scene or world property '%s'; it reads 0" % name)
            value = (0.0, 0.0, 0.0, 0.0)
        return _rgba_outputs(value)
    if kind in {'OBJECT', 'INSTANCER'}:
        if kind == 'INSTANCER':
            nc.walker.note(node, "instancer attributes are read from the instanced object itself")
        key = ("object", name)
    else:
        key = ("name", name)
    color, vector, fac, alpha = nc.attribute(key)
    return {"Color": color, "Vector": vector, "Fac": fac, "Alpha": alpha}


def _vertex_color(nc, node, stack):
    """The Color Attribute node: a colour attribute by name, or the one
    marked for rendering; a mesh without it reads black, alpha 0 (Cycles)."""
    name = getattr(node, "layer_name", "")
    color, _, _, alpha = nc.attribute(("name", name) if name else ("render_color",), flags=1)
    return {"Color": color, "Alpha": alpha}


def _geometry(nc, node, stack):
    coords, pos = nc.coordinates()
    _, normal, true_normal, incoming, backfacing = nc.p.emit(core.PHOS_OP_GEOMETRY, [], [3, 3, 3, 3, 1])
    out = {"Position": pos, "Normal": normal, "True Normal": true_normal, "Incoming": incoming,
           "Backfacing": backfacing}
    linked = {s.identifier for s in node.outputs if s.is_linked}
    if "Pointiness" in linked:
        out["Pointiness"] = nc.attribute(("pointiness",))[2]
    if "Random Per Island" in linked:
        out["Random Per Island"] = nc.attribute(("random_per_island",))[2]
    if "Parametric" in linked:
        out["Parametric"] = nc.attribute(("parametric",))[1]
    if "Tangent" in linked:
        out["Tangent"] = nc.p.emit(core.PHOS_OP_TANGENT, [], [3], mode=core.PHOS_TANGENT_RADIAL_Z)[0]
    return out


def _tangent(nc, node, stack):
    """The Tangent node: radial about an object axis, or the UV map's
    MikkTSpace tangent (the render UV map's)."""
    if node.direction_type == 'UV_MAP':
        if getattr(node, "uv_map", ""):
            nc.walker.note(node, "UV map '%s' is read as the active render UV map" % node.uv_map)
        nc.ctx.tangents_wanted = True
        mode = core.PHOS_TANGENT_UV_MAP
    else:
        mode = {'X': core.PHOS_TANGENT_RADIAL_X, 'Y': core.PHOS_TANGENT_RADIAL_Y}.get(node.axis,
                                                                                  core.PHOS_TANGENT_RADIAL_Z)
    return {"Tangent": nc.p.emit(core.PHOS_OP_TANGENT, [], [3], mode=mode)[0]}


def _object_info(nc, node, stack):
    location, random, index = nc.p.emit(core.PHOS_OP_OBJECT_INFO, [], [3, 1, 1])
    return {"Location": location, "Random": random, "Object Index": index}


def _fresnel(nc, node, stack):
    ins = [nc.input(node, "IOR", 1, stack), nc.input(node, "Normal", 3, stack, implicit=nc.normal)]
    return {"Fac": nc.p.emit(core.PHOS_OP_FRESNEL, ins, [1])[0]}


def _layer_weight(nc, node, stack):
    ins = [nc.input(node, "Blend", 1, stack), nc.input(node, "Normal", 3, stack, implicit=nc.normal)]
    fresnel, facing = nc.p.emit(core.PHOS_OP_LAYER_WEIGHT, ins, [1, 1])
    return {"Fresnel": fresnel, "Facing": facing}


def _light_path(nc, node, stack):
    a = nc.p.emit(core.PHOS_OP_LIGHT_PATH, [], [1, 1, 1, 1, 1], mode=0)
    b = nc.p.emit(core.PHOS_OP_LIGHT_PATH, [], [1, 1, 1, 1, 1], mode=1)
    names = ("Is Camera Ray", "Is Shadow Ray", "Is Diffuse Ray", "Is Glossy Ray", "Is Singular Ray",
             "Is Reflection Ray", "Is Transmission Ray", "Ray Length", "Ray Depth", "Transparent Depth")
    c = nc.p.emit(core.PHOS_OP_LIGHT_PATH, [], [1, 1, 1], mode=2)
    names += ("Diffuse Depth", "Glossy Depth", "Transmission Depth")
    return dict(zip(names, a + b + c))


# --------------------------------------------------------------------- vector

def _mapping(nc, node, stack):
    vec = nc.input(node, "Vector", 3, stack)
    mode = nc.mode(node, "PHOS_MAPPING_", node.vector_type)
    ins = [vec] + [nc.input(node, n, 3, stack) if nc._find_input(node, n) is not None
                   else constant((0.0, 0.0, 0.0)) for n in ("Location", "Rotation")] + \
        [nc.input(node, "Scale", 3, stack)]
    return {"Vector": nc.p.emit(core.PHOS_OP_MAPPING, ins, [3], mode=mode)[0]}


def _vector_rotate(nc, node, stack):
    ins = [nc.input(node, "Vector", 3, stack), nc.input(node, "Center", 3, stack),
           nc.input(node, "Axis", 3, stack), nc.input(node, "Angle", 1, stack),
           nc.input(node, "Rotation", 3, stack)]
    mode = nc.mode(node, "PHOS_VECTOR_ROTATE_", node.rotation_type)
    return {"Vector": nc.p.emit(core.PHOS_OP_VECTOR_ROTATE, ins, [3], mode=mode,
                                flags=1 if node.invert else 0)[0]}


def _vector_transform(nc, node, stack):
    spaces = {'WORLD': 0, 'OBJECT': 1, 'CAMERA': 2}
    mode = nc.mode(node, "PHOS_VECTOR_TRANSFORM_", node.vector_type)
    flags = spaces[node.convert_from] | (spaces[node.convert_to] << 4)
    return {"Vector": nc.p.emit(core.PHOS_OP_VECTOR_TRANSFORM, [nc.input(node, "Vector", 3, stack)], [3],
                                mode=mode, flags=flags)[0]}


def _normal(nc, node, stack):
    direction = [float(x) for x in node.outputs["Normal"].default_value[:3]]
    normal, dot = nc.p.emit(core.PHOS_OP_NORMAL, [nc.input(node, "Normal", 3, stack)], [3, 1], param=direction)
    return {"Normal": normal, "Dot": dot}


def _normal_map(nc, node, stack):
    if node.space not in {'TANGENT', 'OBJECT', 'WORLD'}:
        nc.walker.note(node, "the %s space is not supported; tangent space is used" % node.space)
    mode = _enum("PHOS_NORMAL_MAP_", node.space) or core.PHOS_NORMAL_MAP_TANGENT
    if mode == core.PHOS_NORMAL_MAP_TANGENT:
        nc.ctx.tangents_wanted = True
    ins = [nc.input(node, "Strength", 1, stack), nc.input(node, "Color", 3, stack)]
    flags = 1 if nc.ctx.at_least(4, 0) else 0  # where Strength applies (phos.h)
    table = 0
    uv_map = getattr(node, "uv_map", "")
    if mode == core.PHOS_NORMAL_MAP_TANGENT and uv_map:
        # Another UV map's tangents come as a mesh attribute (phos.h, flags 2).
        key = ("tangent", uv_map)
        nc.p.attributes.add(key)
        flags |= 2
        table = attribute_id(nc.ctx, key)
    return {"Normal": nc.p.emit(core.PHOS_OP_NORMAL_MAP, ins, [3], mode=mode, flags=flags, table=table)[0]}


def _bump_filter_width(nc, node):
    """The fraction of the pixel's footprint Cycles steps a bump's heights
    by: the Bump node's Filter Width (Blender 4.4 added it, 0.1 for new
    nodes, 1 for those of older files); before, the whole footprint."""
    socket = nc._find_input(node, "Filter Width")
    if socket is None:
        return 1.0
    if socket.is_linked:
        nc.walker.note(node, "a linked Filter Width is not supported; its unlinked value is used")
    return max(float(socket.default_value), 0.0)


def _bump_flags(nc, invert):
    """BUMP's flags (phos.h): invert, and before Blender 4.0 the tilt that
    keeps the viewer's reflection above the surface."""
    return (1 if invert else 0) | (0 if nc.ctx.at_least(4, 0) else 2)


def _bump_heights(nc, height, width):
    """The height at the point and at its two moved points: height(), a
    function compiling it, called with nc.bump set to each move."""
    heights = []
    outer, outer_width = nc.bump, nc.bump_width
    try:
        for mode in (0, 1, 2):
            if outer == 0:
                nc.bump, nc.bump_width = mode, (width if mode else 0.0)
            heights.append(height())
    finally:
        nc.bump, nc.bump_width = outer, outer_width
    return heights


def _bump(nc, node, stack):
    height_socket = nc._find_input(node, "Height")
    width = _bump_filter_width(nc, node)
    heights = _bump_heights(nc, lambda: nc.socket(height_socket, 1, stack), width)
    ins = [nc.input(node, "Strength", 1, stack), nc.input(node, "Distance", 1, stack)] + heights + \
        [nc.input(node, "Normal", 3, stack, implicit=nc.normal)]
    return {"Normal": nc.p.emit(core.PHOS_OP_BUMP, ins, [3], flags=_bump_flags(nc, node.invert),
                                param=(width,))[0]}


_HANDLERS = {
    'ShaderNodeMath': _math,
    'ShaderNodeVectorMath': _vector_math,
    'ShaderNodeMapRange': _map_range,
    'ShaderNodeClamp': _clamp_node,
    'ShaderNodeCombineXYZ': _combine_xyz,
    'ShaderNodeSeparateXYZ': _separate_xyz,
    'ShaderNodeValue': _math_value,
    'ShaderNodeRGB': _rgb,
    'ShaderNodeRGBToBW': _rgb_to_bw,
    'ShaderNodeBlackbody': _blackbody,
    'ShaderNodeWavelength': _wavelength,
    'ShaderNodeMix': _mix,
    'ShaderNodeMixRGB': _mix_rgb,
    'ShaderNodeValToRGB': _color_ramp,
    'ShaderNodeRGBCurve': _rgb_curves,
    'ShaderNodeVectorCurve': _vector_curves,
    'ShaderNodeFloatCurve': _float_curve,
    'ShaderNodeHueSaturation': _hue_saturation,
    'ShaderNodeBrightContrast': _bright_contrast,
    'ShaderNodeGamma': _gamma,
    'ShaderNodeInvert': _invert,
    'ShaderNodeSeparateColor': _separate_color,
    'ShaderNodeCombineColor': _combine_color,
    'ShaderNodeSeparateRGB': _separate_rgb,
    'ShaderNodeCombineRGB': _combine_rgb,
    'ShaderNodeSeparateHSV': _separate_hsv,
    'ShaderNodeCombineHSV': _combine_hsv,
    'ShaderNodeTexImage': _tex_image,
    'ShaderNodeTexEnvironment': _tex_environment,
    'ShaderNodeTexSky': _tex_sky,
    'ShaderNodeTexNoise': _tex_noise,
    'ShaderNodeTexMusgrave': _tex_musgrave,
    'ShaderNodeTexWhiteNoise': _tex_white_noise,
    'ShaderNodeTexVoronoi': _tex_voronoi,
    'ShaderNodeTexWave': _tex_wave,
    'ShaderNodeTexBrick': _tex_brick,
    'ShaderNodeTexChecker': _tex_checker,
    'ShaderNodeTexMagic': _tex_magic,
    'ShaderNodeTexGradient': _tex_gradient,
    'ShaderNodeTexCoord': _tex_coord,
    'ShaderNodeUVMap': _uv_map,
    'ShaderNodeAttribute': _attribute,
    'ShaderNodeVertexColor': _vertex_color,
    'ShaderNodeNewGeometry': _geometry,
    'ShaderNodeTangent': _tangent,
    'ShaderNodeObjectInfo': _object_info,
    'ShaderNodeFresnel': _fresnel,
    'ShaderNodeLayerWeight': _layer_weight,
    'ShaderNodeLightPath': _light_path,
    'ShaderNodeMapping': _mapping,
    'ShaderNodeVectorRotate': _vector_rotate,
    'ShaderNodeVectorTransform': _vector_transform,
    'ShaderNodeNormal': _normal,
    'ShaderNodeNormalMap': _normal_map,
    'ShaderNodeBump': _bump,
}


def displacement_bump(nc, node, stack):
    """The Material Output's Displacement through a Displacement node,
    rendered as bump (Cycles' default method): the surface normal of the
    height (Height − Midlevel)·Scale, evaluated at the point and at the two
    moved points, as a Bump of distance 1 and strength 1 (Cycles adds such
    a Bump node, with the version's filter width)."""
    if getattr(node, "space", 'OBJECT') == 'OBJECT':
        pass  # object-space heights scale with the object; scenes at unit scale agree

    def height():
        h = nc.input(node, "Height", 1, stack)
        mid = nc.input(node, "Midlevel", 1, stack)
        scale = nc.input(node, "Scale", 1, stack)
        return (h - mid) * scale

    width = 0.1 if nc.ctx.at_least(4, 4) else 1.0  # the Bump node's default from 4.4
    heights = _bump_heights(nc, height, width)
    ins = [constant(1.0), constant(1.0)] + heights + [nc.input(node, "Normal", 3, stack, implicit=nc.normal)]
    return nc.p.emit(core.PHOS_OP_BUMP, ins, [3], flags=_bump_flags(nc, False), param=(width,))[0]
