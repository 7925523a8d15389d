# SPDX-License-Identifier: GPL-3.0-or-later
"""The Principled BSDF → closures, as the Cycles of each Blender builds it.

Blender 3.x (Principled v1, Cycles 3.4's svm closure code): Burley diffuse,
a GGX specular whose colour blends from f0 = mix(0.08·Specular·tint, base,
metallic) to white, and a glass of weight transmission·(1 − metallic).

Blender 4.x and 5.x (Principled v2, Cycles 4's layer stack; docs/algorithms.md
§8): from the top,

    alpha        a transparent closure of weight 1 − Alpha; the rest × Alpha
    sheen        microfiber sheen of weight Sheen Weight × Sheen Tint, a
                 layer over everything below
    coat         a dielectric GGX of Coat IOR and Coat Roughness (always with
                 Multiscatter energy compensation from 4.5), a layer over
                 everything below, which it also tints: Coat Tint raised to
                 the optical depth 1/cos θt of a unit-thick coat
    emission
    metallic     F82-tint GGX: Base Color at normal incidence, Specular Tint
                 near grazing; the rest × (1 − Metallic)
    transmission a glass of IOR, f0 = F0(IOR)·Specular Tint, refracted light
                 tinted by √Base Color, the thin film; the rest × (1 − Transmission)
    specular     a dielectric GGX whose f0 = F0(IOR)·2·Specular IOR Level
                 ·Specular Tint, with the thin film: a layer over the rest
    subsurface   Lambertian of weight Subsurface Weight × Base Color (Phos
                 has no subsurface scattering; this is what Cycles itself
                 falls back to)
    diffuse      Lambert, or Oren-Nayar with Diffuse Roughness (4.3+)

A layer scales those under it by 1 − its directional albedo toward the
viewer; the core evaluates that at every shading point (phos.h,
layer_span).
"""

import math

import numpy as np

from .. import core
from . import program as prog
from .material import (WEIGHT_CUTOFF, Closure, _clamp01, _enum_name, find_input, oren_nayar_tint,
                       thin_film)
from .microfacet import (dielectric_fss, f0_from_ior, f82_fss, fresnel_blend_fss, ior_from_f0,
                         microfacet_model, principled_anisotropy, unit_rgb)


def principled(walker, node):
    if walker.ctx.at_least(4, 0):
        return principled_v2(walker, node)
    return principled_v1(walker, node)


# ----------------------------------------------------------------- 4.x, 5.x

def principled_v2(walker, node):
    w = walker
    ctx = w.ctx
    consumed = set()
    base, _, _ = w.color(node, ('Base Color',), consumed)
    metallic = _clamp01(w.value(node, ('Metallic',), 0.0, consumed))
    roughness = _clamp01(w.value(node, ('Roughness',), 0.5, consumed))
    ior = prog.maximum(w.value(node, ('IOR',), 1.5, consumed), 1e-5)
    alpha = _clamp01(w.value(node, ('Alpha',), 1.0, consumed))
    transmission = _clamp01(w.value(node, ('Transmission Weight',), 0.0, consumed))
    specular_level = prog.maximum(w.value(node, ('Specular IOR Level',), 0.5, consumed), 0.0)
    spec_tint, _, _ = w.color(node, ('Specular Tint',), consumed)
    spec_tint = prog.maximum(spec_tint, 0.0)
    diffuse_roughness = _clamp01(w.value(node, ('Diffuse Roughness',), 0.0, consumed))
    subsurface = _clamp01(w.value(node, ('Subsurface Weight',), 0.0, consumed))
    sheen = prog.maximum(w.value(node, ('Sheen Weight',), 0.0, consumed), 0.0)
    coat = prog.maximum(w.value(node, ('Coat Weight',), 0.0, consumed), 0.0)
    emission, _, _ = w.color(node, ('Emission Color',), consumed)
    emission_strength = w.value(node, ('Emission Strength',), 0.0, consumed)
    film = thin_film(w, node, consumed)
    model, _ = w.distribution(node)
    normal = w.normal(node, ('Normal',), consumed)
    coat_normal = w.normal(node, ('Coat Normal',), consumed)

    # Anisotropic GGX for the metal and the specular (Cycles 4: along the
    # Tangent turned by Anisotropic Rotation about the Normal).
    aniso = w.anisotropy(node, roughness, consumed, ('Anisotropic',), ('Anisotropic Rotation',),
                         principled_anisotropy)

    # What the core cannot render: said once, naming the inputs.
    ignored = []
    # Blender 5.3's thin walls and dispersion.
    if find_input(node, 'Thin Wall') is not None and prog.may_exceed(w.value(node, ('Thin Wall',), 0.0, consumed),
                                                                      0.5):
        ignored.append("Thin Wall")
    if prog.may_exceed(w.value(node, ('Transmission Dispersion Scale',), 0.0, consumed), WEIGHT_CUTOFF):
        ignored.append("Transmission Dispersion")
    consumed |= {s.identifier for s in node.inputs if s.name.startswith(("Subsurface", "Transmission Dispersion"))}
    # The coat's shading normal: Coat Normal when linked; unlinked, Cycles
    # takes the surface's own normal, not the Normal input (sd->N), in every
    # version from 4.0 (the principled_coat_over_bump parity scene: D/V 3.1
    # on 5.3 with the Normal input, 1.06 with the surface's).
    # From 4.2 Cycles lays the sheen over the coat: its normal is
    # normalize(mix(Normal, coat normal, clamp(Coat Weight, 0, 1))).
    sheen_normal = normal
    if (ctx.at_least(4, 2) and coat_normal is not normal and prog.may_exceed(sheen, WEIGHT_CUTOFF)
            and prog.may_exceed(coat, WEIGHT_CUTOFF)):
        surface = w.nodes.normal()
        below = surface if normal is None else normal
        above = surface if coat_normal is None else coat_normal
        sheen_normal = w.nodes.vector_math('NORMALIZE', below + (above - below) * _clamp01(coat))
    if prog.may_exceed(subsurface, WEIGHT_CUTOFF):
        w.note(node, "Subsurface scattering is not supported; its share is rendered as a diffuse "
                     "of the Base Color (as Cycles does for tiny radii)")
    if _nonzero(emission_strength) and _nonzero(emission):
        if prog.may_exceed(sheen, WEIGHT_CUTOFF) or prog.may_exceed(coat, WEIGHT_CUTOFF):
            ignored.append("the dimming of Emission by Sheen and Coat")

    base_unit = unit_rgb(base)

    top, below = [], []   # the closures so far, and the weight left for the layers below
    weight = np.ones(3)
    if prog.may_be_below(alpha, 1.0):
        top.append(Closure(core.PHOS_CLOSURE_TRANSPARENT, _full3(1.0 - alpha)))
        weight = weight * alpha
    layers = []           # (closure, index in `top` where its children start)

    def add_layer(closure):
        top.append(closure)
        layers.append((closure, len(top)))

    if prog.may_exceed(sheen, WEIGHT_CUTOFF):
        sheen_tint, _, _ = w.color(node, ('Sheen Tint',), consumed)
        sheen_rel = sheen * prog.maximum(sheen_tint, 0.0)
        add_layer(Closure(core.PHOS_CLOSURE_SHEEN, sheen_rel * weight, sheen_normal,
                          roughness=_clamp01(w.value(node, ('Sheen Roughness',), 0.5, consumed)),
                          layer_weight=sheen_rel))

    if prog.may_exceed(coat, WEIGHT_CUTOFF):
        coat_ior = prog.maximum(w.value(node, ('Coat IOR',), 1.5, consumed), 1.0)
        coat_tint, _, _ = w.color(node, ('Coat Tint',), consumed)
        f0 = f0_from_ior(coat_ior)
        # Cycles compensates the coat's energy whatever the distribution from 4.5.
        coat_model = (core.PHOS_MICROFACET_GGX_MULTISCATTER if ctx.at_least(4, 5)
                      else microfacet_model(ctx, 'GGX'))
        add_layer(Closure(core.PHOS_CLOSURE_REFLECTION_FRESNEL, coat * weight, coat_normal,
                          roughness=_clamp01(w.value(node, ('Coat Roughness',), 0.03, consumed)),
                          ior=coat_ior, specular_color=_full3(f0), microfacet=coat_model,
                          multiscatter_fresnel=_full3(prog.clamp(dielectric_fss(coat_ior), 0.0, 1.0)),
                          layer_weight=_full3(coat), layer_tint=prog.maximum(coat_tint, 0.0),
                          layer_tint_weight=coat))
    consumed |= {s.identifier for s in node.inputs if s.name.startswith(("Sheen", "Coat"))}

    emitted = emission * emission_strength
    if _nonzero(emitted):
        top.append(Closure(core.PHOS_CLOSURE_EMISSION, emitted * weight))

    if prog.may_exceed(metallic, WEIGHT_CUTOFF):
        tint = unit_rgb(spec_tint)
        top.append(Closure(core.PHOS_CLOSURE_METAL, _full3(metallic) * weight, normal,
                           microfacet=model, specular_color=base_unit, specular_tint=tint,
                           multiscatter_fresnel=f82_fss(base_unit, tint), **aniso))
        weight = weight * (1.0 - metallic)

    if prog.may_exceed(transmission, WEIGHT_CUTOFF):
        refracted = prog.sqrt(base_unit)
        top.append(Closure(core.PHOS_CLOSURE_GLASS, _full3(transmission) * weight, normal, roughness=roughness,
                           ior=ior, glass_fresnel=core.PHOS_GLASS_FRESNEL_MICROFACET, microfacet=model,
                           specular_tint=unit_rgb(spec_tint), transmission_tint=refracted,
                           multiscatter_fresnel=refracted, **film))
        weight = weight * (1.0 - transmission)

    # Specular IOR Level scales f0, and the IOR the specular's Fresnel curve follows.
    f0 = f0_from_ior(ior)
    eta = ior
    if prog.varies(specular_level) or specular_level != 0.5:
        f0 = f0 * (2.0 * specular_level)
        eta = ior_from_f0(f0)
        if not prog.varies(ior) and ior < 1.0:
            eta = 1.0 / eta
    if prog.varies(eta) or eta != 1.0 or film:
        spec_f0 = prog.clamp(f0 * spec_tint, 0.0, 1.0)
        add_layer(Closure(core.PHOS_CLOSURE_REFLECTION_FRESNEL, _copy(weight), normal,
                          ior=eta, specular_color=spec_f0, microfacet=model,
                          multiscatter_fresnel=fresnel_blend_fss(spec_f0, eta), layer_weight=np.ones(3),
                          **film, **aniso))

    if prog.may_exceed(subsurface, WEIGHT_CUTOFF):
        top.append(Closure(core.PHOS_CLOSURE_DIFFUSE, base_unit * subsurface * weight, normal))
    diffuse_weight = (1.0 - subsurface) * weight
    if prog.may_exceed(diffuse_weight, WEIGHT_CUTOFF):
        if prog.may_exceed(diffuse_roughness, 1e-5 - 1e-12):
            top.append(Closure(core.PHOS_CLOSURE_OREN_NAYAR, base * diffuse_weight, normal,
                               roughness=diffuse_roughness, specular_color=prog.clamp(base, 0.0, 1.0),
                               specular_tint=oren_nayar_tint(ctx, base)))
        else:
            top.append(Closure(core.PHOS_CLOSURE_DIFFUSE, base * diffuse_weight, normal))

    for closure, start in layers:
        closure.layer_children = top[start:]
    if ignored:
        w.note(node, "%s not supported; ignored" % ", ".join(ignored))
    w.check_unused_links(node, consumed)
    return top


def _full3(x):
    """A float (or float Value) as an RGB of three equal channels."""
    if prog.varies(x):
        return x.program.convert(x, 3)
    return np.full(3, float(prog.const_value(x)) if isinstance(x, prog.Value) else float(x))


def _copy(x):
    return x if prog.varies(x) else np.array(prog.plain(x), dtype=np.float64, copy=True)


def _nonzero(x):
    return prog.varies(x) or float(np.max(np.abs(np.asarray(prog.plain(x), dtype=np.float64)))) > 0.0


# ---------------------------------------------------------------------- 3.x

def principled_v1(walker, node):
    """Cycles 3.4's Principled BSDF: diffuse_weight = (1 − metallic)(1 −
    transmission); the specular has weight 1 − final_transmission, f0 =
    mix(specular·0.08·tint, base, metallic) and the IOR Cycles derives from
    Specular; the transmission is a glass of weight final_transmission =
    transmission·(1 − metallic), its refraction tinted by the base colour and
    of roughness 1 − (1 − Roughness)(1 − Transmission Roughness). Cycles 3.4
    also tints the glass's reflection by mix(white, base, specular_tint):
    that tint is left out. With an image base colour the image tints the
    whole glass."""
    w = walker
    consumed = set()
    base, _, _ = w.color(node, ('Base Color',), consumed)
    metallic = _clamp01(w.value(node, ('Metallic',), 0.0, consumed))
    roughness = _clamp01(w.value(node, ('Roughness',), 0.5, consumed))
    ior = prog.maximum(w.value(node, ('IOR',), 1.45, consumed), 1e-5)
    transmission = _clamp01(w.value(node, ('Transmission',), 0.0, consumed))
    alpha = _clamp01(w.value(node, ('Alpha',), 1.0, consumed))
    emission, _, _ = w.color(node, ('Emission',), consumed)
    emission_strength = w.value(node, ('Emission Strength',), 1.0, consumed)
    specular = prog.maximum(w.value(node, ('Specular',), 0.5, consumed), 0.0)
    tint_scalar = _clamp01(w.value(node, ('Specular Tint',), 0.0, consumed))
    model, _ = w.distribution(node)
    normal = w.normal(node, ('Normal',), consumed)

    # Parts of the Principled BSDF the core does not have: named once.
    ignored = []
    subsurface = w.value(node, ('Subsurface',), 0.0, consumed)
    approximated = ("Subsurface scattering is rendered as a diffuse of Subsurface Color mixed in"
                    if prog.may_exceed(subsurface, WEIGHT_CUTOFF) else "")
    if prog.may_exceed(w.value(node, ('Sheen',), 0.0, consumed), WEIGHT_CUTOFF):
        ignored.append("Sheen")
    if prog.may_exceed(w.value(node, ('Clearcoat',), 0.0, consumed), WEIGHT_CUTOFF):
        ignored.append("Clearcoat")
    # Cycles 3.4 turns the Tangent by Anisotropic Rotation even when
    # Anisotropic is 0, where it does not matter.
    aniso = w.anisotropy(node, roughness, consumed, ('Anisotropic',), ('Anisotropic Rotation',),
                         principled_anisotropy)
    transmission_roughness = w.value(node, ('Transmission Roughness',), 0.0, consumed)
    final_transmission = transmission * (1.0 - metallic)
    # Inputs that only matter for ignored features: not worth a second warning.
    consumed |= {s.identifier for s in node.inputs
                 if s.name.startswith(("Subsurface", "Sheen", "Clearcoat"))}
    if ignored or approximated:
        parts = [approximated] if approximated else []
        if ignored:
            parts.append("%s not supported; ignored" % ", ".join(ignored))
        w.note(node, "; ".join(parts))
    w.check_unused_links(node, consumed)

    closures = []
    diffuse_weight = (1.0 - metallic) * (1.0 - transmission)
    specular_weight = 1.0 - final_transmission

    if prog.may_exceed(diffuse_weight, WEIGHT_CUTOFF):
        color = base
        if prog.may_exceed(subsurface, WEIGHT_CUTOFF):
            # Closest to Cycles' subsurface albedo: the mixed subsurface colour.
            ss_color, _, _ = w.color(node, ('Subsurface Color',), consumed)
            s = _clamp01(subsurface)
            color = ss_color * s + base * (1.0 - s)
        closures.append(Closure(core.PHOS_CLOSURE_PRINCIPLED_DIFFUSE, color * diffuse_weight, normal,
                                roughness=roughness))

    if prog.may_exceed(specular_weight, WEIGHT_CUTOFF) and (prog.may_exceed(specular, WEIGHT_CUTOFF)
                                                            or prog.may_exceed(metallic, WEIGHT_CUTOFF)):
        # IOR from Specular, f0 tinted towards the base hue.
        if prog.varies(specular):
            spec_ior = 2.0 / (1.0 - prog.sqrt(prog.clamp(0.08 * specular, 0.0, 0.999999))) - 1.0
        else:
            spec_ior = 2.0 / (1.0 - math.sqrt(min(0.08 * specular, 0.999999))) - 1.0
        tmp = _specular_tint(base, tint_scalar)
        f0 = (specular * 0.08 * tmp) * (1.0 - metallic) + base * metallic
        closures.append(Closure(core.PHOS_CLOSURE_REFLECTION_FRESNEL, _full3(specular_weight), normal,
                                ior=spec_ior, specular_color=f0, microfacet=model,
                                multiscatter_fresnel=fresnel_blend_fss(unit_rgb(f0), spec_ior), **aniso))

    if prog.may_exceed(final_transmission, WEIGHT_CUTOFF):
        refraction_roughness = 1.0 - (1.0 - roughness) * (1.0 - _clamp01(transmission_roughness))
        multi = model == core.PHOS_MICROFACET_GGX_MULTISCATTER  # 3.x's random walk: Fresnel per microfacet
        closures.append(Closure(core.PHOS_CLOSURE_GLASS, _full3(final_transmission), normal, roughness=roughness,
                                ior=ior, glass_fresnel=core.PHOS_GLASS_FRESNEL_MICROFACET if multi
                                else core.PHOS_GLASS_FRESNEL_MACRO, transmission_tint=base,
                                transmission_roughness=refraction_roughness, microfacet=model,
                                multiscatter_fresnel=unit_rgb(base)))

    emitted = emission * emission_strength
    if _nonzero(emitted):
        closures.append(Closure(core.PHOS_CLOSURE_EMISSION, emitted))

    if prog.may_be_below(alpha, 1.0):
        # Cycles mixes the whole node (emission included) with a transparent BSDF.
        closures = [c.scale(alpha) for c in closures]
        closures.append(Closure(core.PHOS_CLOSURE_TRANSPARENT, _full3(1.0 - alpha)))
    return closures


def _specular_tint(base, tint_scalar):
    """mix(1, base/lum(base), tint): the hue Principled v1 tints its specular
    with, lum = 0.3 R + 0.6 G + 0.1 B (white where lum = 0)."""
    if not prog.varies(base) and not prog.varies(tint_scalar):
        base = np.asarray(base, dtype=np.float64)
        lum = 0.3 * base[0] + 0.6 * base[1] + 0.1 * base[2]
        ctint = base / lum if lum > 0.0 else np.ones(3)
        return (1.0 - tint_scalar) + ctint * tint_scalar
    p = base.program if prog.varies(base) else tint_scalar.program
    b = p.convert(base if prog.varies(base) else prog.constant(base), 3)
    lum = p.emit(core.PHOS_OP_VECTOR_MATH, [b, prog.constant((0.3, 0.6, 0.1)), prog.constant((0, 0, 0)), 1.0],
                 [3, 1], mode=core.PHOS_VECTOR_MATH_DOT_PRODUCT)[1]
    ctint = b / lum  # Cycles' safe divide gives 0 where lum = 0; white is the limit
    return (1.0 - tint_scalar) + ctint * tint_scalar
