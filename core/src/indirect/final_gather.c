/*
 * final_gather.c — indirect diffuse light from the photon maps: final
 * gathering (Jensen 1996; Jensen 2001 §9.3.2) over precomputed radiance
 * photons (Christensen 1999), or the global map's estimate read at the
 * surface itself (the fast estimate).
 */
#include "indirect/hemisphere.h"
#include "indirect/indirect_diffuse.h"
#include "photons/radiance_estimate.h"
#include "scene/ray.h"
#include "transport/direct_light.h"
#include "transport/specular_chain.h"

#define GATHER_SPECULAR_BOUNCES 4   /* specular surfaces a gather ray passes before it reads a map */
/* A gather ray that lands nearer than GATHER_NEAR_RADII estimate radii
 * from where it left goes on by one BSDF sample instead of reading the
 * maps there, up to GATHER_NEAR_STEPS times: near a corner the estimate is
 * blurred over a disc as wide as the distance to the wall, and the gather
 * would copy its dark edge (Jensen 2001 §9.3.2, "secondary gathering").
 * The radius is the estimate's own where a radiance photon answers (its
 * k-th photon's distance, radiance_photon_radius), and otherwise the
 * largest an estimate may have: with the largest everywhere, gather rays
 * in a well-lit room bounced again where the estimate they landed on
 * was a fraction of that wide. */
#define GATHER_NEAR_RADII 2.0f
#define GATHER_NEAR_STEPS 2u

/* The dimension plan of one gather ray's stream (hemisphere.h gives each
 * ray its own; each near step splits a stream of its own off it). */
enum {
    GATHER_DIM_CHAIN = 0,          /* 3 per specular step: the specular chain */
    GATHER_LIGHT_VERTEX = 4,       /* the light sample at the hit: dim_bounce(4, ·) = 36 ... 43 */
    GATHER_DIM_CONTINUE = 48       /* 1 + 2: the near hit's BSDF lobe and direction */
};

/* Light leaving the surface a gather ray stopped at toward the ray that
 * scattered there at least once before, from the photon maps: the
 * radiance photon (diffuse reflection) where there is one facing this way,
 * otherwise the global map's estimate on the fly, and the glossy lobes
 * through the global map (Jensen 2001 §9.3: the estimate is consistent for
 * glossy BSDFs too). Direct photons are left out: the light sample at the
 * hit counts direct light exactly, where the map would blur the sharp edge
 * of a sunlit patch over a disc and brighten the shade around it. */
/* The radiance photon at a gather ray's hit, looked up once: the near rule
 * (gather_ray) reads its radius, and hit_radiance_from_maps its radiance. */
typedef struct radiance_at_hit {
    int looked_up, found;
    vec3 L;       /* W/(m²·sr) */
    float radius; /* of the estimate behind it, scene units */
} radiance_at_hit;

/* Whether b has a part bsdf_split calls diffuse: the part a radiance
 * photon answers for. */
static int has_diffuse_part(const bsdf *b)
{
    for (uint32_t k = 0; k < b->count; k++)
        if (closure_is_diffuse(&b->closures[k]))
            return 1;
    return 0;
}

static radiance_at_hit look_up_radiance(const indirect_query *q, const specular_chain_end *end)
{
    const integrator_settings *is = q->is;
    radiance_at_hit r = {1, 0, v3s(0.0f), 0.0f};
    if (is->maps->radiance.count)
        r.found = radiance_photon_lookup_radius(&is->maps->radiance, end->sf.p, end->sf.ns,
                                                is->radiance_lookup_radius, &q->scratch->radiance, &r.L, &r.radius);
    return r;
}

static vec3 hit_radiance_from_maps(const indirect_query *q, const specular_chain_end *end, radiance_at_hit *at)
{
    const integrator_settings *is = q->is;
    estimate_params ep = is->global_estimate;
    ep.exclude_flags = PHOTON_DIRECT;
    bsdf diffuse, rest;
    bsdf_split(&end->read, &diffuse, &rest);
    vec3 L = v3s(0.0f);
    if (diffuse.count) {
        if (!at->looked_up)
            *at = look_up_radiance(q, end);
        L = at->found ? at->L
                      : photon_radiance(&is->maps->global, &diffuse, end->wo, end->sf.p, end->sf.ns, &ep,
                                        &q->scratch->global);
    }
    if (bsdf_has_non_delta(&rest)) {
        L = v3_add(L, photon_radiance(&is->maps->global, &rest, end->wo, end->sf.p, end->sf.ns, &ep,
                                      &q->scratch->global));
        /* Rough refraction: light transmitted toward the ray comes from the
         * photons that reached the other side (a lamp in a frosted shade). */
        if (bsdf_transmits(&rest))
            L = v3_add(L, photon_radiance(&is->maps->global, &rest, end->wo, end->sf.p, v3_neg(end->sf.ns), &ep,
                                          &q->scratch->global));
    }
    return L;
}

/* Direct light leaving the hit toward the ray: one light sample through
 * the whole BSDF, unweighted (nothing else at the hit finds emitters). */
static vec3 hit_direct(const indirect_query *q, const specular_chain_end *end, const sampler *smp)
{
    if (!bsdf_has_non_delta(&end->read) || q->s->lights.count == 0)
        return v3s(0.0f);
    bsdf none;
    none.count = 0;
    light_context c = light_context_at(&end->sf);
    return direct_light(q->s, &c, &end->sf, &none, &end->read, 0, end->wo, smp, GATHER_LIGHT_VERTEX);
}

/* Radiance arriving along a gather ray: at the surface it lands on after
 * following specular ones, the light sample and the maps' estimate; plus
 * the emitters its first segment reaches, MIS-weighted against the light
 * sample at the gather's point (indirect_diffuse.h). Emission found
 * through specular surfaces is a caustic, which the caustic map counts. */
static gather_estimate gather_ray(const indirect_query *q, vec3 o, vec3 d, const sampler *g, uint32_t ray_index,
                                  float ray_pdf)
{
    const integrator_settings *is = q->is;
    sampler ray_smp = sampler_split(g, HEMISPHERE_RAY_STREAM + ray_index); /* hemisphere.h */
    float near2 = GATHER_NEAR_RADII * GATHER_NEAR_RADII * is->radiance_lookup_radius * is->radiance_lookup_radius;
    vec3 beta = v3s(1.0f), L = v3s(0.0f);
    gather_estimate out = GATHER_ESTIMATE_ZERO;
    for (uint32_t step = 0;; step++) {
        sampler smp = step ? sampler_split(&ray_smp, step) : ray_smp;
        /* Only the first segment counts emitters; later ones would find
         * what the light sample at the previous hit already counted. */
        specular_chain c = {STOP_AT_NON_CAUSTIC, GATHER_SPECULAR_BOUNCES + 1, 0, &smp, GATHER_DIM_CHAIN,
                            step ? 0.0f : ray_pdf, q->light, is->caustic_roughness};
        specular_chain_end end;
        int hit = specular_chain_follow(q->s, &c, o, d, 0.0f, INFINITY, &end);
        if (step == 0) {
            out.direct = end.emission;
            out.distance = end.first_distance;
        }
        if (!hit)
            break;
        beta = v3_mul(beta, end.beta);
        L = v3_add(L, v3_mul(beta, hit_direct(q, &end, &smp)));
        float hit2 = v3_length2(v3_sub(end.sf.p, o));
        int near = hit2 < near2;
        radiance_at_hit at = {0, 0, v3s(0.0f), 0.0f};
        if (near && step + 1 <= GATHER_NEAR_STEPS && has_diffuse_part(&end.read)) {
            /* Near by the largest radius an estimate can have; the
             * radiance photon there says how wide its own was. */
            at = look_up_radiance(q, &end);
            if (at.found)
                near = hit2 < GATHER_NEAR_RADII * GATHER_NEAR_RADII * at.radius * at.radius;
        }
        bsdf_sample bs;
        if (!near || step + 1 > GATHER_NEAR_STEPS ||
            !bsdf_sample_direction(&end.read, end.wo, sampler_1d(&smp, GATHER_DIM_CONTINUE),
                                   sampler_2d(&smp, GATHER_DIM_CONTINUE + 1), &bs)) {
            L = v3_add(L, v3_mul(beta, hit_radiance_from_maps(q, &end, &at)));
            break;
        }
        /* Near: the caustics arriving at the hit from the caustic map, and
         * the rest by one more ray through the BSDF. */
        L = v3_add(L, v3_mul(beta, photon_radiance(&is->maps->caustic, &end.read, end.wo, end.sf.p, end.sf.ns,
                                                   &is->caustic_estimate, &q->scratch->caustic)));
        beta = v3_mul(beta, bs.weight);
        if (v3_is_zero(beta) || !v3_is_finite(beta))
            break;
        o = ray_leave_surface(end.sf.p, end.sf.ng, bs.wi);
        d = bs.wi;
    }
    out.indirect = L;
    return out;
}

/* Final gathering: the stratified hemisphere of gather rays. */
static gather_estimate final_gather(const indirect_query *q)
{
    return hemisphere_gather(q, q->is->final_gather_rays, gather_ray, 1);
}

/* The global map's estimate at the surface, leaving out its direct and
 * caustic photons, which next-event estimation and the caustic map count. */
static gather_estimate photon_map_estimate(const indirect_query *q)
{
    estimate_params ep = q->is->global_estimate;
    ep.exclude_flags = PHOTON_DIRECT | PHOTON_CAUSTIC;
    vec3 L = photon_radiance(&q->is->maps->global, q->diffuse, q->wo, q->sf->p, q->sf->ns, &ep, &q->scratch->global);
    gather_estimate out = GATHER_ESTIMATE_ZERO;
    out.indirect = L;
    return out;
}

const indirect_diffuse_provider indirect_final_gather = {"final gather", 1, final_gather, gather_ray};
const indirect_diffuse_provider indirect_photon_map = {"photon map", 0, photon_map_estimate, NULL};

