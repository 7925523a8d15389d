/*
 * ggx_albedo.h — directional albedos of single-scattering GGX lobes, as
 * tables computed once per process by quadrature of the lobes themselves
 * (height-correlated Smith G, visible-normal sampling: microfacet.h).
 *
 * They serve two mechanisms of Cycles 4's shading model:
 *  - Multiscatter GGX: a single-scattering lobe loses the light that
 *    bounces between microfacets, 1 − E(μo) of it; Kulla & Conty 2017
 *    ("Revisiting Physically Based Shading at Imageworks") restore it, and
 *    Cycles 4 does so by albedo scaling: the lobe times
 *    1 + F_ms (1 − E)/E, with F_ms = F_ss E_avg / (1 − F_ss (1 − E_avg))
 *    the Fresnel of the multiply scattered light (docs/algorithms.md §8);
 *  - layering: the share of light a dielectric layer (Principled specular,
 *    coat) reflects toward the viewer, f0 + (1 − f0)·s, with s the mean
 *    Fresnel interpolation factor over the visible microfacets.
 *
 * μ is the cosine of the viewing direction to the normal, roughness is
 * Blender's (α = roughness²), eta the relative IOR of the interface.
 * Lookups interpolate linearly and clamp to the tables' ranges.
 */
#ifndef PHOS_GGX_ALBEDO_H
#define PHOS_GGX_ALBEDO_H

#include "util/vec.h"

/* E(μ): albedo of GGX reflection with F = 1. */
float ggx_albedo(float mu, float roughness);

/* E_avg = ∫ E(μ) 2μ dμ, the cosine-weighted mean over the hemisphere. */
float ggx_albedo_average(float roughness);

/* Albedo of the GGX dielectric (reflection + refraction, Fresnel per
 * microfacet, no 1/η² radiance scaling) seen from the side where the
 * relative IOR is eta (eta < 1: from inside). */
float ggx_glass_albedo(float mu, float roughness, float eta);
float ggx_glass_albedo_average(float roughness, float eta);

/* s(μ): the mean of fresnel_blend_factor(eta, wo·h) over the microfacets h
 * visible from wo, counting reflections below the horizon as 0 (Cycles'
 * estimate of a Fresnel-blended lobe's albedo, f0 + (1 − f0)·s, eta > 1). */
float ggx_fresnel_blend_average(float mu, float roughness, float eta);

/* The Multiscatter GGX factor 1 + F_ms (1 − E)/E for the lobe's E(μ),
 * E_avg and mean single-scattering Fresnel F_ss (per channel). */
vec3 ggx_multiscatter_scale(float E, float E_avg, vec3 F_ss);

#endif /* PHOS_GGX_ALBEDO_H */
