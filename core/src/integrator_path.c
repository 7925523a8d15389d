/*
 * integrator_path.c — the reference integrator: unbiased path tracing with
 * next-event estimation at every non-delta vertex, combined with BSDF
 * sampling by the power heuristic (Veach 1997, ch. 9), and Russian
 * roulette (Arvo & Kirk 1990) after three bounces.
 *
 * Bounce counting follows Cycles: with max_bounces = N the path has at
 * most N scattering events after the camera hit; the ray leaving the last
 * vertex is still traced so that emission it finds completes the MIS pair
 * of that vertex's next-event estimate. Transparent pass-through is not a
 * bounce and keeps the ray's origin, so MIS pdfs stay those of the vertex
 * the ray left.
 */
#include <string.h>

#include "embree.h"
#include "integrator.h"
#include "light.h"
#include "material.h"

#define MAX_TRANSPARENT_STEPS 64
#define ROULETTE_START_DEPTH 3

static inline uint32_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof(u));
    return u;
}
static inline float bits_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof(f));
    return f;
}

static float offset_component(float p, float n)
{
    const float origin = 1.0f / 32.0f;
    const float float_scale = 1.0f / 65536.0f;
    const float int_scale = 256.0f;
    if (fabsf(p) < origin)
        return p + float_scale * n;
    int32_t of = (int32_t)(int_scale * n);
    int32_t bits = (int32_t)float_bits(p);
    bits += (p < 0.0f) ? -of : of;
    return bits_float((uint32_t)bits);
}

vec3 offset_ray_origin(vec3 p, vec3 n)
{
    return v3(offset_component(p.x, n.x), offset_component(p.y, n.y), offset_component(p.z, n.z));
}

/* Fraction of light that reaches p from direction wi over distance dist:
 * 0 or 1 for opaque occluders, the product of transparent weights through
 * Transparent closures. */
vec3 shadow_transmittance(const scene *s, const surface *sf, vec3 wi, float dist)
{
    vec3 n = v3_dot(wi, sf->ng) >= 0.0f ? sf->ng : v3_neg(sf->ng);
    vec3 o = offset_ray_origin(sf->p, n);
    float tmax = isfinite(dist) ? dist * (1.0f - 1e-4f) : INFINITY;
    if (!s->has_transparency)
        return embree_occluded(s->bvh, o, wi, 0.0f, tmax) ? v3s(0.0f) : v3s(1.0f);
    vec3 T = v3s(1.0f);
    float tmin = 0.0f;
    for (int step = 0; step < MAX_TRANSPARENT_STEPS; step++) {
        ray_hit h;
        if (!embree_intersect(s->bvh, o, wi, tmin, tmax, 0, &h))
            return T;
        surface occ;
        surface_from_hit(s, h.instance, h.prim, h.b1, h.b2, wi, &occ);
        T = v3_mul(T, material_transparency(s, &occ));
        if (v3_is_zero(T))
            return T;
        tmin = t_after_hit(h.t);
    }
    return v3s(0.0f);
}

/* Next-event estimate of direct light at a vertex, MIS-weighted against
 * BSDF sampling. */
static vec3 estimate_direct(const scene *s, const surface *sf, const bsdf *b, vec3 wo, const sampler *smp,
                            uint32_t vertex)
{
    light_sample ls;
    float2 u = sampler_2d(smp, dim_bounce(vertex, DIM_LIGHT_POINT));
    if (!light_sample_pick(s, sf->p, sampler_1d(smp, dim_bounce(vertex, DIM_LIGHT_PICK)), u, &ls))
        return v3s(0.0f);
    float bsdf_pdf;
    vec3 f = bsdf_eval(b, wo, ls.wi, &bsdf_pdf);
    if (v3_is_zero(f))
        return v3s(0.0f);
    vec3 T = shadow_transmittance(s, sf, ls.wi, ls.distance);
    if (v3_is_zero(T))
        return T;
    float w = ls.delta ? 1.0f : mis_power_heuristic(ls.pdf, bsdf_pdf);
    return v3_scale(v3_mul(v3_mul(f, ls.radiance), T), w / ls.pdf);
}

/* Which component a contribution belongs to, from the scattering events on
 * its path: how many, whether the first was diffuse, and whether all the
 * later ones were delta lobes. */
static int classify(uint32_t events, int first_diffuse, int later_delta)
{
    if (events == 0)
        return COMPONENT_EMISSION;
    if (events == 1)
        return COMPONENT_DIRECT;
    if (!first_diffuse)
        return COMPONENT_SPECULAR;
    return later_delta ? COMPONENT_CAUSTICS : COMPONENT_INDIRECT;
}

static void add_to(sample_result *res, int component, vec3 beta, vec3 L, float w)
{
    res->component[component] = v3_madd(res->component[component], v3_mul(beta, L), w);
}

sample_result path_trace(const scene *s, const integrator_settings *is, camera_ray ray, const sampler *smp,
                         integrator_scratch *scratch)
{
    (void)scratch;
    sample_result res;
    memset(&res, 0, sizeof(res));
    int first_diffuse = 0, later_delta = 1; /* path type so far (classify) */
    vec3 beta = v3s(1.0f);                     /* path throughput */
    vec3 o = ray.o, d = ray.d;
    float tmin = ray.tmin, tmax = ray.tmax;
    uint32_t depth = 0;                        /* scattering events so far */
    int camera_segment = 1;                    /* still on the camera ray (through transparency) */
    int emission_only = 0;                     /* past max_bounces: collect emission, then stop */
    float prev_pdf = 0.0f;
    int prev_delta = 1;                        /* the camera ray takes emission unweighted */
    int transparent_steps = 0;
    uint32_t vertex = 0;                       /* surface interactions, for sample dimensions */

    for (;;) {
        ray_hit h;
        int hit = embree_intersect(s->bvh, o, d, tmin, tmax, camera_segment, &h);
        float t_hit = hit ? h.t : tmax;

        light_hit lh;
        if (lights_intersect(s, o, d, t_hit, camera_segment, &lh)) {
            float w = prev_delta ? 1.0f : mis_power_heuristic(prev_pdf, lh.pdf);
            add_to(&res, classify(depth, first_diffuse, later_delta), beta, lh.radiance, w);
        }
        if (!hit) {
            if (!(camera_segment && is->transparent_background))
                add_to(&res, classify(depth, first_diffuse, later_delta), beta,
                       lights_escape(s, d, prev_pdf, prev_delta, camera_segment), 1.0f);
            if (camera_segment && !is->transparent_background)
                res.alpha = 1.0f;
            break;
        }

        surface sf;
        surface_from_hit(s, h.instance, h.prim, h.b1, h.b2, d, &sf);
        uint32_t v_index = vertex++;
        if (sf.mat->emissive) {
            vec3 Le = material_emission(s, &sf);
            float w = 1.0f;
            if (!prev_delta) {
                const instance *inst = &s->instances[sf.instance];
                int32_t li = inst->emitter_of_triangle ? inst->emitter_of_triangle[sf.prim] : -1;
                w = mis_power_heuristic(prev_pdf, light_pdf_triangle(s, li, o, sf.p, sf.ng));
            }
            add_to(&res, classify(depth, first_diffuse, later_delta), beta, Le, w);
        }
        if (emission_only)
            break;

        bsdf b;
        material_bsdf(s, &sf, &b);
        if (b.count == 0) {
            if (camera_segment)
                res.alpha = 1.0f;
            break;
        }
        vec3 wo = v3_neg(d);
        if (bsdf_has_non_delta(&b) && s->lights.count > 0)
            add_to(&res, classify(depth + 1, first_diffuse, depth == 0), beta,
                   estimate_direct(s, &sf, &b, wo, smp, v_index), 1.0f);

        bsdf_sample bs;
        float u_pick = sampler_1d(smp, dim_bounce(v_index, DIM_BSDF_PICK));
        if (!bsdf_sample_direction(&b, wo, u_pick, sampler_2d(smp, dim_bounce(v_index, DIM_BSDF_DIR)), &bs)) {
            if (camera_segment)
                res.alpha = 1.0f;
            break;
        }
        beta = v3_mul(beta, bs.weight);
        if (!v3_is_finite(beta) || v3_is_zero(beta))
            break;

        if (bs.flags & BSDF_TRANSPARENT) {
            if (++transparent_steps > MAX_TRANSPARENT_STEPS)
                break;
            tmin = t_after_hit(h.t);
            continue;
        }
        if (camera_segment)
            res.alpha = 1.0f;
        camera_segment = 0;
        transparent_steps = 0;
        if (depth == 0)
            first_diffuse = (bs.flags & BSDF_DIFFUSE) != 0;
        else
            later_delta &= (bs.flags & BSDF_DELTA) != 0;

        /* Leave the surface on the side of the sampled direction. */
        vec3 n = v3_dot(bs.wi, sf.ng) >= 0.0f ? sf.ng : v3_neg(sf.ng);
        o = offset_ray_origin(sf.p, n);
        d = bs.wi;
        tmin = 0.0f;
        tmax = INFINITY;
        prev_pdf = bs.pdf;
        prev_delta = (bs.flags & BSDF_DELTA) != 0;
        depth++;
        if (depth > is->max_bounces)
            emission_only = 1;

        if (depth >= ROULETTE_START_DEPTH) {
            float q = fminf(v3_max_component(beta), 1.0f);
            if (sampler_1d(smp, dim_bounce(v_index, DIM_ROULETTE)) >= q)
                break;
            beta = v3_scale(beta, 1.0f / q);
        }
    }
    return res;
}
