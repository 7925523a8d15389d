/*
 * diffuse_split.c — the vertex policy that splits the BSDF into its
 * diffuse part f_d and the rest f_s (Jensen 1996; course notes 2002,
 * "Rendering Equation Solution"), which PHOTON uses everywhere and PATH
 * with the irradiance cache (Ward et al. 1988):
 *
 *   direct     ∫ f_r L_light cos      next-event estimation (f_s also by MIS
 *                                     with the ray traced through f_s)
 *   specular   ∫ f_s (L_c + L_d) cos  ray tracing: the camera path goes on
 *                                     through f_s and the same split recurs
 *   caustics   ∫ f_d L_c cos          the caustic map's radiance estimate, or
 *                                     where there is none the provider's rays
 *   indirect   ∫ f_d L_d cos          the indirect-diffuse provider
 *
 * The caustic map is read only on camera paths, since the global map (and
 * so every gather) already holds caustic photons (docs/algorithms.md §5).
 * It is read through the glossy receivers too (rough glossy reflection,
 * bsdf.h): ∫ f_g L_c cos, the course's "caustics on glossy surfaces",
 * which a path through f_g cannot find from a point, spot or sun lamp and
 * finds as fireflies from a small area lamp. The path still goes on
 * through f_g for the rest of its light and leaves out what the map
 * counted (camera_path.c, count_caustics_once).
 */
#include "indirect/hemisphere.h"
#include "indirect/indirect_diffuse.h"
#include "integrators/camera_path.h"
#include "photons/radiance_estimate.h"
#include "transport/direct_light.h"

/* The light sample's share of the part the path goes on through: its
 * closures that carry caustics count only the light no receiver before
 * has counted (camera_path.c, count_caustics_once). */
static vec3 direct_light_once(const camera_path *p, const path_vertex *v, const bsdf *rest, const bsdf *diffuse,
                              uint32_t gather_rays)
{
    const bsdf *sampled = rest;
    bsdf scaled;
    if (!v3_is_zero(p->caustic_counted)) {
        scaled = *rest;
        bsdf_scale_caustic_carriers(&scaled, p->is->caustic_roughness, v3_sub(v3s(1.0f), p->caustic_counted));
        sampled = &scaled;
    }
    return direct_light(p->s, v->light, v->sf, sampled, diffuse, gather_rays, v->wo, p->smp, v->index);
}

const bsdf *diffuse_split_vertex_policy(camera_path *p, const path_vertex *v, bsdf *rest)
{
    const scene *s = p->s;
    const integrator_settings *is = p->is;
    bsdf diffuse;
    bsdf_split(v->b, &diffuse, rest);
    /* The rays the gather really sends (its M×N strata), for the MIS weights. */
    uint32_t gather_rays = is->indirect->gathers_emitters ? hemisphere_ray_count(is->final_gather_rays) : 0;
    if (bsdf_has_non_delta(v->b) && s->lights.count > 0)
        camera_path_add_direct(p, direct_light_once(p, v, rest, &diffuse, gather_rays));
    if (diffuse.count) {
        indirect_query q = {s, is, v->sf, v->light, &diffuse, v->wo, p->smp, v->index, p->depth, p->scratch};
        gather_estimate g = is->indirect->estimate(&q);
        if (is->gathers_find_caustics)
            camera_path_add_diffuse(p, 1, g.caustic);
        camera_path_add_diffuse(p, 0, g.indirect);
        camera_path_add_direct(p, g.direct);
    }
    if (!is->gathers_find_caustics) {
        bsdf receivers;
        bsdf_caustic_receivers(v->b, is->caustic_roughness, &receivers);
        /* With caustic_reads, the first vertex's estimate is made by the
         * pixel's first samples only and averaged over them (render.c); it
         * still counts for this sample's later vertices (reads_caustics),
         * since the pixel's caustics include it. */
        int shared = is->caustic_reads && p->depth == 0;
        if (receivers.count && (!shared || p->smp->index < is->caustic_reads)) {
            vec3 L = photon_caustic_radiance(is, &receivers, v->wo, v->sf->p, v->sf->ns, p->scratch);
            if (shared)
                p->res->caustic_read = v3_madd(p->res->caustic_read, v3_mul(p->beta, L), 1.0f);
            else
                camera_path_add_diffuse(p, 1, L);
        }
        p->reads_caustics = 1;
    }
    /* Go on through the specular and glossy part. */
    return rest->count ? rest : NULL;
}
