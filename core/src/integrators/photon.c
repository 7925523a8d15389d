/*
 * photon.c — PHOTON, rendering with photon maps (Jensen 1996, "Global
 * Illumination using Photon Maps"; Jensen 2001 ch. 9; course notes 2002,
 * "Rendering Equation Solution"): the diffuse-split policy at every vertex
 * (diffuse_split.c) with the photon maps behind it, and the maps' debug
 * estimates.
 */
#include "integrators/camera_path.h"
#include "photons/progressive_caustics.h"
#include "photons/radiance_estimate.h"
#include "transport/specular_chain.h"

#define DEBUG_CHAIN_STEPS 16   /* surfaces the debug passes follow from the camera */

void photon_render(const scene *s, const integrator_settings *is, camera_ray ray, const sampler *smp,
                   integrator_scratch *scratch, sample_result *res)
{
    camera_path_walk(s, is, ray, smp, scratch, diffuse_split_vertex_policy, res);
}

vec3 photon_caustic_radiance(const integrator_settings *is, const bsdf *b, vec3 wo, vec3 x, vec3 n,
                             integrator_scratch *scratch)
{
    if (is->progressive)
        return progressive_caustic_radiance(is->progressive, b, wo, x, n, &scratch->caustic);
    return photon_radiance(&is->maps->caustic, b, wo, x, n, &is->caustic_estimate, &scratch->caustic);
}

void photon_debug_estimates(const scene *s, const integrator_settings *is, camera_ray ray,
                            integrator_scratch *scratch, sample_result *res)
{
    if (!is->maps)
        return;
    /* Through specular and glossy surfaces, always along the lobe and
     * direction at u = 0.5, to the first diffuse surface. */
    specular_chain c = {STOP_AT_DIFFUSE, DEBUG_CHAIN_STEPS, 1, NULL, 0, 0.0f, NULL, 0.0f};
    specular_chain_end end;
    if (!specular_chain_follow(s, &c, ray.o, ray.d, ray.tmin, ray.tmax, &end))
        return;
    bsdf diffuse, rest;
    bsdf_split(&end.b, &diffuse, &rest);
    res->photon_map = v3_mul(end.beta, photon_radiance(&is->maps->global, &diffuse, end.wo, end.sf.p, end.sf.ns,
                                                       &is->global_estimate, &scratch->global));
    res->caustic_map = v3_mul(end.beta, photon_caustic_radiance(is, &diffuse, end.wo, end.sf.p, end.sf.ns, scratch));
}
