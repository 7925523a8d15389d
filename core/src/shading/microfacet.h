/*
 * microfacet.h — the GGX (Trowbridge-Reitz) microfacet model, isotropic
 * (α) and anisotropic (αx along the local x axis, the closure's tangent;
 * αy along y): normal distribution, Smith masking, visible-normal sampling
 * and the change of variables from half vectors to scattered directions.
 *
 * Everything here works in the local shading frame (z = macro normal) on
 * unit vectors; the caller (bsdf.c) decides which lobes exist and applies
 * Fresnel and colour. wo is the direction toward the viewer with wo.z > 0.
 *
 * References:
 *   Walter, Marschner, Li, Torrance 2007, "Microfacet Models for Refraction
 *     through Rough Surfaces" (EGSR): D, G, the refraction half vector and
 *     the Jacobians (eq. 14, 16, 17, 33, 34).
 *   Heitz 2014, "Understanding the Masking-Shadowing Function in
 *     Microfacet-Based BRDFs" (JCGT 3(2)): Λ (eq. 72), separable and
 *     height-correlated G (eq. 98, 99), visible normals D_wo (eq. 16),
 *     anisotropic D and Λ (eq. 85, 86).
 *   Heitz 2018, "Sampling the GGX Distribution of Visible Normals"
 *     (JCGT 7(4)): the exact sampler of D_wo.
 *   Heitz, d'Eon 2014, "Importance Sampling Microfacet-Based BSDFs using
 *     the Distribution of Visible Normals" (EGSR): D_wo sampled through
 *     the slopes of the stretched α = 1 surface.
 *   Jakob 2014, "An Improved Visible Normal Sampling Routine for the
 *     Beckmann Distribution" (technical note): the slope CDF inverted by
 *     safeguarded Newton steps.
 *   Giles 2010, "Approximating the erfinv function" (GPU Computing Gems,
 *     Jade Edition): erf⁻¹ in single precision.
 */
#ifndef PHOS_MICROFACET_H
#define PHOS_MICROFACET_H

#include "sampling/sampler.h"
#include "util/vec.h"

/* GGX distribution of normals D(h) (1/sr, projected so ∫ D(h) h.z dω = 1)
 * for a unit half vector h with h.z > 0; 0 otherwise. */
float ggx_D(vec3 h, float alpha);

/* Smith Λ(w) for GGX (dimensionless); uses |w.z| so it also serves
 * directions below the surface (transmission). */
float ggx_lambda(vec3 w, float alpha);

/* Smith masking G1(w) = 1 / (1 + Λ(w)). */
float ggx_G1(vec3 w, float alpha);

/* Separable masking-shadowing G1(wo)·G1(wi): what Cycles up to 3.4 uses. */
float ggx_G_separable(vec3 wo, vec3 wi, float alpha);

/* Height-correlated masking-shadowing 1 / (1 + Λ(wo) + Λ(wi)): Cycles 3.5+. */
float ggx_G_correlated(vec3 wo, vec3 wi, float alpha);

/* Samples a half vector h from the distribution of normals visible from wo
 * (wo.z > 0), D_wo(h) = G1(wo)·max(0, wo·h)·D(h) / wo.z. */
vec3 ggx_sample_visible_normal(vec3 wo, float alpha, float2 u);

/* The density D_wo(h) of ggx_sample_visible_normal (1/sr of h). */
float ggx_visible_normal_pdf(vec3 wo, vec3 h, float alpha);

/* The anisotropic forms of the above: D, Λ, G and the visible normals
 * with roughness ax along x and ay along y; equal to them at ax = ay. */
float ggx_D_aniso(vec3 h, float ax, float ay);
float ggx_lambda_aniso(vec3 w, float ax, float ay);
float ggx_G_separable_aniso(vec3 wo, vec3 wi, float ax, float ay);
float ggx_G_correlated_aniso(vec3 wo, vec3 wi, float ax, float ay);
vec3 ggx_sample_visible_normal_aniso(vec3 wo, float ax, float ay, float2 u);
float ggx_visible_normal_pdf_aniso(vec3 wo, vec3 h, float ax, float ay);

/* Beckmann (Walter 2007 eq. 25, 27), anisotropic as GGX above: D; Λ by
 * Walter's rational approximation (as Cycles), for the BSDF's value; the
 * exact Λ (erf form), for the sampler's density; a sampler of the visible
 * normals D_wo(h) = G1(wo)·max(0, wo·h)·D(h) / wo.z (Heitz & d'Eon 2014,
 * Jakob 2014) and its density (1/sr of h), with the exact G1. Smith G
 * from Λ as for GGX: 1/((1 + Λo)(1 + Λi)) or 1/(1 + Λo + Λi). */
float beckmann_D_aniso(vec3 h, float ax, float ay);
float beckmann_lambda_aniso(vec3 w, float ax, float ay);
float beckmann_lambda_exact_aniso(vec3 w, float ax, float ay);
vec3 beckmann_sample_visible_normal_aniso(vec3 wo, float ax, float ay, float2 u);
float beckmann_visible_normal_pdf_aniso(vec3 wo, vec3 h, float ax, float ay);

/* erf⁻¹(x) for x in (−1, 1), single precision (Giles 2010); x is clamped
 * to ±(1 − 2⁻²⁴). */
float erfinvf_approx(float x);

/* Ashikhmin-Shirley (2000), Cycles' ASHIKHMIN_SHIRLEY: the Phong exponent
 * n = 2/α² − 2 of α (clamped to [1e-4, 1] as Cycles); the density p(h)
 * of half vectors (eq. 2, 6) and its sampler (eq. 9), exponents nx along
 * x and ny along y. */
float ashikhmin_shirley_exponent(float alpha);
float ashikhmin_shirley_h_pdf(vec3 h, float nx, float ny);
vec3 ashikhmin_shirley_sample_h(float nx, float ny, float2 u);

/* Half vector of a reflection pair, normalize(wo + wi); 0 if degenerate. */
int microfacet_reflect_half_vector(vec3 wo, vec3 wi, vec3 *h);

/* Generalized half vector of a refraction pair (Walter 2007 eq. 16) with
 * eta = η_wi-side / η_wo-side, oriented to h.z > 0. Returns 0 when no
 * microfacet refracts wo into wi (needs wo·h > 0 > wi·h). */
int microfacet_refract_half_vector(vec3 wo, vec3 wi, float eta, vec3 *h);

/* |dω_h / dω_i| for reflection: 1 / (4 |wo·h|) (Walter 2007 eq. 14). */
float microfacet_reflect_jacobian(vec3 wo, vec3 h);

/* |dω_h / dω_i| for refraction: η² |wi·h| / (wo·h + η wi·h)²
 * (Walter 2007 eq. 17, with wo the viewer side). */
float microfacet_refract_jacobian(vec3 wo, vec3 wi, vec3 h, float eta);

#endif /* PHOS_MICROFACET_H */
