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
from . import image as image_export
from .material import (WEIGHT_CUTOFF, Closure, _clamp01, _enum_name, find_input, oren_nayar_tint,
                       thin_film)
from .microfacet import (dielectric_fss, f0_from_ior, f82_fss, fresnel_blend_fss, ior_from_f0,
                         microfacet_model, unit_rgb)


def principled(walker, node):
    if walker.ctx.at_least(4, 0):
        return principled_v2(walker, node)
    return principled_v1(walker, node)


# ----------------------------------------------------------------- 4.x, 5.x

def principled_v2(walker, node):
    w = walker
    ctx = w.ctx
    consumed = set()
    base, base_img, base_node = w.color(node, ('Base Color',), consumed)
    metallic = _clamp01(w.value(node, ('Metallic',), 0.0, consumed))
    roughness = _clamp01(w.value(node, ('Roughness',), 0.5, consumed))
    ior = max(w.value(node, ('IOR',), 1.5, consumed), 1e-5)
    alpha = _clamp01(w.value(node, ('Alpha',), 1.0, consumed))
    transmission = _clamp01(w.value(node, ('Transmission Weight',), 0.0, consumed))
    specular_level = max(w.value(node, ('Specular IOR Level',), 0.5, consumed), 0.0)
    spec_tint, _, _ = w.color(node, ('Specular Tint',), consumed, allow_image=False)
    spec_tint = np.maximum(spec_tint, 0.0)
    diffuse_roughness = _clamp01(w.value(node, ('Diffuse Roughness',), 0.0, consumed))
    subsurface = _clamp01(w.value(node, ('Subsurface Weight',), 0.0, consumed))
    sheen = max(w.value(node, ('Sheen Weight',), 0.0, consumed), 0.0)
    coat = max(w.value(node, ('Coat Weight',), 0.0, consumed), 0.0)
    emission, emission_img, _ = w.color(node, ('Emission Color',), consumed)
    emission_strength = w.value(node, ('Emission Strength',), 0.0, consumed)
    film = thin_film(w, node, consumed)
    model, _ = w.distribution(node)

    # What the core cannot render: said once, naming the inputs.
    ignored = []
    if w.value(node, ('Anisotropic',), 0.0, consumed) > WEIGHT_CUTOFF:
        ignored.append("Anisotropic")
    # Blender 5.3's thin walls and dispersion.
    if find_input(node, 'Thin Wall') is not None and w.value(node, ('Thin Wall',), 0.0, consumed) > 0.5:
        ignored.append("Thin Wall")
    if w.value(node, ('Transmission Dispersion Scale',), 0.0, consumed) > WEIGHT_CUTOFF:
        ignored.append("Transmission Dispersion")
    consumed |= {s.identifier for s in node.inputs
                 if s.name.startswith(("Anisotropic", "Subsurface", "Transmission Dispersion"))}
    for name in ('Normal', 'Coat Normal', 'Tangent'):
        socket = find_input(node, name)
        if socket is not None:
            consumed.add(socket.identifier)
            if socket.is_linked:
                ignored.append("%s (the surface's own normal is used)" % name)
    if subsurface > WEIGHT_CUTOFF:
        w.note(node, "Subsurface scattering is not supported; its share is rendered as a diffuse "
                     "of the Base Color (as Cycles does for tiny radii)")
    if emission_img is not None or (emission_strength != 0.0 and np.any(emission)):
        if sheen > WEIGHT_CUTOFF or coat > WEIGHT_CUTOFF:
            ignored.append("the dimming of Emission by Sheen and Coat")

    base_const = image_export.average_color(base_node, ctx) if base_img is not None else base
    base_unit = unit_rgb(base_const)
    if base_img is not None and (metallic > WEIGHT_CUTOFF or transmission > WEIGHT_CUTOFF):
        w.note(node, "metallic or transmission with an image Base Color uses the image's average colour")

    top, below = [], []   # the closures so far, and the weight left for the layers below
    weight = np.ones(3)
    if alpha < 1.0:
        top.append(Closure(core.PHOS_CLOSURE_TRANSPARENT, np.full(3, 1.0 - alpha)))
        weight = weight * alpha
    layers = []           # (closure, index in `top` where its children start)

    def add_layer(closure):
        top.append(closure)
        layers.append((closure, len(top)))

    if sheen > WEIGHT_CUTOFF:
        sheen_tint, _, _ = w.color(node, ('Sheen Tint',), consumed, allow_image=False)
        sheen_rel = sheen * np.maximum(sheen_tint, 0.0)
        add_layer(Closure(core.PHOS_CLOSURE_SHEEN, sheen_rel * weight,
                          roughness=_clamp01(w.value(node, ('Sheen Roughness',), 0.5, consumed)),
                          layer_weight=sheen_rel))

    if coat > WEIGHT_CUTOFF:
        coat_ior = max(w.value(node, ('Coat IOR',), 1.5, consumed), 1.0)
        coat_tint, _, _ = w.color(node, ('Coat Tint',), consumed, allow_image=False)
        f0 = f0_from_ior(coat_ior)
        # Cycles compensates the coat's energy whatever the distribution from 4.5.
        coat_model = (core.PHOS_MICROFACET_GGX_MULTISCATTER if ctx.at_least(4, 5)
                      else microfacet_model(ctx, 'GGX'))
        add_layer(Closure(core.PHOS_CLOSURE_REFLECTION_FRESNEL, coat * weight,
                          roughness=_clamp01(w.value(node, ('Coat Roughness',), 0.03, consumed)),
                          ior=coat_ior, specular_color=np.full(3, f0), microfacet=coat_model,
                          multiscatter_fresnel=np.full(3, min(max(dielectric_fss(coat_ior), 0.0), 1.0)),
                          layer_weight=np.full(3, coat), layer_tint=np.maximum(coat_tint, 0.0),
                          layer_tint_weight=coat))
    consumed |= {s.identifier for s in node.inputs if s.name.startswith(("Sheen", "Coat"))}

    emitted = emission * emission_strength
    if emission_img is not None or float(np.max(np.abs(emitted))) > 0.0:
        top.append(Closure(core.PHOS_CLOSURE_EMISSION, emitted * weight, emission_img))

    if metallic > WEIGHT_CUTOFF:
        tint = unit_rgb(spec_tint)
        top.append(Closure(core.PHOS_CLOSURE_METAL, metallic * weight, roughness=roughness, microfacet=model,
                           specular_color=base_unit, specular_tint=tint,
                           multiscatter_fresnel=f82_fss(base_unit, tint)))
        weight = weight * (1.0 - metallic)

    if transmission > WEIGHT_CUTOFF:
        refracted = np.sqrt(base_unit) if base_img is None else np.ones(3)
        glass_weight = transmission * weight
        if base_img is not None:
            glass_weight = glass_weight * base        # the image tints the glass (approximation)
        top.append(Closure(core.PHOS_CLOSURE_GLASS, glass_weight, base_img, roughness=roughness, ior=ior,
                           glass_fresnel=core.PHOS_GLASS_FRESNEL_MICROFACET, microfacet=model,
                           specular_tint=unit_rgb(spec_tint), transmission_tint=refracted,
                           multiscatter_fresnel=np.sqrt(base_unit), **film))
        weight = weight * (1.0 - transmission)

    # Specular IOR Level scales f0, and the IOR the specular's Fresnel curve follows.
    f0 = f0_from_ior(ior)
    eta = ior
    if specular_level != 0.5:
        f0 *= 2.0 * specular_level
        eta = ior_from_f0(f0)
        if ior < 1.0:
            eta = 1.0 / eta
    if eta != 1.0 or film:
        spec_f0 = np.clip(f0 * spec_tint, 0.0, 1.0)
        add_layer(Closure(core.PHOS_CLOSURE_REFLECTION_FRESNEL, weight.copy(), roughness=roughness, ior=eta,
                          specular_color=spec_f0, microfacet=model,
                          multiscatter_fresnel=fresnel_blend_fss(spec_f0, eta), layer_weight=np.ones(3), **film))

    if subsurface > WEIGHT_CUTOFF:
        top.append(Closure(core.PHOS_CLOSURE_DIFFUSE, base_unit * subsurface * weight if base_img is None
                           else base * subsurface * weight, base_img))
    diffuse_weight = (1.0 - subsurface) * weight
    if float(np.max(diffuse_weight)) > WEIGHT_CUTOFF:
        if diffuse_roughness >= 1e-5:
            albedo = np.ones(3) if base_img is not None else np.clip(base, 0.0, 1.0)
            top.append(Closure(core.PHOS_CLOSURE_OREN_NAYAR, base * diffuse_weight, base_img,
                               roughness=diffuse_roughness, specular_color=albedo,
                               specular_tint=oren_nayar_tint(ctx, base_const)))
        else:
            top.append(Closure(core.PHOS_CLOSURE_DIFFUSE, base * diffuse_weight, base_img))

    for closure, start in layers:
        closure.layer_children = top[start:]
    if ignored:
        w.note(node, "%s not supported; ignored" % ", ".join(ignored))
    w.check_unused_links(node, consumed)
    return top


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
    base, base_img, base_node = w.color(node, ('Base Color',), consumed)
    metallic = _clamp01(w.value(node, ('Metallic',), 0.0, consumed))
    roughness = _clamp01(w.value(node, ('Roughness',), 0.5, consumed))
    ior = max(w.value(node, ('IOR',), 1.45, consumed), 1e-5)
    transmission = _clamp01(w.value(node, ('Transmission',), 0.0, consumed))
    alpha = _clamp01(w.value(node, ('Alpha',), 1.0, consumed))
    emission, emission_img, _ = w.color(node, ('Emission',), consumed)
    emission_strength = w.value(node, ('Emission Strength',), 1.0, consumed)
    specular = max(w.value(node, ('Specular',), 0.5, consumed), 0.0)
    tint_scalar = _clamp01(w.value(node, ('Specular Tint',), 0.0, consumed))
    model, _ = w.distribution(node)

    # Parts of the Principled BSDF the core does not have: named once.
    ignored = []
    subsurface = w.value(node, ('Subsurface',), 0.0, consumed)
    if subsurface > WEIGHT_CUTOFF:
        ignored.append("Subsurface")
    if w.value(node, ('Sheen',), 0.0, consumed) > WEIGHT_CUTOFF:
        ignored.append("Sheen")
    if w.value(node, ('Clearcoat',), 0.0, consumed) > WEIGHT_CUTOFF:
        ignored.append("Clearcoat")
    if w.value(node, ('Anisotropic',), 0.0, consumed) > WEIGHT_CUTOFF:
        ignored.append("Anisotropic")
    transmission_roughness = w.value(node, ('Transmission Roughness',), 0.0, consumed)
    final_transmission = transmission * (1.0 - metallic)
    # Inputs that only matter for ignored features: not worth a second warning.
    consumed |= {s.identifier for s in node.inputs
                 if s.name.startswith(("Subsurface", "Sheen", "Clearcoat", "Anisotropic"))}
    if ignored:
        w.note(node, "%s not supported; ignored" % ", ".join(ignored))
    w.check_unused_links(node, consumed)

    # Colour used where the core needs a constant (specular f0, tint): the
    # image's average when the base colour is an image.
    base_const = image_export.average_color(base_node, w.ctx) if base_img is not None else base
    if base_img is not None and (metallic > WEIGHT_CUTOFF or tint_scalar > 0.0):
        w.note(node, "metallic/tinted specular with an image Base Color uses the image's average colour")

    closures = []
    diffuse_weight = (1.0 - metallic) * (1.0 - transmission)
    specular_weight = 1.0 - final_transmission

    if diffuse_weight > WEIGHT_CUTOFF:
        color, img = base, base_img
        if subsurface > WEIGHT_CUTOFF and img is None:
            # Closest to Cycles' subsurface albedo: the mixed subsurface colour.
            ss_color, _, _ = w.color(node, ('Subsurface Color',), consumed, allow_image=False)
            s = _clamp01(subsurface)
            color = ss_color * s + base * (1.0 - s)
        closures.append(Closure(core.PHOS_CLOSURE_PRINCIPLED_DIFFUSE, color * diffuse_weight, img,
                                roughness=roughness))

    if specular_weight > WEIGHT_CUTOFF and (specular > WEIGHT_CUTOFF or metallic > WEIGHT_CUTOFF):
        # IOR from Specular, f0 tinted towards the base hue.
        spec_ior = 2.0 / (1.0 - math.sqrt(min(0.08 * specular, 0.999999))) - 1.0
        lum = 0.3 * base_const[0] + 0.6 * base_const[1] + 0.1 * base_const[2]
        ctint = base_const / lum if lum > 0.0 else np.ones(3, dtype=np.float32)
        tmp = (1.0 - tint_scalar) + ctint * tint_scalar
        f0 = (specular * 0.08 * tmp) * (1.0 - metallic) + base_const * metallic
        closures.append(Closure(core.PHOS_CLOSURE_REFLECTION_FRESNEL, np.full(3, specular_weight),
                                roughness=roughness, ior=spec_ior, specular_color=f0, microfacet=model,
                                multiscatter_fresnel=fresnel_blend_fss(unit_rgb(f0), spec_ior)))

    if final_transmission > WEIGHT_CUTOFF:
        refraction_roughness = 1.0 - (1.0 - roughness) * (1.0 - _clamp01(transmission_roughness))
        if base_img is None:
            tint, weight = base, np.full(3, final_transmission)
        else:
            weight, tint = base * final_transmission, (1.0, 1.0, 1.0)
        multi = model == core.PHOS_MICROFACET_GGX_MULTISCATTER  # 3.x's random walk: Fresnel per microfacet
        closures.append(Closure(core.PHOS_CLOSURE_GLASS, weight, base_img, roughness=roughness,
                                ior=ior, glass_fresnel=core.PHOS_GLASS_FRESNEL_MICROFACET if multi
                                else core.PHOS_GLASS_FRESNEL_MACRO, transmission_tint=tint,
                                transmission_roughness=refraction_roughness, microfacet=model,
                                multiscatter_fresnel=unit_rgb(tint)))

    emitted = emission * emission_strength
    if emission_img is not None or float(np.max(np.abs(emitted))) > 0.0:
        closures.append(Closure(core.PHOS_CLOSURE_EMISSION, emitted, emission_img))

    if alpha < 1.0:
        # Cycles mixes the whole node (emission included) with a transparent BSDF.
        closures = [c.scale(alpha) for c in closures]
        closures.append(Closure(core.PHOS_CLOSURE_TRANSPARENT, np.full(3, 1.0 - alpha)))
    return closures
