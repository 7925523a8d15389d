/*
 * sheen.h — the microfiber sheen of Cycles 4's Principled BSDF (Zeltner,
 * Burley & Chiang 2022, "Practical Multiple-Scattering Sheen Using Linearly
 * Transformed Cosines"): the light a layer of fibres scatters back, as a
 * Linearly Transformed Cosine (Heitz et al. 2016) whose two parameters and
 * albedo are tabulated over the view angle and the sheen roughness
 * (sheen_table.c, fitted here by tools/fit_sheen_ltc.py).
 *
 * Directions are in the local shading frame (z = normal); wo is toward the
 * viewer, wi toward the light. The lobe's frame turns with wo: its x axis
 * is wo's projection onto the surface.
 */
#ifndef PHOS_SHEEN_H
#define PHOS_SHEEN_H

#include "sampling/sampler.h"
#include "util/vec.h"

/* The directional albedo R(μo) of the sheen layer (the closure's weight is
 * scaled by it). */
float sheen_albedo(float mu, float roughness);

/* The normalised lobe D(wi) = cos θ'/π |M⁻¹| / |M⁻¹ wi|³ (1/sr, cosine
 * included): its own sampling density, and the BSDF·cos divided by R. */
float sheen_eval(vec3 wo, vec3 wi, float roughness);

/* Samples wi with density sheen_eval(wo, wi, roughness). */
vec3 sheen_sample(vec3 wo, float roughness, float2 u);

#endif /* PHOS_SHEEN_H */
