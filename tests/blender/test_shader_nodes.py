# SPDX-License-Identifier: GPL-3.0-or-later
"""Value nodes against Cycles, pixel by pixel (issue 21; docs/architecture.md,
"Shader programs").

Each family is a grid of unit planes seen straight down by an orthographic
camera, one plane per node setting, each with an Emission shader whose
colour is the node under test: Phos's pixels must equal Cycles'. Both
engines sample each pixel at 16 positions within ±0.005 px of its centre
(filter width 0.01), so a pixel is the node's value at the centre up to
the pattern's change over a hundredth of a pixel; only pixels on a sharp
edge (a checker's, a Voronoi cell's) can differ by more, hence the
tolerances: the 97th percentile of the per-pixel difference within
TOLERANCE (relative where the value exceeds 1), and the mean within half
of it. A wrong hash, gradient or
formula moves most pixels by tenths.

Inputs are driven by the planes' own coordinates (Object, Generated, UV),
scaled so that the patterns vary over a few cells of each plane. Negative
outputs go through Absolute first: an emission below zero renders black in
Phos (a closure weight is never negative) and negative in Cycles.
"""

import math

import bpy
import numpy as np
import pytest

import phostest as pt

CELL = 32            # pixels per plane
SAMPLES = 16
TOLERANCE = 2e-3
V4 = bpy.app.version >= (4, 0, 0)
V41 = bpy.app.version >= (4, 1, 0)


# --------------------------------------------------------------- building

def sock(sockets, key):
    """A socket by index, name or identifier, available or not (Blender 4.2+
    leaves unavailable sockets out of lookups by name)."""
    if isinstance(key, int):
        return sockets[key]
    for s in sockets:
        if s.name == key and getattr(s, "enabled", True):
            return s
    for s in sockets:
        if s.name == key or s.identifier == key:
            return s
    raise KeyError(key)


class Tree:
    """A material's node tree with small helpers for wiring test graphs."""

    def __init__(self, name):
        self.mat = bpy.data.materials.new(name)
        pt.use_nodes(self.mat)
        self.nt = self.mat.node_tree
        self.nt.nodes.clear()
        self.out = self.nt.nodes.new("ShaderNodeOutputMaterial")
        self.emission = self.nt.nodes.new("ShaderNodeEmission")
        self.link(sock(self.emission.outputs, 0), sock(self.out.inputs, "Surface"))

    def node(self, kind, inputs=None, **props):
        n = self.nt.nodes.new(kind)
        for k, v in props.items():
            setattr(n, k, v)
        for k, v in (inputs or {}).items():
            if isinstance(v, bpy.types.NodeSocket):
                self.link(v, sock(n.inputs, k))
            else:
                target = sock(n.inputs, k)
                if isinstance(v, (tuple, list)) and len(v) == 3 and target.type == "RGBA":
                    v = (*v, 1.0)
                target.default_value = v
        return n

    def link(self, a, b):
        self.nt.links.new(a, b)

    def coords(self, output="Object", scale=(1.0, 1.0, 1.0), location=(0.0123, 0.0271, 0.0)):
        """Coordinates moved off the pixel grid: an edge of a pattern that
        ran through pixel centres would be split by the sampling jitter."""
        tc = self.node("ShaderNodeTexCoord")
        m = self.node("ShaderNodeMapping", vector_type="POINT")
        self.link(sock(tc.outputs, output), sock(m.inputs, "Vector"))
        sock(m.inputs, "Scale").default_value = scale
        sock(m.inputs, "Location").default_value = location
        return sock(m.outputs, "Vector")

    def component(self, vector, axis):
        sep = self.node("ShaderNodeSeparateXYZ")
        self.link(vector, sock(sep.inputs, 0))
        return sock(sep.outputs, axis)

    def absolute(self, socket):
        if socket.type == "VALUE":
            n = self.node("ShaderNodeMath", operation="ABSOLUTE")
        else:
            n = self.node("ShaderNodeVectorMath", operation="ABSOLUTE")
        self.link(socket, sock(n.inputs, 0))
        return sock(n.outputs, 0)

    def show(self, socket):
        self.link(socket, sock(self.emission.inputs, "Color"))
        return self.mat


def render_grid(builders, tmp_path, name):
    """Build the cases (name, builder(name) → material) in a fresh file and
    render them with both engines; the per-case crops."""
    pt.reset_file()
    scene = bpy.context.scene
    cases = [(case, build(case)) for case, build in builders]
    n = len(cases)
    cols = int(math.ceil(math.sqrt(n)))
    rows = int(math.ceil(n / cols))
    for i, (case, mat) in enumerate(cases):
        c, r = i % cols, i // cols
        pt.add_plane(scene, case, size=1.0, location=(c + 0.5, r + 0.5, 0.0), material=mat)
    cam = pt.add_camera(scene, location=(cols / 2, rows / 2, 5.0), target=(cols / 2, rows / 2, 0.0),
                        ortho_scale=float(max(cols, rows)))
    cam.rotation_euler = (0.0, 0.0, 0.0)
    pt.set_world(scene, (0.0, 0.0, 0.0))
    pt.configure_output(scene, cols * CELL, rows * CELL)
    if cols != rows:  # the ortho scale spans the larger side
        cam.data.sensor_fit = "HORIZONTAL" if cols >= rows else "VERTICAL"
    pt.configure_cycles(scene, SAMPLES, filter_width=0.01)
    pt.configure_phos(scene, SAMPLES, filter_width=0.01)
    cyc = pt.render_array(scene, tmp_path, engine="CYCLES", name=name + "_cycles")[..., :3]
    pho = pt.render_array(scene, tmp_path, engine="PHOS", name=name + "_phos")[..., :3]
    crops = {}
    for i, (case, _) in enumerate(cases):
        c, r = i % cols, i // cols
        ys, xs = slice(r * CELL + 1, (r + 1) * CELL - 1), slice(c * CELL + 1, (c + 1) * CELL - 1)
        crops[case] = (pho[ys, xs].astype(np.float64), cyc[ys, xs].astype(np.float64))
    return crops


def check(crops):
    failures = []
    for case, (p, c) in crops.items():
        # Relative above 1: divisions and powers reach large values.
        d = (np.abs(p - c) / np.maximum(1.0, np.abs(c))).max(axis=2)
        p97, mean = float(np.percentile(d, 97)), float(d.mean())
        if not np.all(np.isfinite(p)) or p97 > TOLERANCE or mean > 0.5 * TOLERANCE:
            failures.append("%s: 97th percentile |Phos − Cycles| %.3g, mean %.3g (Phos mean %s, Cycles %s)"
                            % (case, p97, mean, np.round(p.mean(axis=(0, 1)), 4), np.round(c.mean(axis=(0, 1)), 4)))
    assert not failures, "pixels differ from Cycles:\n  " + "\n  ".join(failures)


# ------------------------------------------------------------------ textures

def _texture(kind, output=0, coords="Generated", scale=(1.0, 1.0, 1.0), inputs=None, absolute=False, **props):
    def build(name):
        t = Tree(name)
        tex = t.node(kind, inputs, **props)
        t.link(t.coords(coords, scale), sock(tex.inputs, "Vector"))
        out = sock(tex.outputs, output)
        return t.show(t.absolute(out) if absolute else out)
    return build


def texture_cases():
    cases = []
    for dims in ("1D", "2D", "3D", "4D"):
        cases.append(("noise %s" % dims, _texture("ShaderNodeTexNoise", 0, noise_dimensions=dims,
                                                    inputs={"W": 0.3, "Detail": 3.0})))
    cases.append(("noise colour distorted", _texture("ShaderNodeTexNoise", 1, inputs={"Distortion": 1.5,
                                                                                       "Roughness": 0.7})))
    if V41:
        for kind in ("MULTIFRACTAL", "HYBRID_MULTIFRACTAL", "RIDGED_MULTIFRACTAL", "HETERO_TERRAIN"):
            cases.append(("noise %s" % kind.lower(),
                          _texture("ShaderNodeTexNoise", 0, noise_type=kind, absolute=True,
                                   inputs={"Detail": 2.0, "Roughness": 0.6, "Offset": 0.5, "Gain": 1.2})))
    else:
        for kind in ("FBM", "MULTIFRACTAL", "HYBRID_MULTIFRACTAL", "RIDGED_MULTIFRACTAL", "HETERO_TERRAIN"):
            cases.append(("musgrave %s" % kind.lower(),
                          _texture("ShaderNodeTexMusgrave", 0, musgrave_type=kind, absolute=True,
                                   inputs={"Detail": 2.0, "Offset": 0.5, "Gain": 1.2})))
    for feature in ("F1", "F2", "SMOOTH_F1", "DISTANCE_TO_EDGE", "N_SPHERE_RADIUS"):
        out = "Radius" if feature == "N_SPHERE_RADIUS" else "Distance"
        cases.append(("voronoi %s" % feature.lower(), _texture("ShaderNodeTexVoronoi", out, feature=feature)))
    for metric in ("MANHATTAN", "CHEBYCHEV", "MINKOWSKI"):
        cases.append(("voronoi %s" % metric.lower(),
                      _texture("ShaderNodeTexVoronoi", "Color", distance=metric, inputs={"Exponent": 1.5})))
    cases.append(("voronoi 2D position", _texture("ShaderNodeTexVoronoi", "Position", voronoi_dimensions="2D")))
    cases.append(("voronoi 4D", _texture("ShaderNodeTexVoronoi", "Distance", voronoi_dimensions="4D",
                                         inputs={"W": 0.7})))
    if V4:
        cases.append(("voronoi fractal", _texture("ShaderNodeTexVoronoi", "Distance",
                                                  inputs={"Detail": 2.0, "Roughness": 0.6})))
    for wave, direction, profile in (("BANDS", "X", "SIN"), ("BANDS", "DIAGONAL", "SAW"),
                                     ("RINGS", "SPHERICAL", "TRI"), ("RINGS", "Z", "SIN")):
        props = {"wave_type": wave, "wave_profile": profile}
        props["bands_direction" if wave == "BANDS" else "rings_direction"] = direction
        cases.append(("wave %s %s %s" % (wave, direction, profile),
                      _texture("ShaderNodeTexWave", "Fac", inputs={"Distortion": 2.0, "Detail": 2.0}, **props)))
    cases.append(("brick", _texture("ShaderNodeTexBrick", "Color", inputs={"Scale": 3.0, "Mortar Smooth": 0.2},
                                    offset=0.3, offset_frequency=3, squash=1.5, squash_frequency=2)))
    cases.append(("checker", _texture("ShaderNodeTexChecker", "Color", inputs={"Scale": 3.0})))
    for depth in (1, 4):
        cases.append(("magic %d" % depth, _texture("ShaderNodeTexMagic", "Color", turbulence_depth=depth,
                                                   inputs={"Distortion": 1.0, "Scale": 3.0})))
    for kind in ("LINEAR", "QUADRATIC", "EASING", "DIAGONAL", "SPHERICAL", "QUADRATIC_SPHERE", "RADIAL"):
        cases.append(("gradient %s" % kind.lower(), _texture("ShaderNodeTexGradient", "Color", coords="Object",
                                                             gradient_type=kind)))
    return cases


def _white_noise(dims):
    def build(name):
        # Quantised coordinates: white noise changes with every bit of its
        # input, so each pixel must read a whole cell's constant.
        t = Tree(name)
        snap = t.node("ShaderNodeVectorMath", operation="SNAP", inputs={1: (0.1307, 0.1307, 0.1307)})
        t.link(t.coords("Generated"), sock(snap.inputs, 0))
        off = t.node("ShaderNodeVectorMath", operation="ADD", inputs={1: (0.0625, 0.0625, 0.0625)})
        t.link(sock(snap.outputs, 0), sock(off.inputs, 0))
        wn = t.node("ShaderNodeTexWhiteNoise", noise_dimensions=dims)
        t.link(sock(off.outputs, 0), sock(wn.inputs, "Vector"))
        t.link(t.component(sock(off.outputs, 0), "X"), sock(wn.inputs, "W"))
        return t.show(sock(wn.outputs, "Color"))
    return build


def test_textures(addon, tmp_path):
    cases = texture_cases() + [("white noise %s" % d, _white_noise(d)) for d in ("1D", "2D", "3D", "4D")]
    check(render_grid(cases, tmp_path, "textures"))


# ------------------------------------------------------ converters, colour

MATH_OPS = ["ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "MULTIPLY_ADD", "POWER", "LOGARITHM", "SQRT",
            "INVERSE_SQRT", "ABSOLUTE", "EXPONENT", "MINIMUM", "MAXIMUM", "LESS_THAN", "GREATER_THAN", "SIGN",
            "COMPARE", "SMOOTH_MIN", "SMOOTH_MAX", "ROUND", "FLOOR", "CEIL", "TRUNC", "FRACT", "MODULO",
            "WRAP", "SNAP", "PINGPONG", "SINE", "COSINE", "TANGENT", "ARCSINE", "ARCCOSINE", "ARCTANGENT",
            "ARCTAN2", "SINH", "COSH", "TANH", "RADIANS", "DEGREES"] + (["FLOORED_MODULO"] if V4 else [])

VECTOR_OPS = ["ADD", "SUBTRACT", "MULTIPLY", "DIVIDE", "MULTIPLY_ADD", "CROSS_PRODUCT", "PROJECT", "REFLECT",
              "REFRACT", "FACEFORWARD", "DOT_PRODUCT", "DISTANCE", "LENGTH", "SCALE", "NORMALIZE", "ABSOLUTE",
              "MINIMUM", "MAXIMUM", "FLOOR", "CEIL", "FRACTION", "MODULO", "WRAP", "SNAP", "SINE", "COSINE",
              "TANGENT"] + (["POWER", "SIGN"] if bpy.app.version >= (4, 5, 0) else [])


def _math(op):
    def build(name):
        t = Tree(name)
        p = t.coords("Object", (1.618, 1.414, 1.0), (0.0123, 0.0456, 0.0))
        m = t.node("ShaderNodeMath", operation=op)
        t.link(t.component(p, "X"), sock(m.inputs, 0))
        t.link(t.component(p, "Y"), sock(m.inputs, 1))
        sock(m.inputs, 2).default_value = 0.3
        return t.show(t.absolute(sock(m.outputs, 0)))
    return build


def _vector_math(op):
    def build(name):
        t = Tree(name)
        a = t.coords("Object", (1.5, 1.2, 1.0), (0.1, -0.2, 0.4))
        b = t.coords("Generated", (0.7, -1.3, 0.9), (0.3, 0.2, -0.5))
        m = t.node("ShaderNodeVectorMath", operation=op)
        t.link(a, sock(m.inputs, 0))
        t.link(b, sock(m.inputs, 1))
        sock(m.inputs, 2).default_value = (0.5, -0.25, 0.75)
        sock(m.inputs, 3).default_value = 1.3
        v = t.absolute(sock(m.outputs, "Vector"))
        if op in {"DOT_PRODUCT", "DISTANCE", "LENGTH"}:
            v = t.absolute(sock(m.outputs, "Value"))
        return t.show(v)
    return build


def test_math(addon, tmp_path):
    cases = [("math %s" % op.lower(), _math(op)) for op in MATH_OPS]
    cases += [("vector %s" % op.lower(), _vector_math(op)) for op in VECTOR_OPS]
    check(render_grid(cases, tmp_path, "math"))


def _two_colours(t):
    noise = t.node("ShaderNodeTexNoise", {"Scale": 3.0})
    t.link(t.coords("Generated"), sock(noise.inputs, "Vector"))
    checker = t.node("ShaderNodeTexChecker", {"Scale": 2.0, "Color1": (0.9, 0.3, 0.1), "Color2": (0.2, 0.5, 0.8)})
    t.link(t.coords("Generated"), sock(checker.inputs, "Vector"))
    return sock(noise.outputs, "Color"), sock(checker.outputs, "Color")


BLENDS = ["MIX", "DARKEN", "MULTIPLY", "BURN", "LIGHTEN", "SCREEN", "DODGE", "ADD", "OVERLAY", "SOFT_LIGHT",
          "LINEAR_LIGHT", "DIFFERENCE", "SUBTRACT", "DIVIDE", "HUE", "SATURATION", "VALUE", "COLOR"] + \
    (["EXCLUSION"] if bpy.app.version >= (3, 5, 0) else [])


def _mix(blend):
    def build(name):
        t = Tree(name)
        a, b = _two_colours(t)
        mix = t.node("ShaderNodeMix", data_type="RGBA", blend_type=blend)
        mix.clamp_result = True
        sockets = {s.identifier: s for s in mix.inputs}
        t.link(a, sockets["A_Color"])
        t.link(b, sockets["B_Color"])
        t.link(t.component(t.coords("Generated"), "X"), sockets["Factor_Float"])
        return t.show(sock(mix.outputs, 2))
    return build


def _color_node(kind, inputs=None, color_socket="Color", out=0, setup=None, **props):
    def build(name):
        t = Tree(name)
        a, _ = _two_colours(t)
        n = t.node(kind, inputs, **props)
        if setup:
            setup(n)
        if color_socket is not None:
            t.link(a, sock(n.inputs, color_socket))
        return t.show(sock(n.outputs, out))
    return build


def _ramp(interpolation):
    def setup(n):
        ramp = n.color_ramp
        ramp.interpolation = interpolation
        ramp.elements[0].color = (0.1, 0.2, 0.9, 1.0)
        ramp.elements[1].position = 0.8
        e = ramp.elements.new(0.45)
        e.color = (0.9, 0.6, 0.1, 1.0)

    def build(name):
        t = Tree(name)
        n = t.node("ShaderNodeValToRGB")
        setup(n)
        t.link(t.component(t.coords("Generated"), "X"), sock(n.inputs, "Fac"))
        return t.show(sock(n.outputs, "Color"))
    return build


def _curves(n):
    curve = n.mapping.curves[-1] if n.bl_idname == "ShaderNodeRGBCurve" else n.mapping.curves[0]
    curve.points.new(0.3, 0.6)
    n.mapping.curves[0].points.new(0.6, 0.2)
    n.mapping.update()


def _map_range(mode, vector=False):
    def build(name):
        t = Tree(name)
        n = t.node("ShaderNodeMapRange", interpolation_type=mode)
        if vector:
            n.data_type = "FLOAT_VECTOR"
            t.link(t.coords("Generated"), sock(n.inputs, 6))
            sock(n.inputs, 7).default_value = (0.2, 0.1, 0.0)
            sock(n.inputs, 8).default_value = (0.8, 0.7, 1.0)
            sock(n.inputs, 11).default_value = (4.0, 4.0, 4.0)
            return t.show(sock(n.outputs, "Vector"))
        t.link(t.component(t.coords("Generated"), "X"), sock(n.inputs, 0))
        sock(n.inputs, 1).default_value, sock(n.inputs, 2).default_value = 0.2, 0.8
        sock(n.inputs, 5).default_value = 4.0
        return t.show(sock(n.outputs, 0))
    return build


def _scalar_to_colour(kind, lo, hi, socket):
    def build(name):
        t = Tree(name)
        n = t.node("ShaderNodeMapRange", {1: 0.0, 2: 1.0, 3: lo, 4: hi})
        t.link(t.component(t.coords("Generated"), "X"), sock(n.inputs, 0))
        b = t.node(kind)
        t.link(sock(n.outputs, 0), sock(b.inputs, socket))
        return t.show(sock(b.outputs, 0))
    return build


def _separate_combine(mode):
    def build(name):
        t = Tree(name)
        a, _ = _two_colours(t)
        sep = t.node("ShaderNodeSeparateColor", mode=mode)
        comb = t.node("ShaderNodeCombineColor", mode=mode)
        t.link(a, sock(sep.inputs, 0))
        t.link(sock(sep.outputs, 0), sock(comb.inputs, 1))
        t.link(sock(sep.outputs, 1), sock(comb.inputs, 2))
        t.link(sock(sep.outputs, 2), sock(comb.inputs, 0))
        return t.show(sock(comb.outputs, 0))
    return build


def colour_cases():
    cases = [("mix %s" % b.lower(), _mix(b)) for b in BLENDS]
    cases += [("ramp %s" % i.lower(), _ramp(i)) for i in ("LINEAR", "CONSTANT", "EASE", "B_SPLINE", "CARDINAL")]
    cases += [("map range %s" % m.lower(), _map_range(m)) for m in ("LINEAR", "STEPPED", "SMOOTHSTEP",
                                                                      "SMOOTHERSTEP")]
    cases += [("map range vector stepped", _map_range("STEPPED", True))]
    cases += [
        ("hue saturation", _color_node("ShaderNodeHueSaturation", {"Hue": 0.3, "Saturation": 1.4, "Value": 0.8})),
        ("bright contrast", _color_node("ShaderNodeBrightContrast", {"Bright": 0.1, "Contrast": 0.4})),
        ("gamma", _color_node("ShaderNodeGamma", {"Gamma": 2.2})),
        ("invert", _color_node("ShaderNodeInvert", {"Fac": 0.8})),
        ("rgb curves", _color_node("ShaderNodeRGBCurve", setup=_curves)),
        ("vector curves", _color_node("ShaderNodeVectorCurve", color_socket="Vector", setup=_curves)),
        ("clamp range", _scalar_to_colour("ShaderNodeClamp", -0.3, 1.4, "Value")),
        ("rgb to bw", _color_node("ShaderNodeRGBToBW")),
        ("blackbody", _scalar_to_colour("ShaderNodeBlackbody", 1500.0, 12000.0, "Temperature")),
        ("wavelength", _scalar_to_colour("ShaderNodeWavelength", 380.0, 780.0, "Wavelength")),
        ("separate combine rgb", _separate_combine("RGB")),
        ("separate combine hsv", _separate_combine("HSV")),
        ("separate combine hsl", _separate_combine("HSL")),
    ]
    return cases


def test_colour(addon, tmp_path):
    check(render_grid(colour_cases(), tmp_path, "colour"))


# ---------------------------------------------------------- vector, inputs

def _coordinate(output, absolute=True):
    def build(name):
        t = Tree(name)
        tc = t.node("ShaderNodeTexCoord")
        out = sock(tc.outputs, output)
        return t.show(t.absolute(out) if absolute else out)
    return build


def _mapping(kind):
    def build(name):
        t = Tree(name)
        tc = t.node("ShaderNodeTexCoord")
        m = t.node("ShaderNodeMapping", vector_type=kind)
        t.link(sock(tc.outputs, "Object"), sock(m.inputs, "Vector"))
        if kind in {"POINT", "TEXTURE"}:
            sock(m.inputs, "Location").default_value = (0.2, -0.1, 0.3)
        sock(m.inputs, "Rotation").default_value = (0.4, -0.3, 0.9)
        sock(m.inputs, "Scale").default_value = (1.5, 0.7, 1.2)
        return t.show(t.absolute(sock(m.outputs, 0)))
    return build


def _rotate(kind):
    def build(name):
        t = Tree(name)
        tc = t.node("ShaderNodeTexCoord")
        n = t.node("ShaderNodeVectorRotate", rotation_type=kind)
        t.link(sock(tc.outputs, "Object"), sock(n.inputs, "Vector"))
        sock(n.inputs, "Center").default_value = (0.1, 0.2, 0.0)
        sock(n.inputs, "Axis").default_value = (0.3, 0.4, 1.0)
        sock(n.inputs, "Angle").default_value = 0.8
        sock(n.inputs, "Rotation").default_value = (0.3, 0.6, -0.4)
        return t.show(t.absolute(sock(n.outputs, 0)))
    return build


def _textured_by_image(tmp_path, interpolation, extension, projection):
    def build(name):
        t = Tree(name)
        img = bpy.data.images.get("parity_image")
        if img is None:
            img = bpy.data.images.new("parity_image", 8, 8, alpha=True, float_buffer=True)
            rng = np.random.default_rng(7)
            px = rng.random((8, 8, 4)).astype(np.float32)
            px[..., 3] = 1.0
            img.pixels.foreach_set(px.ravel())
            img.pack()
        tex = t.node("ShaderNodeTexImage", interpolation=interpolation, extension=extension, projection=projection)
        tex.image = img
        t.link(t.coords("UV" if projection == "FLAT" else "Generated", (1.7, 1.3, 1.0), (-0.2, -0.1, 0.0)),
               sock(tex.inputs, "Vector"))
        return t.show(sock(tex.outputs, "Color"))
    return build


def _bump(invert):
    """Bump of a smooth height: Cycles differentiates over the pixel's
    footprint (a forward difference, so the normal of a point half a
    footprint away), Phos over 10⁻⁴ of the scene's size; on a height that
    bends little over a pixel both are its derivative."""
    def build(name):
        t = Tree(name)
        noise = t.node("ShaderNodeTexNoise", {"Scale": 0.3, "Detail": 0.0})
        t.link(t.coords("Object"), sock(noise.inputs, "Vector"))
        bump = t.node("ShaderNodeBump", {"Strength": 0.8, "Distance": 0.6}, invert=invert)
        t.link(sock(noise.outputs, "Fac"), sock(bump.inputs, "Height"))
        return t.show(t.absolute(sock(bump.outputs, "Normal")))
    return build


def _normal_map(space):
    def build(name):
        t = Tree(name)
        img = bpy.data.images.get("normal_image")
        if img is None:
            img = bpy.data.images.new("normal_image", 8, 8, alpha=True, float_buffer=True)
            rng = np.random.default_rng(3)
            px = np.empty((8, 8, 4), np.float32)
            px[..., 0:2] = 0.5 + 0.3 * (rng.random((8, 8, 2)) - 0.5)
            px[..., 2] = 0.9
            px[..., 3] = 1.0
            img.pixels.foreach_set(px.ravel())
            img.colorspace_settings.is_data = True
            img.pack()
        tex = t.node("ShaderNodeTexImage", interpolation="Linear")
        tex.image = img
        nm = t.node("ShaderNodeNormalMap", {"Strength": 0.7}, space=space)
        t.link(sock(tex.outputs, "Color"), sock(nm.inputs, "Color"))
        return t.show(t.absolute(sock(nm.outputs, "Normal")))
    return build


def _input_node(kind, output, inputs=None):
    def build(name):
        t = Tree(name)
        n = t.node(kind, inputs)
        out = sock(n.outputs, output)
        return t.show(t.absolute(out) if out.type != "RGBA" else out)
    return build


def _tangent_node(direction, axis):
    def build(name):
        t = Tree(name)
        n = t.node("ShaderNodeTangent")
        n.direction_type = direction
        n.axis = axis
        return t.show(t.absolute(sock(n.outputs, "Tangent")))
    return build


def vector_cases(tmp_path):
    cases = [("coordinates %s" % o.lower(), _coordinate(o)) for o in ("Generated", "Normal", "UV", "Object",
                                                                       "Camera", "Window", "Reflection")]
    cases += [("mapping %s" % k.lower(), _mapping(k)) for k in ("POINT", "TEXTURE", "VECTOR", "NORMAL")]
    cases += [("rotate %s" % k.lower(), _rotate(k)) for k in ("AXIS_ANGLE", "X_AXIS", "Z_AXIS", "EULER_XYZ")]
    for interp in ("Closest", "Linear", "Cubic"):
        for ext in ("REPEAT", "EXTEND", "CLIP"):
            cases.append(("image %s %s" % (interp.lower(), ext.lower()),
                          _textured_by_image(tmp_path, interp, ext, "FLAT")))
    for proj in ("SPHERE", "TUBE", "BOX"):
        cases.append(("image %s" % proj.lower(), _textured_by_image(tmp_path, "Linear", "REPEAT", proj)))
    cases += [("bump", _bump(False)), ("bump inverted", _bump(True))]
    cases += [("normal map %s" % s.lower(), _normal_map(s)) for s in ("TANGENT", "OBJECT", "WORLD")]
    cases += [("fresnel", _input_node("ShaderNodeFresnel", "Fac", {"IOR": 1.8})),
              ("layer weight fresnel", _input_node("ShaderNodeLayerWeight", "Fresnel", {"Blend": 0.3})),
              ("layer weight facing", _input_node("ShaderNodeLayerWeight", "Facing", {"Blend": 0.7})),
              ("geometry position", _input_node("ShaderNodeNewGeometry", "Position")),
              ("geometry incoming", _input_node("ShaderNodeNewGeometry", "Incoming")),
              ("geometry tangent", _input_node("ShaderNodeNewGeometry", "Tangent")),
              ("tangent radial z", _tangent_node('RADIAL', 'Z')),
              ("tangent uv map", _tangent_node('UV_MAP', 'Z')),
              ("object info location", _input_node("ShaderNodeObjectInfo", "Location")),
              ("object info random", _input_node("ShaderNodeObjectInfo", "Random")),
              ("light path camera", _input_node("ShaderNodeLightPath", "Is Camera Ray"))]
    return cases


def test_vector_and_inputs(addon, tmp_path):
    cases = vector_cases(tmp_path)
    check(render_grid(cases, tmp_path, "vector"))
