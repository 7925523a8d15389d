/*
 * mesh_emitter.c — emissive triangles: one light per triangle of a visible
 * instance whose material emits, both faces emitting the material's
 * radiance L(x) (W/(m²·sr)) at each point. Rays find them through the BVH
 * (light_pdf_triangle gives their MIS pdf), not in lights_intersect.
 *
 * Sampled uniformly by area (the square-root warp to barycentrics) and
 * converted to solid angle, pdf_ω = d² / (A·|cos θ_l|) (pbrt-v4's triangle
 * sampling). Their power, for picking, is 2πA·L̄ with L̄ the material's
 * emission estimated over the triangle; photons pick a face with ½ and
 * leave it cosine-weighted, carrying 2πA·L(x) (Jensen 2001 §5.1;
 * docs/algorithms.md §3.1).
 */
#include "lights/light_kind.h"

#include <stdlib.h>
#include <string.h>

#include "sampling/warp.h"

static void triangle_barycentrics(float2 u, float *b1, float *b2)
{
    /* Uniform on the triangle (pbrt-v4's square-root-free warp would also do). */
    float su = sqrtf(u.x);
    *b1 = 1.0f - su;
    *b2 = u.y * su;
}

static vec3 triangle_point(const light *l, float b1, float b2)
{
    return v3_add(v3_add(v3_scale(l->p0, 1.0f - b1 - b2), v3_scale(l->p1, b1)), v3_scale(l->p2, b2));
}

static vec3 triangle_normal(const light *l)
{
    return v3_normalize(v3_cross(v3_sub(l->p1, l->p0), v3_sub(l->p2, l->p0)));
}

/* The light of triangle p of instance i_inst; 0 if it has no area or its
 * emission is black. */
static int triangle_light(scene *s, uint32_t i_inst, uint32_t p, light *l)
{
    memset(l, 0, sizeof(*l));
    l->kind = LIGHT_TRIANGLE;
    l->instance = i_inst;
    l->prim = p;
    vec3 v[3];
    scene_triangle_vertices(s, &s->instances[i_inst], p, v);
    l->p0 = v[0];
    l->p1 = v[1];
    l->p2 = v[2];
    l->area = 0.5f * v3_length(v3_cross(v3_sub(v[1], v[0]), v3_sub(v[2], v[0])));
    l->color = material_emission_estimate_triangle(s, i_inst, p);
    return l->area > 0.0f && !v3_is_zero(l->color);
}

static int instance_may_emit(const scene *s, const instance *inst)
{
    if (inst->hidden)
        return 0;
    for (uint32_t k = 0; k < inst->material_count; k++)
        if (s->materials[inst->materials[k]].emissive)
            return 1;
    return 0;
}

phos_status light_mesh_emitters_add(scene *s, light_table *t, uint32_t *capacity)
{
    for (uint32_t i = 0; i < s->instance_count; i++) {
        instance *inst = &s->instances[i];
        const mesh *m = &s->meshes[inst->mesh_id];
        if (!instance_may_emit(s, inst))
            continue;
        inst->emitter_of_triangle = malloc(sizeof(int32_t) * (m->triangle_count ? m->triangle_count : 1));
        if (!inst->emitter_of_triangle)
            return PHOS_ERROR_OUT_OF_MEMORY;
        for (uint32_t p = 0; p < m->triangle_count; p++) {
            inst->emitter_of_triangle[p] = -1;
            const material *mat = scene_instance_material(s, inst, mesh_triangle_slot(m, p));
            light l;
            if (!mat->emissive || !triangle_light(s, i, p, &l))
                continue;
            inst->emitter_of_triangle[p] = (int32_t)t->count;
            if (!light_table_append(t, capacity, &l))
                return PHOS_ERROR_OUT_OF_MEMORY;
        }
    }
    return PHOS_OK;
}

static float mesh_power(const light *l, float scene_radius)
{
    return 2.0f * PHOS_PI * l->area * light_mean_color(l); /* both faces emit */
}

static int mesh_sample(const scene *s, const light *l, const light_context *c, float2 u, light_sample *out)
{
    float b1, b2;
    triangle_barycentrics(u, &b1, &b2);
    vec3 wi;
    float d, d2;
    if (!light_direction_to(c->p, triangle_point(l, b1, b2), &wi, &d, &d2))
        return 0;
    float cos_l = fabsf(v3_dot(wi, triangle_normal(l)));
    if (!(cos_l > 0.0f))
        return 0;
    out->wi = wi;
    out->distance = d;
    out->radiance = material_emission_at(s, l->instance, l->prim, b1, b2);
    out->pdf = d2 / (l->area * cos_l);
    out->delta = 0;
    return !v3_is_zero(out->radiance);
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

/* A face with ½, then cosine-weighted about it. */
static vec3 mesh_emission_direction(const light *l, float2 u, float *pdf)
{
    vec3 ng = triangle_normal(l);
    if (u.x < 0.5f) {
        ng = v3_neg(ng);
        u.x = 2.0f * u.x;
    } else {
        u.x = 2.0f * u.x - 1.0f;
    }
    vec3 d = warp_cosine_about(ng, u);
    *pdf = 0.5f * maxf(v3_dot(d, ng), 0.0f) * PHOS_INV_PI;
    return d;
}

static int mesh_emit_toward(const scene *s, const light *l, vec3 d, float2 u, vec3 *origin, vec3 *intensity)
{
    float b1, b2;
    triangle_barycentrics(u, &b1, &b2);
    *origin = triangle_point(l, b1, b2);
    float c = fabsf(v3_dot(d, triangle_normal(l))); /* both faces emit */
    *intensity = v3_scale(material_emission_at(s, l->instance, l->prim, b1, b2), l->area * c);
    return c > 0.0f;
}

const light_kind_ops light_mesh_ops = {
    .name = "emissive triangle",
    .desc_type = -1,
    .power = mesh_power,
    .sample = mesh_sample,
    .emission_direction = mesh_emission_direction,
    .emit_toward = mesh_emit_toward,
};
