# SPDX-License-Identifier: GPL-3.0-or-later
"""Cycles shader node trees → core materials (weighted lists of closures).

Cycles itself flattens a node tree into a sum of weighted closures: Mix and
Add shaders with constant factors only scale and concatenate closure lists.
Phos does the same in Python, walking back from the active Material Output's
Surface socket, so the materials users already have render without a Phos
node set.

Shader nodes (Principled BSDF, Diffuse, Glossy, Glass, Refraction, Metallic,
Emission, Transparent, Translucent, Holdout, Mix and Add Shader) become
closures; the value nodes
feeding their inputs (textures, colour, converter, vector and input nodes:
nodes.py) compile into the material's shader program (program.py), whose
outputs the core writes into the closures' fields at each shading point.
A closure's Normal input (Bump, Normal Map) gives that closure its own
shading normal, as Cycles' closures each carry their own N; closures without
one shade about the surface's normal. An input that folds to a constant
costs nothing. Anything unsupported
renders with the closest match and one warning per (material, node), so a
user sees what was approximated.

The Principled BSDF is decomposed the way Cycles 3.4 does it (svm_closure.h,
CLOSURE_BSDF_PRINCIPLED_ID): Burley diffuse, a GGX specular layer with the
"principled v1" Fresnel, and a glass layer for transmission.

Anisotropy (3.x Anisotropic BSDF, 4.x Glossy, Principled, Metallic) maps to
GGX roughness along and across the closure's tangent as each Cycles does
(microfacet.py); the tangent is a linked Tangent, else Cycles' default,
which the core computes, turned by the node's rotation.

Microfacet distributions (Glossy, Glass, Refraction, Metallic, Principled):
the core has GGX, Beckmann and (Glossy only) Ashikhmin-Shirley, and a lobe
whose alpha = roughness² is below 1e-4 is a perfect mirror/refraction. 'SHARP' (3.x only) is GGX with
roughness 0, as is 4.x's way of making a sharp BSDF (roughness 0).
'MULTI_GGX' (Multiscatter GGX, the 4.x default) is 4.x's energy-compensated
GGX; on 3.x it is rendered so too, with one warning.
"""

import math

import bpy
import numpy as np

from .. import core
from . import program as prog
from .microfacet import (anisotropic_roughness, conductor_as_f82, f82_fss, glossy_anisotropy, microfacet_model,
                         principled_anisotropy, unit_rgb)
from .program import Program, Value

# Closures whose weight is below this are dropped (Cycles: CLOSURE_WEIGHT_CUTOFF).
WEIGHT_CUTOFF = 1e-5

# Nodes that only pass data through.
_REROUTE = 'NodeReroute'
_GROUP = 'ShaderNodeGroup'
_GROUP_INPUT = 'NodeGroupInput'
_GROUP_OUTPUT = 'NodeGroupOutput'

_LUMA = np.array([0.2126, 0.7152, 0.0722], dtype=np.float32)  # colour → float, as Blender's rgb_to_bw


def _rgb(value):
    return np.asarray(value, dtype=np.float32).reshape(3).copy()


class Closure:
    """One weighted closure before it becomes a core.phos_closure_desc.

    Parameters beyond the first three are keyword arguments named as the
    desc's fields (phos.h); `layer_children`, when set, lists the closures
    this one lies over (Principled v2's sheen, coat and specular layers),
    which must follow it in the material's list.
    """

    _FIELDS = dict(roughness=0.0, ior=1.45, specular_color=(0.0, 0.0, 0.0),
                   glass_fresnel=core.PHOS_GLASS_FRESNEL_MACRO, transmission_tint=(1.0, 1.0, 1.0),
                   transmission_roughness=-1.0, microfacet=core.PHOS_MICROFACET_GGX_SEPARABLE,
                   multiscatter_fresnel=(1.0, 1.0, 1.0), specular_tint=(1.0, 1.0, 1.0),
                   thin_film_thickness=0.0, thin_film_ior=1.33, layer_weight=(1.0, 1.0, 1.0),
                   layer_tint=(1.0, 1.0, 1.0), layer_tint_weight=0.0, roughness_y=-1.0, tangent_rotation=0.0)
    _VECTORS = {"specular_color", "transmission_tint", "multiscatter_fresnel", "specular_tint",
                "layer_weight", "layer_tint"}

    __slots__ = ("type", "weight", "normal", "tangent", "layer_children") + tuple(_FIELDS)

    # Fields a shader program may set, with their phos.h field ids and widths.
    _BINDABLE = {"weight": ("PHOS_FIELD_WEIGHT", 3), "roughness": ("PHOS_FIELD_ROUGHNESS", 1),
                 "ior": ("PHOS_FIELD_IOR", 1), "specular_color": ("PHOS_FIELD_SPECULAR_COLOR", 3),
                 "transmission_tint": ("PHOS_FIELD_TRANSMISSION_TINT", 3),
                 "transmission_roughness": ("PHOS_FIELD_TRANSMISSION_ROUGHNESS", 1),
                 "multiscatter_fresnel": ("PHOS_FIELD_MULTISCATTER_FRESNEL", 3),
                 "specular_tint": ("PHOS_FIELD_SPECULAR_TINT", 3),
                 "thin_film_thickness": ("PHOS_FIELD_THIN_FILM_THICKNESS", 1),
                 "thin_film_ior": ("PHOS_FIELD_THIN_FILM_IOR", 1),
                 "layer_weight": ("PHOS_FIELD_LAYER_WEIGHT", 3), "layer_tint": ("PHOS_FIELD_LAYER_TINT", 3),
                 "layer_tint_weight": ("PHOS_FIELD_LAYER_TINT_WEIGHT", 1), "normal": ("PHOS_FIELD_NORMAL", 3),
                 "roughness_y": ("PHOS_FIELD_ROUGHNESS_Y", 1),
                 "tangent_rotation": ("PHOS_FIELD_TANGENT_ROTATION", 1), "tangent": ("PHOS_FIELD_TANGENT", 3)}

    def __init__(self, type, weight, normal=None, layer_children=None, tangent=None, **fields):
        unknown = set(fields) - set(self._FIELDS)
        if unknown:
            raise TypeError("Closure: unknown fields %s" % sorted(unknown))
        self.type = type
        self.weight = _field(weight, 3)
        self.normal = normal          # a Value (Bump, Normal Map) or None: the surface's own
        self.tangent = tangent        # a Value (a linked Tangent) or None: Cycles' default
        self.layer_children = layer_children
        for name, default in self._FIELDS.items():
            value = fields.get(name, default)
            setattr(self, name, _field(value, 3) if name in self._VECTORS else _field(value, 1))

    def scale(self, factor):
        self.weight = _field(self.weight * factor if isinstance(self.weight, Value) or not isinstance(factor, Value)
                             else factor * self.weight, 3)
        return self

    def negligible(self):
        if prog.varies(self.weight):
            return False
        return float(np.max(np.abs(self.weight))) <= WEIGHT_CUTOFF

    def bind(self, program, index):
        """Bindings of this closure's varying fields (closure `index`); the
        desc then holds placeholders the program overwrites."""
        for name, (field, width) in self._BINDABLE.items():
            value = getattr(self, name)
            if prog.varies(value):
                program.bind(index, getattr(core, field), value, width)

    def to_desc(self, layer_span=0, normal_correction=core.PHOS_NORMAL_CORRECTION_NONE):
        c = {name: (_placeholder(name) if prog.varies(getattr(self, name)) else getattr(self, name))
             for name in ("weight",) + tuple(self._FIELDS)}
        d = core.new_closure()
        d.type = self.type
        d.weight[:] = [float(x) for x in c["weight"]]
        self_roughness = c["roughness"]
        d.roughness = min(max(float(self_roughness), 0.0), 1.0)
        d.ior = max(float(c["ior"]), 1e-5)
        d.specular_color[:] = [max(float(x), 0.0) for x in c["specular_color"]]
        d.glass_fresnel = self.glass_fresnel
        d.transmission_tint[:] = [max(float(x), 0.0) for x in c["transmission_tint"]]
        d.transmission_roughness = min(float(c["transmission_roughness"]), 1.0)
        d.microfacet = self.microfacet
        d.multiscatter_fresnel[:] = [min(max(float(x), 0.0), 1.0) for x in c["multiscatter_fresnel"]]
        d.specular_tint[:] = [min(max(float(x), 0.0), 1.0) for x in c["specular_tint"]]
        d.thin_film_thickness = min(max(float(c["thin_film_thickness"]), 0.0), 1e6)
        d.thin_film_ior = max(float(c["thin_film_ior"]), 1e-5)
        d.layer_span = layer_span
        d.layer_weight[:] = [max(float(x), 0.0) for x in c["layer_weight"]]
        d.layer_tint[:] = [max(float(x), 0.0) for x in c["layer_tint"]]
        d.layer_tint_weight = max(float(c["layer_tint_weight"]), 0.0)
        d.roughness_y = min(float(c["roughness_y"]), 1.0)
        d.tangent_rotation = float(c["tangent_rotation"])
        d.normal_correction = normal_correction
        return d


def _field(value, width):
    """A closure field: a float or float64 array when constant, else the Value."""
    if isinstance(value, Value):
        if not value.is_const:
            return value
        value = value.const
    if width == 3:
        return _rgb(value).astype(np.float64)
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        return value  # enum fields (microfacet, glass_fresnel)
    return float(np.asarray(value, dtype=np.float64).reshape(-1)[0])


def _placeholder(name):
    """The constant a desc holds where a program sets the field, and what
    renders if the program has to be dropped (too large): white colours,
    roughness ½, IOR 1.45, no thin film."""
    if name in Closure._VECTORS or name == "weight":
        return np.ones(3)
    return {"ior": 1.45, "thin_film_ior": 1.33, "roughness": 0.5, "transmission_roughness": 0.5,
            "roughness_y": 0.5}.get(name, 0.0)


# Closures whose normal Cycles 4.0+ keeps from reflecting the viewer into
# the surface (the glossy, glass and translucent ones; the Principled BSDF's
# specular, metal, glass and coat layers), and those that have no normal.
_SPECULAR_CLOSURES = frozenset((core.PHOS_CLOSURE_REFLECTION, core.PHOS_CLOSURE_REFLECTION_FRESNEL,
                                core.PHOS_CLOSURE_METAL, core.PHOS_CLOSURE_GLASS, core.PHOS_CLOSURE_REFRACTION,
                                core.PHOS_CLOSURE_TRANSLUCENT))
_NORMAL_FREE_CLOSURES = frozenset((core.PHOS_CLOSURE_EMISSION, core.PHOS_CLOSURE_TRANSPARENT,
                                   core.PHOS_CLOSURE_HOLDOUT))


def normal_correction(closure_type, ctx, mat=None):
    """How the running Blender's Cycles keeps a closure's normal from
    reflecting the viewer into the surface (phos.h, docs/algorithms.md
    §8.1): before 4.0 every closure's, by the two-root rule; from 4.0 the
    specular closures' only, by the one-root rule, unless the material's
    Bump Map Correction (Settings, Cycles' default on) is off."""
    if closure_type in _NORMAL_FREE_CLOSURES:
        return core.PHOS_NORMAL_CORRECTION_NONE
    if not ctx.at_least(4, 0):
        return core.PHOS_NORMAL_CORRECTION_BOTH_ROOTS
    settings = getattr(mat, "cycles", None) if mat is not None else None
    if not getattr(settings, "use_bump_map_correction", True) or closure_type not in _SPECULAR_CLOSURES:
        return core.PHOS_NORMAL_CORRECTION_NONE
    return core.PHOS_NORMAL_CORRECTION_ONE_ROOT


def closure_descs(closures, program=None, correction=None):
    """core descs of a material's final closure list, with each layer's span
    counted among the closures that remain (filtering only removes, so a
    layer's surviving children still follow it), the program's bindings of
    their varying fields, and each one's normal correction (a function of
    the closure type; none when not given)."""
    descs = []
    for i, c in enumerate(closures):
        span = 0
        if c.layer_children:
            children = {id(k) for k in c.layer_children}
            span = sum(1 for k in closures[i + 1:] if id(k) in children)
        rule = correction(c.type) if correction else core.PHOS_NORMAL_CORRECTION_NONE
        descs.append(c.to_desc(span, rule))
        if program is not None:
            c.bind(program, i)
    return descs


class _Source:
    """Where an input socket gets its value from, after reroutes, mutes and groups.

    Either `socket` (an unlinked input: use its default_value), or `node`
    and `output` (a real node's output socket, with the group `stack` it
    sits in), or neither (nothing: a muted node without pass-through).
    """

    __slots__ = ("socket", "node", "output", "stack")

    def __init__(self, socket=None, node=None, output=None, stack=()):
        self.socket, self.node, self.output, self.stack = socket, node, output, stack


def _first_link(socket):
    for link in socket.links:
        if link.is_valid and not getattr(link, "is_muted", False):
            return link
    return None


def _resolve(socket, stack):
    """Follow an input socket back to the node output that feeds it."""
    for _ in range(1000):  # guards against cycles through groups
        link = _first_link(socket) if socket.is_linked else None
        if link is None:
            return _Source(socket=socket, stack=stack)
        node, output = link.from_node, link.from_socket
        if node.bl_idname == _REROUTE:
            socket = node.inputs[0]
            continue
        if node.mute:
            through = [l.from_socket for l in node.internal_links if l.to_socket == output]
            if not through:
                return _Source(stack=stack)
            socket = through[0]
            continue
        if node.bl_idname == _GROUP:
            tree = node.node_tree
            out_node = _group_output(tree) if tree is not None else None
            inner = _socket_by_identifier(out_node.inputs, output.identifier) if out_node else None
            if inner is None:
                return _Source(stack=stack)
            socket, stack = inner, stack + (node,)
            continue
        if node.bl_idname == _GROUP_INPUT:
            if not stack:
                return _Source(stack=stack)
            outer = stack[-1]
            socket = _socket_by_identifier(outer.inputs, output.identifier)
            stack = stack[:-1]
            if socket is None:
                return _Source(stack=stack)
            continue
        return _Source(node=node, output=output, stack=stack)
    return _Source(stack=stack)


def _group_output(tree):
    outputs = [n for n in tree.nodes if n.bl_idname == _GROUP_OUTPUT]
    for n in outputs:
        if n.is_active_output:
            return n
    return outputs[0] if outputs else None


def _socket_by_identifier(sockets, identifier):
    for s in sockets:
        if s.identifier == identifier:
            return s
    return None


def find_input(node, *names):
    """The first enabled input called one of `names` (names change between versions)."""
    for name in names:
        for s in node.inputs:
            if (s.name == name or s.identifier == name) and s.enabled:
                return s
    for name in names:
        s = node.inputs.get(name)
        if s is not None:
            return s
    return None


def active_output(tree, bl_idname):
    """The output node Cycles would use: the active one targeting Cycles or All."""
    try:
        node = tree.get_output_node('CYCLES')
    except (AttributeError, TypeError):
        node = None
    if node is not None and node.bl_idname == bl_idname:
        return node
    candidates = [n for n in tree.nodes if n.bl_idname == bl_idname]
    for n in candidates:
        if n.is_active_output and getattr(n, "target", 'ALL') in {'ALL', 'CYCLES'}:
            return n
    for n in candidates:
        if getattr(n, "target", 'ALL') in {'ALL', 'CYCLES'}:
            return n
    return candidates[0] if candidates else None


class NodeTreeWalker:
    """Turns the shader feeding one socket into a list of Closures.

    `owner` names the material or world in warnings ("material 'Floor'").
    With `world=True` a Background node becomes an EMISSION closure whose
    weight the program may vary with direction (world.py); BSDFs are
    meaningless there.
    """

    def __init__(self, ctx, owner, world=False):
        self.ctx = ctx
        self.owner = owner
        self.world = world
        self.glass_fresnel = (core.PHOS_GLASS_FRESNEL_MICROFACET if ctx.at_least(4, 0)
                              else core.PHOS_GLASS_FRESNEL_MACRO)
        self.stack = ()  # group nodes around the node being translated
        self.program = Program()  # the material's shader program
        self._nodes = None
        # Shader nodes being translated, with their group stack: a node met
        # again while its own inputs are read is a cycle. Blender marks the
        # link that closes a cycle invalid as soon as it is made (3.4, also
        # from Python) and _first_link skips it, so this only guards against
        # a tree Blender has not validated: the walk must end whatever the
        # tree, never recurse until Python's stack overflows.
        self._active = set()

    # -------------------------------------------------------------- warnings

    def unsupported(self, node, consequence="using its default input"):
        self.ctx.warn("Phos: %s: node '%s'%s is not supported; %s"
                      % (self.owner, node.name, _node_type(node), consequence))

    def note(self, node, what):
        self.ctx.warn("Phos: %s: node '%s': %s" % (self.owner, node.name, what))

    # ---------------------------------------------------------------- values

    @property
    def nodes(self):
        """The compiler of the value nodes, with the material's program."""
        if self._nodes is None:
            from .nodes import NodeCompiler
            self._nodes = NodeCompiler(self, self.program)
        return self._nodes

    def _input(self, node, names, width, consumed):
        socket = find_input(node, *names) if isinstance(names, tuple) else find_input(node, names)
        if socket is None:
            return None
        if consumed is not None:
            consumed.add(socket.identifier)
        return self.nodes.socket(socket, width, self.stack)

    def value(self, node, names, default=0.0, consumed=None):
        """A float input: a float when constant, else the program's Value."""
        value = self._input(node, names, 1, consumed)
        if value is None:
            return float(default)
        return prog.plain(value)

    def color(self, node, names, consumed=None, allow_image=True):
        """A colour input: (float64[3] when constant, else the program's
        Value; None; None) — the tuple of the image-only translator, whose
        callers this keeps."""
        value = self._input(node, names, 3, consumed)
        if value is None:
            return np.zeros(3), None, None
        if not allow_image and prog.varies(value):
            self.note(node, "a texture on this input is not supported; using its default")
            socket = find_input(node, *names) if isinstance(names, tuple) else find_input(node, names)
            return _socket_color(socket).astype(np.float64), None, None
        return prog.plain(value), None, None

    def normal(self, node, names=('Normal',), consumed=None):
        """A linked Normal input (Bump, Normal Map) as a Value, else None."""
        socket = find_input(node, *names) if isinstance(names, tuple) else find_input(node, names)
        if socket is None:
            return None
        if consumed is not None:
            consumed.add(socket.identifier)
        if self.world or not self.nodes.value_node_linked(socket, self.stack):
            return None
        value = self.nodes.socket(socket, 3, self.stack)
        return value if prog.varies(value) else None

    def tangent(self, node, names=('Tangent',), consumed=None):
        """A linked Tangent input as a Value, else None (Cycles' default,
        the Geometry node's Tangent, which the core computes)."""
        return self.normal(node, names, consumed)

    def anisotropy(self, node, roughness, consumed, amount, rotation, mapping):
        """The closure fields of Cycles' anisotropic GGX for a node whose
        input `amount` (Anisotropy, Anisotropic) maps to the α scales by
        `mapping` (microfacet.py), turned by the input `rotation` (turns)
        about the normal, along its Tangent: roughness along the tangent,
        roughness_y across it, tangent_rotation, tangent. Isotropic (only
        roughness) when the amount is 0."""
        a = self.value(node, amount, 0.0, consumed)
        rot = self.value(node, rotation, 0.0, consumed)
        tangent = self.tangent(node, consumed=consumed)
        if not prog.varies(a) and float(prog.plain(a)) == 0.0:
            return dict(roughness=roughness)
        rx, ry = anisotropic_roughness(roughness, mapping(a))
        return dict(roughness=rx, roughness_y=ry, tangent_rotation=rot, tangent=tangent)

    def check_unused_links(self, node, consumed):
        """Warn about links into inputs this node's translation does not read."""
        for socket in node.inputs:
            if not socket.enabled or socket.identifier in consumed or not socket.is_linked:
                continue
            if socket.type == 'SHADER':
                continue
            src = _resolve(socket, self.stack)
            if src.node is not None:
                self.unsupported(src.node)

    # -------------------------------------------------------------- closures

    def closures(self, socket, stack=()):
        """Closures of the shader feeding an input socket (e.g. the Surface)."""
        src = _resolve(socket, stack)
        if src.node is None:
            return []  # an unlinked shader socket renders black, as in Cycles
        if src.output.type != 'SHADER':
            # Cycles turns a colour linked into a shader socket into an emission.
            outer, self.stack = self.stack, stack
            try:
                rgb = prog.plain(self.nodes.socket(socket, 3, stack))
            finally:
                self.stack = outer
            return [Closure(core.PHOS_CLOSURE_EMISSION, rgb)]
        return self.node_closures(src.node, src.output, src.stack)

    def node_closures(self, node, output, stack):
        key = (node.as_pointer(),) + tuple(group.as_pointer() for group in stack)
        if key in self._active:
            self.ctx.warn("Phos: %s: the node tree has a cycle through node '%s'; "
                          "the cycle is cut there (renders black)" % (self.owner, node.name))
            return []
        handler = _HANDLERS.get(node.bl_idname, NodeTreeWalker._fallback_handler)
        outer, self.stack = self.stack, stack
        self._active.add(key)
        try:
            return handler(self, node, stack)
        finally:
            self._active.discard(key)
            self.stack = outer

    def _fallback_handler(self, node, stack):
        return self._fallback(node)

    def _fallback(self, node):
        """An unsupported shader node: a diffuse of its colour if it has one."""
        if self.world:
            self.unsupported(node, "it renders black")
            return []
        color_socket = find_input(node, 'Color', 'Base Color')
        if color_socket is None:
            self.unsupported(node, "it renders black")
            return []
        self.unsupported(node, "rendered as a diffuse of its %s" % color_socket.name)
        rgb, _, _ = self.color(node, color_socket.name)
        return [Closure(core.PHOS_CLOSURE_DIFFUSE, rgb, self.normal(node))]

    # ---------------------------------------------------------- shader nodes

    def _mix(self, node, stack):
        consumed = {node.inputs[0].identifier}
        fac_socket = node.inputs[0]
        fac = prog.clamp(prog.plain(self.nodes.socket(fac_socket, 1, stack)), 0.0, 1.0)  # Cycles clamps it
        self.check_unused_links(node, consumed)
        a = [c.scale(1.0 - fac) for c in self.closures(node.inputs[1], stack)] if prog.may_be_below(fac, 1.0) else []
        b = [c.scale(fac) for c in self.closures(node.inputs[2], stack)] if prog.may_exceed(fac, 0.0) else []
        return a + b

    def _add(self, node, stack):
        return self.closures(node.inputs[0], stack) + self.closures(node.inputs[1], stack)

    def _diffuse(self, node, stack):
        if self.world:
            return self._fallback(node)
        consumed = set()
        rgb, _, _ = self.color(node, 'Color', consumed)
        roughness = prog.clamp(self.value(node, 'Roughness', 0.0, consumed), 0.0, 1.0)
        normal = self.normal(node, consumed=consumed)
        self.check_unused_links(node, consumed)
        if prog.may_exceed(roughness, 1e-5 - 1e-12):
            if self.ctx.at_least(4, 3):
                # Cycles 4.3+: the energy-preserving Oren-Nayar, its colour
                # also the albedo of its multiple-scattering term.
                return [Closure(core.PHOS_CLOSURE_OREN_NAYAR, rgb, normal, roughness=roughness,
                                specular_color=prog.clamp(rgb, 0.0, 1.0),
                                specular_tint=oren_nayar_tint(self.ctx, rgb))]
            self.note(node, "Oren-Nayar roughness before Blender 4.3 is not supported; rendered as Lambertian")
        return [Closure(core.PHOS_CLOSURE_DIFFUSE, rgb, normal)]

    def distribution(self, node, allowed=('GGX', 'MULTI_GGX', 'BECKMANN', 'ASHIKHMIN_SHIRLEY')):
        """(microfacet model, roughness override) of a node's distribution:
        'SHARP' (3.x) is GGX of roughness 0; one warning names any other
        distribution the core does not have, rendered as GGX."""
        dist = getattr(node, "distribution", 'GGX')
        if dist == 'SHARP':
            return microfacet_model(self.ctx, 'GGX'), 0.0
        if dist not in allowed:
            self.note(node, "%s distribution is not supported; using GGX"
                      % _enum_name(node, "distribution", dist))
            dist = 'GGX'
        elif dist == 'MULTI_GGX' and not self.ctx.at_least(4, 0):
            self.note(node, "Multiscatter GGX is rendered with Blender 4's energy compensation, not 3.x's "
                            "random walk: the same brightness, slightly different highlights")
        return microfacet_model(self.ctx, dist), None

    def _glossy(self, node, stack):
        """The Glossy BSDF, and 3.x's Anisotropic BSDF: GGX, anisotropic by
        Anisotropy along the Tangent turned by Rotation (4.x Glossy, 3.x
        Anisotropic; 3.x's Glossy has no such inputs)."""
        if self.world:
            return self._fallback(node)
        consumed = set()
        rgb, _, _ = self.color(node, 'Color', consumed)
        roughness = prog.clamp(self.value(node, 'Roughness', 0.5, consumed), 0.0, 1.0)
        model, override = self.distribution(node)
        if override is not None:
            roughness = override
        if find_input(node, 'Anisotropy') is not None:
            fields = self.anisotropy(node, roughness, consumed, 'Anisotropy', 'Rotation', glossy_anisotropy)
        else:
            fields = dict(roughness=roughness)
        normal = self.normal(node, consumed=consumed)
        self.check_unused_links(node, consumed)
        # Multiscatter: its colour is the mean Fresnel of the multiply
        # scattered light (Cycles' constant-Fresnel Glossy).
        return [Closure(core.PHOS_CLOSURE_REFLECTION, rgb, normal, microfacet=model,
                        multiscatter_fresnel=unit_rgb(rgb), **fields)]

    _anisotropic = _glossy

    def _glass(self, node, stack):
        if self.world:
            return self._fallback(node)
        consumed = set()
        rgb, _, _ = self.color(node, 'Color', consumed)
        roughness = prog.clamp(self.value(node, 'Roughness', 0.0, consumed), 0.0, 1.0)
        ior = prog.maximum(self.value(node, 'IOR', 1.45, consumed), 1e-5)
        model, override = self.distribution(node)
        if override is not None:
            roughness = override
        film = thin_film(self, node, consumed)
        if _nonzero(self.value(node, 'Anisotropy', 0.0, consumed)):  # Blender 5.3's glass
            self.note(node, "anisotropy is not supported; ignored")
        normal = self.normal(node, consumed=consumed)
        self.check_unused_links(node, consumed)
        fss = unit_rgb(rgb)
        # Multiscatter glass splits by the Fresnel of each microfacet in every
        # version (3.x's random walk does too).
        fresnel = core.PHOS_GLASS_FRESNEL_MICROFACET if model == core.PHOS_MICROFACET_GGX_MULTISCATTER \
            else self.glass_fresnel
        return [Closure(core.PHOS_CLOSURE_GLASS, rgb, normal, roughness=roughness, ior=ior,
                        glass_fresnel=fresnel, microfacet=model, multiscatter_fresnel=fss, **film)]

    def _refraction(self, node, stack):
        if self.world:
            return self._fallback(node)
        consumed = set()
        rgb, _, _ = self.color(node, 'Color', consumed)
        roughness = prog.clamp(self.value(node, 'Roughness', 0.0, consumed), 0.0, 1.0)
        ior = prog.maximum(self.value(node, 'IOR', 1.45, consumed), 1e-5)
        model, override = self.distribution(node)
        if override is not None:
            roughness = override
        if model == core.PHOS_MICROFACET_GGX_MULTISCATTER:
            model = microfacet_model(self.ctx, 'GGX')  # Cycles never compensates refraction
        normal = self.normal(node, consumed=consumed)
        self.check_unused_links(node, consumed)
        return [Closure(core.PHOS_CLOSURE_REFRACTION, rgb, normal, roughness=roughness, ior=ior,
                        microfacet=model)]

    def _metallic(self, node, stack):
        """The Metallic BSDF (4.3+): F82-tint, or a physical conductor's
        complex IOR fitted by F82 at 0° and 82° (Cycles fits it the same
        way for its F_ss; the reflectance in between differs by under 1 %)."""
        if self.world:
            return self._fallback(node)
        consumed = set()
        roughness = prog.clamp(self.value(node, 'Roughness', 0.5, consumed), 0.0, 1.0)
        model, override = self.distribution(node)
        if override is not None:
            roughness = override
        if getattr(node, "fresnel_type", 'F82') == 'PHYSICAL_CONDUCTOR':
            n, _, _ = self.color(node, 'IOR', consumed, allow_image=False)
            k, _, _ = self.color(node, 'Extinction', consumed, allow_image=False)
            f0, tint = conductor_as_f82(n, k)
        else:
            base, _, _ = self.color(node, 'Base Color', consumed)
            edge, _, _ = self.color(node, 'Edge Tint', consumed)
            f0 = unit_rgb(base)
            tint = unit_rgb(edge)
        fields = self.anisotropy(node, roughness, consumed, 'Anisotropy', 'Rotation', principled_anisotropy)
        if prog.may_exceed(self.value(node, 'Thin Film Thickness', 0.0, consumed), 0.1):
            self.note(node, "a thin film on a metal is not supported; ignored")
        consumed |= {sk.identifier for sk in node.inputs if sk.name.startswith("Thin Film")}
        normal = self.normal(node, consumed=consumed)
        self.check_unused_links(node, consumed)
        return [Closure(core.PHOS_CLOSURE_METAL, (1.0, 1.0, 1.0), normal, microfacet=model,
                        specular_color=f0, specular_tint=tint, multiscatter_fresnel=f82_fss(f0, tint), **fields)]

    def _sheen(self, node, stack):
        """The Sheen BSDF (4.0+): Microfiber is the core's sheen lobe;
        Ashikhmin (and 3.x's Velvet BSDF) is rendered with it, with one
        warning."""
        if self.world:
            return self._fallback(node)
        consumed = set()
        rgb, _, _ = self.color(node, 'Color', consumed)
        roughness = prog.clamp(self.value(node, ('Roughness', 'Sigma'), 0.5, consumed), 0.0, 1.0)
        if getattr(node, "distribution", 'ASHIKHMIN') != 'MICROFIBER':
            self.note(node, "Ashikhmin velvet is rendered as the microfiber sheen of the same roughness")
        normal = self.normal(node, consumed=consumed)
        self.check_unused_links(node, consumed)
        return [Closure(core.PHOS_CLOSURE_SHEEN, rgb, normal, roughness=roughness)]

    def _emission(self, node, stack):
        consumed = set()
        rgb, _, _ = self.color(node, 'Color', consumed)
        strength = self.value(node, 'Strength', 1.0, consumed)
        self.check_unused_links(node, consumed)
        return [Closure(core.PHOS_CLOSURE_EMISSION, rgb * strength)]

    def _background(self, node, stack):
        if not self.world:
            self.unsupported(node, "it renders black")
            return []
        consumed = set()
        rgb, _, _ = self.color(node, 'Color', consumed)
        strength = self.value(node, 'Strength', 1.0, consumed)
        self.check_unused_links(node, consumed)
        return [Closure(core.PHOS_CLOSURE_EMISSION, rgb * strength)]

    def _transparent(self, node, stack):
        if self.world:
            return self._fallback(node)
        consumed = set()
        rgb, _, _ = self.color(node, 'Color', consumed)
        self.check_unused_links(node, consumed)
        return [Closure(core.PHOS_CLOSURE_TRANSPARENT, rgb)]

    def _translucent(self, node, stack):
        """The Translucent BSDF: Lambertian transmission of its colour."""
        if self.world:
            return self._fallback(node)
        consumed = set()
        rgb, _, _ = self.color(node, 'Color', consumed)
        normal = self.normal(node, consumed=consumed)
        self.check_unused_links(node, consumed)
        return [Closure(core.PHOS_CLOSURE_TRANSLUCENT, rgb, normal)]

    def _holdout(self, node, stack):
        """The Holdout: a hole in the film where the camera sees it, by the
        weight the Mix and Add Shaders give it (Cycles' holdout closure)."""
        if self.world:
            return self._fallback(node)
        return [Closure(core.PHOS_CLOSURE_HOLDOUT, (1.0, 1.0, 1.0))]

    def _principled(self, node, stack):
        if self.world:
            return self._fallback(node)
        from .principled import principled
        return principled(self, node)


def _node_type(node):
    """" (Toon BSDF)": the node's type, when its name does not already say it."""
    label = getattr(node, "bl_label", "") or node.bl_idname
    return "" if node.name == label else " (%s)" % label


def _pretty(identifier):
    return identifier.replace('_', ' ').title().replace('Ggx', 'GGX')


def _enum_name(node, prop, identifier):
    """The UI name of an enum value ('MULTI_GGX' → 'Multiscatter GGX')."""
    try:
        return node.bl_rna.properties[prop].enum_items[identifier].name
    except (AttributeError, KeyError, TypeError):
        return _pretty(identifier)


def _socket_float(socket, default):
    value = getattr(socket, "default_value", default)
    try:
        return float(value)
    except TypeError:  # a colour or vector socket read as a float
        v = np.array(value[:3], dtype=np.float32)
        return float(np.dot(_LUMA, v)) if len(v) == 3 else float(v.mean())


def _socket_color(socket):
    value = getattr(socket, "default_value", None)
    if value is None:
        return np.zeros(3, dtype=np.float32)
    try:
        return np.array(value[:3], dtype=np.float32)
    except TypeError:  # a float socket read as a colour
        return np.full(3, float(value), dtype=np.float32)


def oren_nayar_tint(ctx, albedo):
    """The extra colour of the Oren-Nayar multiple-scattering term: Cycles
    4.3-5.2 tint it by the albedo a second time (the term goes as ρ³;
    measured: a ρ = 0.7, σ = 0.8 sphere under a white world reflects 0.6314
    head-on in 4.5, 5.0 and 5.2), 5.3 does not (ρ², OpenPBR's EON: 0.6572).
    With a texture, its mean colour stands in for the albedo."""
    if ctx.at_least(5, 3):
        return np.ones(3)
    return prog.clamp(albedo if prog.varies(albedo) else np.asarray(albedo, dtype=float)[:3], 0.0, 1.0)


def thin_film(walker, node, consumed):
    """The Closure fields of a node's thin film (Principled 4.2+, Glass 5.0+):
    thickness (nm) and IOR, the IOR faded toward 1 below the thickness at
    which Cycles fades the film in (30 nm before 5.0, 1 nm from 5.0)."""
    if find_input(node, 'Thin Film Thickness') is None:
        return {}
    d = prog.maximum(walker.value(node, ('Thin Film Thickness',), 0.0, consumed), 0.0)
    n = prog.maximum(walker.value(node, ('Thin Film IOR',), 1.33, consumed), 1e-5)
    if prog.varies(d) or prog.varies(n):
        return dict(thin_film_thickness=d, thin_film_ior=n)  # the fade-in below aside
    if d <= 0.1:
        return {}
    fade = 1.0 if walker.ctx.at_least(5, 0) else 30.0
    if d < fade:
        t = d / fade
        n = 1.0 + (n - 1.0) * t * t * (3.0 - 2.0 * t)
    return dict(thin_film_thickness=d, thin_film_ior=n)


def _clamp01(x):
    return prog.clamp(x, 0.0, 1.0)


def _nonzero(x):
    """Whether a value can differ from 0 (a varying one can)."""
    return prog.varies(x) or float(np.max(np.abs(prog._arr(x)))) != 0.0


_HANDLERS = {
    'ShaderNodeMixShader': NodeTreeWalker._mix,
    'ShaderNodeAddShader': NodeTreeWalker._add,
    'ShaderNodeBsdfDiffuse': NodeTreeWalker._diffuse,
    'ShaderNodeBsdfGlossy': NodeTreeWalker._glossy,
    'ShaderNodeBsdfAnisotropic': NodeTreeWalker._anisotropic,
    'ShaderNodeBsdfGlass': NodeTreeWalker._glass,
    'ShaderNodeBsdfRefraction': NodeTreeWalker._refraction,
    'ShaderNodeEmission': NodeTreeWalker._emission,
    'ShaderNodeBackground': NodeTreeWalker._background,
    'ShaderNodeBsdfTransparent': NodeTreeWalker._transparent,
    'ShaderNodeBsdfTranslucent': NodeTreeWalker._translucent,
    'ShaderNodeHoldout': NodeTreeWalker._holdout,
    'ShaderNodeBsdfPrincipled': NodeTreeWalker._principled,
    'ShaderNodeBsdfMetallic': NodeTreeWalker._metallic,
    'ShaderNodeBsdfSheen': NodeTreeWalker._sheen,
    'ShaderNodeBsdfVelvet': NodeTreeWalker._sheen,
}


# ------------------------------------------------------------------ materials

def uses_nodes(id_data):
    """Whether Cycles renders a material's or world's node tree: always from
    5.0, which deprecated `use_nodes` (it reads True and cannot be cleared,
    and files saved without nodes get an equivalent tree when loaded)."""
    if id_data.node_tree is None:
        return False
    return bpy.app.version >= (5, 0, 0) or id_data.use_nodes


def material_closures(mat, ctx):
    """The closure list of a material (before truncation and conversion)."""
    return compile_material(mat, ctx)[0]


def compile_material(mat, ctx):
    """The closure list of a material (before truncation and conversion)
    and the shader program that sets its varying fields."""
    owner = "material '%s'" % mat.name
    if not uses_nodes(mat):
        # What Cycles renders for a material without nodes: a diffuse of its colour.
        return [Closure(core.PHOS_CLOSURE_DIFFUSE, mat.diffuse_color[:3])], Program()
    out = active_output(mat.node_tree, 'ShaderNodeOutputMaterial')
    if out is None:
        ctx.warn("Phos: %s has no Material Output node; it renders black" % owner)
        return [], Program()
    for link in mat.node_tree.links:
        if not link.is_valid:
            # Blender marks a link that closes a cycle (or joins sockets that
            # cannot be joined) invalid and draws it red; Cycles ignores it.
            ctx.warn("Phos: %s: the link from node '%s' to node '%s' is invalid (it closes a "
                     "cycle or joins incompatible sockets); ignored" % (
                         owner, link.from_node.name, link.to_node.name))
    walker = NodeTreeWalker(ctx, owner)
    closures = walker.closures(out.inputs['Surface'])
    s = out.inputs.get('Volume')
    if s is not None and s.is_linked:
        ctx.warn("Phos: %s: the volume output is not supported; ignored" % owner)
    displacement = displacement_as_bump(walker, out)
    if displacement is not None:
        for c in closures:
            if c.normal is None:
                c.normal = displacement
    return closures, walker.program


def displacement_as_bump(walker, out):
    """The Material Output's Displacement rendered as Cycles renders it by
    default (Displacement Only is not the default): a bump of the height
    that a Displacement node computes, as a normal Value; None when unlinked
    or not a Displacement node."""
    socket = out.inputs.get('Displacement')
    if socket is None or not socket.is_linked:
        return None
    src = _resolve(socket, ())
    if src.node is None:
        return None
    method = getattr(getattr(walker.ctx.scene, "cycles", None), "displacement_method", None)
    material = getattr(out.id_data, "cycles", None)
    method = getattr(material, "displacement_method", 'BUMP') if material is not None else 'BUMP'
    if method not in {'BUMP', 'BOTH'}:
        walker.ctx.warn("Phos: %s: true displacement is not supported; rendered as bump" % walker.owner)
    if src.node.bl_idname != 'ShaderNodeDisplacement':
        walker.unsupported(src.node, "the displacement is ignored")
        return None
    from .nodes import displacement_bump
    return displacement_bump(walker.nodes, src.node, src.stack)


def add_material(mat, ctx):
    """Core material id of a Blender material, exporting it on first use."""
    if mat is None:
        return default_material(ctx)
    key = mat.original.as_pointer()
    mat_id = ctx.materials.get(key)
    if mat_id is not None:
        return mat_id
    closures, descs, program = _material_parts(mat, ctx)
    try:
        mat_id = ctx.core.add_material(descs, None if program.empty() else program.desc())
    except core.PhosError as ex:
        raise core.PhosError("material '%s': %s" % (mat.name, ex), ex.status) from None
    ctx.materials[key] = mat_id
    ctx.material_attributes[mat_id] = frozenset(program.attributes)
    ctx.stats["materials"] += 1
    if any(c.type == core.PHOS_CLOSURE_EMISSION for c in closures):
        ctx.stats["emissive_materials"] += 1
    return mat_id


def _material_parts(mat, ctx):
    """(closures, their descriptions, program) of a Blender material."""
    closures, program = compile_material(mat, ctx)
    closures = [c for c in closures if not c.negligible()]
    if len(closures) > core.PHOS_MAX_CLOSURES:
        ctx.warn("Phos: material '%s' has %d closures; only the first %d are rendered"
                 % (mat.name, len(closures), core.PHOS_MAX_CLOSURES))
        closures = closures[:core.PHOS_MAX_CLOSURES]
    descs = closure_descs(closures, program, lambda kind: normal_correction(kind, ctx, mat))
    if program.too_large():
        ctx.warn("Phos: material '%s': its shader program exceeds the core's limits (%d registers, %d "
                 "instructions); it renders without them: white colours, roughness 0.5"
                 % (mat.name, core.PHOS_SHADER_MAX_REGISTERS, core.PHOS_SHADER_MAX_INSTRUCTIONS))
        program = Program()
    return closures, descs, program


def update_material(mat, ctx):
    """Replace an exported material in place (scene updates, phos.h).
    Returns False when that cannot stand for an export: the scene never
    used the material, or its program now reads other mesh attributes
    than the meshes were exported with."""
    mat_id = ctx.materials.get(mat.original.as_pointer())
    if mat_id is None:
        return False
    closures, descs, program = _material_parts(mat, ctx)
    if frozenset(program.attributes) != ctx.material_attributes.get(mat_id):
        return False
    try:
        ctx.core.update_material(mat_id, descs, None if program.empty() else program.desc())
    except core.PhosError as ex:
        raise core.PhosError("material '%s': %s" % (mat.name, ex), ex.status) from None
    return True


def default_material(ctx):
    """The grey diffuse (0.8) of objects and slots without a material."""
    if ctx.default_material is None:
        grey = Closure(core.PHOS_CLOSURE_DIFFUSE, (0.8, 0.8, 0.8))
        ctx.default_material = ctx.core.add_material(
            [grey.to_desc(normal_correction=normal_correction(grey.type, ctx))])
    return ctx.default_material
