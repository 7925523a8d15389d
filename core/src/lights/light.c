/*
 * light.c — sampling, evaluation and intersection of every emitter.
 *
 * Sampling follows pbrt-v4 (lights.cpp): uniform area sampling converted to
 * solid angle (pdf_ω = d² / (A·|cos θ_l|)), uniform cone sampling for suns
 * with an angle and for spheres, and the light picked in proportion to its
 * power. What a light emits is defined by the add-on in Cycles' units (see
 * docs/blender.md §1); here everything is already radiometric.
 */
#include "lights/light.h"

#include <stdlib.h>
#include <string.h>

#include "shading/material.h"
#include "scene/scene.h"
#include "sampling/warp.h"

static float smoothstepf(float x)
{
    x = clampf(x, 0.0f, 1.0f);
    return x * x * (3.0f - 2.0f * x);
}

float light_spot_attenuation(const light *l, vec3 dir_from_light)
{
    float c = v3_dot(dir_from_light, l->direction);
    if (c <= l->spot_cos_half)
        return 0.0f;
    float a = l->spot_cosine ? c : 1.0f;
    float t = c - l->spot_cos_half;
    if (l->spot_smooth > 0.0f && t < l->spot_smooth)
        a *= smoothstepf(t / l->spot_smooth);
    return a;
}

/* ∫ a(ω) dω over the spot's cone (sr): 2π ∫ a dcos θ, by the midpoint
 * rule in cos θ, where the blend and the cosine make a smooth. */
static float spot_solid_angle(const light *l)
{
    const int steps = 256;
    float width = 1.0f - l->spot_cos_half, sum = 0.0f;
    for (int k = 0; k < steps; k++) {
        float c = l->spot_cos_half + width * ((float)k + 0.5f) / (float)steps;
        float sin_t = safe_sqrtf(1.0f - c * c);
        vec3 d = v3_add(v3_scale(l->direction, c), v3_scale(frame_from_normal(l->direction).t, sin_t));
        sum += light_spot_attenuation(l, d);
    }
    return 2.0f * PHOS_PI * width * sum / (float)steps;
}

float light_power(const light *l, float scene_radius)
{
    float c = maxf(v3_average(l->color), 0.0f);
    float disk = PHOS_PI * scene_radius * scene_radius; /* m², cross-section of the scene */
    switch (l->kind) {
    case LIGHT_POINT:
        return 4.0f * PHOS_PI * c;                       /* Φ = 4πI */
    case LIGHT_SPOT:
        return spot_solid_angle(l) * c;                  /* Φ = I ∫ a dω */
    case LIGHT_AREA:
        return PHOS_PI * l->area * c;                    /* Φ = πAL, one-sided */
    case LIGHT_SUN: /* Φ = E·πR², or L·Ω·πR² with an angle (light_sample_emission) */
        /* Ω written out: disk·L·cone_solid_angle() would round differently
         * and move the photons' pick probabilities by an ulp. */
        return l->sun_cos_half < 1.0f
                   ? disk * maxf(v3_average(l->sun_radiance), 0.0f) * 2.0f * PHOS_PI * (1.0f - l->sun_cos_half)
                   : disk * c;
    case LIGHT_TRIANGLE:
        return 2.0f * PHOS_PI * l->area * c;             /* both faces emit */
    case LIGHT_WORLD:
        return 4.0f * PHOS_PI * c * disk;                /* L·πR² per steradian, from every direction */
    }
    return 0.0f;
}

/* ---------------------------------------------------------------- build */

static int append_light(light_table *t, uint32_t *capacity, const light *l)
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
    switch (d->type) {
    case PHOS_LIGHT_POINT:
        l->kind = LIGHT_POINT;
        break;
    case PHOS_LIGHT_SPOT:
        l->kind = LIGHT_SPOT;
        l->spot_cos_half = cosf(0.5f * d->spot_angle);
        l->spot_smooth = (1.0f - l->spot_cos_half) * d->spot_blend;
        l->spot_cosine = d->spot_cosine != 0;
        break;
    case PHOS_LIGHT_AREA:
        l->kind = LIGHT_AREA;
        l->axis_u = v3_load(d->axis_u);
        l->axis_v = v3_load(d->axis_v);
        l->area_shape = d->area_shape;
        l->area = v3_length(v3_cross(l->axis_u, l->axis_v));
        if (d->area_shape == PHOS_AREA_ELLIPSE)
            l->area *= PHOS_PI * 0.25f;
        break;
    case PHOS_LIGHT_SUN:
        l->kind = LIGHT_SUN;
        if (d->sun_angle > 0.0f) {
            /* Uniform radiance over the cone gives irradiance L·π·sin²(α/2)
             * at normal incidence; choose L so that it equals E. */
            float s = sinf(0.5f * d->sun_angle);
            l->sun_cos_half = cosf(0.5f * d->sun_angle);
            l->sun_radiance = v3_scale(l->color, 1.0f / (PHOS_PI * s * s));
        }
        break;
    }
}

static phos_status add_emissive_triangles(scene *s, light_table *t, uint32_t *capacity)
{
    for (uint32_t i = 0; i < s->instance_count; i++) {
        instance *inst = &s->instances[i];
        const mesh *m = &s->meshes[inst->mesh_id];
        if (inst->hidden)
            continue;
        int any = 0;
        for (uint32_t k = 0; k < inst->material_count && !any; k++)
            any = s->materials[inst->materials[k]].emissive;
        if (!any)
            continue;
        inst->emitter_of_triangle = malloc(sizeof(int32_t) * (m->triangle_count ? m->triangle_count : 1));
        if (!inst->emitter_of_triangle)
            return PHOS_ERROR_OUT_OF_MEMORY;
        for (uint32_t p = 0; p < m->triangle_count; p++) {
            inst->emitter_of_triangle[p] = -1;
            const material *mat = scene_instance_material(s, inst, mesh_triangle_slot(m, p));
            if (!mat->emissive)
                continue;
            light l;
            memset(&l, 0, sizeof(l));
            l.kind = LIGHT_TRIANGLE;
            l.instance = i;
            l.prim = p;
            vec3 v[3];
            scene_triangle_vertices(s, inst, p, v);
            l.p0 = v[0];
            l.p1 = v[1];
            l.p2 = v[2];
            l.area = 0.5f * v3_length(v3_cross(v3_sub(v[1], v[0]), v3_sub(v[2], v[0])));
            l.color = material_emission_estimate_triangle(s, i, p);
            if (!(l.area > 0.0f) || v3_is_zero(l.color))
                continue;
            inst->emitter_of_triangle[p] = (int32_t)t->count;
            if (!append_light(t, capacity, &l))
                return PHOS_ERROR_OUT_OF_MEMORY;
        }
    }
    return PHOS_OK;
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
        light l;
        light_from_desc(&s->light_descs[i], &l);
        if (v3_is_zero(l.color))
            continue;
        if (!append_light(t, &capacity, &l))
            return PHOS_ERROR_OUT_OF_MEMORY;
    }
    phos_status st = add_emissive_triangles(s, t, &capacity);
    if (st != PHOS_OK)
        return st;
    vec3 world = v3_load(s->world.color);
    if (!v3_is_zero(world)) {
        light l;
        memset(&l, 0, sizeof(l));
        l.kind = LIGHT_WORLD;
        l.color = world;
        t->world = (int32_t)t->count;
        if (!append_light(t, &capacity, &l))
            return PHOS_ERROR_OUT_OF_MEMORY;
    }
    if (t->count == 0)
        return PHOS_OK;
    /* Rays test only the lights they can hit, not every emissive triangle. */
    t->shapes = malloc(sizeof(uint32_t) * t->count);
    if (!t->shapes)
        return PHOS_ERROR_OUT_OF_MEMORY;
    for (uint32_t i = 0; i < t->count; i++) {
        const light *l = &t->lights[i];
        int hittable = l->kind == LIGHT_AREA || l->kind == LIGHT_WORLD ||
                       ((l->kind == LIGHT_POINT || l->kind == LIGHT_SPOT) && l->radius > 0.0f) ||
                       (l->kind == LIGHT_SUN && l->sun_cos_half < 1.0f);
        if (hittable)
            t->shapes[t->shape_count++] = i;
    }
    float *power = malloc(sizeof(float) * t->count);
    if (!power)
        return PHOS_ERROR_OUT_OF_MEMORY;
    for (uint32_t i = 0; i < t->count; i++)
        power[i] = light_power(&t->lights[i], t->radius);
    st = distribution_build(&t->pick, power, t->count) ? light_groups_build(t, power) : PHOS_ERROR_OUT_OF_MEMORY;
    free(power);
    return st;
}

/* ------------------------------------------------------------- sampling */

/* Point and spot lights. Radius 0: a delta light of intensity I. Otherwise
 * a disk facing p (Cycles < 4.0) or a sphere (Cycles 4.0+); either way its
 * radiance is I/(πr²), so that it has intensity I seen from afar. */
static int sample_point(const light *l, vec3 p, float2 u, light_sample *out)
{
    vec3 to_light = v3_sub(l->position, p);
    float d2 = v3_length2(to_light);
    float d = sqrtf(d2);
    if (!(d > 0.0f))
        return 0;
    vec3 axis = v3_scale(to_light, 1.0f / d);
    if (l->radius <= 0.0f) {
        float a = l->kind == LIGHT_SPOT ? light_spot_attenuation(l, v3_neg(axis)) : 1.0f;
        out->wi = axis;
        out->distance = d;
        out->radiance = v3_scale(l->color, a / d2);
        out->pdf = 1.0f;
        out->delta = 1;
        return a > 0.0f;
    }
    float r = l->radius;
    vec3 L = v3_scale(l->color, 1.0f / (PHOS_PI * r * r));
    if (l->point_shape == PHOS_POINT_SPHERE) {
        if (d <= r)
            return 0;
        float sin2 = (r * r) / d2;
        float cos_max = safe_sqrtf(1.0f - sin2);
        vec3 wi = warp_cone(axis, cos_max, u);
        /* Distance to the sphere along wi. */
        float b = v3_dot(wi, to_light);
        float disc = b * b - (d2 - r * r);
        float t = b - safe_sqrtf(disc);
        out->wi = wi;
        out->distance = maxf(t, 0.0f);
        out->pdf = 1.0f / cone_solid_angle(cos_max);
        out->delta = 0;
        /* A sphere spot (Cycles 4) shapes its beam by the direction of each
         * ray leaving it, not by where p lies from its centre. */
        float a = l->kind == LIGHT_SPOT ? light_spot_attenuation(l, v3_neg(wi)) : 1.0f;
        out->radiance = v3_scale(L, a);
        return a > 0.0f && out->pdf > 0.0f && isfinite(out->pdf);
    }
    /* Disk of radius r centred on the light, facing p. */
    frame f = frame_from_normal(v3_neg(axis));
    float2 dk = warp_disk_concentric(u);
    vec3 x = v3_add(l->position, v3_add(v3_scale(f.t, dk.x * r), v3_scale(f.b, dk.y * r)));
    vec3 to_x = v3_sub(x, p);
    float dist2 = v3_length2(to_x);
    float dist = sqrtf(dist2);
    vec3 wi = v3_scale(to_x, 1.0f / dist);
    float cos_l = fabsf(v3_dot(wi, axis));
    if (!(cos_l > 0.0f))
        return 0;
    float a = l->kind == LIGHT_SPOT ? light_spot_attenuation(l, v3_neg(wi)) : 1.0f;
    out->wi = wi;
    out->distance = dist;
    out->pdf = dist2 / (PHOS_PI * r * r * cos_l);
    out->radiance = v3_scale(L, a);
    out->delta = 0;
    return a > 0.0f;
}

static vec3 area_point(const light *l, float2 u)
{
    float a, b;
    if (l->area_shape == PHOS_AREA_ELLIPSE) {
        float2 dk = warp_disk_concentric(u);
        a = 0.5f * dk.x;
        b = 0.5f * dk.y;
    } else {
        a = u.x - 0.5f;
        b = u.y - 0.5f;
    }
    return v3_add(l->position, v3_add(v3_scale(l->axis_u, a), v3_scale(l->axis_v, b)));
}

/* Uniform on the area; one-sided: emits toward +direction. */
static int sample_area(const light *l, vec3 p, float2 u, light_sample *out)
{
    vec3 x = area_point(l, u);
    vec3 to_x = v3_sub(x, p);
    float d2 = v3_length2(to_x);
    float d = sqrtf(d2);
    if (!(d > 0.0f))
        return 0;
    vec3 wi = v3_scale(to_x, 1.0f / d);
    float cos_l = -v3_dot(wi, l->direction);
    if (cos_l <= 0.0f)
        return 0;
    out->wi = wi;
    out->distance = d;
    out->radiance = l->color;
    out->pdf = d2 / (l->area * cos_l);
    out->delta = 0;
    return 1;
}

static int sample_sun(const light *l, float2 u, light_sample *out)
{
    vec3 to_sun = v3_neg(l->direction);
    out->distance = INFINITY;
    if (l->sun_cos_half >= 1.0f) {
        out->wi = to_sun;
        out->radiance = l->color;
        out->pdf = 1.0f;
        out->delta = 1;
        return 1;
    }
    out->wi = warp_cone(to_sun, l->sun_cos_half, u);
    out->radiance = l->sun_radiance;
    out->pdf = 1.0f / cone_solid_angle(l->sun_cos_half);
    out->delta = 0;
    return 1;
}

static void triangle_barycentrics(float2 u, float *b1, float *b2)
{
    /* Uniform on the triangle (pbrt-v4's square-root-free warp would also do). */
    float su = sqrtf(u.x);
    *b1 = 1.0f - su;
    *b2 = u.y * su;
}

static int sample_triangle(const scene *s, const light *l, vec3 p, float2 u, light_sample *out)
{
    float b1, b2;
    triangle_barycentrics(u, &b1, &b2);
    vec3 x = v3_add(v3_add(v3_scale(l->p0, 1.0f - b1 - b2), v3_scale(l->p1, b1)), v3_scale(l->p2, b2));
    vec3 ng = v3_normalize(v3_cross(v3_sub(l->p1, l->p0), v3_sub(l->p2, l->p0)));
    vec3 to_x = v3_sub(x, p);
    float d2 = v3_length2(to_x);
    float d = sqrtf(d2);
    if (!(d > 0.0f))
        return 0;
    vec3 wi = v3_scale(to_x, 1.0f / d);
    float cos_l = fabsf(v3_dot(wi, ng));
    if (!(cos_l > 0.0f))
        return 0;
    out->wi = wi;
    out->distance = d;
    out->radiance = material_emission_at(s, l->instance, l->prim, b1, b2);
    out->pdf = d2 / (l->area * cos_l);
    out->delta = 0;
    return !v3_is_zero(out->radiance);
}

/* The world is sampled cosine-weighted about the shading normal where only
 * light from above it can be reflected (bsdf.c: a reflected wi lies above
 * both normals), so that a diffuse surface under a uniform world gets its
 * irradiance with no variance but that of occlusion; over the whole
 * sphere where the surface also transmits. */
static int world_samples_hemisphere(const light_context *c) { return !c->no_normal && !c->two_sided; }

/* Cosine-weighted direction about n (Malley's method). */
static vec3 sample_cosine_about(vec3 n, float2 u)
{
    frame f = frame_from_normal(n);
    return frame_to_world(&f, warp_cosine_hemisphere(u));
}

static vec3 world_direction(const light_context *c, float2 u)
{
    return world_samples_hemisphere(c) ? sample_cosine_about(c->ns, u) : warp_uniform_sphere(u);
}

float light_world_pdf(const light_context *c, vec3 wi)
{
    if (!c || !world_samples_hemisphere(c))
        return PHOS_INV_4PI;
    return maxf(v3_dot(wi, c->ns), 0.0f) * PHOS_INV_PI;
}

int light_sample_pick(const scene *s, const light_context *c, float u_pick, float2 u, light_sample *out)
{
    const light_table *t = &s->lights;
    if (t->count == 0)
        return 0;
    float pick_pdf;
    uint32_t i = light_pick(t, c, u_pick, &pick_pdf);
    if (!(pick_pdf > 0.0f))
        return 0;
    vec3 p = c->p;
    const light *l = &t->lights[i];
    int ok = 0;
    switch (l->kind) {
    case LIGHT_POINT:
    case LIGHT_SPOT:
        ok = sample_point(l, p, u, out);
        break;
    case LIGHT_AREA:
        ok = sample_area(l, p, u, out);
        break;
    case LIGHT_SUN:
        ok = sample_sun(l, u, out);
        break;
    case LIGHT_TRIANGLE:
        ok = sample_triangle(s, l, p, u, out);
        break;
    case LIGHT_WORLD:
        out->wi = world_direction(c, u);
        out->distance = INFINITY;
        out->radiance = l->color;
        out->pdf = light_world_pdf(c, out->wi);
        out->delta = 0;
        ok = 1;
        break;
    }
    if (!ok || !(out->pdf > 0.0f) || !isfinite(out->pdf))
        return 0;
    out->pdf *= pick_pdf;
    return 1;
}

float light_pdf_triangle(const scene *s, int32_t index, const light_context *c, vec3 x, vec3 ng)
{
    vec3 p = c->p;
    if (index < 0 || (uint32_t)index >= s->lights.count)
        return 0.0f;
    const light *l = &s->lights.lights[index];
    vec3 to_x = v3_sub(x, p);
    float d2 = v3_length2(to_x);
    float cos_l = fabsf(v3_dot(v3_normalize(to_x), ng));
    if (!(cos_l > 0.0f) || !(l->area > 0.0f))
        return 0.0f;
    return light_pick_pdf(&s->lights, c, (uint32_t)index) * d2 / (l->area * cos_l);
}

/* ------------------------------------------------------------- emission */


/* Origin on the disk of the scene's bounding sphere that faces a distant
 * light sending photons along d: every photon that can reach the scene
 * crosses it. Returns the disk area πR² (m²). */
static float distant_origin(const light_table *t, vec3 d, float2 u, vec3 *origin)
{
    frame f = frame_from_normal(d);
    float2 dk = warp_disk_concentric(u);
    vec3 c = v3_madd(t->center, d, -t->radius);
    *origin = v3_add(c, v3_add(v3_scale(f.t, dk.x * t->radius), v3_scale(f.b, dk.y * t->radius)));
    return PHOS_PI * t->radius * t->radius;
}

int light_emit_toward(const scene *s, uint32_t index, vec3 d, float2 u, vec3 *origin, vec3 *intensity)
{
    const light *l = &s->lights.lights[index];
    switch (l->kind) {
    case LIGHT_POINT:
    case LIGHT_SPOT: {
        float a = l->kind == LIGHT_SPOT ? light_spot_attenuation(l, d) : 1.0f;
        /* A lamp of radius r emits the same flux from its surface; start
         * the photon there so it is not born inside nearby geometry. */
        *origin = l->radius > 0.0f ? v3_madd(l->position, d, l->radius) : l->position;
        *intensity = v3_scale(l->color, a); /* I·a */
        return a > 0.0f;
    }
    case LIGHT_AREA: {
        float c = v3_dot(d, l->direction);
        *origin = area_point(l, u);
        *intensity = v3_scale(l->color, l->area * maxf(c, 0.0f)); /* L·A·cos, one-sided */
        return c > 0.0f;
    }
    case LIGHT_TRIANGLE: {
        float b1, b2;
        triangle_barycentrics(u, &b1, &b2);
        *origin = v3_add(v3_add(v3_scale(l->p0, 1.0f - b1 - b2), v3_scale(l->p1, b1)), v3_scale(l->p2, b2));
        vec3 ng = v3_normalize(v3_cross(v3_sub(l->p1, l->p0), v3_sub(l->p2, l->p0)));
        float c = fabsf(v3_dot(d, ng)); /* both faces emit */
        *intensity = v3_scale(material_emission_at(s, l->instance, l->prim, b1, b2), l->area * c);
        return c > 0.0f;
    }
    default:
        return 0;
    }
}

/* Samples the direction a local light's photon leaves by, with its
 * density: uniform over the sphere (points) or the cone (spots), cosine-
 * weighted about the emitting side (area lights; emissive triangles pick a
 * side with ½ first). */
static vec3 emission_direction(const light *l, float2 u, float *pdf)
{
    switch (l->kind) {
    case LIGHT_SPOT:
        *pdf = 1.0f / cone_solid_angle(l->spot_cos_half);
        return warp_cone(l->direction, l->spot_cos_half, u);
    case LIGHT_AREA: {
        vec3 d = sample_cosine_about(l->direction, u);
        *pdf = maxf(v3_dot(d, l->direction), 0.0f) * PHOS_INV_PI;
        return d;
    }
    case LIGHT_TRIANGLE: {
        vec3 ng = v3_normalize(v3_cross(v3_sub(l->p1, l->p0), v3_sub(l->p2, l->p0)));
        if (u.x < 0.5f) {
            ng = v3_neg(ng);
            u.x = 2.0f * u.x;
        } else {
            u.x = 2.0f * u.x - 1.0f;
        }
        vec3 d = sample_cosine_about(ng, u);
        *pdf = 0.5f * maxf(v3_dot(d, ng), 0.0f) * PHOS_INV_PI;
        return d;
    }
    default:
        *pdf = PHOS_INV_4PI;
        return warp_uniform_sphere(u);
    }
}

int light_emit(const scene *s, uint32_t index, const float u[4], vec3 *origin, vec3 *direction, vec3 *flux)
{
    const light_table *t = &s->lights;
    const light *l = &t->lights[index];
    float2 ua = {u[0], u[1]}, ub = {u[2], u[3]};
    switch (l->kind) {
    case LIGHT_SUN: {
        vec3 d = l->sun_cos_half < 1.0f ? warp_cone(l->direction, l->sun_cos_half, ub) : l->direction;
        float area = distant_origin(t, d, ua, origin);
        *direction = d;
        /* A photon per direction of the cone carries L·Ω·πR² (Ω the cone's
         * solid angle), not E·πR²: E = ∫ L cos θ dω = L·π sin²α is less
         * than L·Ω by (1 + cos α)/2 (α the half angle). */
        *flux = l->sun_cos_half < 1.0f
                    ? v3_scale(l->sun_radiance, cone_solid_angle(l->sun_cos_half) * area)
                    : v3_scale(l->color, area); /* E · πR² */
        return 1;
    }
    case LIGHT_WORLD: {
        vec3 w = warp_uniform_sphere(ub); /* where the light comes from */
        vec3 d = v3_neg(w);
        float area = distant_origin(t, d, ua, origin);
        *direction = d;
        *flux = v3_scale(l->color, area / PHOS_INV_4PI); /* L · πR² / p_ω */
        return 1;
    }
    default: {
        float pdf;
        vec3 d = emission_direction(l, ub, &pdf);
        vec3 intensity;
        if (!(pdf > 0.0f) || !light_emit_toward(s, index, d, ua, origin, &intensity))
            return 0;
        *direction = d;
        *flux = v3_scale(intensity, 1.0f / pdf); /* e.g. L cos A / (cos/π) = πAL for an area light */
        return 1;
    }
    }
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

static int intersect_point(const light *l, vec3 o, vec3 d, float tmax, light_hit *out)
{
    if (l->radius <= 0.0f)
        return 0;
    float r = l->radius;
    vec3 oc = v3_sub(l->position, o);
    float dist2 = v3_length2(oc);
    if (dist2 <= r * r)
        return 0;
    float t;
    float pdf;
    vec3 dir_from_light;
    if (l->point_shape == PHOS_POINT_SPHERE) {
        float b = v3_dot(d, oc);
        float disc = b * b - (dist2 - r * r);
        if (disc < 0.0f)
            return 0;
        t = b - sqrtf(disc);
        float cos_max = safe_sqrtf(1.0f - r * r / dist2);
        pdf = 1.0f / cone_solid_angle(cos_max);
        dir_from_light = v3_neg(d); /* as sample_point: the ray's own direction */
    } else {
        /* Disk through the centre, facing the ray origin. */
        float dist = sqrtf(dist2);
        vec3 n = v3_scale(oc, -1.0f / dist);
        float denom = v3_dot(d, n);
        if (denom >= 0.0f)
            return 0;
        t = v3_dot(v3_sub(l->position, o), n) / denom;
        vec3 x = v3_madd(o, d, t);
        if (v3_length2(v3_sub(x, l->position)) > r * r)
            return 0;
        pdf = t * t / (PHOS_PI * r * r * -denom);
        dir_from_light = v3_neg(d);
    }
    if (!(t > 0.0f) || t >= tmax)
        return 0;
    float a = l->kind == LIGHT_SPOT ? light_spot_attenuation(l, dir_from_light) : 1.0f;
    out->t = t;
    out->radiance = v3_scale(l->color, a / (PHOS_PI * r * r));
    out->pdf = pdf;
    return 1;
}

static int intersect_area(const light *l, vec3 o, vec3 d, float tmax, light_hit *out)
{
    float denom = v3_dot(d, l->direction);
    if (denom >= 0.0f) /* one-sided: only the emitting face is seen */
        return 0;
    float t = v3_dot(v3_sub(l->position, o), l->direction) / denom;
    if (!(t > 0.0f) || t >= tmax)
        return 0;
    vec3 x = v3_sub(v3_madd(o, d, t), l->position);
    float lu2 = v3_length2(l->axis_u), lv2 = v3_length2(l->axis_v);
    float a = v3_dot(x, l->axis_u) / lu2; /* in [−0.5, 0.5] inside */
    float b = v3_dot(x, l->axis_v) / lv2;
    int inside = l->area_shape == PHOS_AREA_ELLIPSE ? (a * a + b * b <= 0.25f)
                                                    : (fabsf(a) <= 0.5f && fabsf(b) <= 0.5f);
    if (!inside)
        return 0;
    out->t = t;
    out->radiance = l->color;
    out->pdf = t * t / (l->area * -denom);
    return 1;
}

int lights_intersect(const scene *s, const light_context *from, vec3 o, vec3 d, float tmin, float tmax,
                     int camera_ray, light_hit *out)
{
    const light_table *tab = &s->lights;
    int found = 0;
    for (uint32_t k = 0; k < tab->shape_count; k++) {
        uint32_t i = tab->shapes[k];
        const light *l = &tab->lights[i];
        if (camera_ray && !l->camera_visible)
            continue;
        light_hit h;
        int hit = 0;
        if (l->kind == LIGHT_POINT || l->kind == LIGHT_SPOT)
            hit = intersect_point(l, o, d, tmax, &h);
        else if (l->kind == LIGHT_AREA)
            hit = intersect_area(l, o, d, tmax, &h);
        if (hit && h.t > tmin) {
            h.pdf = from ? h.pdf * light_pick_pdf(tab, from, i) : 0.0f;
            *out = h;
            tmax = h.t;
            found = 1;
        }
    }
    return found;
}

vec3 lights_escape(const scene *s, const light_context *from, vec3 d, float bsdf_pdf, int bsdf_delta,
                   int camera_ray)
{
    const light_table *tab = &s->lights;
    vec3 sum = v3s(0.0f);
    for (uint32_t k = 0; k < tab->shape_count; k++) {
        uint32_t i = tab->shapes[k];
        const light *l = &tab->lights[i];
        if (camera_ray && l->kind == LIGHT_SUN && !l->camera_visible)
            continue;
        vec3 L;
        float pdf;
        if (l->kind == LIGHT_WORLD) {
            L = l->color;
            pdf = light_world_pdf(from, d);
        } else if (l->kind == LIGHT_SUN && l->sun_cos_half < 1.0f) {
            if (-v3_dot(d, l->direction) < l->sun_cos_half)
                continue;
            L = l->sun_radiance;
            pdf = 1.0f / cone_solid_angle(l->sun_cos_half);
        } else {
            continue;
        }
        float w = bsdf_delta || !from ? 1.0f : mis_power_heuristic(bsdf_pdf, pdf * light_pick_pdf(tab, from, i));
        sum = v3_madd(sum, L, w);
    }
    return sum;
}
