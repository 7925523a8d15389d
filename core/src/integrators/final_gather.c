/*
 * final_gather.c — indirect diffuse light from the photon maps: final
 * gathering (Jensen 1996; Jensen 2001 §9.3.2) over precomputed radiance
 * photons (Christensen 1999), or the global map's estimate read at the
 * surface itself (the fast estimate).
 */
#include "integrators/hemisphere.h"
#include "integrators/indirect_diffuse.h"
#include "integrators/specular_chain.h"
#include "photons/radiance_estimate.h"

#define GATHER_SPECULAR_BOUNCES 4   /* specular surfaces a gather ray passes before it reads a map */

/* Radiance arriving along a gather ray: the radiance photon where it lands
 * after following specular surfaces, plus the emitters its first segment
 * reaches, MIS-weighted against the light sample (indirect_diffuse.h).
 * Emission found through specular surfaces is a caustic, which the
 * caustic map counts. */
static gather_estimate gather_ray(const indirect_query *q, vec3 o, vec3 d, const sampler *g, uint32_t ray_index,
                                  float ray_pdf)
{
    const integrator_settings *is = q->is;
    /* Each ray's chain draws from a stream of its own (hemisphere.h's
     * dimension plan), so no two rays or steps share a dimension. */
    sampler chain_smp = sampler_split(g, HEMISPHERE_RAY_STREAM + ray_index);
    specular_chain c = {STOP_AT_NON_DELTA, GATHER_SPECULAR_BOUNCES + 1, 0, &chain_smp, 0, ray_pdf};
    specular_chain_end end;
    if (!specular_chain_follow(q->s, &c, o, d, 0.0f, INFINITY, &end))
        return (gather_estimate){v3s(0.0f), end.emission}; /* escaped: the world and lamps it saw */
    bsdf diffuse, rest;
    bsdf_split(&end.b, &diffuse, &rest);
    vec3 L = v3s(0.0f);
    if (diffuse.count &&
        !(is->maps->radiance.count && radiance_photon_lookup(&is->maps->radiance, end.sf.p, end.sf.ns,
                                                             is->radiance_lookup_radius, &q->scratch->radiance, &L)))
        /* No radiance photon faces this way nearby (sparse photons, or no
         * precomputation): the global map's estimate on the fly, through
         * the diffuse part as a radiance photon would have it. */
        L = photon_radiance(&is->maps->global, &diffuse, end.wo, end.sf.p, end.sf.ns, &is->global_estimate,
                            &q->scratch->global);
    /* A radiance photon holds only diffuse reflection. What the glossy lobes
     * reflect toward the gather ray (a lamp seen in rough metal) comes from
     * the global map's estimate through them (Jensen 2001 §9.3: the photon
     * map's estimate is consistent for glossy BSDFs too). */
    if (bsdf_has_non_delta(&rest))
        L = v3_add(L, photon_radiance(&is->maps->global, &rest, end.wo, end.sf.p, end.sf.ns, &is->global_estimate,
                                      &q->scratch->global));
    return (gather_estimate){v3_mul(end.beta, L), end.emission};
}

/* Final gathering: the stratified hemisphere of gather rays. */
static gather_estimate final_gather(const indirect_query *q)
{
    return hemisphere_gather(q, q->is->final_gather_rays, gather_ray);
}

/* The global map's estimate at the surface, leaving out its direct and
 * caustic photons, which next-event estimation and the caustic map count. */
static gather_estimate photon_map_estimate(const indirect_query *q)
{
    estimate_params ep = q->is->global_estimate;
    ep.exclude_flags = PHOTON_DIRECT | PHOTON_CAUSTIC;
    vec3 L = photon_radiance(&q->is->maps->global, q->diffuse, q->wo, q->sf->p, q->sf->ns, &ep, &q->scratch->global);
    return (gather_estimate){L, v3s(0.0f)};
}

const indirect_diffuse_provider indirect_final_gather = {"final gather", 1, final_gather};
const indirect_diffuse_provider indirect_photon_map = {"photon map", 0, photon_map_estimate};

