/*
 * direct_light.h — next-event estimation: light reaching a surface point
 * straight from an emitter, with a shadow ray, MIS-weighted against BSDF
 * sampling by the power heuristic (Veach 1997, ch. 9). In transport/,
 * below the integrators and the indirect-diffuse providers that call it
 * (docs/architecture.md).
 */
#ifndef PHOS_DIRECT_LIGHT_H
#define PHOS_DIRECT_LIGHT_H

#include "lights/light.h"
#include "sampling/sampler.h"
#include "shading/material.h"

/* Fraction of light reaching surface point sf from direction wi over
 * distance dist: 0 or 1 for opaque occluders, the product of transparent
 * weights through Transparent closures. */
vec3 shadow_transmittance(const scene *s, const surface *sf, vec3 wi, float dist);

/* Reflected radiance toward wo (W/(m²·sr)) from one light sample at vertex
 * `vertex` of a path, picked for the receiver c (light.h), plus one of the
 * uniform world, which is sampled apart (light_pick.c).
 *
 * `sampled` is the part of the BSDF the path continues through: its light
 * is MIS-weighted, since the ray that leaves through it can also find the
 * emitter. `unsampled` (NULL: none) is a part the path does not continue
 * through (the diffuse part under photon mapping): with gather_rays = 0
 * the light sample is its only estimate and stays unweighted; otherwise
 * gather_rays cosine-distributed rays about the shading normal also count
 * the emitters they reach, and the light sample is weighted against them
 * (indirect_diffuse.h). */
vec3 direct_light(const scene *s, const light_context *c, const surface *sf, const bsdf *sampled,
                  const bsdf *unsampled, uint32_t gather_rays, vec3 wo, const sampler *smp, uint32_t vertex);

/* Solid-angle pdf of a gather ray of a stratified cosine hemisphere about
 * sf's shading normal, times the number of rays: the MIS weight's
 * denominator for emitters that gather rays reach (hemisphere.c). */
float gather_rays_pdf(const surface *sf, vec3 wi, uint32_t gather_rays);

#endif /* PHOS_DIRECT_LIGHT_H */
