/*
 * hemisphere.h — the stratified hemisphere over a diffuse surface point,
 * shared by every gather of indirect light (final gathering, the
 * path-traced hemisphere, and the irradiance cache's records): M×N strata
 * θ_j = asin √((j+ξ)/M), φ_k = 2π(k+ψ)/N with N ≈ πM (Ward et al. 1988;
 * course notes 2002, "Irradiance Sampling"; docs/algorithms.md §5.2).
 */
#ifndef PHOS_HEMISPHERE_H
#define PHOS_HEMISPHERE_H

#include "integrators/indirect_diffuse.h"

/* The dimension plan of a gather. The gather's sampler g is split off the
 * camera sample's by the vertex; in g, ray i's direction takes dimensions
 * 2i and 2i + 1 and nothing else. Whatever a ray does after it leaves (a
 * specular chain, a path) draws from its own stream,
 * sampler_split(g, HEMISPHERE_RAY_STREAM + i), from dimension 0 on, so no
 * two rays and no two steps of one ray share a dimension, whatever the
 * number of rays or steps. */
#define HEMISPHERE_RAY_STREAM 0x4a7b0000u

/* Radiance W/(m²·sr) arriving at the query's point along wi from a ray
 * leaving o; g is the gather's sampler and ray_index the ray's number.
 * Emitters the ray reaches on its first segment count with the MIS weight
 * of a sample of pdf ray_pdf (all the gather's rays together,
 * gather_rays_pdf) against the light sample of the diffuse part. */
typedef gather_estimate (*hemisphere_incoming)(const indirect_query *q, vec3 o, vec3 wi, const sampler *g,
                                               uint32_t ray_index, float ray_pdf);

/* The M×N strata the gather makes of `rays` requested: M = round(√(rays/π)),
 * N = ⌊rays/M⌋, so M·N may be a little less than rays. MIS weights against
 * the gather must count these, not the request. */
void hemisphere_strata(uint32_t rays, uint32_t *M, uint32_t *N);
static inline uint32_t hemisphere_ray_count(uint32_t rays)
{
    uint32_t M, N;
    hemisphere_strata(rays, &M, &N);
    return M * N;
}

/* ∫ f_d L_i cos dω over the query's hemisphere with `rays` cosine-stratified
 * rays, each weighted by f_d·π (the cosine pdf's cos θ/π cancels the cosine
 * of the integrand). */
gather_estimate hemisphere_gather(const indirect_query *q, uint32_t rays, hemisphere_incoming incoming);

#endif /* PHOS_HEMISPHERE_H */
