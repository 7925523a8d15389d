/*
 * camera_path.c — the camera-path walker shared by PATH and PHOTON (see
 * camera_path.h for what it owns and what a vertex policy decides).
 */
#include "integrators/camera_path.h"

#include <string.h>

#include "lights/light.h"
#include "scene/embree.h"

/* Which component a contribution belongs to, from the scattering events on
 * its path: how many, whether the first was diffuse, and whether all the
 * later ones were delta lobes (integrator.h). */
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
    if (component < 0) /* left out (walk_start.indirect_only) */
        return;
    res->component[component] = v3_madd(res->component[component], v3_mul(beta, L), w);
}

void camera_path_add_direct(camera_path *p, vec3 L)
{
    /* One more event, non-delta (next-event estimation samples no delta lobe). */
    add_to(p->res, classify(p->depth + 1, p->first_diffuse, p->depth == 0), p->beta, L, 1.0f);
}

void camera_path_add_diffuse(camera_path *p, int caustic, vec3 L)
{
    /* Two more events at least, the one here read by an estimate (diffuse,
     * or a glossy receiver's caustics). */
    int component = p->depth == 0 ? (caustic ? COMPONENT_CAUSTICS : COMPONENT_INDIRECT)
                                  : classify(p->depth + 2, p->first_diffuse, 0);
    add_to(p->res, component, p->beta, L, 1.0f);
}

/* The denoising features (Cycles' film denoising features, 4.5): the
 * first surface on the camera path that is more than a quarter
 * diffuse-like gives its albedo and normal; the specular surfaces before it
 * (mirrors, glass, sharp coats, transparency) pass them on, scaled by
 * their own albedo. Returns whether later surfaces still count. */
static int record_features(sample_result *res, const integrator_settings *is, const bsdf *b, vec3 wo,
                           vec3 *feature_beta)
{
    bsdf_features f;
    bsdf_denoising_features(b, wo, &f);
    if (f.weight_total > 0.0f && !(4.0f * f.weight_diffuse > f.weight_total)) {
        *feature_beta = v3_mul(*feature_beta, f.albedo_specular);
        return !v3_is_zero(*feature_beta);
    }
    res->denoising_albedo = v3_add(res->denoising_albedo, v3_mul(*feature_beta, f.albedo_diffuse));
    /* The closures' normals weighted by their sampling weights (bsdf_normal);
     * a surface with no closure (an emitter) has none. */
    if (f.weight_total > 0.0f)
        res->denoising_normal = camera_direction_to_camera_space(is->camera, bsdf_normal(b));
    return 0;
}

/* The scattering events of a path by kind, for the Light Path node's
 * depths, counted as Cycles' path_state_next does: a transparent
 * pass-through only as transparent (it is no bounce); a reflection as
 * diffuse, or glossy (sharp mirrors too); any other transmission
 * (refraction, translucency) as a transmission, whatever its lobe. */
typedef struct path_depths {
    uint32_t diffuse, glossy, transmission, transparent;
} path_depths;

static void count_event(path_depths *d, uint32_t bsdf_flags)
{
    if (bsdf_flags & BSDF_TRANSPARENT)
        d->transparent++;
    else if (bsdf_flags & BSDF_TRANSMISSION)
        d->transmission++;
    else if (bsdf_flags & BSDF_DIFFUSE)
        d->diffuse++;
    else
        d->glossy++;
}

/* Holdout (Cycles' integrate_surface_holdout): while the camera ray goes
 * on only through transparency, a surface's holdout closures make the
 * pixel transparent by the average over the channels of their weight
 * times the throughput, film transparent or not (measured on Blender 3.4:
 * an Emission mixed with a Holdout of weight 0.75 gives colour 0.25 and
 * alpha 0.25 either way). Returns whether the holdout is whole: then the
 * surface gives the pixel nothing more, not even its emission. */
static int apply_holdout(const scene *s, const surface *sf, vec3 beta, float *holdout)
{
    vec3 h = material_holdout(s, sf);
    *holdout += v3_average(v3_mul(h, beta));
    return h.x >= 1.0f && h.y >= 1.0f && h.z >= 1.0f;
}

/* MIS weight of emission found by the ray that left the previous vertex
 * with BSDF pdf prev_pdf, against that vertex's next-event estimate. */
static float emission_weight(int prev_delta, float prev_pdf, float light_pdf)
{
    return prev_delta ? 1.0f : mis_power_heuristic(prev_pdf, light_pdf);
}

/* Glossy receivers (docs/algorithms.md §12). Where the policy read the
 * caustic map through a vertex's receivers (rough glossy reflection as
 * well as diffuse), light that reaches the vertex from an emitter through
 * closures that carry caustics only (L S+ R) is already counted, and the
 * path that goes on from there must leave it out, without a bias: a
 * direction drawn from the mixture of all the closures the path goes on
 * through is not one closure's, so each closure's share of f at that
 * direction (bsdf_caustic_shares: a carrying, r receiving) splits the light
 * it finds. With Q the share of the throughput counted at an earlier
 * receiver and carried since, light found on the next segment counts by
 * 1 − a·Q (the rest reached a receiver through carriers only), and Q
 * becomes r + a·Q. Light found straight after a receiver is direct light
 * there, counted in full; the light sample at a later vertex scales its
 * carriers by 1 − Q the same way (diffuse_split.c). */
static void count_caustics_once(camera_path *p, const bsdf *b, vec3 wo, const bsdf_sample *bs, vec3 *uncounted)
{
    if (!p->reads_caustics) {
        *uncounted = v3s(1.0f);
        p->caustic_counted = v3s(0.0f);
        return;
    }
    vec3 carry, receive;
    bsdf_caustic_shares(b, wo, bs, p->is->caustic_roughness, &carry, &receive);
    *uncounted = v3_sub(v3s(1.0f), v3_mul(carry, p->caustic_counted));
    p->caustic_counted = v3_add(receive, v3_mul(carry, p->caustic_counted));
}

/* Where a walk starts: the camera, or a vertex of a camera path. */
typedef struct walk_start {
    camera_ray ray;
    int from_camera;
    uint32_t depth;         /* scattering events before the ray */
    int indirect_only;      /* leave out emission found after delta events only */
    int caustics_apart;     /* indirect_only: file it as Caustics instead */
    float first_pdf;        /* MIS pdf of the first segment's emission; 0: the camera's rule, or
                               (indirect_only) left out too */
    const light_context *from; /* first_pdf > 0: the vertex the walk leaves, for the light-pick pdf */
} walk_start;

/* Writes the sample into *res in place: a sample_result built locally and
 * returned was copied out in 16-byte loads of fields just written in
 * smaller stores, a stalled store-to-load forward at every sample. */
static void walk(const scene *s, const integrator_settings *is, const walk_start *start, const sampler *smp,
                 integrator_scratch *scratch, vertex_policy policy, sample_result *res)
{
    memset(res, 0, sizeof(*res));
    res->first_distance = INFINITY;
    camera_path p = {s, is, smp, scratch, res, v3s(1.0f), start->depth, 0, 1, v3s(0.0f), 0};
    /* Per channel, the share of light found on the current segment that no
     * caustic-map estimate has counted (glossy receivers, see below). */
    vec3 uncounted = v3s(1.0f);
    vec3 o = start->ray.o, d = start->ray.d;
    float tmin = start->ray.tmin, tmax = start->ray.tmax;
    int camera_segment = start->from_camera;  /* still on the camera ray (through transparency) */
    int emission_only = p.depth > is->max_bounces; /* past max_bounces: collect emission, then stop */
    int only_delta = 1;                        /* no non-delta event since the start */
    float prev_pdf = start->first_pdf;
    int prev_delta = !(start->first_pdf > 0.0f); /* the camera ray takes emission unweighted */
    int transparent_steps = 0;
    uint32_t vertex = 0;                       /* surface interactions, for sample dimensions */
    light_context prev = {v3s(0.0f), v3s(0.0f), v3s(0.0f), 0, 1}; /* the vertex the ray left */
    if (start->from)
        prev = *start->from;
    int features = start->from_camera && is->denoising_features; /* record_features still pending */
    /* The kind of ray that finds each surface, for the Light Path node: a
     * walk that starts on a diffuse vertex (gathers) leaves by a diffuse
     * reflection. */
    uint32_t ray_flags = start->from_camera ? SHADER_RAY_CAMERA : (SHADER_RAY_DIFFUSE | SHADER_RAY_REFLECT);
    /* A walk from a diffuse vertex does not know the kinds of the events
     * before it: they count as the diffuse reflections it starts with. */
    path_depths depths = {start->depth, 0, 0, 0};
    float holdout = 0.0f;                      /* the camera segment's holdout transparency */
    vec3 feature_beta = v3s(1.0f);
    /* The pixel's footprint as Cycles carries it (compact ray
     * differentials): its radius where the ray left, growing with the
     * camera ray's spread per unit of distance. A bounce restarts the radius
     * from the footprint on the surface and keeps the camera's spread
     * (Cycles 3.4 to 4.5 write only dP at a bounce), whatever the lobe. */
    float spread_origin = start->ray.spread_origin, spread_per_distance = start->ray.spread_per_distance;
/* Emission found while the features are pending also shows in their albedo
 * (lamps and the world seen directly or through mirrors), as in Cycles. */
#define ADD_EMISSION(L, w)                                                                          \
    do {                                                                                            \
        vec3 L_ = v3_mul((L), uncounted);                                                           \
        float w_ = (w);                                                                             \
        add_to(res, emission_component, p.beta, L_, w_);                                           \
        if (features)                                                                               \
            res->denoising_albedo = v3_madd(res->denoising_albedo, v3_mul(feature_beta, v3_mul(p.beta, L_)), w_); \
    } while (0)

    for (;;) {
        ray_hit h;
        int hit = embree_intersect(s->bvh, o, d, tmin, tmax, camera_segment, &h);
        float t_hit = hit ? h.t : tmax;
        if (vertex == 0 && hit)
            res->first_distance = h.t;
        int emission_component = classify(p.depth, p.first_diffuse, p.later_delta);
        if (start->indirect_only && only_delta && p.depth > start->depth)
            emission_component = start->caustics_apart ? COMPONENT_CAUSTICS : -1;
        else if (start->indirect_only && only_delta && !(start->first_pdf > 0.0f))
            emission_component = -1;
        else if (!start->from_camera && p.depth == start->depth)
            emission_component = COMPONENT_EMISSION; /* seen by the walk's first segment */

        light_hit lh;
        if (lights_intersect(s, prev_delta ? NULL : &prev, o, d, tmin, t_hit, camera_segment, &lh))
            ADD_EMISSION(lh.radiance, emission_weight(prev_delta, prev_pdf, lh.pdf));
        if (!hit) {
            if (!(camera_segment && is->transparent_background))
                ADD_EMISSION(lights_escape(s, prev_delta ? NULL : &prev, d, prev_pdf, prev_delta, camera_segment),
                             1.0f);
            if (camera_segment && !is->transparent_background)
                res->alpha = 1.0f;
            break;
        }

        surface sf;
        surface_from_hit(s, h.instance, h.prim, h.b1, h.b2, d, &sf);
        sf.ray_flags = ray_flags;
        sf.ray_length = h.t;
        sf.ray_depth = p.depth;
        sf.footprint = spread_origin + h.t * spread_per_distance;
        sf.diffuse_depth = depths.diffuse;
        sf.glossy_depth = depths.glossy;
        sf.transmission_depth = depths.transmission;
        sf.transparent_depth = depths.transparent;
        uint32_t v_index = vertex++;
        if (camera_segment && sf.mat->holdout && apply_holdout(s, &sf, p.beta, &holdout)) {
            res->alpha = 1.0f;
            break;
        }
        if (sf.mat->emissive) {
            float w = 1.0f;
            if (!prev_delta) {
                const instance *inst = &s->instances[sf.instance];
                int32_t li = inst->emitter_of_triangle ? inst->emitter_of_triangle[sf.prim] : -1;
                w = emission_weight(prev_delta, prev_pdf, light_pdf_triangle(s, li, &prev, sf.p, sf.ng));
            }
            ADD_EMISSION(material_emission(s, &sf), w);
        }
        if (emission_only)
            break;

        bsdf b, storage;
        material_bsdf(s, &sf, &b);
        if (features)
            features = record_features(res, is, &b, v3_neg(d), &feature_beta);
        if (b.count == 0) {
            if (camera_segment)
                res->alpha = 1.0f;
            break;
        }
        light_context here = light_context_at(&sf);
        path_vertex v = {&sf, &b, v3_neg(d), v_index, &here};
        p.reads_caustics = 0;
        const bsdf *next = policy(&p, &v, &storage);

        bsdf_sample bs;
        float u_pick = sampler_1d(smp, dim_bounce(v_index, DIM_BSDF_PICK));
        if (!next ||
            !bsdf_sample_direction(next, v.wo, u_pick, sampler_2d(smp, dim_bounce(v_index, DIM_BSDF_DIR)), &bs)) {
            if (camera_segment)
                res->alpha = 1.0f;
            break;
        }
        p.beta = v3_mul(p.beta, bs.weight);
        if (!v3_is_finite(p.beta) || v3_is_zero(p.beta))
            break;

        count_event(&depths, bs.flags);
        if (bs.flags & BSDF_TRANSPARENT) {
            if (++transparent_steps > CAMERA_PATH_MAX_TRANSPARENT_STEPS)
                break;
            tmin = t_after_hit(h.t);
            continue;
        }
        if (camera_segment)
            res->alpha = 1.0f;
        camera_segment = 0;
        transparent_steps = 0;
        count_caustics_once(&p, next, v.wo, &bs, &uncounted);
        ray_flags = ((bs.flags & BSDF_DIFFUSE) ? SHADER_RAY_DIFFUSE
                     : (bs.flags & BSDF_DELTA) ? SHADER_RAY_SINGULAR | SHADER_RAY_GLOSSY
                                               : SHADER_RAY_GLOSSY) |
                    ((bs.flags & BSDF_TRANSMISSION) ? SHADER_RAY_TRANSMIT : SHADER_RAY_REFLECT);
        if (p.depth == 0)
            p.first_diffuse = (bs.flags & BSDF_DIFFUSE) != 0;
        else
            p.later_delta &= (bs.flags & BSDF_DELTA) != 0;

        o = ray_leave_surface(sf.p, sf.ng, bs.wi);
        d = bs.wi;
        spread_origin = sf.footprint;
        prev = here;
        tmin = 0.0f;
        tmax = INFINITY;
        prev_pdf = bs.pdf;
        prev_delta = (bs.flags & BSDF_DELTA) != 0;
        only_delta &= prev_delta;
        p.depth++;
        if (p.depth > is->max_bounces)
            emission_only = 1;

        if (p.depth >= CAMERA_PATH_ROULETTE_START_DEPTH) {
            float q = minf(v3_max_component(p.beta), 1.0f);
            if (sampler_1d(smp, dim_bounce(v_index, DIM_ROULETTE)) >= q)
                break;
            p.beta = v3_scale(p.beta, 1.0f / q);
        }
    }
    res->alpha = clampf(res->alpha - holdout, 0.0f, 1.0f);
#undef ADD_EMISSION
}

void camera_path_walk(const scene *s, const integrator_settings *is, camera_ray ray, const sampler *smp,
                      integrator_scratch *scratch, vertex_policy policy, sample_result *res)
{
    walk_start start = {ray, 1, 0, 0, 0, 0.0f, NULL};
    walk(s, is, &start, smp, scratch, policy, res);
}

void camera_path_walk_indirect(const scene *s, const integrator_settings *is, const light_context *from, vec3 o, vec3 d,
                               uint32_t depth, float first_pdf, int caustics_apart, const sampler *smp,
                               integrator_scratch *scratch, vertex_policy policy, sample_result *res)
{
    /* A gather from a vertex carries no pixel's footprint (0: the bump's
     * fallback step, material.c). */
    walk_start start = {{o, d, 0.0f, INFINITY, 0.0f, 0.0f}, 0, depth, 1, caustics_apart, first_pdf, from};
    walk(s, is, &start, smp, scratch, policy, res);
}
