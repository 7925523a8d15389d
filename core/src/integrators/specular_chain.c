/*
 * specular_chain.c — following specular and transparent surfaces
 * (specular_chain.h).
 */
#include "integrators/specular_chain.h"

#include "scene/embree.h"
#include "scene/ray.h"

static int stops_here(const specular_chain *c, const bsdf *b, bsdf *diffuse, bsdf *rest)
{
    if (c->stop == STOP_AT_NON_DELTA)
        return bsdf_has_non_delta(b);
    bsdf_split(b, diffuse, rest);
    return diffuse->count > 0;
}

int specular_chain_follow(const scene *s, const specular_chain *c, vec3 o, vec3 d, float tmin, float tmax,
                          specular_chain_end *out)
{
    vec3 beta = v3s(1.0f);
    for (uint32_t step = 0; step < c->max_steps; step++) {
        ray_hit h;
        if (!embree_intersect(s->bvh, o, d, tmin, tmax, c->coherent, &h))
            return 0;
        surface_from_hit(s, h.instance, h.prim, h.b1, h.b2, d, &out->sf);
        material_bsdf(s, &out->sf, &out->b);
        if (out->b.count == 0)
            return 0;
        bsdf diffuse, rest;
        vec3 wo = v3_neg(d);
        if (stops_here(c, &out->b, &diffuse, &rest)) {
            out->beta = beta;
            out->wo = wo;
            return 1;
        }
        /* Go on through the part that is not read here. */
        const bsdf *next = c->stop == STOP_AT_NON_DELTA ? &out->b : &rest;
        bsdf_sample bs;
        float u_pick = 0.5f;
        float2 u = {0.5f, 0.5f};
        if (c->smp) {
            u_pick = sampler_1d(c->smp, c->dim + 3u * step);
            u = sampler_2d(c->smp, c->dim + 3u * step + 1u);
        }
        if (next->count == 0 || !bsdf_sample_direction(next, wo, u_pick, u, &bs))
            return 0;
        beta = v3_mul(beta, bs.weight);
        if (bs.flags & BSDF_TRANSPARENT) {
            tmin = t_after_hit(h.t);
            continue;
        }
        o = ray_leave_surface(out->sf.p, out->sf.ng, bs.wi);
        d = bs.wi;
        tmin = 0.0f;
        tmax = INFINITY;
    }
    return 0;
}
