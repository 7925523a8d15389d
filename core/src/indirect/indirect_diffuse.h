/*
 * indirect_diffuse.h — the seam through which a camera-path vertex gets
 * the indirect light its diffuse part reflects,
 *
 *   L_indirect(x → wo) = ∫ f_d(x, wi, wo) L_i,indirect(x ← wi) cos θi dωi,
 *
 * where L_i,indirect leaves out light that reaches x from an emitter
 * through specular surfaces only (the caustic map counts it) or directly
 * (next-event estimation counts it; Jensen 1996, course notes 2002
 * "Rendering Equation Solution"; docs/algorithms.md §5). A provider whose
 * rays also see emitters returns their light separately, as its share of
 * the direct term under MIS (gather_estimate, gathers_emitters).
 *
 * Providers:
 *  - final gathering on the photon maps (PHOTON; final_gather.c);
 *  - the global photon map read at x itself (PHOTON's fast estimate);
 *  - the path-traced hemisphere (path_hemisphere.c): stratified rays, each
 *    continued as an unbiased path, the reference the others converge to.
 * The irradiance cache (Ward et al. 1988; irradiance_cache.h) wraps either
 * gather: it sends the gather's rays at its record positions and
 * interpolates between them.
 */
#ifndef PHOS_INDIRECT_DIFFUSE_H
#define PHOS_INDIRECT_DIFFUSE_H

#include "integrators/integrator.h"
#include "lights/light.h"
#include "shading/material.h"

/* Where and how an indirect estimate is asked for. */
typedef struct indirect_query {
    const scene *s;
    const integrator_settings *is;
    const surface *sf;
    const light_context *light; /* the surface as a receiver of light samples (light.h) */
    const bsdf *diffuse;        /* f_d: the diffuse closures of the surface's BSDF */
    vec3 wo;
    const sampler *smp;         /* the camera sample's */
    uint32_t vertex;            /* the camera-path vertex, for independent sample streams */
    uint32_t depth;             /* scattering events on the camera path before it */
    integrator_scratch *scratch;
} indirect_query;

/* Reflected radiance W/(m²·sr) toward q->wo from the diffuse part: from
 * light that scattered before (indirect), and, for providers whose rays
 * count emitters, from the emitters those rays reach directly, already
 * MIS-weighted (direct: it adds to the Direct component). Where no caustic
 * map counts the light that reaches the point from emitters through
 * specular surfaces only (is->gathers_find_caustics: PATH with the
 * irradiance cache), the gather's rays count it, apart (caustic).
 * As what one gather ray brings (hemisphere_incoming), the same fields are
 * radiance along the ray, and distance is how far the ray went to the
 * first surface it hit (INFINITY: none), which the irradiance cache's
 * records need (Ward et al. 1988). */
typedef struct gather_estimate {
    vec3 indirect, direct, caustic;
    float distance;
} gather_estimate;

#define GATHER_ESTIMATE_ZERO ((gather_estimate){{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, INFINITY})

/* Radiance W/(m²·sr) arriving at the query's point along wi from a ray
 * leaving o (a gather ray); g is the gather's sampler and ray_index the
 * ray's number (hemisphere.h). ray_pdf > 0: emitters the ray reaches on
 * its first segment count, with the MIS weight of a sample of pdf ray_pdf
 * (all the gather's rays together, gather_rays_pdf) against the light
 * sample of the diffuse part; 0: they are left out (the light sample
 * counts them alone). */
typedef gather_estimate (*hemisphere_incoming)(const indirect_query *q, vec3 o, vec3 wi, const sampler *g,
                                               uint32_t ray_index, float ray_pdf);

typedef struct indirect_diffuse_provider {
    const char *name;
    /* 1: the provider sends is->final_gather_rays cosine-distributed rays
     * (stratified, pdf cos θ/π each) that also count the emitters they
     * reach on their first segment, MIS-weighted against the light sample
     * of the diffuse part (Veach 1997 §9.2, multi-sample power heuristic):
     * direct_light weights that sample with the same rule. 0: emitters
     * reach the diffuse part only through the light sample. */
    int gathers_emitters;
    gather_estimate (*estimate)(const indirect_query *q);
    /* What one of its gather rays brings, for the irradiance cache's
     * records; NULL: the provider sends no rays. */
    hemisphere_incoming incoming;
} indirect_diffuse_provider;

extern const indirect_diffuse_provider indirect_final_gather;   /* final_gather.c */
extern const indirect_diffuse_provider indirect_photon_map;     /* final_gather.c */
extern const indirect_diffuse_provider indirect_path_hemisphere; /* path_hemisphere.c */
extern const indirect_diffuse_provider indirect_irradiance_cache; /* irradiance_cache_provider.c */


/* The provider of a photon view (enum phos_photon_view); path_hemisphere.c. */
const indirect_diffuse_provider *indirect_provider_for(uint32_t photon_view);

#endif /* PHOS_INDIRECT_DIFFUSE_H */
