/*
 * path_hemisphere.c — indirect diffuse light by the path-traced hemisphere:
 * the stratified gather rays of final gathering, each continued as an
 * unbiased path (PATH's vertex policy) instead of reading a photon map.
 * This is the reference every biased provider converges to, and with an
 * irradiance cache around it, Ward's original method (Ward et al. 1988).
 */
#include "integrators/camera_path.h"
#include "indirect/hemisphere.h"

/* Radiance arriving along a gather ray: the sum of the components of an
 * indirect-only walk, which weights the emitters of its first segment
 * against the light sample there and leaves out the caustics the caustic
 * map counts at the gather's point, or files them apart where no caustic
 * map does (is->gathers_find_caustics). */
static gather_estimate path_traced_ray(const indirect_query *q, vec3 o, vec3 wi, const sampler *g, uint32_t ray_index,
                                       float ray_pdf)
{
    sampler ray_smp = sampler_split(g, HEMISPHERE_RAY_STREAM + ray_index); /* hemisphere.h */
    sample_result r;
    camera_path_walk_indirect(q->s, q->is, q->light, o, wi, q->depth + 1, ray_pdf, q->is->gathers_find_caustics,
                              &ray_smp, q->scratch, path_vertex_policy, &r);
    /* The walk files what its first segment sees as its Emission and the
     * caustics as its Caustics. */
    gather_estimate out = GATHER_ESTIMATE_ZERO;
    for (int c = COMPONENT_EMISSION + 1; c < COMPONENT_COUNT; c++)
        if (c != COMPONENT_CAUSTICS)
            out.indirect = v3_add(out.indirect, r.component[c]);
    out.direct = r.component[COMPONENT_EMISSION];
    out.caustic = r.component[COMPONENT_CAUSTICS];
    out.distance = r.first_distance;
    return out;
}

static gather_estimate path_hemisphere(const indirect_query *q)
{
    return hemisphere_gather(q, q->is->final_gather_rays, path_traced_ray, 1);
}

const indirect_diffuse_provider indirect_path_hemisphere = {"path-traced hemisphere", 1, path_hemisphere,
                                                            path_traced_ray};

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
