/*
 * photon.c — PHOTON, rendering with photon maps (Jensen 1996, "Global
 * Illumination using Photon Maps"; Jensen 2001 ch. 9; course notes 2002,
 * "Rendering Equation Solution"). At a surface the BSDF splits into a
 * diffuse part f_d and the rest f_s, and the reflected radiance into
 *
 *   direct     ∫ f_r L_light cos      next-event estimation (f_s also by MIS
 *                                     with the ray traced through f_s)
 *   specular   ∫ f_s (L_c + L_d) cos  ray tracing: the camera path goes on
 *                                     through f_s and the same split recurs
 *   caustics   ∫ f_d L_c cos          the caustic map's radiance estimate
 *   indirect   ∫ f_d L_d cos          the indirect-diffuse provider: final
 *                                     gathering, or the global map read here
 *
 * The caustic map is read only on camera paths, since the global map (and
 * so every gather) already holds caustic photons (docs/algorithms.md §5).
 * The walk is camera_path.c; this file is the policy at a vertex.
 */
#include "integrators/camera_path.h"
#include "integrators/direct_light.h"
#include "integrators/hemisphere.h"
#include "integrators/indirect_diffuse.h"
#include "integrators/specular_chain.h"
#include "photons/radiance_estimate.h"

#define DEBUG_CHAIN_STEPS 16   /* surfaces the debug passes follow from the camera */

static const bsdf *photon_vertex_policy(camera_path *p, const path_vertex *v, bsdf *rest)
{
    const scene *s = p->s;
    const integrator_settings *is = p->is;
    bsdf diffuse;
    bsdf_split(v->b, &diffuse, rest);
    /* The rays the gather really sends (its M×N strata), for the MIS weights. */
    uint32_t gather_rays = is->indirect->gathers_emitters ? hemisphere_ray_count(is->final_gather_rays) : 0;
    if (diffuse.count && !gather_rays)
        v->light->rays_find_world = 0; /* the map's estimate of the diffuse part does not count it */
    if (bsdf_has_non_delta(v->b) && s->lights.count > 0)
        camera_path_add_direct(p, direct_light(s, v->light, v->sf, rest, &diffuse, gather_rays, v->wo, p->smp,
                                               v->index));
    if (diffuse.count) {
        vec3 caustics = photon_radiance(&is->maps->caustic, &diffuse, v->wo, v->sf->p, v->sf->ns,
                                        &is->caustic_estimate, &p->scratch->caustic);
        indirect_query q = {s, is, v->sf, v->light, &diffuse, v->wo, p->smp, v->index, p->depth, p->scratch};
        gather_estimate g = is->indirect->estimate(&q);
        camera_path_add_diffuse(p, 1, caustics);
        camera_path_add_diffuse(p, 0, g.indirect);
        camera_path_add_direct(p, g.direct);
    }
    /* Go on through the specular and glossy part. */
    return rest->count ? rest : NULL;
}

sample_result photon_render(const scene *s, const integrator_settings *is, camera_ray ray, const sampler *smp,
                            integrator_scratch *scratch)
{
    return camera_path_walk(s, is, ray, smp, scratch, photon_vertex_policy);
}

void photon_debug_estimates(const scene *s, const integrator_settings *is, camera_ray ray,
                            integrator_scratch *scratch, sample_result *res)
{
    if (!is->maps)
        return;
    /* Through specular and glossy surfaces, always along the lobe and
     * direction at u = 0.5, to the first diffuse surface. */
    specular_chain c = {STOP_AT_DIFFUSE, DEBUG_CHAIN_STEPS, 1, NULL, 0, 0.0f, NULL};
    specular_chain_end end;
    if (!specular_chain_follow(s, &c, ray.o, ray.d, ray.tmin, ray.tmax, &end))
        return;
    bsdf diffuse, rest;
    bsdf_split(&end.b, &diffuse, &rest);
    res->photon_map = v3_mul(end.beta, photon_radiance(&is->maps->global, &diffuse, end.wo, end.sf.p, end.sf.ns,
                                                       &is->global_estimate, &scratch->global));
    res->caustic_map = v3_mul(end.beta, photon_radiance(&is->maps->caustic, &diffuse, end.wo, end.sf.p, end.sf.ns,
                                                        &is->caustic_estimate, &scratch->caustic));
}
