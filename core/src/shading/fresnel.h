/*
 * fresnel.h — the reflectance of an interface as a function of the cosine
 * of the incident angle: the exact dielectric Fresnel equations and the
 * artist-facing forms Cycles builds on them (Principled specular colour,
 * F82-tint metals), plus their hemispherical averages F_ss, which the
 * Multiscatter GGX energy compensation needs (docs/algorithms.md §8).
 *
 * eta is the relative IOR, transmitted side over incident side.
 */
#ifndef PHOS_FRESNEL_H
#define PHOS_FRESNEL_H

#include "util/vec.h"

/* Exact unpolarised Fresnel reflectance of a dielectric interface; 1 under
 * total internal reflection. */
float fresnel_dielectric(float cos_theta_i, float eta);

/* 1 − fresnel_dielectric, computed without cancellation at grazing angles. */
float fresnel_dielectric_transmittance(float cos_theta_i, float eta);

/* Reflectance at normal incidence, ((η − 1)/(η + 1))². */
float fresnel_f0_from_ior(float eta);

/* Principled specular colour (Cycles' "real Fresnel curve" interpolation):
 * the dielectric Fresnel of eta remapped from [F(0°), 1] to [f0, 1], so
 * that f0 sets normal incidence and every colour goes white at grazing.
 * With f0 = fresnel_f0_from_ior(eta) it is the dielectric Fresnel itself. */
vec3 fresnel_blend_f0(vec3 f0, float eta, float cos_theta);

/* The interpolation factor of fresnel_blend_f0, in [0, 1]. */
float fresnel_blend_factor(float eta, float cos_theta);

/* F82-tint metal (Kutz et al. 2021, "Novel aspects of the Adobe Standard
 * Material"; Hoffman 2019): Schlick's f0 + (1 − f0)(1 − μ)⁵ minus
 * b μ (1 − μ)⁶, with b chosen so that at μ = 1/7 (about 82°) the value is
 * Schlick's times `tint`; clamped to [0, 1]. */
vec3 fresnel_f82_b(vec3 f0, vec3 tint);
vec3 fresnel_f82(vec3 f0, vec3 b, float cos_theta);

/* Thin-film interference (Belcour & Barla 2017, "A Practical Extension to
 * Microfacet Theory for the Modeling of Varying Iridescence"): the RGB
 * reflectance of a film of index film_ior and thickness_nm over a
 * substrate of relative index substrate_eta (both relative to the outside),
 * seen at cos_theta; 1 under total internal reflection. */
#define THIN_FILM_MIN_THICKNESS 0.1f /* nm; thinner films are ignored (as Cycles) */
vec3 fresnel_thin_film(float cos_theta, float film_ior, float substrate_eta, float thickness_nm);

/* The Principled form: fresnel_thin_film over a substrate of IOR eta, each
 * channel scaled toward f0 / F0(eta) near normal incidence so that f0
 * (Specular Tint, Specular IOR Level) still acts on the film. */
vec3 fresnel_thin_film_blend(vec3 f0, float eta, float cos_theta, float film_ior, float thickness_nm);

#endif /* PHOS_FRESNEL_H */
