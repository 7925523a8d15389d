/*
 * layering.h — the directional albedo of a specular layer, for layered
 * materials: Cycles 4's Principled BSDF scales its base (diffuse) by
 * 1 − the albedo of the dielectric specular on top, seen from the viewer
 * (Cycles' closure_layering_weight; Kulla & Conty 2017, "Revisiting
 * Physically Based Shading at Imageworks").
 */
#ifndef PHOS_LAYERING_H
#define PHOS_LAYERING_H

#include "util/vec.h"

/* Directional albedo E(wo) = ∫ f cos θi dωi of the REFLECTION_FRESNEL lobe
 * (GGX, Fresnel blended from f0 to 1 by the dielectric Fresnel of eta) for
 * cos θo = mu, Blender roughness r; per channel of f0. Tabulated on first
 * use (thread-safe), linear in f0, trilinear in (mu, r, eta). */
vec3 specular_layer_albedo(float mu, float roughness, float eta, vec3 f0);

#endif /* PHOS_LAYERING_H */
