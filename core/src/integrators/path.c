/*
 * path.c — PATH, the reference integrator: unbiased path tracing with
 * next-event estimation at every non-delta vertex, combined with BSDF
 * sampling by the power heuristic (Veach 1997, ch. 9). The walk itself
 * (roulette, transparency, bounce counting as Cycles) is camera_path.c.
 *
 * At a vertex the whole BSDF is both light-sampled and followed, so the
 * indirect light of its diffuse part is the path-traced hemisphere with
 * one sample: the path's own continuation. With the irradiance cache
 * (is->indirect set), the diffuse part's indirect light comes from the
 * cache instead and the path goes on through the rest of the BSDF only:
 * Ward's method (Ward et al. 1988; diffuse_split.c).
 */
#include "integrators/camera_path.h"
#include "transport/direct_light.h"

const bsdf *path_vertex_policy(camera_path *p, const path_vertex *v, bsdf *storage)
{
    (void)storage;
    if (bsdf_has_non_delta(v->b) && p->s->lights.count > 0)
        camera_path_add_direct(p, direct_light(p->s, v->light, v->sf, v->b, NULL, 0, v->wo, p->smp, v->index));
    return v->b;
}

void path_trace(const scene *s, const integrator_settings *is, camera_ray ray, const sampler *smp,
                integrator_scratch *scratch, sample_result *res)
{
    camera_path_walk(s, is, ray, smp, scratch, is->indirect ? diffuse_split_vertex_policy : path_vertex_policy, res);
}
