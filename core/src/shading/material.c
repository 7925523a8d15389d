/*
 * material.c — evaluates a material's closure list at a surface point.
 * Shading normals come from per-corner normals transformed by the inverse
 * transpose of the instance transform; textures multiply closure weights.
 */
#include "shading/material.h"

#include "scene/camera.h"
#include "shading/texture.h"
#include "shading/valid_reflection.h"

#include <string.h>

const material scene_default_material = {
    .closure_count = 1,
    .closures = {{.type = PHOS_CLOSURE_DIFFUSE, .weight = {0.8f, 0.8f, 0.8f},
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
    out->ray_flags = 0;
    out->ray_length = 0.0f;
    out->ray_depth = 0;
    out->footprint = 0.0f;
    out->diffuse_depth = out->glossy_depth = out->transmission_depth = out->transparent_depth = 0;
    out->instance = instance_id;
    out->prim = prim;
    out->b1 = b1;
    out->b2 = b2;
    out->mat = scene_instance_material(s, inst, mesh_triangle_slot(m, prim));
}

/* A layer closure's parameters as bsdf.c's layering reads them. */
static bsdf_layer layer_of(const phos_closure_desc *d, float eta, uint32_t frame)
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
    l.frame = frame;
    return l;
}

/* ------------------------------------------------------- shader programs */

static float finite_or(float x, float fallback) { return isfinite(x) ? x : fallback; }

/* Writes a program's value into a closure field, clamped to the range
 * phos_scene_add_material accepts for it (api.c), so a texture can never
 * make a closure invalid. */
static void closure_set_field(phos_closure_desc *c, uint32_t field, const float *v)
{
    float x = finite_or(v[0], 0.0f);
    float rgb[3] = {finite_or(v[0], 0.0f), finite_or(v[1], 0.0f), finite_or(v[2], 0.0f)};
    switch (field) {
    case PHOS_FIELD_WEIGHT:
        for (int k = 0; k < 3; k++)
            c->weight[k] = maxf(rgb[k], 0.0f);
        break;
    case PHOS_FIELD_ROUGHNESS:
        c->roughness = clampf(x, 0.0f, 1.0f);
        break;
    case PHOS_FIELD_IOR:
        c->ior = maxf(x, 1e-5f);
        break;
    case PHOS_FIELD_SPECULAR_COLOR:
        for (int k = 0; k < 3; k++)
            c->specular_color[k] = maxf(rgb[k], 0.0f);
        break;
    case PHOS_FIELD_TRANSMISSION_TINT:
        for (int k = 0; k < 3; k++)
            c->transmission_tint[k] = maxf(rgb[k], 0.0f);
        break;
    case PHOS_FIELD_TRANSMISSION_ROUGHNESS:
        c->transmission_roughness = clampf(x, 0.0f, 1.0f);
        break;
    case PHOS_FIELD_MULTISCATTER_FRESNEL:
        for (int k = 0; k < 3; k++)
            c->multiscatter_fresnel[k] = clampf(rgb[k], 0.0f, 1.0f);
        break;
    case PHOS_FIELD_SPECULAR_TINT:
        for (int k = 0; k < 3; k++)
            c->specular_tint[k] = clampf(rgb[k], 0.0f, 1.0f);
        break;
    case PHOS_FIELD_THIN_FILM_THICKNESS:
        c->thin_film_thickness = clampf(x, 0.0f, 1e6f);
        break;
    case PHOS_FIELD_THIN_FILM_IOR:
        c->thin_film_ior = maxf(x, 1e-5f);
        break;
    case PHOS_FIELD_LAYER_WEIGHT:
        for (int k = 0; k < 3; k++)
            c->layer_weight[k] = maxf(rgb[k], 0.0f);
        break;
    case PHOS_FIELD_LAYER_TINT:
        for (int k = 0; k < 3; k++)
            c->layer_tint[k] = maxf(rgb[k], 0.0f);
        break;
    case PHOS_FIELD_LAYER_TINT_WEIGHT:
        c->layer_tint_weight = maxf(x, 0.0f);
        break;
    case PHOS_FIELD_ROUGHNESS_Y:
        c->roughness_y = clampf(x, 0.0f, 1.0f);
        break;
    case PHOS_FIELD_TANGENT_ROTATION:
        c->tangent_rotation = x;
        break;
    default: /* PHOS_FIELD_NORMAL and _TANGENT set the closure's shading frame (material_eval) */
        break;
    }
}

void material_set_program(const scene *s, material *m, shader_program *p)
{
    float *values = malloc(sizeof(float) * (p->register_count ? p->register_count : 1));
    phos_shader_binding *baked = malloc(sizeof(phos_shader_binding) * (p->binding_count ? p->binding_count : 1));
    uint32_t baked_count = 0;
    if (values && baked) {
        shader_program_fold(p, s, values, baked, &baked_count);
        for (uint32_t b = 0; b < baked_count; b++)
            closure_set_field(&m->closures[baked[b].closure], baked[b].field, values + baked[b].reg);
    }
    free(values);
    free(baked);
    if (p->binding_count == 0) {
        shader_program_free(p); /* constant: costs what a closure list costs */
        m->has_program = 0;
        return;
    }
    m->program = *p;
    m->has_program = 1;
}

/* Barycentric interpolation of a per-corner attribute of n floats. */
static void corner_lerp(const float *corners, int n, float b0, float b1, float b2, float *out)
{
    for (int k = 0; k < n; k++)
        out[k] = b0 * corners[k] + b1 * corners[n + k] + b2 * corners[2 * n + k];
}

/* Tangents along the UV map: with edges e1, e2 and their UV differences,
 * [e1 e2] = [dPdu dPdv] [[du1 du2] [dv1 dv2]]. */
static void uv_tangents(const vec3 v[3], const float *uv, vec3 *dpdu, vec3 *dpdv)
{
    float du1 = uv[2] - uv[0], dv1 = uv[3] - uv[1], du2 = uv[4] - uv[0], dv2 = uv[5] - uv[1];
    float det = du1 * dv2 - du2 * dv1;
    vec3 e1 = v3_sub(v[1], v[0]), e2 = v3_sub(v[2], v[0]);
    if (fabsf(det) < 1e-20f) {
        *dpdu = *dpdv = v3s(0.0f);
        return;
    }
    float k = 1.0f / det;
    *dpdu = v3_scale(v3_sub(v3_scale(e1, dv2), v3_scale(e2, dv1)), k);
    *dpdv = v3_scale(v3_sub(v3_scale(e2, du1), v3_scale(e1, du2)), k);
}

/* Texture Coordinate's Window: the point's place on the camera's frame. */
static vec3 window_coordinates(const scene *s, vec3 p)
{
    float fx = 0.0f, fy = 0.0f;
    vec3 pc;
    if (!s->has_camera || !camera_project(&s->camera, p, &fx, &fy, &pc))
        return v3s(0.0f);
    return v3(fx, fy, 0.0f);
}

/* Two unit vectors that complete n to an orthonormal frame, chosen as
 * Cycles chooses them (make_orthonormals: a = normalize((1,1,1) × n), or
 * (−1,1,1) × n when n lies along (1,1,1); b = n × a), so that the bump's
 * offsets point the same way as Cycles' and a height that bends within
 * them gives the same normal. */
static void footprint_axes(vec3 n, vec3 *a, vec3 *b)
{
    vec3 t = (n.x != n.y || n.x != n.z) ? v3(n.z - n.y, n.x - n.z, n.y - n.x) : v3(n.z - n.y, n.x + n.z, -n.y - n.x);
    *a = v3_normalize(t);
    *b = v3_cross(n, *a);
}

/* The position differentials: the footprint's radius along two orthogonal
 * axes of the plane ⊥ Ng (Cycles' differential_from_compact). A point no
 * camera ray found (a photon hit, a gather ray's) has no footprint: it
 * steps 10⁻⁴ of the scene's size, short enough to be the height's
 * derivative (docs/architecture.md, "Shader programs"). */
static void position_differentials(const scene *s, const surface *sf, shader_globals *g)
{
    float radius = sf->footprint > 0.0f ? sf->footprint : s->bump_offset;
    vec3 a, b;
    footprint_axes(sf->ng, &a, &b);
    g->dPdx = v3_scale(a, radius);
    g->dPdy = v3_scale(b, radius);
}

void material_shader_globals(const scene *s, const surface *sf, uint32_t needs, shader_globals *g)
{
    memset(g, 0, sizeof(*g));
    const instance *inst = &s->instances[sf->instance];
    const mesh *m = &s->meshes[inst->mesh_id];
    float b1 = sf->b1, b2 = sf->b2, b0 = 1.0f - b1 - b2;
    g->P = sf->p;
    g->N = sf->ns;
    g->Ng = sf->ng;
    g->I = sf->wo;
    g->u = sf->u;
    g->v = sf->v;
    g->backfacing = sf->backfacing;
    g->object_to_world = inst->transform;
    g->world_to_object = inst->inverse;
    g->normal_to_world = inst->normal_matrix;
    g->camera_to_world = s->camera.transform;
    g->world_to_camera = s->world_to_camera;
    g->object_P = xform_point(inst->inverse, sf->p);
    for (int k = 0; k < 3; k++) {
        /* Generated = (p − location)·½/size + ½; an axis of size 0 stays at ½. */
        float size = m->texspace_size[k];
        float scale = size != 0.0f ? 0.5f / size : 0.0f;
        float o = k == 0 ? g->object_P.x : k == 1 ? g->object_P.y : g->object_P.z;
        float gen = (o - m->texspace_location[k]) * scale + 0.5f;
        if (k == 0)
            g->generated.x = gen, g->generated_scale.x = scale;
        else if (k == 1)
            g->generated.y = gen, g->generated_scale.y = scale;
        else
            g->generated.z = gen, g->generated_scale.z = scale;
    }
    if (m->uvs && (needs & SHADER_NEEDS_UV_TANGENTS)) {
        vec3 v[3];
        scene_triangle_vertices(s, inst, sf->prim, v);
        uv_tangents(v, m->uvs + 6 * (size_t)sf->prim, &g->dPdu, &g->dPdv);
    }
    if (m->tangents && (needs & SHADER_NEEDS_TANGENT)) {
        float t[4];
        corner_lerp(m->tangents + 12 * (size_t)sf->prim, 4, b0, b1, b2, t);
        vec3 tw = xform_vector(inst->transform, v3(t[0], t[1], t[2]));
        /* Orthogonal to the shading normal, as interpolation breaks it. */
        vec3 n = sf->backfacing ? v3_neg(sf->ns) : sf->ns;
        tw = v3_sub(tw, v3_scale(n, v3_dot(tw, n)));
        if (v3_length2(tw) > 0.0f) {
            g->tangent = v3_normalize(tw);
            g->tangent_sign = t[3] < 0.0f ? -1.0f : 1.0f;
        }
    }
    if (needs & SHADER_NEEDS_WINDOW)
        g->window = window_coordinates(s, sf->p);
    if (needs & SHADER_NEEDS_ATTRIBUTES) {
        g->mesh = m;
        g->prim = sf->prim;
        g->b1 = b1;
        g->b2 = b2;
    }
    g->object_location = v3(inst->transform[3], inst->transform[7], inst->transform[11]);
    g->object_random = inst->random;
    g->object_index = inst->pass_index;
    g->ray_flags = sf->ray_flags;
    g->ray_length = sf->ray_length;
    g->ray_depth = sf->ray_depth;
    if (needs & SHADER_NEEDS_UV_TANGENTS)
        position_differentials(s, sf, g);
    g->diffuse_depth = sf->diffuse_depth;
    g->glossy_depth = sf->glossy_depth;
    g->transmission_depth = sf->transmission_depth;
    g->transparent_depth = sf->transparent_depth;
}

/* A closure's bound Normal as its shading normal: kept when finite and on
 * the viewer's side of the geometric surface, else the surface's. */
static vec3 bound_normal(const surface *sf, const float *r)
{
    vec3 n = v3_load(r);
    if (v3_is_finite(n) && v3_length2(n) > 0.5f && v3_dot(n, sf->ng) > 0.0f)
        return v3_normalize(n);
    return sf->ns;
}

/* The material's closures at the surface: its own when constant, else a
 * copy with the program's values written in, and each closure's shading
 * normal and tangent (ns and ts, when given: the surface's normal and no
 * tangent unless the program binds them). */
static const phos_closure_desc *material_eval(const scene *s, const surface *sf, phos_closure_desc *local,
                                              vec3 *ns, vec3 *ts)
{
    const material *m = sf->mat;
    for (uint32_t i = 0; ns && i < m->closure_count; i++) {
        ns[i] = sf->ns;
        ts[i] = v3s(0.0f);
    }
    if (!m->has_program)
        return m->closures;
    shader_globals g;
    material_shader_globals(s, sf, m->program.needs, &g);
    float r[PHOS_SHADER_MAX_REGISTERS];
    shader_program_eval(&m->program, s, &g, r);
    memcpy(local, m->closures, sizeof(phos_closure_desc) * m->closure_count);
    for (uint32_t b = 0; b < m->program.binding_count; b++) {
        const phos_shader_binding *bd = &m->program.bindings[b];
        if (bd->field == PHOS_FIELD_NORMAL) {
            if (ns)
                ns[bd->closure] = bound_normal(sf, r + bd->reg);
        } else if (bd->field == PHOS_FIELD_TANGENT) {
            vec3 t = v3_load(r + bd->reg);
            if (ts && v3_is_finite(t))
                ts[bd->closure] = t;
        } else {
            closure_set_field(&local[bd->closure], bd->field, r + bd->reg);
        }
    }
    return local;
}

/* Cycles' default tangent (Geometry's Tangent, primitive_tangent): about
 * the object's Z axis through the centre of its texture space,
 * (−(g.y − ½), g.x − ½, 0) in generated coordinates g, to world space as
 * a normal is, then made perpendicular to the surface's normal. */
static vec3 default_tangent(const scene *s, const surface *sf)
{
    shader_globals g;
    material_shader_globals(s, sf, 0, &g);
    vec3 t = normal_to_world(&s->instances[sf->instance], v3(-(g.generated.y - 0.5f), g.generated.x - 0.5f, 0.0f));
    vec3 across = v3_cross(t, sf->ns);
    if (!(v3_length2(across) > 0.0f))
        return v3s(0.0f); /* on the axis: no direction, the frame takes any */
    return v3_cross(sf->ns, v3_normalize(across));
}

/* p turned by angle (radians) about the unit axis k, right-handed
 * (Rodrigues): p cos + (k × p) sin + k (k·p)(1 − cos). */
static vec3 rotate_about(vec3 p, vec3 k, float angle)
{
    float c = cosf(angle), sn = sinf(angle);
    return v3_add(v3_add(v3_scale(p, c), v3_scale(v3_cross(k, p), sn)), v3_scale(k, v3_dot(k, p) * (1.0f - c)));
}

/* Whether a closure is anisotropic GGX (bsdf.h: the reflection closures). */
static int desc_anisotropic(const phos_closure_desc *d)
{
    int reflection = d->type == PHOS_CLOSURE_REFLECTION || d->type == PHOS_CLOSURE_REFLECTION_FRESNEL ||
                     d->type == PHOS_CLOSURE_METAL;
    return reflection && d->roughness_y >= 0.0f && d->roughness_y != clampf(d->roughness, 0.0f, 1.0f);
}

/* The tangent of an anisotropic closure about its normal n: the bound one
 * (t) or Cycles' default, turned by its rotation (turns). */
static vec3 closure_tangent(const scene *s, const surface *sf, const phos_closure_desc *d, vec3 n, vec3 t,
                            vec3 *fallback, int *have_fallback)
{
    if (!(v3_length2(t) > 0.0f)) {
        if (!*have_fallback) {
            *fallback = default_tangent(s, sf);
            *have_fallback = 1;
        }
        t = *fallback;
    }
    if (d->tangent_rotation != 0.0f)
        t = rotate_about(t, n, d->tangent_rotation * 2.0f * PHOS_PI);
    return t;
}

void material_bsdf(const scene *s, const surface *sf, bsdf *out)
{
    phos_closure_desc local[PHOS_MAX_CLOSURES];
    vec3 ns[PHOS_MAX_CLOSURES], ts[PHOS_MAX_CLOSURES];
    const phos_closure_desc *closures = material_eval(s, sf, local, ns, ts);
    vec3 fallback_tangent = v3s(0.0f);
    int have_fallback = 0;
    bsdf_init(out, sf->ns, sf->ng);
    const material *m = sf->mat;
    /* under[i]: the layers over closure i (bit j: the bsdf's layers[j]). */
    uint32_t under[PHOS_MAX_CLOSURES] = {0};
    for (uint32_t i = 0; i < m->closure_count; i++) {
        const phos_closure_desc *d = &closures[i];
        /* The Principled specular IOR describes the coating from outside
         * only; dielectric interfaces invert it when hit from inside. */
        int interface = d->type == PHOS_CLOSURE_GLASS || d->type == PHOS_CLOSURE_REFRACTION;
        float eta = (sf->backfacing && interface) ? 1.0f / d->ior : d->ior;
        /* Each closure in its own frame (bsdf.h): shared when normals agree;
         * an anisotropic one's x axis along its tangent, turned about the
         * normal before the normal is kept from reflecting the viewer into
         * the surface (as Cycles orders them). */
        int anisotropic = desc_anisotropic(d);
        vec3 t = anisotropic ? closure_tangent(s, sf, d, ns[i], ts[i], &fallback_tangent, &have_fallback)
                             : v3s(0.0f);
        vec3 n = valid_reflection_normal(sf->ng, sf->wo, ns[i], d->normal_correction);
        uint32_t frame = bsdf_add_frame(out, n, t);
        if (d->layer_span) {
            bsdf_layer layer = layer_of(d, eta, frame);
            int j = bsdf_add_layer(out, &layer);
            for (uint32_t k = i + 1; j >= 0 && k <= i + d->layer_span && k < m->closure_count; k++)
                under[k] |= 1u << j;
        }
        if (d->type == PHOS_CLOSURE_EMISSION)
            continue;
        closure c;
        c.type = d->type;
        c.weight = v3_load(d->weight);
        c.roughness = clampf(d->roughness, 0.0f, 1.0f);
        c.alpha = c.roughness * c.roughness;
        c.alpha_y = anisotropic ? d->roughness_y * d->roughness_y : c.alpha;
        float rt = d->transmission_roughness < 0.0f ? c.roughness : d->transmission_roughness;
        c.alpha_t = rt * rt;
        c.transmission_tint = v3_load(d->transmission_tint);
        c.eta = eta;
        c.f0 = v3_load(d->specular_color);
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
        c.frame = frame;
        bsdf_add_closure(out, &c);
    }
    bsdf_weight_picks(out, sf->wo);
}

/* The summed weights of the material's closures of one type at the
 * surface (emission, transparency, holdout), textures applied. */
static vec3 weight_of_type(const scene *s, const surface *sf, uint32_t type)
{
    phos_closure_desc local[PHOS_MAX_CLOSURES];
    const phos_closure_desc *closures = material_eval(s, sf, local, NULL, NULL);
    vec3 sum = v3s(0.0f);
    for (uint32_t i = 0; i < sf->mat->closure_count; i++)
        if (closures[i].type == type)
            sum = v3_add(sum, v3_load(closures[i].weight));
    return sum;
}

static vec3 emission_of(const scene *s, const surface *sf)
{
    return weight_of_type(s, sf, PHOS_CLOSURE_EMISSION);
}

vec3 material_emission(const scene *s, const surface *sf)
{
    if (!sf->mat->emissive)
        return v3s(0.0f);
    return emission_of(s, sf);
}

/* Cycles' background shader (shader_setup_from_background): the point is
 * the ray's direction, the normal and the incoming vector its opposite,
 * no object; Generated and Object read the direction too. */
static void background_globals(const scene *s, vec3 d, uint32_t ray_flags, shader_globals *g)
{
    memset(g, 0, sizeof(*g));
    g->P = d;
    g->N = g->Ng = g->I = v3_neg(d);
    g->generated = d;
    g->object_P = d;
    g->background = 1;
    g->camera_to_world = s->camera.transform;
    g->world_to_camera = s->world_to_camera;
    g->ray_flags = ray_flags;
}

vec3 material_background(const scene *s, const material *m, vec3 d, uint32_t ray_flags)
{
    vec3 sum = v3s(0.0f);
    if (!m->has_program) {
        for (uint32_t i = 0; i < m->closure_count; i++)
            if (m->closures[i].type == PHOS_CLOSURE_EMISSION)
                sum = v3_add(sum, v3_load(m->closures[i].weight));
        return sum;
    }
    shader_globals g;
    background_globals(s, d, ray_flags, &g);
    float r[PHOS_SHADER_MAX_REGISTERS];
    shader_program_eval(&m->program, s, &g, r);
    phos_closure_desc local[PHOS_MAX_CLOSURES];
    memcpy(local, m->closures, sizeof(phos_closure_desc) * m->closure_count);
    for (uint32_t b = 0; b < m->program.binding_count; b++) {
        const phos_shader_binding *bd = &m->program.bindings[b];
        if (bd->field != PHOS_FIELD_NORMAL && bd->field != PHOS_FIELD_TANGENT)
            closure_set_field(&local[bd->closure], bd->field, r + bd->reg);
    }
    for (uint32_t i = 0; i < m->closure_count; i++)
        if (local[i].type == PHOS_CLOSURE_EMISSION)
            sum = v3_add(sum, v3_load(local[i].weight));
    /* A program can make NaN or infinity (a division by zero): no light. */
    return v3_is_finite(sum) ? v3_max(sum, v3s(0.0f)) : v3s(0.0f);
}

vec3 material_emission_at(const scene *s, uint32_t instance_id, uint32_t prim, float b1, float b2)
{
    /* A light sample sees the emitter's front: the direction into the
     * triangle against its winding normal. */
    vec3 v[3];
    scene_triangle_vertices(s, &s->instances[instance_id], prim, v);
    vec3 d = v3_neg(v3_normalize(v3_cross(v3_sub(v[1], v[0]), v3_sub(v[2], v[0]))));
    surface sf;
    surface_from_hit(s, instance_id, prim, b1, b2, v3_is_finite(d) ? d : v3(0.0f, 0.0f, -1.0f), &sf);
    return emission_of(s, &sf);
}

vec3 material_emission_estimate_triangle(const scene *s, uint32_t instance_id, uint32_t prim)
{
    const instance *inst = &s->instances[instance_id];
    const material *m = scene_instance_material(s, inst, mesh_triangle_slot(&s->meshes[inst->mesh_id], prim));
    if (!m->has_program)
        return material_emission_estimate(s, m);
    /* A textured emitter: the mean over seven points of the triangle, never
     * zero, so that light picking proportional to it still reaches every
     * part that emits (an estimate only sets the sampling density). */
    static const float b[7][2] = {{1.0f / 3, 1.0f / 3}, {0.1f, 0.1f}, {0.8f, 0.1f}, {0.1f, 0.8f},
                                  {0.45f, 0.1f}, {0.45f, 0.45f}, {0.1f, 0.45f}};
    vec3 sum = v3s(0.0f);
    for (int k = 0; k < 7; k++)
        sum = v3_add(sum, material_emission_at(s, instance_id, prim, b[k][0], b[k][1]));
    return v3_max(v3_scale(sum, 1.0f / 7.0f), v3s(1e-6f));
}

vec3 material_emission_estimate(const scene *s, const material *m)
{
    vec3 sum = v3s(0.0f);
    for (uint32_t i = 0; i < m->closure_count; i++) {
        const phos_closure_desc *c = &m->closures[i];
        if (c->type != PHOS_CLOSURE_EMISSION)
            continue;
        sum = v3_add(sum, v3_load(c->weight));
    }
    return sum;
}

vec3 material_transparency(const scene *s, const surface *sf)
{
    return sf->mat->transparent ? weight_of_type(s, sf, PHOS_CLOSURE_TRANSPARENT) : v3s(0.0f);
}

vec3 material_holdout(const scene *s, const surface *sf)
{
    return sf->mat->holdout ? weight_of_type(s, sf, PHOS_CLOSURE_HOLDOUT) : v3s(0.0f);
}

int material_can_scatter_caustic(const material *m, float max_roughness)
{
    for (uint32_t i = 0; i < m->closure_count; i++) {
        const phos_closure_desc *d = &m->closures[i];
        float r = clampf(d->roughness, 0.0f, 1.0f);
        float rt = d->transmission_roughness < 0.0f ? r : d->transmission_roughness;
        /* Anisotropic: sharp when √(αx αy) is (bsdf.c). */
        float ry = desc_anisotropic(d) ? d->roughness_y : r;
        /* Smoother than max_roughness: glossy, but carrying caustics (bsdf.h;
         * not a dielectric layer, REFLECTION_FRESNEL). */
        int smooth = d->type != PHOS_CLOSURE_REFLECTION_FRESNEL &&
                     fmaxf(r, fmaxf(ry, d->type == PHOS_CLOSURE_GLASS ? rt : 0.0f)) < max_roughness;
        int sharp = r * ry < BSDF_SHARP_ALPHA || smooth, sharp_refraction = rt * rt < BSDF_SHARP_ALPHA;
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

int scene_can_scatter_caustic(const scene *s, float max_roughness)
{
    if (material_can_scatter_caustic(&scene_default_material, max_roughness))
        return 1;
    for (uint32_t i = 0; i < s->material_count; i++)
        if (material_can_scatter_caustic(&s->materials[i], max_roughness))
            return 1;
    return 0;
}
