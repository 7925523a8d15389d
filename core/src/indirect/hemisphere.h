/*
 * hemisphere.h — the stratified hemisphere over a diffuse surface point,
 * shared by every gather of indirect light (final gathering, the
 * path-traced hemisphere, and the irradiance cache's records): M×N strata
 * θ_j = asin √((j+ξ)/M), φ_k = 2π(k+ψ)/N with N ≈ πM (Ward et al. 1988;
 * course notes 2002, "Irradiance Sampling"; docs/algorithms.md §5.2).
 */
#ifndef PHOS_HEMISPHERE_H
#define PHOS_HEMISPHERE_H

#include "indirect/indirect_diffuse.h"

/* The dimension plan of a gather. The gather's sampler g is split off the
 * camera sample's by the vertex; in g, ray i's direction takes dimensions
 * 2i and 2i + 1 and nothing else. Whatever a ray does after it leaves (a
 * specular chain, a path) draws from its own stream,
 * sampler_split(g, HEMISPHERE_RAY_STREAM + i), from dimension 0 on, so no
 * two rays and no two steps of one ray share a dimension, whatever the
 * number of rays or steps. */
#define HEMISPHERE_RAY_STREAM 0x4a7b0000u

/* The sampler of the gather at the query's vertex, split off the camera
 * sample's (or the irradiance record's) own. */
#define HEMISPHERE_GATHER_STREAM 0x9a7e0000u

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

/* The direction, in the frame of the normal, of stratum (j, k) of M×N at
 * the jitter u: θ = asin √((j + u.x)/M), φ = 2π(k + u.y)/N. */
static inline vec3 hemisphere_stratum_direction(uint32_t j, uint32_t k, uint32_t M, uint32_t N, float2 u)
{
    float sin2 = ((float)j + u.x) / (float)M;
    float sin_t = sqrtf(sin2), cos_t = sqrtf(fmaxf(1.0f - sin2, 0.0f));
    float phi = 2.0f * PHOS_PI * ((float)k + u.y) / (float)N;
    return v3(cosf(phi) * sin_t, sinf(phi) * sin_t, cos_t);
}

/* The one loop over a hemisphere's strata, for every gather that stands on
 * it: for each of the M×N strata of `rays` (index = j·N + k), the jittered
 * direction wi (world space) and its cosine to the normal, in the frame of
 * the query's shading normal, from the gather's own sampler g (dimensions
 * 2·index and 2·index + 1). Strata whose direction lies below the
 * geometric or the shading surface are left out (their light is zero and
 * they see no surface). A cancel stops the walk within a row of strata,
 * a few hundred rays at most: it then returns 0 and the caller discards
 * what it gathered. */
typedef struct hemisphere_ray {
    uint32_t index; /* stratum j·N + k */
    vec3 wi;        /* world space, unit */
    float cos_t;    /* wi · the shading normal, > 0 */
    vec3 origin;    /* where the ray leaves: the point lifted off the surface */
} hemisphere_ray;
typedef void (*hemisphere_visit)(void *ctx, const indirect_query *q, const hemisphere_ray *ray, const sampler *g);
int hemisphere_walk(const indirect_query *q, uint32_t M, uint32_t N, hemisphere_visit visit, void *ctx);

/* ∫ f_d L_i cos dω over the query's hemisphere with `rays` cosine-stratified
 * rays, each weighted by f_d·π (the cosine pdf's cos θ/π cancels the cosine
 * of the integrand). count_emitters: the rays count the emitters their
 * first segment reaches, MIS-weighted (indirect_diffuse.h); 0: they leave
 * them to the light sample. */
gather_estimate hemisphere_gather(const indirect_query *q, uint32_t rays, hemisphere_incoming incoming,
                                  int count_emitters);

#endif /* PHOS_HEMISPHERE_H */
