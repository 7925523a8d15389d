/*
 * path_hemisphere.c — indirect diffuse light by the path-traced hemisphere:
 * the stratified gather rays of final gathering, each continued as an
 * unbiased path (PATH's vertex policy) instead of reading a photon map.
 * This is the reference every biased provider converges to, and with an
 * irradiance cache around it, Ward's original method (Ward et al. 1988).
 */
#include "integrators/camera_path.h"
#include "integrators/hemisphere.h"

/* Radiance arriving along a gather ray: the sum of the components of an
 * indirect-only walk, which leaves out the caustics the caustic map counts
 * at the gather's point and weights the emitters of its first segment
 * against the light sample there. */
static gather_estimate path_traced_ray(const indirect_query *q, vec3 o, vec3 wi, const sampler *g, uint32_t ray_index,
                                       float ray_pdf)
{
    sampler ray_smp = sampler_split(g, HEMISPHERE_RAY_STREAM + ray_index); /* hemisphere.h */
    sample_result r = camera_path_walk_indirect(q->s, q->is, q->light, o, wi, q->depth + 1, ray_pdf, &ray_smp, q->scratch,
                                                path_vertex_policy);
    /* The walk files what its first segment sees as its Emission. */
    vec3 L = v3s(0.0f);
    for (int c = COMPONENT_EMISSION + 1; c < COMPONENT_COUNT; c++)
        L = v3_add(L, r.component[c]);
    return (gather_estimate){L, r.component[COMPONENT_EMISSION]};
}

static gather_estimate path_hemisphere(const indirect_query *q)
{
    return hemisphere_gather(q, q->is->final_gather_rays, path_traced_ray);
}

const indirect_diffuse_provider indirect_path_hemisphere = {"path-traced hemisphere", 1, path_hemisphere};

const indirect_diffuse_provider *indirect_provider_for(uint32_t photon_view)
{
    switch (photon_view) {
    case PHOS_PHOTON_VIEW_FAST:
        return &indirect_photon_map;
    case PHOS_PHOTON_VIEW_PATH_TRACED:
        return &indirect_path_hemisphere;
    default:
        return &indirect_final_gather;
    }
}
