/*
 * light.c — the light table and light.h's functions, dispatched to each
 * kind of light through its operations (light_kind.h): point.c, spot.c,
 * area.c, sun.c, mesh_emitter.c, world.c.
 *
 * Sampling follows pbrt-v4: uniform area sampling converted to solid angle
 * (pdf_ω = d² / (A·|cos θ_l|)), uniform cone sampling for suns with an
 * angle and for spheres; photons leave a light picked in proportion to its
 * power (Jensen 2001 §5.1), next-event estimation picks by what each light
 * can give the receiver (light_pick.c). What a light emits is defined by
 * the add-on in Cycles' units (see docs/blender.md §1); here everything is
 * already radiometric.
 */
#include "lights/light.h"

#include <stdlib.h>
#include <string.h>

#include "lights/light_kind.h"
#include "sampling/warp.h"

const light_kind_ops *const light_kinds[LIGHT_KIND_COUNT] = {
    [LIGHT_POINT] = &light_point_ops, [LIGHT_SPOT] = &light_spot_ops,     [LIGHT_AREA] = &light_area_ops,
    [LIGHT_SUN] = &light_sun_ops,     [LIGHT_TRIANGLE] = &light_mesh_ops, [LIGHT_WORLD] = &light_world_ops,
    [LIGHT_ENVIRONMENT] = &light_environment_ops,
};

float light_power(const light *l, float scene_radius) { return light_ops(l)->power(l, scene_radius); }

/* ---------------------------------------------------------------- build */

int light_table_append(light_table *t, uint32_t *capacity, const light *l)
{
    if (t->count == *capacity) {
        uint32_t cap = *capacity ? *capacity * 2 : 16;
        light *n = realloc(t->lights, sizeof(light) * cap);
        if (!n)
            return 0;
        t->lights = n;
        *capacity = cap;
    }
    t->lights[t->count++] = *l;
    return 1;
}

/* The fields every lamp has; the kind described by d fills its own. */
static void light_from_desc(const phos_light_desc *d, light *l)
{
    memset(l, 0, sizeof(*l));
    l->color = v3_load(d->color);
    l->position = v3_load(d->position);
    l->direction = v3_normalize(v3_load(d->direction));
    l->radius = d->radius;
    l->point_shape = d->point_shape;
    l->camera_visible = d->camera_visible != 0;
    l->sun_cos_half = 1.0f;
    for (uint32_t k = 0; k < LIGHT_KIND_COUNT; k++) {
        const light_kind_ops *ops = light_kinds[k];
        if (ops->desc_type != (int)d->type)
            continue;
        l->kind = k;
        if (ops->from_desc)
            ops->from_desc(d, l);
        return;
    }
}

/* A portal (portal.c): the shape of an area lamp, kept apart from the
 * lights, since it emits nothing. */
static int add_portal(light_table *t, const phos_light_desc *d)
{
    light *n = realloc(t->portals, sizeof(light) * (t->portal_count + 1));
    if (!n)
        return 0;
    t->portals = n;
    light *p = &t->portals[t->portal_count++];
    memset(p, 0, sizeof(*p));
    p->kind = LIGHT_AREA;
    p->position = v3_load(d->position);
    p->direction = v3_normalize(v3_load(d->direction));
    light_area_from_desc(d, p);
    return 1;
}

/* Rays test only the lights they can hit, not every emissive triangle. */
static phos_status list_shapes(light_table *t)
{
    t->shapes = malloc(sizeof(uint32_t) * t->count);
    if (!t->shapes)
        return PHOS_ERROR_OUT_OF_MEMORY;
    for (uint32_t i = 0; i < t->count; i++) {
        const light *l = &t->lights[i];
        const light_kind_ops *ops = light_ops(l);
        if (ops->hittable && ops->hittable(l))
            t->shapes[t->shape_count++] = i;
    }
    return PHOS_OK;
}

/* The pick by power and the groups of light_pick.c. */
static phos_status build_picking(light_table *t)
{
    float *power = malloc(sizeof(float) * t->count);
    if (!power)
        return PHOS_ERROR_OUT_OF_MEMORY;
    for (uint32_t i = 0; i < t->count; i++)
        power[i] = light_power(&t->lights[i], t->radius);
    phos_status st = distribution_build(&t->pick, power, t->count) ? light_groups_build(t, power)
                                                                   : PHOS_ERROR_OUT_OF_MEMORY;
    if (st == PHOS_OK && light_world_sampled_apart(t))
        power[t->world] = 0.0f; /* sampled apart (light_pick.c) */
    if (st == PHOS_OK && !distribution_build(&t->pick_nee, power, t->count))
        st = PHOS_ERROR_OUT_OF_MEMORY;
    free(power);
    return st;
}

phos_status light_table_build(scene *s)
{
    light_table *t = &s->lights;
    uint32_t capacity = 0;
    memset(t, 0, sizeof(*t));
    t->world = -1;
    t->center = v3_scale(v3_add(s->bounds_min, s->bounds_max), 0.5f);
    t->radius = maxf(0.5f * v3_length(v3_sub(s->bounds_max, s->bounds_min)), 1e-3f);

    for (uint32_t i = 0; i < s->light_desc_count; i++) {
        if (s->light_descs[i].type == PHOS_LIGHT_PORTAL) {
            if (!add_portal(t, &s->light_descs[i]))
                return PHOS_ERROR_OUT_OF_MEMORY;
            continue;
        }
        light l;
        light_from_desc(&s->light_descs[i], &l);
        if (v3_is_zero(l.color))
            continue;
        if (!light_table_append(t, &capacity, &l))
            return PHOS_ERROR_OUT_OF_MEMORY;
    }
    phos_status st = light_mesh_emitters_add(s, t, &capacity);
    if (st == PHOS_OK)
        st = light_world_add(s, t, &capacity);
    if (st != PHOS_OK || t->count == 0)
        return st;
    st = list_shapes(t);
    return st == PHOS_OK ? build_picking(t) : st;
}

/* ------------------------------------------------------------- sampling */

int light_sample_pick(const scene *s, const light_context *c, float u_pick, float2 u, light_sample *out)
{
    const light_table *t = &s->lights;
    if (t->count == 0)
        return 0;
    float pick_pdf;
    uint32_t i = light_pick(t, c, u_pick, &pick_pdf);
    if (!(pick_pdf > 0.0f))
        return 0;
    const light *l = &t->lights[i];
    int ok = light_ops(l)->sample(s, l, c, u, out);
    if (!ok || !(out->pdf > 0.0f) || !isfinite(out->pdf))
        return 0;
    out->pdf *= pick_pdf;
    return 1;
}

int light_sample_world(const scene *s, const light_context *c, float2 u, light_sample *out)
{
    const light *l = &s->lights.lights[s->lights.world];
    int ok = light_ops(l)->sample(s, l, c, u, out);
    return ok && out->pdf > 0.0f && isfinite(out->pdf);
}

/* ------------------------------------------------------------- emission */

float distant_disk_area(float scene_radius) { return PHOS_PI * scene_radius * scene_radius; }

float distant_origin(const light_table *t, vec3 d, float2 u, vec3 *origin)
{
    frame f = frame_from_normal(d);
    float2 dk = warp_disk_concentric(u);
    vec3 c = v3_madd(t->center, d, -t->radius);
    *origin = v3_add(c, v3_add(v3_scale(f.t, dk.x * t->radius), v3_scale(f.b, dk.y * t->radius)));
    return distant_disk_area(t->radius);
}

int light_emit_toward(const scene *s, uint32_t index, vec3 d, float2 u, vec3 *origin, vec3 *intensity)
{
    const light *l = &s->lights.lights[index];
    const light_kind_ops *ops = light_ops(l);
    return ops->emit_toward ? ops->emit_toward(s, l, d, u, origin, intensity) : 0;
}

int light_emit(const scene *s, uint32_t index, const float u[4], vec3 *origin, vec3 *direction, vec3 *flux)
{
    const light_table *t = &s->lights;
    const light *l = &t->lights[index];
    const light_kind_ops *ops = light_ops(l);
    float2 ua = {u[0], u[1]}, ub = {u[2], u[3]};
    if (ops->emit)
        return ops->emit(s, l, ua, ub, origin, direction, flux);
    /* A local light: a direction by its density, then the origin and the
     * intensity along it. */
    float pdf;
    vec3 d = ops->emission_direction(l, ub, &pdf);
    vec3 intensity;
    if (!(pdf > 0.0f) || !light_emit_toward(s, index, d, ua, origin, &intensity))
        return 0;
    *direction = d;
    *flux = v3_scale(intensity, 1.0f / pdf); /* e.g. L cos A / (cos/π) = πAL for an area light */
    return 1;
}

int light_sample_emission(const scene *s, const float u[5], vec3 *origin, vec3 *direction, vec3 *power)
{
    const light_table *t = &s->lights;
    if (t->count == 0)
        return 0;
    float pick_pdf;
    uint32_t i = distribution_sample(&t->pick, u[0], &pick_pdf, NULL);
    if (!(pick_pdf > 0.0f) || !light_emit(s, i, u + 1, origin, direction, power))
        return 0;
    *power = v3_scale(*power, 1.0f / pick_pdf);
    return !v3_is_zero(*power) && v3_is_finite(*power);
}

/* --------------------------------------------------------- intersection */

int lights_intersect(const scene *s, const light_context *from, vec3 o, vec3 d, float tmin, float tmax,
                     int camera_ray, light_hit *out)
{
    const light_table *tab = &s->lights;
    int found = 0;
    for (uint32_t k = 0; k < tab->shape_count; k++) {
        uint32_t i = tab->shapes[k];
        const light *l = &tab->lights[i];
        const light_kind_ops *ops = light_ops(l);
        if (!ops->intersect || (camera_ray && !l->camera_visible))
            continue;
        light_hit h;
        if (ops->intersect(l, o, d, tmax, &h) && h.t > tmin) {
            h.pdf = from ? h.pdf * light_pick_pdf(tab, from, i) : 0.0f;
            *out = h;
            tmax = h.t;
            found = 1;
        }
    }
    return found;
}

float light_escape_pdf(const scene *s, const light_context *c, uint32_t index, vec3 d)
{
    const light *l = &s->lights.lights[index];
    const light_kind_ops *ops = light_ops(l);
    vec3 L;
    float pdf;
    if (!ops->escape || !ops->escape(s, l, c, d, 0, &L, &pdf))
        return 0.0f;
    return pdf;
}

vec3 lights_escape(const scene *s, const light_context *from, vec3 d, float bsdf_pdf, int bsdf_delta,
                   int camera_ray)
{
    const light_table *tab = &s->lights;
    vec3 sum = v3s(0.0f);
    for (uint32_t k = 0; k < tab->shape_count; k++) {
        uint32_t i = tab->shapes[k];
        const light *l = &tab->lights[i];
        const light_kind_ops *ops = light_ops(l);
        vec3 L;
        float pdf;
        if (!ops->escape || !ops->escape(s, l, from, d, camera_ray, &L, &pdf))
            continue;
        float w = bsdf_delta || !from ? 1.0f : mis_power_heuristic(bsdf_pdf, pdf * light_pick_pdf(tab, from, i));
        sum = v3_madd(sum, L, w);
    }
    return sum;
}
