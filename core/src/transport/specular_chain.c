/*
 * specular_chain.c — following specular and transparent surfaces
 * (specular_chain.h).
 */
#include "transport/specular_chain.h"

#include "lights/light.h"
#include "scene/embree.h"
#include "scene/ray.h"

/* Emitters on the first segment of a ray from o (hit: the surface at t_hit,
 * or the ray escaped), each weighted by the power heuristic between the
 * ray's pdf and the light sample's (Veach 1997 §9.2). */
static vec3 first_segment_emission(const scene *s, const specular_chain *c, vec3 o, vec3 d, float tmin,
                                   const ray_hit *hit, const surface *sf)
{
    float ray_pdf = c->first_pdf;
    const light_context *from = c->origin;
    vec3 E = v3s(0.0f);
    light_hit lh;
    if (lights_intersect(s, from, o, d, tmin, hit ? hit->t : INFINITY, 0, &lh))
        E = v3_madd(E, lh.radiance, mis_power_heuristic(ray_pdf, lh.pdf));
    if (!hit)
        return v3_add(E, lights_escape(s, from, d, ray_pdf, 0, 0));
    if (sf->mat->emissive) {
        const instance *inst = &s->instances[sf->instance];
        int32_t li = inst->emitter_of_triangle ? inst->emitter_of_triangle[sf->prim] : -1;
        float w = mis_power_heuristic(ray_pdf, light_pdf_triangle(s, li, from, sf->p, sf->ng));
        E = v3_madd(E, material_emission(s, sf), w);
    }
    return E;
}

/* Whether the chain stops at b; if not, *next is the part it goes on
 * through and *weight the factor of that choice. u_pick (in [0, 1)) is the
 * step's lobe choice: where b mixes closures that carry caustics with
 * others (STOP_AT_NON_CAUSTIC), u_pick < P_carry goes on through the
 * former, rescaled to pick among them, else the chain stops with weight
 * 1/(1 − P_carry) (end->read: the others). */
static int stops_here(const specular_chain *c, specular_chain_end *end, float *u_pick, bsdf *next, vec3 *weight)
{
    const bsdf *b = &end->b;
    *weight = v3s(1.0f);
    if (c->stop == STOP_AT_DIFFUSE) {
        bsdf diffuse;
        bsdf_split(b, &diffuse, next);
        end->read = *b;
        return diffuse.count > 0;
    }
    if (!bsdf_has_non_caustic(b, c->caustic_roughness)) {
        *next = *b;
        return 0;
    }
    float p_carry = bsdf_split_caustic(b, c->caustic_roughness, next, &end->read);
    if (!(p_carry > 0.0f))
        return 1;
    if (*u_pick < p_carry) {
        *u_pick = minf(*u_pick / p_carry, 0x1.fffffep-1f);
        *weight = v3s(1.0f / p_carry);
        return 0;
    }
    *weight = v3s(1.0f / (1.0f - p_carry));
    return 1;
}

int specular_chain_follow(const scene *s, const specular_chain *c, vec3 o, vec3 d, float tmin, float tmax,
                          specular_chain_end *out)
{
    vec3 beta = v3s(1.0f);
    out->emission = v3s(0.0f);
    out->first_distance = INFINITY;
    int first = c->first_pdf > 0.0f; /* still on the first segment: nothing but transparent surfaces passed */
    for (uint32_t step = 0; step < c->max_steps; step++) {
        ray_hit h;
        int hit = embree_intersect(s->bvh, o, d, tmin, tmax, c->coherent, &h);
        if (!hit) {
            if (first)
                out->emission = v3_add(out->emission, v3_mul(beta, first_segment_emission(s, c, o, d, tmin, NULL,
                                                                                          NULL)));
            return 0;
        }
        if (step == 0)
            out->first_distance = h.t;
        surface_from_hit(s, h.instance, h.prim, h.b1, h.b2, d, &out->sf);
        if (first)
            out->emission = v3_add(out->emission, v3_mul(beta, first_segment_emission(s, c, o, d, tmin, &h,
                                                                                      &out->sf)));
        material_bsdf(s, &out->sf, &out->b);
        if (out->b.count == 0)
            return 0;
        vec3 wo = v3_neg(d);
        float u_pick = 0.5f;
        float2 u = {0.5f, 0.5f};
        if (c->smp) {
            u_pick = sampler_1d(c->smp, c->dim + 3u * step);
            u = sampler_2d(c->smp, c->dim + 3u * step + 1u);
        }
        bsdf next;
        vec3 choice;
        if (stops_here(c, out, &u_pick, &next, &choice)) {
            out->beta = v3_mul(beta, choice);
            out->wo = wo;
            return 1;
        }
        /* Go on through the part that is not read here. */
        bsdf_sample bs;
        if (next.count == 0 || !bsdf_sample_direction(&next, wo, u_pick, u, &bs))
            return 0;
        beta = v3_mul(v3_mul(beta, choice), bs.weight);
        if (bs.flags & BSDF_TRANSPARENT) {
            tmin = t_after_hit(h.t);
            continue;
        }
        first = 0;
        o = ray_leave_surface(out->sf.p, out->sf.ng, bs.wi);
        d = bs.wi;
        tmin = 0.0f;
        tmax = INFINITY;
    }
    return 0;
}
