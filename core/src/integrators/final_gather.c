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

/* Radiance leaving a gather hit toward the gather ray's origin: the
 * radiance photon there, after following specular surfaces. Gather rays
 * add no emission: light found through specular surfaces only is direct
 * light or a caustic, counted by next-event estimation and the caustic map. */
static vec3 gather_ray(const indirect_query *q, vec3 o, vec3 d, const sampler *g, uint32_t ray_index)
{
    const integrator_settings *is = q->is;
    /* Each ray's chain draws from a stream of its own (hemisphere.h's
     * dimension plan), so no two rays or steps share a dimension. */
    sampler chain_smp = sampler_split(g, HEMISPHERE_RAY_STREAM + ray_index);
    specular_chain c = {STOP_AT_NON_DELTA, GATHER_SPECULAR_BOUNCES + 1, 0, &chain_smp, 0};
    specular_chain_end end;
    if (!specular_chain_follow(q->s, &c, o, d, 0.0f, INFINITY, &end))
        return v3s(0.0f); /* the world is direct light, counted already */
    vec3 L;
    if (is->maps->radiance.count &&
        radiance_photon_lookup(&is->maps->radiance, end.sf.p, end.sf.ns, is->radiance_lookup_radius,
                               &q->scratch->radiance, &L))
        return v3_mul(end.beta, L);
    /* No radiance photon faces this way nearby (sparse photons, or no
     * precomputation): the global map's estimate on the fly, through the
     * diffuse part as a radiance photon would have it. */
    bsdf diffuse, rest;
    bsdf_split(&end.b, &diffuse, &rest);
    L = photon_radiance(&is->maps->global, &diffuse, end.wo, end.sf.p, end.sf.ns, &is->global_estimate,
                        &q->scratch->global);
    return v3_mul(end.beta, L);
}

/* Final gathering: the stratified hemisphere of gather rays. */
static vec3 final_gather(const indirect_query *q)
{
    return hemisphere_gather(q, q->is->final_gather_rays, gather_ray);
}

/* The global map's estimate at the surface, leaving out its direct and
 * caustic photons, which next-event estimation and the caustic map count. */
static vec3 photon_map_estimate(const indirect_query *q)
{
    estimate_params ep = q->is->global_estimate;
    ep.exclude_flags = PHOTON_DIRECT | PHOTON_CAUSTIC;
    return photon_radiance(&q->is->maps->global, q->diffuse, q->wo, q->sf->p, q->sf->ns, &ep, &q->scratch->global);
}

const indirect_diffuse_provider indirect_final_gather = {"final gather", final_gather};
const indirect_diffuse_provider indirect_photon_map = {"photon map", photon_map_estimate};

