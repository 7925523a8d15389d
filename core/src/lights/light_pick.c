/*
 * light_pick.c — which light a next-event estimate samples (light.h).
 *
 * A light is picked in two steps: a group (a lamp, a sun, the world, or the
 * emissive triangles of one instance) in proportion to a bound on the
 * irradiance it can give the shading point, then a light within the group
 * in proportion to its power. The bound is the idea of Cycles' light tree
 * and pbrt-v4's BVHLightSampler (Conty Estevez & Kulla 2018, "Importance
 * Sampling of Many Lights with Adaptive Tree Splitting"), evaluated here for
 * every group since scenes hold few: power over squared distance, times the
 * largest cosine any point of the light's bounding sphere can make with the
 * receiver's normal and, for one-sided area lights, with the light's.
 *
 * A group the bound gives zero cannot light the point at all (it lies below
 * a surface that only reflects, behind a one-sided light, outside a spot's
 * cone), so the samples a power-only pick would waste on it go to the
 * others. On Blender's default cube this is what makes the world-lit face
 * as clean as Cycles': the 1000 W lamp behind it is never picked there.
 *
 * The same function gives the probability for MIS when a BSDF-sampled ray
 * finds a light, so the context must be the one of the vertex the ray
 * left (light_context_at).
 */
#include "lights/light.h"
#include "lights/light_kind.h"

#include <float.h>

/* cos(max(0, θ − β)) for cos θ = cos_theta and a half angle β given by its
 * sine and cosine: the largest cosine a direction within β of the axis can
 * make with the normal. ≤ 0 when the whole cone lies beyond the horizon. */
static float cone_cos_bound(float cos_theta, float sin_beta, float cos_beta)
{
    if (cos_theta >= cos_beta)
        return 1.0f;
    float sin_theta = safe_sqrtf(1.0f - cos_theta * cos_theta);
    return cos_theta * cos_beta + sin_theta * sin_beta;
}

/* The receiver's factor for light arriving within β of direction w: both
 * the geometric and the shading normal are tried (either can let light
 * in), and a surface that transmits sees both sides. Zero only when no
 * direction of the cone can reach the surface; a margin of 10⁻³ in cosine
 * keeps rounding from zeroing a light at the horizon. */
static float receiver_bound(const light_context *c, vec3 w, float sin_beta, float cos_beta)
{
    if (c->no_normal)
        return 1.0f;
    float a = v3_dot(c->ng, w), b = v3_dot(c->ns, w);
    float cos_theta = c->two_sided ? maxf(fabsf(a), fabsf(b)) : maxf(a, b);
    float bound = cone_cos_bound(clampf(cos_theta, -1.0f, 1.0f), sin_beta, cos_beta);
    if (bound <= -1e-3f)
        return 0.0f;
    return maxf(bound, 1e-3f);
}

/* The largest spot attenuation any ray from the lamp to p can carry. A
 * spot with a radius shapes its beam by the direction of each ray leaving
 * its sphere (point.c), and those directions lie within β of the one from
 * its centre, so the largest is the attenuation at the angle θ − β to the
 * axis: it never falls as the angle shrinks. Any smaller figure is no
 * bound: a point just outside the cone, or in its blend, would be picked
 * for less than the light it gets, and each pick would weigh too much. */
static float spot_bound(const light *l, vec3 from_light, float sin_beta, float cos_beta, int inside)
{
    if (l->radius <= 0.0f)
        return light_spot_attenuation(l, from_light);
    if (inside)
        return light_spot_attenuation_cos(l, 1.0f);
    return light_spot_attenuation_cos(l, cone_cos_bound(v3_dot(from_light, l->direction), sin_beta, cos_beta));
}

/* Bound on the irradiance (W/m²) group g can give the point. */
static float group_importance(const light_table *t, const light_group *g, const light_context *c)
{
    const light *l = &t->lights[g->first];
    if (light_is_world(l)) /* an environment's l->color is its mean radiance */
        return PHOS_PI * maxf(v3_average(l->color), 0.0f); /* E = πL from a whole hemisphere */
    if (l->kind == LIGHT_SUN) {
        float cos_a = l->sun_cos_half, sin_a = safe_sqrtf(1.0f - cos_a * cos_a);
        return maxf(v3_average(l->color), 0.0f) * receiver_bound(c, v3_neg(l->direction), sin_a, cos_a);
    }
    vec3 v = v3_sub(g->center, c->p);
    float d2 = v3_length2(v), r2 = g->radius * g->radius;
    float d = sqrtf(d2);
    int inside = d2 <= r2 || !(d > 0.0f);
    float sin_b = inside ? 1.0f : g->radius / d, cos_b = inside ? 0.0f : safe_sqrtf(1.0f - sin_b * sin_b);
    vec3 w = inside ? c->ng : v3_scale(v, 1.0f / d); /* toward the light */
    float receiver = inside ? 1.0f : receiver_bound(c, w, sin_b, cos_b);
    if (!(receiver > 0.0f))
        return 0.0f;
    float inv_d2 = 1.0f / maxf(d2, maxf(r2, FLT_MIN));
    switch (l->kind) {
    case LIGHT_POINT:
    case LIGHT_SPOT: { /* E = I·a/d² */
        float a = l->kind == LIGHT_SPOT ? spot_bound(l, v3_neg(w), sin_b, cos_b, inside) : 1.0f;
        return maxf(v3_average(l->color), 0.0f) * a * receiver * inv_d2;
    }
    case LIGHT_AREA: { /* E = L·A·cos θ_l·cos θ/d², one-sided */
        float h = v3_dot(v3_sub(c->p, l->position), l->direction);
        if (!(h > 0.0f))
            return 0.0f; /* behind the emitting face */
        float emitter = inside ? 1.0f : cone_cos_bound(h / d, sin_b, cos_b);
        return maxf(v3_average(l->color), 0.0f) * l->area * maxf(emitter, 1e-3f) * receiver * inv_d2;
    }
    default: /* emissive triangles, both faces: L·A = Φ/(2π) */
        return g->power * (0.5f * PHOS_INV_PI) * receiver * inv_d2;
    }
}

/*
 * A uniform world is never picked: it gets a light sample of its own at
 * every vertex, besides the picked light's (transport/direct_light.c).
 * Picking it would make every other light's estimate pay pick variance: on
 * a surface lit by a lamp, the lamp's light is counted 1/(1 − p_world)
 * times in most samples and not at all in the rest. Leaving it to the
 * BSDF's rays alone is no better where the BSDF is glossy, since those
 * rays sample the lobe, not the world. Measured on Blender's default cube
 * (a 1000 W lamp, a 0.05 grey world, Principled roughness 0.5), direct
 * light at 16 samples against a Cycles 5.3 reference, MSE on the lamp-lit
 * faces: BSDF rays only 2.4e-5, picked by its bound 1.2e-4, sampled apart
 * 4.9e-6, Cycles 6.7e-6 (docs/benchmarks.md). The extra shadow ray costs
 * less than the variance it removes.
 *
 * A world that varies with direction is sampled apart too when there are
 * other lights: above all the Sky Texture's sun (lights/sky_sun.c), whose
 * pick against the sky cost more than the second shadow ray. Measured on a
 * diffuse sphere and floor under a sky with its sun 14° high, 64 samples,
 * Phos's pixel variance over Cycles 3.4's: 1.92 picked, 0.21 apart for
 * direct light; 1.42 and 0.45 with 4 bounces, at the same time. Alone, it
 * is the only light to pick and keeps the path's own sampler dimensions.
 */
int light_world_sampled_apart(const light_table *t)
{
    if (t->world < 0)
        return 0;
    uint32_t kind = t->lights[t->world].kind;
    return kind == LIGHT_WORLD || (kind == LIGHT_ENVIRONMENT && t->count > 1);
}

int light_world_apart(const light_table *t, const light_context *c) { return c && light_world_sampled_apart(t); }

/* The groups' importances at c into w; returns their sum. A world sampled
 * apart (light_world_apart) is not among them. */
static double group_importances(const light_table *t, const light_context *c, float *w)
{
    double total = 0.0;
    int apart = light_world_apart(t, c);
    for (uint32_t g = 0; g < t->group_count; g++) {
        w[g] = apart && (int32_t)t->groups[g].first == t->world ? 0.0f : group_importance(t, &t->groups[g], c);
        if (!(w[g] > 0.0f) || !isfinite(w[g]))
            w[g] = 0.0f;
        total += w[g];
    }
    return total;
}

static int picks_by_power(const light_table *t, const light_context *c)
{
    return !c || t->group_count > LIGHT_PICK_MAX_GROUPS;
}

uint32_t light_pick(const light_table *t, const light_context *c, float u, float *pdf)
{
    *pdf = 0.0f;
    if (t->count == 0)
        return 0;
    if (picks_by_power(t, c)) {
        uint32_t i = distribution_sample(c ? &t->pick_nee : &t->pick, u, pdf, NULL);
        if ((int32_t)i == t->world && light_world_apart(t, c))
            *pdf = 0.0f; /* only when nothing else has power: the world has its own sample */
        return i;
    }
    float w[LIGHT_PICK_MAX_GROUPS];
    double total = group_importances(t, c, w);
    if (!(total > 0.0))
        return 0;
    uint32_t g = 0;
    float p_group = 1.0f;
    if (t->group_count > 1) {
        double x = (double)u * total, below = 0.0;
        g = t->group_count - 1;
        for (uint32_t k = 0; k < t->group_count; k++) {
            if (w[k] > 0.0f && x < below + w[k]) {
                g = k;
                break;
            }
            below += w[k];
        }
        while (!(w[g] > 0.0f)) /* u rounded past the last nonzero group */
            g--;
        u = minf(maxf((float)((x - below) / w[g]), 0.0f), 0x1.fffffep-1f);
        p_group = (float)(w[g] / total);
    }
    const light_group *grp = &t->groups[g];
    if (grp->count == 1) {
        *pdf = p_group;
        return grp->first;
    }
    float p_within;
    uint32_t i = distribution_sample(&grp->within, u, &p_within, NULL);
    *pdf = p_group * p_within;
    return grp->first + i;
}

float light_pick_pdf(const light_table *t, const light_context *c, uint32_t light)
{
    if (light >= t->count)
        return 0.0f;
    if ((int32_t)light == t->world && light_world_apart(t, c))
        return 1.0f;
    if (picks_by_power(t, c))
        return distribution_pdf(c ? &t->pick_nee : &t->pick, light);
    uint32_t g = t->lights[light].group;
    const light_group *grp = &t->groups[g];
    float p = grp->count > 1 ? distribution_pdf(&grp->within, light - grp->first) : 1.0f;
    float w[LIGHT_PICK_MAX_GROUPS];
    double total = group_importances(t, c, w);
    if (!(total > 0.0))
        return 0.0f;
    return p * (float)(w[g] / total);
}

/* ---------------------------------------------------------------- build */

static void group_bounds(const light_table *t, light_group *g)
{
    const light *l = &t->lights[g->first];
    switch (l->kind) {
    case LIGHT_POINT:
    case LIGHT_SPOT:
        g->center = l->position;
        g->radius = l->radius;
        return;
    case LIGHT_AREA:
        g->center = l->position;
        g->radius = 0.5f * sqrtf(v3_length2(l->axis_u) + v3_length2(l->axis_v));
        return;
    case LIGHT_TRIANGLE: {
        vec3 lo = l->p0, hi = l->p0;
        for (uint32_t i = 0; i < g->count; i++) {
            const light *tri = &t->lights[g->first + i];
            vec3 c[3] = {tri->p0, tri->p1, tri->p2};
            for (int k = 0; k < 3; k++) {
                lo = v3_min(lo, c[k]);
                hi = v3_max(hi, c[k]);
            }
        }
        g->center = v3_scale(v3_add(lo, hi), 0.5f);
        g->radius = 0.5f * v3_length(v3_sub(hi, lo));
        return;
    }
    default: /* distant */
        g->center = v3s(0.0f);
        g->radius = 0.0f;
        return;
    }
}

/* Emissive triangles are appended instance by instance (mesh_emitter.c),
 * so an instance's triangles are consecutive. */
static int starts_group(const light_table *t, uint32_t i)
{
    const light *l = &t->lights[i];
    return i == 0 || l->kind != LIGHT_TRIANGLE || t->lights[i - 1].kind != LIGHT_TRIANGLE ||
           t->lights[i - 1].instance != l->instance;
}

phos_status light_groups_build(light_table *t, const float *power)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < t->count; i++)
        n += starts_group(t, i);
    t->groups = calloc(n ? n : 1, sizeof(light_group));
    if (!t->groups)
        return PHOS_ERROR_OUT_OF_MEMORY;
    t->group_count = 0;
    for (uint32_t i = 0; i < t->count; i++) {
        if (starts_group(t, i))
            t->groups[t->group_count++].first = i;
        light_group *g = &t->groups[t->group_count - 1];
        g->count++;
        g->power += power[i];
        t->lights[i].group = t->group_count - 1;
    }
    for (uint32_t k = 0; k < t->group_count; k++) {
        light_group *g = &t->groups[k];
        group_bounds(t, g);
        if (g->count > 1 && !distribution_build(&g->within, power + g->first, g->count))
            return PHOS_ERROR_OUT_OF_MEMORY;
    }
    return PHOS_OK;
}
