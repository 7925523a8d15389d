/*
 * integrator_photon.c — rendering with photon maps (Jensen 1996, "Global
 * Illumination using Photon Maps"; Jensen 2001 ch. 9; course notes 2002,
 * "Rendering Equation Solution"). At a surface the BSDF splits into a
 * diffuse part f_d and the rest f_s, and the reflected radiance into
 *
 *   direct     ∫ f_r L_light cos      next-event estimation (f_s also by MIS
 *                                     with the ray traced through f_s)
 *   specular   ∫ f_s (L_c + L_d) cos  ray tracing: the camera path goes on
 *                                     through f_s and the same split recurs
 *   caustics   ∫ f_d L_c cos          the caustic map's radiance estimate
 *   indirect   ∫ f_d L_d cos          final gathering: stratified cosine rays
 *                                     read the precomputed radiance photons
 *                                     (Christensen 1999) where they land
 *
 * Gather rays add no emission, and the caustic map is read only on camera
 * paths, since the global map already holds caustic photons (ALGORITHMS.md
 * §5.1). With the fast estimate the global map is read directly at the
 * first diffuse hit, leaving out its direct and caustic photons, which the
 * other two terms already count.
 */
#include <string.h>

#include "embree.h"
#include "integrator.h"
#include "light.h"
#include "material.h"

#define GATHER_SPECULAR_BOUNCES 4   /* specular surfaces a gather ray passes before it reads a map */

static void add_to(sample_result *res, int component, vec3 beta, vec3 L, float w)
{
    res->component[component] = v3_madd(res->component[component], v3_mul(beta, L), w);
}

/* Next-event estimate at a vertex: the diffuse part unweighted (nothing
 * else samples it), the rest MIS-weighted against continuing through it. */
static vec3 direct_light(const scene *s, const surface *sf, const bsdf *bd, const bsdf *bs, vec3 wo,
                         const sampler *smp, uint32_t vertex)
{
    light_sample ls;
    float2 u = sampler_2d(smp, dim_bounce(vertex, DIM_LIGHT_POINT));
    if (!light_sample_pick(s, sf->p, sampler_1d(smp, dim_bounce(vertex, DIM_LIGHT_PICK)), u, &ls))
        return v3s(0.0f);
    float pdf_s = 0.0f;
    vec3 fd = bd->count ? bsdf_eval(bd, wo, ls.wi, NULL) : v3s(0.0f);
    vec3 fs = bs->count ? bsdf_eval(bs, wo, ls.wi, &pdf_s) : v3s(0.0f);
    float w = ls.delta ? 1.0f : mis_power_heuristic(ls.pdf, pdf_s);
    vec3 f = v3_madd(fd, fs, w);
    if (v3_is_zero(f))
        return f;
    vec3 T = shadow_transmittance(s, sf, ls.wi, ls.distance);
    return v3_scale(v3_mul(v3_mul(f, ls.radiance), T), 1.0f / ls.pdf);
}

/* Radiance leaving a gather hit toward the gather ray's origin: the
 * radiance photon there, after following specular surfaces. */
static vec3 gather_ray(const scene *s, const integrator_settings *is, vec3 o, vec3 d, integrator_scratch *scratch,
                       const sampler *g, uint32_t ray_index)
{
    vec3 beta = v3s(1.0f);
    float tmin = 0.0f;
    for (uint32_t bounce = 0; bounce <= GATHER_SPECULAR_BOUNCES; bounce++) {
        ray_hit h;
        if (!embree_intersect(s->bvh, o, d, tmin, INFINITY, 0, &h))
            return v3s(0.0f); /* the world is direct light, counted already */
        surface sf;
        surface_from_hit(s, h.instance, h.prim, h.b1, h.b2, d, &sf);
        bsdf b;
        material_bsdf(s, &sf, &b);
        if (b.count == 0)
            return v3s(0.0f);
        if (bsdf_has_non_delta(&b)) {
            vec3 L;
            if (is->maps->radiance.count)
                L = radiance_photon_lookup(&is->maps->radiance, sf.p, sf.ns, is->radiance_lookup_radius,
                                           &scratch->radiance);
            else
                L = photon_radiance(&is->maps->global, &b, v3_neg(d), sf.p, sf.ns, &is->global_estimate,
                                    &scratch->global);
            return v3_mul(beta, L);
        }
        /* A specular surface: follow it. */
        uint32_t dim = 2u * 4096u + ray_index * 8u + bounce * 3u;
        bsdf_sample bs;
        if (!bsdf_sample_direction(&b, v3_neg(d), sampler_1d(g, dim), sampler_2d(g, dim + 1), &bs))
            return v3s(0.0f);
        beta = v3_mul(beta, bs.weight);
        if (bs.flags & BSDF_TRANSPARENT) {
            tmin = t_after_hit(h.t);
            continue;
        }
        vec3 n = v3_dot(bs.wi, sf.ng) >= 0.0f ? sf.ng : v3_neg(sf.ng);
        o = offset_ray_origin(sf.p, n);
        d = bs.wi;
        tmin = 0.0f;
    }
    return v3s(0.0f);
}

/* Final gathering over the diffuse part: M×N cosine-stratified directions
 * θ_j = asin √((j+ξ)/M), φ_k = 2π(k+ψ)/N with N ≈ πM (Ward 1988; course
 * notes "Irradiance Sampling"), each weighted by f_d·π (the cosine pdf's
 * cos θ/π cancels the cosine of the integrand). */
static vec3 final_gather(const scene *s, const integrator_settings *is, const surface *sf, const bsdf *bd, vec3 wo,
                         const sampler *smp, uint32_t vertex, integrator_scratch *scratch)
{
    uint32_t total = is->final_gather_rays;
    uint32_t M = (uint32_t)(sqrtf((float)total / PHOS_PI) + 0.5f);
    if (M < 1)
        M = 1;
    uint32_t N = total / M;
    if (N < 1)
        N = 1;
    sampler g = sampler_split(smp, 0x9a7e0000u + vertex);
    frame f = frame_from_normal(sf->ns);
    vec3 o_up = offset_ray_origin(sf->p, sf->ng);
    vec3 sum = v3s(0.0f);
    uint32_t index = 0;
    for (uint32_t j = 0; j < M; j++) {
        for (uint32_t k = 0; k < N; k++, index++) {
            float2 u = sampler_2d(&g, 2u * index);
            float sin2 = ((float)j + u.x) / (float)M;
            float sin_t = sqrtf(sin2), cos_t = safe_sqrtf(1.0f - sin2);
            float phi = 2.0f * PHOS_PI * ((float)k + u.y) / (float)N;
            vec3 wi = frame_to_world(&f, v3(cosf(phi) * sin_t, sinf(phi) * sin_t, cos_t));
            if (v3_dot(wi, sf->ng) <= 0.0f || cos_t <= 0.0f)
                continue;
            vec3 fcos = bsdf_eval(bd, wo, wi, NULL);
            if (v3_is_zero(fcos))
                continue;
            vec3 Li = gather_ray(s, is, o_up, wi, scratch, &g, index);
            /* f·cos / (cos/π) = π·f */
            sum = v3_add(sum, v3_scale(v3_mul(fcos, Li), PHOS_PI / cos_t));
        }
    }
    return v3_scale(sum, 1.0f / (float)(M * N));
}

/* The diffuse part's caustic and indirect terms at a surface. */
static void diffuse_terms(const scene *s, const integrator_settings *is, const surface *sf, const bsdf *bd,
                          vec3 wo, const sampler *smp, uint32_t vertex, integrator_scratch *scratch, vec3 *caustics,
                          vec3 *indirect)
{
    const photon_maps *m = is->maps;
    *caustics = photon_radiance(&m->caustic, bd, wo, sf->p, sf->ns, &is->caustic_estimate, &scratch->caustic);
    if (is->fast_estimate) {
        estimate_params ep = is->global_estimate;
        ep.exclude_flags = PHOTON_DIRECT | PHOTON_CAUSTIC;
        *indirect = photon_radiance(&m->global, bd, wo, sf->p, sf->ns, &ep, &scratch->global);
    } else {
        *indirect = final_gather(s, is, sf, bd, wo, smp, vertex, scratch);
    }
}

sample_result photon_render(const scene *s, const integrator_settings *is, camera_ray ray, const sampler *smp,
                            integrator_scratch *scratch)
{
    sample_result res;
    memset(&res, 0, sizeof(res));
    vec3 beta = v3s(1.0f);
    vec3 o = ray.o, d = ray.d;
    float tmin = ray.tmin, tmax = ray.tmax;
    uint32_t depth = 0, vertex = 0;
    int camera_segment = 1, emission_only = 0, transparent_steps = 0;
    float prev_pdf = 0.0f;
    int prev_delta = 1;
    /* Emission found after `depth` scattering events on the (specular)
     * camera path: 0 emission, 1 direct, more: specular. */
#define EMISSION_COMPONENT (depth == 0 ? COMPONENT_EMISSION : depth == 1 ? COMPONENT_DIRECT : COMPONENT_SPECULAR)

    for (;;) {
        ray_hit h;
        int hit = embree_intersect(s->bvh, o, d, tmin, tmax, camera_segment, &h);
        light_hit lh;
        if (lights_intersect(s, o, d, hit ? h.t : tmax, camera_segment, &lh))
            add_to(&res, EMISSION_COMPONENT, beta, lh.radiance, prev_delta ? 1.0f : mis_power_heuristic(prev_pdf, lh.pdf));
        if (!hit) {
            if (!(camera_segment && is->transparent_background))
                add_to(&res, EMISSION_COMPONENT, beta, lights_escape(s, d, prev_pdf, prev_delta, camera_segment), 1.0f);
            if (camera_segment && !is->transparent_background)
                res.alpha = 1.0f;
            break;
        }
        surface sf;
        surface_from_hit(s, h.instance, h.prim, h.b1, h.b2, d, &sf);
        uint32_t v_index = vertex++;
        if (sf.mat->emissive) {
            float w = 1.0f;
            if (!prev_delta) {
                const instance *inst = &s->instances[sf.instance];
                int32_t li = inst->emitter_of_triangle ? inst->emitter_of_triangle[sf.prim] : -1;
                w = mis_power_heuristic(prev_pdf, light_pdf_triangle(s, li, o, sf.p, sf.ng));
            }
            add_to(&res, EMISSION_COMPONENT, beta, material_emission(s, &sf), w);
        }
        if (emission_only)
            break;
        bsdf b, bd, bs;
        material_bsdf(s, &sf, &b);
        if (b.count == 0) {
            if (camera_segment)
                res.alpha = 1.0f;
            break;
        }
        bsdf_split(&b, &bd, &bs);
        vec3 wo = v3_neg(d);
        int here = depth == 0; /* components of the first surface; deeper ones are specular */
        if (bsdf_has_non_delta(&b) && s->lights.count > 0)
            add_to(&res, here ? COMPONENT_DIRECT : COMPONENT_SPECULAR, beta,
                   direct_light(s, &sf, &bd, &bs, wo, smp, v_index), 1.0f);
        if (bd.count) {
            vec3 caustics, indirect;
            diffuse_terms(s, is, &sf, &bd, wo, smp, v_index, scratch, &caustics, &indirect);
            add_to(&res, here ? COMPONENT_CAUSTICS : COMPONENT_SPECULAR, beta, caustics, 1.0f);
            add_to(&res, here ? COMPONENT_INDIRECT : COMPONENT_SPECULAR, beta, indirect, 1.0f);
        }
        /* Go on through the specular and glossy part. */
        bsdf_sample bsmp;
        float u_pick = sampler_1d(smp, dim_bounce(v_index, DIM_BSDF_PICK));
        if (bs.count == 0 ||
            !bsdf_sample_direction(&bs, wo, u_pick, sampler_2d(smp, dim_bounce(v_index, DIM_BSDF_DIR)), &bsmp)) {
            if (camera_segment)
                res.alpha = 1.0f;
            break;
        }
        beta = v3_mul(beta, bsmp.weight);
        if (!v3_is_finite(beta) || v3_is_zero(beta))
            break;
        if (bsmp.flags & BSDF_TRANSPARENT) {
            if (++transparent_steps > 64)
                break;
            tmin = t_after_hit(h.t);
            continue;
        }
        if (camera_segment)
            res.alpha = 1.0f;
        camera_segment = 0;
        transparent_steps = 0;
        vec3 n = v3_dot(bsmp.wi, sf.ng) >= 0.0f ? sf.ng : v3_neg(sf.ng);
        o = offset_ray_origin(sf.p, n);
        d = bsmp.wi;
        tmin = 0.0f;
        tmax = INFINITY;
        prev_pdf = bsmp.pdf;
        prev_delta = (bsmp.flags & BSDF_DELTA) != 0;
        depth++;
        if (depth > is->max_bounces)
            emission_only = 1;
        if (depth >= 3) {
            float q = fminf(v3_max_component(beta), 1.0f);
            if (sampler_1d(smp, dim_bounce(v_index, DIM_ROULETTE)) >= q)
                break;
            beta = v3_scale(beta, 1.0f / q);
        }
    }
#undef EMISSION_COMPONENT
    return res;
}

void photon_debug_estimates(const scene *s, const integrator_settings *is, camera_ray ray,
                            integrator_scratch *scratch, sample_result *res)
{
    if (!is->maps)
        return;
    /* Follow the camera ray through specular surfaces (the first lobe the
     * sampler would pick is not needed: take the strongest delta lobe
     * deterministically via u = 0.5) to the first diffuse surface. */
    vec3 o = ray.o, d = ray.d, beta = v3s(1.0f);
    float tmin = ray.tmin, tmax = ray.tmax;
    for (int step = 0; step < 16; step++) {
        ray_hit h;
        if (!embree_intersect(s->bvh, o, d, tmin, tmax, 1, &h))
            return;
        surface sf;
        surface_from_hit(s, h.instance, h.prim, h.b1, h.b2, d, &sf);
        bsdf b, bd, bs;
        material_bsdf(s, &sf, &b);
        bsdf_split(&b, &bd, &bs);
        vec3 wo = v3_neg(d);
        if (bd.count) {
            res->photon_map = v3_mul(beta, photon_radiance(&is->maps->global, &bd, wo, sf.p, sf.ns, &is->global_estimate,
                                                           &scratch->global));
            res->caustic_map = v3_mul(beta, photon_radiance(&is->maps->caustic, &bd, wo, sf.p, sf.ns,
                                                            &is->caustic_estimate, &scratch->caustic));
            return;
        }
        bsdf_sample smp;
        if (bs.count == 0 || !bsdf_sample_direction(&bs, wo, 0.5f, (float2){0.5f, 0.5f}, &smp))
            return;
        beta = v3_mul(beta, smp.weight);
        if (smp.flags & BSDF_TRANSPARENT) {
            tmin = t_after_hit(h.t);
            continue;
        }
        vec3 n = v3_dot(smp.wi, sf.ng) >= 0.0f ? sf.ng : v3_neg(sf.ng);
        o = offset_ray_origin(sf.p, n);
        d = smp.wi;
        tmin = 0.0f;
        tmax = INFINITY;
    }
}
