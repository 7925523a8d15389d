/*
 * direct_light.c — next-event estimation and shadow rays (direct_light.h).
 */
#include "transport/direct_light.h"

#include "lights/light.h"
#include "scene/embree.h"
#include "scene/ray.h"

#define SHADOW_MAX_TRANSPARENT_STEPS 64
/* The world's own light sample (light_pick.c) draws from a sampler
 * split off the path's, at the light-point dimensions of its vertex, so it
 * is stratified over the pixel's samples apart from the picked light's. */
#define WORLD_SAMPLE_STREAM 0x3f1d0000u

vec3 shadow_transmittance(const scene *s, const surface *sf, vec3 wi, float dist)
{
    vec3 o = ray_leave_surface(sf->p, sf->ng, wi);
    float tmax = isfinite(dist) ? dist * (1.0f - 1e-4f) : INFINITY;
    if (!s->has_transparency)
        return embree_occluded(s->bvh, o, wi, 0.0f, tmax) ? v3s(0.0f) : v3s(1.0f);
    vec3 T = v3s(1.0f);
    float tmin = 0.0f;
    for (int step = 0; step < SHADOW_MAX_TRANSPARENT_STEPS; step++) {
        ray_hit h;
        if (!embree_intersect(s->bvh, o, wi, tmin, tmax, 0, &h))
            return T;
        surface occ;
        surface_from_hit(s, h.instance, h.prim, h.b1, h.b2, wi, &occ);
        occ.ray_flags = SHADER_RAY_SHADOW;
        T = v3_mul(T, material_transparency(s, &occ));
        if (v3_is_zero(T))
            return T;
        tmin = t_after_hit(h.t);
    }
    return v3s(0.0f);
}

float gather_rays_pdf(const surface *sf, vec3 wi, uint32_t gather_rays)
{
    float c = v3_dot(wi, sf->ns);
    if (c <= 0.0f || v3_dot(wi, sf->ng) <= 0.0f) /* the gather never sends such a ray */
        return 0.0f;
    return (float)gather_rays * c * PHOS_INV_PI;
}

/* One light sample's estimate (see direct_light). */
static vec3 light_sample_estimate(const scene *s, const light_sample *ls, const surface *sf, const bsdf *sampled,
                                  const bsdf *unsampled, uint32_t gather_rays, vec3 wo)
{
    float pdf_sampled = 0.0f;
    vec3 f_sampled = sampled->count ? bsdf_eval(sampled, wo, ls->wi, &pdf_sampled) : v3s(0.0f);
    float w = ls->delta ? 1.0f : mis_power_heuristic(ls->pdf, pdf_sampled);
    if (!unsampled) {
        /* f·L·T·w/pdf */
        if (v3_is_zero(f_sampled))
            return f_sampled;
        vec3 T = shadow_transmittance(s, sf, ls->wi, ls->distance);
        if (v3_is_zero(T))
            return T;
        return v3_scale(v3_mul(v3_mul(f_sampled, ls->radiance), T), w / ls->pdf);
    }
    /* (w_u·f_u + w·f_s)·L·T/pdf */
    vec3 f_unsampled = unsampled->count ? bsdf_eval(unsampled, wo, ls->wi, NULL) : v3s(0.0f);
    if (gather_rays && !ls->delta)
        f_unsampled = v3_scale(f_unsampled, mis_power_heuristic(ls->pdf, gather_rays_pdf(sf, ls->wi, gather_rays)));
    vec3 f = v3_madd(f_unsampled, f_sampled, w);
    if (v3_is_zero(f))
        return f;
    vec3 T = shadow_transmittance(s, sf, ls->wi, ls->distance);
    return v3_scale(v3_mul(v3_mul(f, ls->radiance), T), 1.0f / ls->pdf);
}

vec3 direct_light(const scene *s, const light_context *c, const surface *sf, const bsdf *sampled,
                  const bsdf *unsampled, uint32_t gather_rays, vec3 wo, const sampler *smp, uint32_t vertex)
{
    vec3 sum = v3s(0.0f);
    light_sample ls;
    float2 u = sampler_2d(smp, dim_bounce(vertex, DIM_LIGHT_POINT));
    if (light_sample_pick(s, c, sampler_1d(smp, dim_bounce(vertex, DIM_LIGHT_PICK)), u, &ls))
        sum = light_sample_estimate(s, &ls, sf, sampled, unsampled, gather_rays, wo);
    if (light_world_apart(&s->lights, c)) {
        sampler world = sampler_split(smp, WORLD_SAMPLE_STREAM);
        if (light_sample_world(s, c, sampler_2d(&world, dim_bounce(vertex, DIM_LIGHT_POINT)), &ls))
            sum = v3_add(sum, light_sample_estimate(s, &ls, sf, sampled, unsampled, gather_rays, wo));
    }
    return sum;
}
