/*
 * material.c — evaluates a material's closure list at a surface point.
 * Shading normals come from per-corner normals transformed by the inverse
 * transpose of the instance transform; textures multiply closure weights.
 */
#include "shading/material.h"

#include "shading/texture.h"

const material scene_default_material = {
    .closure_count = 1,
    .closures = {{.type = PHOS_CLOSURE_DIFFUSE, .weight = {0.8f, 0.8f, 0.8f}, .weight_image = -1,
                  .roughness = 0.5f, .ior = 1.45f, .transmission_tint = {1.0f, 1.0f, 1.0f},
                  .transmission_roughness = -1.0f}},
};

static vec3 normal_to_world(const instance *inst, vec3 n)
{
    const float *m = inst->normal_matrix;
    return v3(m[0] * n.x + m[1] * n.y + m[2] * n.z, m[3] * n.x + m[4] * n.y + m[5] * n.z,
              m[6] * n.x + m[7] * n.y + m[8] * n.z);
}

void surface_from_hit(const scene *s, uint32_t instance_id, uint32_t prim, float b1, float b2, vec3 d,
                      surface *out)
{
    const instance *inst = &s->instances[instance_id];
    const mesh *m = &s->meshes[inst->mesh_id];
    vec3 v[3];
    scene_triangle_vertices(s, inst, prim, v);
    float b0 = 1.0f - b1 - b2;
    out->p = v3_add(v3_add(v3_scale(v[0], b0), v3_scale(v[1], b1)), v3_scale(v[2], b2));
    vec3 ng = v3_normalize(v3_cross(v3_sub(v[1], v[0]), v3_sub(v[2], v[0])));
    vec3 ns = ng;
    if (m->normals) {
        const float *n = m->normals + 9 * (size_t)prim;
        vec3 nl = v3_add(v3_add(v3_scale(v3_load(n), b0), v3_scale(v3_load(n + 3), b1)), v3_scale(v3_load(n + 6), b2));
        vec3 nw = v3_normalize(normal_to_world(inst, nl));
        if (v3_is_finite(nw) && v3_length2(nw) > 0.5f)
            ns = v3_dot(nw, ng) < 0.0f ? v3_neg(nw) : nw; /* keep it on the winding side */
    }
    out->wo = v3_neg(d);
    out->backfacing = v3_dot(ng, d) > 0.0f;
    if (out->backfacing) {
        ng = v3_neg(ng);
        ns = v3_neg(ns);
    }
    out->ng = ng;
    out->ns = ns;
    if (m->uvs) {
        const float *t = m->uvs + 6 * (size_t)prim;
        out->u = b0 * t[0] + b1 * t[2] + b2 * t[4];
        out->v = b0 * t[1] + b1 * t[3] + b2 * t[5];
    } else {
        out->u = out->v = 0.0f; /* no UV map: Cycles reads (0, 0) */
    }
    out->instance = instance_id;
    out->prim = prim;
    out->mat = scene_instance_material(s, inst, mesh_triangle_slot(m, prim));
}

static vec3 closure_weight(const scene *s, const phos_closure_desc *c, float u, float v)
{
    vec3 w = v3_load(c->weight);
    if (c->weight_image >= 0 && (uint32_t)c->weight_image < s->image_count)
        w = v3_mul(w, image_lookup(&s->images[c->weight_image], u, v));
    return w;
}

/* A layer closure's parameters as bsdf.c's layering reads them. */
static bsdf_layer layer_of(const phos_closure_desc *d, float eta)
{
    bsdf_layer l;
    l.type = d->type;
    l.roughness = clampf(d->roughness, 0.0f, 1.0f);
    l.eta = eta;
    l.microfacet = d->microfacet;
    l.f0 = v3_load(d->specular_color);
    l.fss = v3_load(d->multiscatter_fresnel);
    l.film_thickness = d->thin_film_thickness;
    l.film_ior = d->thin_film_ior;
    l.weight = v3_load(d->layer_weight);
    l.tint = v3_load(d->layer_tint);
    l.tint_weight = d->layer_tint_weight;
    return l;
}

void material_bsdf(const scene *s, const surface *sf, bsdf *out)
{
    bsdf_init(out, sf->ns, sf->ng);
    const material *m = sf->mat;
    /* under[i]: the layers over closure i (bit j: the bsdf's layers[j]). */
    uint32_t under[PHOS_MAX_CLOSURES] = {0};
    for (uint32_t i = 0; i < m->closure_count; i++) {
        const phos_closure_desc *d = &m->closures[i];
        /* The Principled specular IOR describes the coating from outside
         * only; dielectric interfaces invert it when hit from inside. */
        int interface = d->type == PHOS_CLOSURE_GLASS || d->type == PHOS_CLOSURE_REFRACTION;
        float eta = (sf->backfacing && interface) ? 1.0f / d->ior : d->ior;
        if (d->layer_span) {
            bsdf_layer layer = layer_of(d, eta);
            int j = bsdf_add_layer(out, &layer);
            for (uint32_t k = i + 1; j >= 0 && k <= i + d->layer_span && k < m->closure_count; k++)
                under[k] |= 1u << j;
        }
        if (d->type == PHOS_CLOSURE_EMISSION)
            continue;
        closure c;
        c.type = d->type;
        c.weight = closure_weight(s, d, sf->u, sf->v);
        c.roughness = clampf(d->roughness, 0.0f, 1.0f);
        c.alpha = c.roughness * c.roughness;
        float rt = d->transmission_roughness < 0.0f ? c.roughness : d->transmission_roughness;
        c.alpha_t = rt * rt;
        c.transmission_tint = v3_load(d->transmission_tint);
        c.eta = eta;
        c.f0 = v3_load(d->specular_color);
        if (d->type == PHOS_CLOSURE_OREN_NAYAR && d->weight_image >= 0 && (uint32_t)d->weight_image < s->image_count)
            c.f0 = v3_mul(c.f0, image_lookup(&s->images[d->weight_image], sf->u, sf->v)); /* a textured colour */
        c.specular_tint = v3_load(d->specular_tint);
        c.glass_fresnel = d->glass_fresnel;
        c.microfacet = d->microfacet;
        c.fss = v3_load(d->multiscatter_fresnel);
        c.film_thickness = d->thin_film_thickness;
        /* The film's IOR is relative to the outside; seen from inside a
         * glass, the outside medium is the glass (Cycles). */
        c.film_ior = (sf->backfacing && interface) ? d->thin_film_ior / d->ior : d->thin_film_ior;
        c.under_layers = under[i];
        c.sample_weight = 0.0f;
        c.adjoint = 0;
        bsdf_add_closure(out, &c);
    }
}

static vec3 emission_of(const scene *s, const material *m, float u, float v)
{
    vec3 sum = v3s(0.0f);
    for (uint32_t i = 0; i < m->closure_count; i++)
        if (m->closures[i].type == PHOS_CLOSURE_EMISSION)
            sum = v3_add(sum, closure_weight(s, &m->closures[i], u, v));
    return sum;
}

vec3 material_emission(const scene *s, const surface *sf)
{
    if (!sf->mat->emissive)
        return v3s(0.0f);
    return emission_of(s, sf->mat, sf->u, sf->v);
}

vec3 material_emission_at(const scene *s, uint32_t instance_id, uint32_t prim, float b1, float b2)
{
    const instance *inst = &s->instances[instance_id];
    const mesh *m = &s->meshes[inst->mesh_id];
    const material *mat = scene_instance_material(s, inst, mesh_triangle_slot(m, prim));
    float u = 0.0f, v = 0.0f;
    if (m->uvs) {
        const float *t = m->uvs + 6 * (size_t)prim;
        float b0 = 1.0f - b1 - b2;
        u = b0 * t[0] + b1 * t[2] + b2 * t[4];
        v = b0 * t[1] + b1 * t[3] + b2 * t[5];
    }
    return emission_of(s, mat, u, v);
}

vec3 material_emission_estimate(const scene *s, const material *m)
{
    vec3 sum = v3s(0.0f);
    for (uint32_t i = 0; i < m->closure_count; i++) {
        const phos_closure_desc *c = &m->closures[i];
        if (c->type != PHOS_CLOSURE_EMISSION)
            continue;
        vec3 w = v3_load(c->weight);
        if (c->weight_image >= 0 && (uint32_t)c->weight_image < s->image_count)
            w = v3_mul(w, s->images[c->weight_image].average);
        sum = v3_add(sum, w);
    }
    return sum;
}

vec3 material_transparency(const scene *s, const surface *sf)
{
    vec3 sum = v3s(0.0f);
    const material *m = sf->mat;
    if (!m->transparent)
        return sum;
    for (uint32_t i = 0; i < m->closure_count; i++)
        if (m->closures[i].type == PHOS_CLOSURE_TRANSPARENT)
            sum = v3_add(sum, closure_weight(s, &m->closures[i], sf->u, sf->v));
    return sum;
}

int material_can_scatter_delta(const material *m)
{
    for (uint32_t i = 0; i < m->closure_count; i++) {
        const phos_closure_desc *d = &m->closures[i];
        float r = clampf(d->roughness, 0.0f, 1.0f);
        float rt = d->transmission_roughness < 0.0f ? r : d->transmission_roughness;
        int sharp = r * r < BSDF_SHARP_ALPHA, sharp_refraction = rt * rt < BSDF_SHARP_ALPHA;
        int index_matched = fabsf(d->ior - 1.0f) < BSDF_INDEX_MATCHED;
        switch (d->type) {
        case PHOS_CLOSURE_REFLECTION:
        case PHOS_CLOSURE_REFLECTION_FRESNEL:
        case PHOS_CLOSURE_METAL:
            if (sharp)
                return 1;
            break;
        case PHOS_CLOSURE_REFRACTION:
            if (sharp || index_matched)
                return 1;
            break;
        case PHOS_CLOSURE_GLASS:
            if (sharp || sharp_refraction || index_matched)
                return 1;
            break;
        default:
            break;
        }
    }
    return 0;
}

int scene_can_scatter_delta(const scene *s)
{
    if (material_can_scatter_delta(&scene_default_material))
        return 1;
    for (uint32_t i = 0; i < s->material_count; i++)
        if (material_can_scatter_delta(&s->materials[i]))
            return 1;
    return 0;
}
