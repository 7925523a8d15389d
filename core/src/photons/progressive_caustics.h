/*
 * progressive_caustics.h — stochastic progressive photon mapping for the
 * caustic map (Hachisuka & Jensen 2009, "Stochastic Progressive Photon
 * Mapping"), in the form of Knaus & Zwicker 2011 ("Progressive Photon
 * Mapping: A Probabilistic Approach"): every sample i of a pixel reads a
 * caustic map of its own, traced for that sample alone, with a radius
 * that shrinks from sample to sample,
 *
 *     R_i² = R_0² · Π_{j=1..i} (j + α)/(j + 1)   (∝ i^(α−1)),
 *
 * and the pixel's caustics are the mean of these fixed-radius estimates.
 * Each estimate's bias is the blur of a disc of radius R_i and its
 * variance grows as 1/R_i²; averaged over n samples, both fall to zero
 * (variance as n^(−α), bias as n^(α−1)), so the caustics converge to
 * the exact image as samples grow, where a fixed k nearest photons leaves
 * a blur no number of samples removes (docs/algorithms.md §4.6).
 *
 * R_0 adapts to the photon density at each point without biasing the
 * estimate: it is the distance of the k-th nearest photon in the map of
 * the sample before (a pilot map for sample 0), which is independent of
 * the map the estimate sums.
 */
#ifndef PHOS_PROGRESSIVE_CAUSTICS_H
#define PHOS_PROGRESSIVE_CAUSTICS_H

#include "photons/photon_trace.h"
#include "shading/bsdf.h"

typedef struct progressive_caustics {
    photon_maps maps[2];          /* this sample's map and the one before, alternating */
    const photon_map *current;    /* the estimates sum its photons */
    const photon_map *previous;   /* its k nearest set R_0 */
    float shrink;                 /* R_i / R_0 for this sample */
    float alpha;                  /* Knaus & Zwicker's α in (0, 1) */
    uint32_t k;                   /* photons within R_0 */
    float max_radius;             /* R_0 where fewer than k lie within it, scene units */
    const struct phos_scene *clip; /* the scene whose walls cut the discs (radiance_estimate.h) */
    photon_trace_settings trace;  /* for every sample's map: no global map, its own count */
    projection_map aim;           /* every sample's caustic photons are aimed by it (photon_trace.h) */
    int aim_built;
    uint32_t sample;              /* the sample whose map is current; UINT32_MAX before the first */
    uint64_t photons_traced;      /* stored over all samples so far, for the progress line */
} progressive_caustics;

/* Settings from the render's photon settings (ps: seed, threads, bounces,
 * roughness), photons per sample, α, k and the largest radius. */
void progressive_caustics_init(progressive_caustics *pc, const photon_trace_settings *ps, uint32_t photons,
                               float alpha, uint32_t k, float max_radius);
void progressive_caustics_free(progressive_caustics *pc);

/* Makes sample i's map current: traces and builds it (and the pilot map
 * before sample 0, or when i does not follow the last sample). Each map
 * depends only on the scene, the settings and i. PHOS_ERROR_CANCELLED
 * soon after *cancel is set. */
phos_status progressive_caustics_begin_sample(progressive_caustics *pc, const scene *s, uint32_t i,
                                              atomic_int *cancel);

/* The shrink factor R_i/R_0 of sample i for α. */
float progressive_caustics_shrink(uint32_t i, float alpha);

/* The caustic radiance W/(m²·sr) reflected toward wo through b at x (n on
 * wo's side), for the current sample; q holds at least k results. */
vec3 progressive_caustic_radiance(const progressive_caustics *pc, const bsdf *b, vec3 wo, vec3 x, vec3 n,
                                  kdtree_query *q);

#endif /* PHOS_PROGRESSIVE_CAUSTICS_H */
