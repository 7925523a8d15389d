# SPDX-License-Identifier: GPL-3.0-or-later
"""Cycles shader node trees → core materials (weighted lists of closures).

Cycles itself flattens a node tree into a sum of weighted closures: Mix and
Add shaders with constant factors only scale and concatenate closure lists.
Phos does the same in Python, walking back from the active Material Output's
Surface socket, so the materials users already have render without a Phos
node set.

Supported: Principled BSDF, Diffuse, Glossy, Glass, Refraction, Emission,
Transparent, Mix and Add Shader, Image Texture on colour inputs, RGB and
Value nodes, reroutes, muted nodes and node groups. Anything else renders
with the default value of the socket it feeds (the closest match) and one
warning per (material, node), so a user sees what was approximated.

The Principled BSDF is decomposed the way Cycles 3.4 does it (svm_closure.h,
CLOSURE_BSDF_PRINCIPLED_ID): Burley diffuse, a GGX specular layer with the
"principled v1" Fresnel, and a glass layer for transmission.

Microfacet distributions (Glossy, Glass, Refraction, Principled): the core
has GGX only, and a GGX whose alpha = roughness² is below 1e-4 is a perfect
mirror/refraction. 'SHARP' (3.x only) is GGX with roughness 0, as is 4.x's
way of making a sharp BSDF (GGX or Multiscatter GGX with roughness 0).
'MULTI_GGX' (Multiscatter GGX, the 4.x default) is rendered as GGX without a
warning on 4.x; on 3.x, and for 'BECKMANN' and 'ASHIKHMIN_SHIRLEY' in any
version, GGX is used with one warning naming the distribution.
"""

import math

import bpy
import numpy as np

from .. import core
from . import image as image_export
from .microfacet import conductor_as_f82, f82_fss, microfacet_model, unit_rgb

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
                   layer_tint=(1.0, 1.0, 1.0), layer_tint_weight=0.0)
    _VECTORS = {"specular_color", "transmission_tint", "multiscatter_fresnel", "specular_tint",
                "layer_weight", "layer_tint"}

    __slots__ = ("type", "weight", "image", "layer_children") + tuple(_FIELDS)

    def __init__(self, type, weight, image=None, layer_children=None, **fields):
        unknown = set(fields) - set(self._FIELDS)
        if unknown:
            raise TypeError("Closure: unknown fields %s" % sorted(unknown))
        self.type = type
        self.weight = _rgb(weight)
        self.image = image
        self.layer_children = layer_children
        for name, default in self._FIELDS.items():
            value = fields.get(name, default)
            setattr(self, name, _rgb(value) if name in self._VECTORS else value)

    def scale(self, factor):
        self.weight *= factor
        return self

    def negligible(self):
        return float(np.max(np.abs(self.weight))) <= WEIGHT_CUTOFF

    def to_desc(self, layer_span=0):
        d = core.new_closure()
        d.type = self.type
        d.weight[:] = [float(x) for x in self.weight]
        d.weight_image = -1 if self.image is None else int(self.image)
        d.roughness = min(max(float(self.roughness), 0.0), 1.0)
        d.ior = max(float(self.ior), 1e-5)
        d.specular_color[:] = [max(float(x), 0.0) for x in self.specular_color]
        d.glass_fresnel = self.glass_fresnel
        d.transmission_tint[:] = [max(float(x), 0.0) for x in self.transmission_tint]
        d.transmission_roughness = min(float(self.transmission_roughness), 1.0)
        d.microfacet = self.microfacet
        d.multiscatter_fresnel[:] = [min(max(float(x), 0.0), 1.0) for x in self.multiscatter_fresnel]
        d.specular_tint[:] = [min(max(float(x), 0.0), 1.0) for x in self.specular_tint]
        d.thin_film_thickness = min(max(float(self.thin_film_thickness), 0.0), 1e6)
        d.thin_film_ior = max(float(self.thin_film_ior), 1e-5)
        d.layer_span = layer_span
        d.layer_weight[:] = [max(float(x), 0.0) for x in self.layer_weight]
        d.layer_tint[:] = [max(float(x), 0.0) for x in self.layer_tint]
        d.layer_tint_weight = max(float(self.layer_tint_weight), 0.0)
        return d


def closure_descs(closures):
    """core descs of a material's final closure list, with each layer's span
    counted among the closures that remain (filtering only removes, so a
    layer's surviving children still follow it)."""
    descs = []
    for i, c in enumerate(closures):
        span = 0
        if c.layer_children:
            children = {id(k) for k in c.layer_children}
            span = sum(1 for k in closures[i + 1:] if id(k) in children)
        descs.append(c.to_desc(span))
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
    With `world=True` a Background node becomes an EMISSION closure (the
    world exporter sums them); BSDFs are meaningless there.
    """

    def __init__(self, ctx, owner, world=False):
        self.ctx = ctx
        self.owner = owner
        self.world = world
        self.glass_fresnel = (core.PHOS_GLASS_FRESNEL_MICROFACET if ctx.at_least(4, 0)
                              else core.PHOS_GLASS_FRESNEL_MACRO)
        self.stack = ()  # group nodes around the node being translated
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

    def value(self, node, names, default=0.0, consumed=None):
        """A float input: its default, or a constant node feeding it."""
        socket = find_input(node, *names) if isinstance(names, tuple) else find_input(node, names)
        if socket is None:
            return float(default)
        if consumed is not None:
            consumed.add(socket.identifier)
        src = _resolve(socket, self.stack)
        return self._float_of(src, socket, default)

    def _float_of(self, src, socket, default):
        if src.socket is not None:
            return _socket_float(src.socket, default)
        if src.node is None:
            return _socket_float(socket, default)
        n = src.node
        if n.bl_idname == 'ShaderNodeValue':
            return float(n.outputs[0].default_value)
        if n.bl_idname == 'ShaderNodeRGB':
            return float(np.dot(_LUMA, np.array(n.outputs[0].default_value[:3], dtype=np.float32)))
        if n.bl_idname == 'ShaderNodeTexImage':
            self.note(n, "images are only supported on colour inputs; using the default of '%s'"
                      % socket.name)
            return _socket_float(socket, default)
        self.unsupported(n)
        return _socket_float(socket, default)

    def color(self, node, names, consumed=None, allow_image=True):
        """A colour input: (linear rgb float32[3], image id or None, image node or None).

        An Image Texture's Color output gives the image with weight (1,1,1).
        """
        socket = find_input(node, *names) if isinstance(names, tuple) else find_input(node, names)
        if socket is None:
            return np.zeros(3, dtype=np.float32), None, None
        if consumed is not None:
            consumed.add(socket.identifier)
        # The core's world is a constant colour: no images there.
        return self._color_of(_resolve(socket, self.stack), socket, allow_image and not self.world)

    def _color_of(self, src, socket, allow_image):
        if src.socket is not None:
            return _socket_color(src.socket), None, None
        if src.node is None:
            return _socket_color(socket), None, None
        n = src.node
        if n.bl_idname == 'ShaderNodeRGB':
            return np.array(n.outputs[0].default_value[:3], dtype=np.float32), None, None
        if n.bl_idname == 'ShaderNodeValue':
            return np.full(3, n.outputs[0].default_value, dtype=np.float32), None, None
        if n.bl_idname == 'ShaderNodeTexImage':
            if allow_image and src.output.identifier == 'Color':
                self._check_image_vector(n, src.stack)
                image_id = image_export.add_image(n, self.ctx, self.owner)
                if image_id is not None:
                    return np.ones(3, dtype=np.float32), image_id, n
                return _socket_color(socket), None, None
            why = ("its Alpha output is not supported" if src.output.identifier != 'Color'
                   else "images are not supported here")
            self.note(n, "%s; using the default of '%s'" % (why, socket.name))
            return _socket_color(socket), None, None
        self.unsupported(n)
        return _socket_color(socket), None, None

    def _check_image_vector(self, node, stack):
        """Images are looked up with the mesh's active render UVs only."""
        vector = node.inputs.get('Vector')
        if vector is None or not vector.is_linked:
            return
        src = _resolve(vector, stack)
        n = src.node
        if n is None:
            return
        if n.bl_idname == 'ShaderNodeTexCoord' and src.output.identifier == 'UV':
            return
        if n.bl_idname == 'ShaderNodeUVMap':
            if n.uv_map:
                self.note(node, "UV map '%s' is ignored; the active render UV map is used" % n.uv_map)
            return
        self.unsupported(n, "the image uses the active render UV map")

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
            outer, self.stack = self.stack, src.stack
            try:
                rgb, img, _ = self._color_of(src, socket, True)
            finally:
                self.stack = outer
            return [Closure(core.PHOS_CLOSURE_EMISSION, rgb, img)]
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
        rgb, img, _ = self.color(node, color_socket.name)
        return [Closure(core.PHOS_CLOSURE_DIFFUSE, rgb, img)]

    # ---------------------------------------------------------- shader nodes

    def _mix(self, node, stack):
        consumed = {node.inputs[0].identifier}
        fac_socket = node.inputs[0]
        src = _resolve(fac_socket, stack)
        fac = min(max(self._float_of(src, fac_socket, 0.5), 0.0), 1.0)  # Cycles clamps the factor
        self.check_unused_links(node, consumed)
        a = [c.scale(1.0 - fac) for c in self.closures(node.inputs[1], stack)] if fac < 1.0 else []
        b = [c.scale(fac) for c in self.closures(node.inputs[2], stack)] if fac > 0.0 else []
        return a + b

    def _add(self, node, stack):
        return self.closures(node.inputs[0], stack) + self.closures(node.inputs[1], stack)

    def _diffuse(self, node, stack):
        if self.world:
            return self._fallback(node)
        consumed = set()
        rgb, img, _ = self.color(node, 'Color', consumed)
        roughness = _clamp01(self.value(node, 'Roughness', 0.0, consumed))
        self.check_unused_links(node, consumed)
        if roughness >= 1e-5:
            if self.ctx.at_least(4, 3):
                # Cycles 4.3+: the energy-preserving Oren-Nayar, its colour
                # also the albedo of its multiple-scattering term.
                albedo = (image_export.average_color(self._image_node(node, 'Color'), self.ctx)
                          if img is not None else rgb)
                return [Closure(core.PHOS_CLOSURE_OREN_NAYAR, rgb, img, roughness=roughness,
                                specular_color=np.clip(rgb, 0.0, 1.0),
                                specular_tint=oren_nayar_tint(self.ctx, albedo))]
            self.note(node, "Oren-Nayar roughness before Blender 4.3 is not supported; rendered as Lambertian")
        return [Closure(core.PHOS_CLOSURE_DIFFUSE, rgb, img)]

    def distribution(self, node, allowed=('GGX', 'MULTI_GGX')):
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

    def _glossy(self, node, stack, anisotropy_note="anisotropy is not supported; ignored"):
        if self.world:
            return self._fallback(node)
        consumed = set()
        rgb, img, _ = self.color(node, 'Color', consumed)
        roughness = self.value(node, 'Roughness', 0.5, consumed)
        model, override = self.distribution(node)
        if override is not None:
            roughness = override
        if self.value(node, 'Anisotropy', 0.0, consumed) != 0.0:
            self.note(node, anisotropy_note)
        self.check_unused_links(node, consumed)
        # Multiscatter: its colour is the mean Fresnel of the multiply
        # scattered light (Cycles' constant-Fresnel Glossy).
        fss = unit_rgb(image_export.average_color(self._image_node(node, 'Color'), self.ctx) if img is not None
                       else rgb)
        return [Closure(core.PHOS_CLOSURE_REFLECTION, rgb, img, roughness=roughness, microfacet=model,
                        multiscatter_fresnel=fss)]

    def _image_node(self, node, name):
        src = _resolve(find_input(node, name), self.stack)
        return src.node

    def _anisotropic(self, node, stack):
        """The 3.x Anisotropic BSDF: a Glossy BSDF whose anisotropy Phos ignores."""
        return self._glossy(node, stack, "anisotropy is not supported; rendered as Glossy")

    def _glass(self, node, stack):
        if self.world:
            return self._fallback(node)
        consumed = set()
        rgb, img, _ = self.color(node, 'Color', consumed)
        roughness = self.value(node, 'Roughness', 0.0, consumed)
        ior = self.value(node, 'IOR', 1.45, consumed)
        model, override = self.distribution(node)
        if override is not None:
            roughness = override
        film = thin_film(self, node, consumed)
        if self.value(node, 'Anisotropy', 0.0, consumed) != 0.0:  # Blender 5.3's glass
            self.note(node, "anisotropy is not supported; ignored")
        self.check_unused_links(node, consumed)
        fss = unit_rgb(image_export.average_color(self._image_node(node, 'Color'), self.ctx) if img is not None
                       else rgb)
        # Multiscatter glass splits by the Fresnel of each microfacet in every
        # version (3.x's random walk does too).
        fresnel = core.PHOS_GLASS_FRESNEL_MICROFACET if model == core.PHOS_MICROFACET_GGX_MULTISCATTER \
            else self.glass_fresnel
        return [Closure(core.PHOS_CLOSURE_GLASS, rgb, img, roughness=roughness, ior=ior,
                        glass_fresnel=fresnel, microfacet=model, multiscatter_fresnel=fss, **film)]

    def _refraction(self, node, stack):
        if self.world:
            return self._fallback(node)
        consumed = set()
        rgb, img, _ = self.color(node, 'Color', consumed)
        roughness = self.value(node, 'Roughness', 0.0, consumed)
        ior = self.value(node, 'IOR', 1.45, consumed)
        model, override = self.distribution(node)
        if override is not None:
            roughness = override
        if model == core.PHOS_MICROFACET_GGX_MULTISCATTER:
            model = microfacet_model(self.ctx, 'GGX')  # Cycles never compensates refraction
        self.check_unused_links(node, consumed)
        return [Closure(core.PHOS_CLOSURE_REFRACTION, rgb, img, roughness=roughness, ior=ior, microfacet=model)]

    def _metallic(self, node, stack):
        """The Metallic BSDF (4.3+): F82-tint, or a physical conductor's
        complex IOR fitted by F82 at 0° and 82° (Cycles fits it the same
        way for its F_ss; the reflectance in between differs by under 1 %)."""
        if self.world:
            return self._fallback(node)
        consumed = set()
        roughness = self.value(node, 'Roughness', 0.5, consumed)
        model, override = self.distribution(node)
        if override is not None:
            roughness = override
        if getattr(node, "fresnel_type", 'F82') == 'PHYSICAL_CONDUCTOR':
            n, _, _ = self.color(node, 'IOR', consumed, allow_image=False)
            k, _, _ = self.color(node, 'Extinction', consumed, allow_image=False)
            f0, tint = conductor_as_f82(n, k)
            img = None
        else:
            base, img, base_node = self.color(node, 'Base Color', consumed)
            edge, _, _ = self.color(node, 'Edge Tint', consumed, allow_image=False)
            f0 = unit_rgb(image_export.average_color(base_node, self.ctx) if img is not None else base)
            tint = unit_rgb(edge)
            if img is not None:
                self.note(node, "an image Base Color uses the image's average colour")
                img = None
        if self.value(node, 'Anisotropy', 0.0, consumed) != 0.0:
            self.note(node, "anisotropy is not supported; ignored")
        if self.value(node, 'Thin Film Thickness', 0.0, consumed) > 0.1:
            self.note(node, "a thin film on a metal is not supported; ignored")
        consumed |= {sk.identifier for sk in node.inputs if sk.name.startswith("Thin Film")}
        self.check_unused_links(node, consumed)
        return [Closure(core.PHOS_CLOSURE_METAL, (1.0, 1.0, 1.0), img, roughness=roughness, microfacet=model,
                        specular_color=f0, specular_tint=tint, multiscatter_fresnel=f82_fss(f0, tint))]

    def _emission(self, node, stack):
        consumed = set()
        rgb, img, _ = self.color(node, 'Color', consumed)
        strength = self.value(node, 'Strength', 1.0, consumed)
        self.check_unused_links(node, consumed)
        return [Closure(core.PHOS_CLOSURE_EMISSION, rgb * strength, img)]

    def _background(self, node, stack):
        if not self.world:
            self.unsupported(node, "it renders black")
            return []
        consumed = set()
        rgb, _, _ = self.color(node, 'Color', consumed, allow_image=False)
        strength = self.value(node, 'Strength', 1.0, consumed)
        self.check_unused_links(node, consumed)
        return [Closure(core.PHOS_CLOSURE_EMISSION, rgb * strength)]

    def _transparent(self, node, stack):
        if self.world:
            return self._fallback(node)
        consumed = set()
        rgb, img, _ = self.color(node, 'Color', consumed)
        self.check_unused_links(node, consumed)
        return [Closure(core.PHOS_CLOSURE_TRANSPARENT, rgb, img)]

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
    return np.clip(np.asarray(albedo, dtype=float)[:3], 0.0, 1.0)


def thin_film(walker, node, consumed):
    """The Closure fields of a node's thin film (Principled 4.2+, Glass 5.0+):
    thickness (nm) and IOR, the IOR faded toward 1 below the thickness at
    which Cycles fades the film in (30 nm before 5.0, 1 nm from 5.0)."""
    if find_input(node, 'Thin Film Thickness') is None:
        return {}
    d = max(walker.value(node, ('Thin Film Thickness',), 0.0, consumed), 0.0)
    n = max(walker.value(node, ('Thin Film IOR',), 1.33, consumed), 1e-5)
    if d <= 0.1:
        return {}
    fade = 1.0 if walker.ctx.at_least(5, 0) else 30.0
    if d < fade:
        t = d / fade
        n = 1.0 + (n - 1.0) * t * t * (3.0 - 2.0 * t)
    return dict(thin_film_thickness=d, thin_film_ior=n)


def _clamp01(x):
    return min(max(float(x), 0.0), 1.0)


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
    'ShaderNodeBsdfPrincipled': NodeTreeWalker._principled,
    'ShaderNodeBsdfMetallic': NodeTreeWalker._metallic,
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
    owner = "material '%s'" % mat.name
    if not uses_nodes(mat):
        # What Cycles renders for a material without nodes: a diffuse of its colour.
        return [Closure(core.PHOS_CLOSURE_DIFFUSE, mat.diffuse_color[:3])]
    out = active_output(mat.node_tree, 'ShaderNodeOutputMaterial')
    if out is None:
        ctx.warn("Phos: %s has no Material Output node; it renders black" % owner)
        return []
    for link in mat.node_tree.links:
        if not link.is_valid:
            # Blender marks a link that closes a cycle (or joins sockets that
            # cannot be joined) invalid and draws it red; Cycles ignores it.
            ctx.warn("Phos: %s: the link from node '%s' to node '%s' is invalid (it closes a "
                     "cycle or joins incompatible sockets); ignored" % (
                         owner, link.from_node.name, link.to_node.name))
    walker = NodeTreeWalker(ctx, owner)
    closures = walker.closures(out.inputs['Surface'])
    for name in ('Volume', 'Displacement'):
        s = out.inputs.get(name)
        if s is not None and s.is_linked:
            ctx.warn("Phos: %s: the %s output is not supported; ignored" % (owner, name.lower()))
    return closures


def add_material(mat, ctx):
    """Core material id of a Blender material, exporting it on first use."""
    if mat is None:
        return default_material(ctx)
    key = mat.original.as_pointer()
    mat_id = ctx.materials.get(key)
    if mat_id is not None:
        return mat_id
    closures = [c for c in material_closures(mat, ctx) if not c.negligible() or c.image is not None]
    if len(closures) > core.PHOS_MAX_CLOSURES:
        ctx.warn("Phos: material '%s' has %d closures; only the first %d are rendered"
                 % (mat.name, len(closures), core.PHOS_MAX_CLOSURES))
        closures = closures[:core.PHOS_MAX_CLOSURES]
    try:
        mat_id = ctx.core.add_material(closure_descs(closures))
    except core.PhosError as ex:
        raise core.PhosError("material '%s': %s" % (mat.name, ex), ex.status) from None
    ctx.materials[key] = mat_id
    ctx.stats["materials"] += 1
    if any(c.type == core.PHOS_CLOSURE_EMISSION for c in closures):
        ctx.stats["emissive_materials"] += 1
    return mat_id


def default_material(ctx):
    """The grey diffuse (0.8) of objects and slots without a material."""
    if ctx.default_material is None:
        grey = Closure(core.PHOS_CLOSURE_DIFFUSE, (0.8, 0.8, 0.8))
        ctx.default_material = ctx.core.add_material([grey.to_desc()])
    return ctx.default_material
