# SPDX-License-Identifier: GPL-3.0-or-later
"""The microfacet model of each Blender version, and the Fresnel averages
Multiscatter GGX needs (docs/algorithms.md §8).

Cycles changed its GGX in 4.0: the masking-shadowing term became the
height-correlated one, and Multiscatter GGX (the default distribution of
Glossy, Glass, Metallic and Principled from 4.0) became albedo scaling of
that single-scattering lobe. Phos's core renders each; the exporter picks
the one of the Blender it runs in. Cycles 3.x's Multiscatter GGX is a
random walk between microfacets (Heitz et al. 2016) that the core does not
have; it is rendered with the 4.x albedo scaling, which restores the same
energy with a slightly different lobe shape.

F_ss, the mean single-scattering Fresnel ∫ F(μ) 2μ dμ, sets how coloured
the multiply scattered light is (Kulla & Conty 2017): the colour for the
Glossy BSDF, their fit for a dielectric, the closed form for F82 metals.
"""

import math

import numpy as np

from .. import core
from . import program as prog
from .program import Value


def _varies(*xs):
    """Whether any argument is a shader-program value that is not constant:
    the helpers below then build the same formula as instructions."""
    return any(isinstance(x, Value) and not x.is_const for x in xs)

# Cycles' lower bound of a microfacet closure's weight.
WEIGHT_CUTOFF = 1e-5


def microfacet_model(ctx, distribution):
    """The core's enum phos_microfacet for a node's distribution ('GGX',
    'MULTI_GGX', 'BECKMANN', 'ASHIKHMIN_SHIRLEY') in the running Blender
    (separable Smith G up to 3.x, height-correlated from 4.0); other
    distributions are GGX (the caller warns)."""
    if distribution == 'MULTI_GGX':
        return core.PHOS_MICROFACET_GGX_MULTISCATTER
    if distribution == 'ASHIKHMIN_SHIRLEY':
        return core.PHOS_MICROFACET_ASHIKHMIN_SHIRLEY
    if distribution == 'BECKMANN':
        return core.PHOS_MICROFACET_BECKMANN if ctx.at_least(4, 0) else core.PHOS_MICROFACET_BECKMANN_SEPARABLE
    return core.PHOS_MICROFACET_GGX if ctx.at_least(4, 0) else core.PHOS_MICROFACET_GGX_SEPARABLE


def f0_from_ior(ior):
    if _varies(ior):
        r = (ior - 1.0) / (ior + 1.0)
        return r * r
    return ((ior - 1.0) / (ior + 1.0)) ** 2


def ior_from_f0(f0):
    """The IOR whose normal reflectance is f0 (f0 clamped below 1, as Cycles)."""
    if _varies(f0):
        s = prog.sqrt(prog.clamp(f0, 0.0, 0.99))
        return (1.0 + s) / (1.0 - s)
    s = math.sqrt(min(max(f0, 0.0), 0.99))
    return (1.0 + s) / (1.0 - s)


def dielectric_fss(eta):
    """Mean Fresnel of a dielectric of relative IOR eta: Kulla & Conty's fit
    (2017, the one Cycles uses), within 0.3 % of the integral. A varying
    eta takes the branch of eta >= 1 (IORs of real dielectrics)."""
    if _varies(eta):
        return (eta - 1.0) / (4.08567 + 1.00071 * eta)
    if eta < 1.0:
        return 0.997118 + eta * (0.1014 - eta * (0.965241 + 0.130607 * eta))
    return (eta - 1.0) / (4.08567 + 1.00071 * eta)


def fresnel_blend_fss(f0, eta):
    """F_ss of the Principled specular colour: f0 blended to white by the
    dielectric Fresnel of eta, averaged (the blend is linear in its factor)."""
    if _varies(f0, eta):
        F0 = f0_from_ior(eta)
        s = prog.clamp((dielectric_fss(eta) - F0) / (1.0 - F0), 0.0, 1.0)
        return prog.clamp(f0 * (1.0 - s) + s, 0.0, 1.0)
    F0 = f0_from_ior(eta)
    s = 1.0 if F0 >= 1.0 - 1e-6 else min(max((dielectric_fss(eta) - F0) / (1.0 - F0), 0.0), 1.0)
    return np.asarray(f0, dtype=np.float64) * (1.0 - s) + s


def f82_b(f0, tint):
    """F82-tint's b: at μ = 1/7 the reflectance is Schlick's times tint."""
    if _varies(f0, tint):
        schlick = f0 + (1.0 - f0) * (6.0 / 7.0) ** 5
        return schlick * (1.0 - tint) * (7.0 / (6.0 / 7.0) ** 6)
    f0 = np.asarray(f0, dtype=np.float64)
    schlick = f0 + (1.0 - f0) * (6.0 / 7.0) ** 5
    return schlick * (1.0 - np.asarray(tint, dtype=np.float64)) * 7.0 / (6.0 / 7.0) ** 6


def f82_fss(f0, tint):
    """∫ F82(μ) 2μ dμ = f0 + (1 − f0)/21 − b/126 (the clamp to [0,1] aside)."""
    if _varies(f0, tint):
        return prog.clamp(f0 + (1.0 - f0) / 21.0 - f82_b(f0, tint) / 126.0, 0.0, 1.0)
    f0 = np.asarray(f0, dtype=np.float64)
    return np.clip(f0 + (1.0 - f0) / 21.0 - f82_b(f0, tint) / 126.0, 0.0, 1.0)


def unit_rgb(c):
    """A colour clamped to [0, 1] per channel (Fresnel colours and tints)."""
    if _varies(c):
        return prog.clamp(c, 0.0, 1.0)
    return np.clip(np.asarray(c, dtype=np.float64).reshape(3), 0.0, 1.0)


def conductor_fresnel(n, k, mu):
    """Unpolarised reflectance of a conductor of complex IOR n + ik from air
    at cos θ = mu (Born & Wolf), per channel."""
    n, k = np.asarray(n, dtype=np.float64), np.asarray(k, dtype=np.float64)
    c2 = mu * mu
    t1 = n * n - k * k - (1.0 - c2)
    t2 = np.sqrt(t1 * t1 + 4.0 * n * n * k * k)
    u2, v2 = np.maximum((t2 + t1) / 2.0, 0.0), np.maximum((t2 - t1) / 2.0, 0.0)
    u, v = np.sqrt(u2), np.sqrt(v2)
    rs = ((mu - u) ** 2 + v2) / ((mu + u) ** 2 + v2)
    t3, t4 = (n * n - k * k) * mu, 2.0 * n * k * mu
    rp = ((t3 - u) ** 2 + (t4 - v) ** 2) / ((t3 + u) ** 2 + (t4 + v) ** 2)
    return (rs + rp) / 2.0


def conductor_as_f82(n, k):
    """(f0, tint) of the F82-tint curve through a conductor's reflectance at
    normal incidence and at μ = 1/7."""
    f0 = np.clip(conductor_fresnel(n, k, 1.0), 0.0, 1.0)
    f82 = conductor_fresnel(n, k, 1.0 / 7.0)
    schlick = f0 + (1.0 - f0) * (6.0 / 7.0) ** 5
    return f0, np.clip(np.where(schlick > 0.0, f82 / np.maximum(schlick, 1e-12), 1.0), 0.0, 1.0)


# ------------------------------------------------------------ anisotropy

def glossy_anisotropy(anisotropy):
    """The factors (sx, sy) by which Cycles scales α = roughness² along and
    across the tangent for the 3.x Anisotropic BSDF and the 4.x Glossy BSDF
    (svm closure.h): a = Anisotropy clamped to [−0.99, 0.99]; a < 0 gives
    (1/(1 + a), 1 + a), a ≥ 0 gives (1 − a, 1/(1 − a)). Written without a
    branch, so a texture can drive it: with a₋ = min(a, 0) and a₊ = max(a, 0),
    sx = (1 − a₊)/(1 + a₋) and sy = (1 + a₋)/(1 − a₊)."""
    a = prog.clamp(anisotropy, -0.99, 0.99)
    a_pos = prog.maximum(a, 0.0)
    a_neg = -prog.maximum(-a, 0.0)
    return (1.0 - a_pos) / (1.0 + a_neg), (1.0 + a_neg) / (1.0 - a_pos)


def principled_anisotropy(anisotropic):
    """(sx, sy) of the Principled BSDF (3.x and 4.x) and the Metallic BSDF:
    aspect = √(1 − 0.9·Anisotropic), αx = α/aspect, αy = α·aspect."""
    aspect = prog.sqrt(1.0 - 0.9 * prog.clamp(anisotropic, 0.0, 1.0))
    return 1.0 / aspect, aspect


def anisotropic_roughness(roughness, scales):
    """(roughness along the tangent, roughness across it) for the core:
    √(α·s) each, clamped to 1 as Cycles clamps each α to 1."""
    sx, sy = scales
    return (prog.clamp(roughness * prog.sqrt(sx), 0.0, 1.0), prog.clamp(roughness * prog.sqrt(sy), 0.0, 1.0))
