/*
 * scene.c — storage of scene data, and the parts of commit that need only
 * that data (normal matrices, material flags, bounds).
 * Arguments have been validated by api.c; here we copy and build.
 */
#include "scene/scene.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/embree.h"

void scene_set_error(scene *s, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(s->error, sizeof(s->error), fmt, ap);
    va_end(ap);
}

void scene_triangle_vertices(const scene *s, const instance *inst, uint32_t prim, vec3 out[3])
{
    const mesh *m = &s->meshes[inst->mesh_id];
    const uint32_t *idx = m->indices + 3 * (size_t)prim;
    for (int k = 0; k < 3; k++)
        out[k] = xform_point(inst->transform, v3_load(m->positions + 3 * (size_t)idx[k]));
}

/* Inverse transpose of the 3x3 part, for normals; singular matrices give
 * the cofactor matrix, which still maps normals to the right direction. */
static void normal_matrix(const float m[12], float out[9])
{
    float a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], i = m[10];
    /* Cofactors = det · inverse transpose; the scale drops out on normalising. */
    out[0] = e * i - f * h;
    out[1] = f * g - d * i;
    out[2] = d * h - e * g;
    out[3] = c * h - b * i;
    out[4] = a * i - c * g;
    out[5] = b * g - a * h;
    out[6] = b * f - c * e;
    out[7] = c * d - a * f;
    out[8] = a * e - b * d;
    float det = a * out[0] + b * out[1] + c * out[2];
    if (det < 0.0f) /* mirrored instance: keep normals on the winding side */
        for (int k = 0; k < 9; k++)
            out[k] = -out[k];
}

/* The inverse of an affine 3x4 transform (identity for a singular one,
 * whose instance does not render). */
static void affine_inverse(const float m[12], float out[12])
{
    float a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], i = m[10];
    float c00 = e * i - f * h, c01 = f * g - d * i, c02 = d * h - e * g;
    float det = a * c00 + b * c01 + c * c02;
    if (!(fabsf(det) > 0.0f)) {
        static const float identity[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
        memcpy(out, identity, sizeof(identity));
        return;
    }
    float k = 1.0f / det;
    /* inverse = adjugate / det: the adjugate is the transposed cofactors. */
    float r[9] = {c00 * k, (c * h - b * i) * k, (b * f - c * e) * k,
                  c01 * k, (a * i - c * g) * k, (c * d - a * f) * k,
                  c02 * k, (b * g - a * h) * k, (a * e - b * d) * k};
    for (int row = 0; row < 3; row++) {
        out[4 * row + 0] = r[3 * row + 0];
        out[4 * row + 1] = r[3 * row + 1];
        out[4 * row + 2] = r[3 * row + 2];
        out[4 * row + 3] = -(r[3 * row + 0] * m[3] + r[3 * row + 1] * m[7] + r[3 * row + 2] * m[11]);
    }
}

/* Blender's automatic texture space: the bounding box of the positions,
 * with a zero extent replaced by 1 and a tiny one raised (BKE's rule). */
static void auto_texture_space(mesh *m)
{
    float s0 = m->texspace_size[0], s1 = m->texspace_size[1], s2 = m->texspace_size[2];
    if (s0 != 0.0f || s1 != 0.0f || s2 != 0.0f)
        return;
    vec3 lo = v3s(INFINITY), hi = v3s(-INFINITY);
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        lo = v3_min(lo, v3_load(m->positions + 3 * (size_t)v));
        hi = v3_max(hi, v3_load(m->positions + 3 * (size_t)v));
    }
    if (lo.x > hi.x)
        lo = hi = v3s(0.0f);
    float loc[3] = {0.5f * (lo.x + hi.x), 0.5f * (lo.y + hi.y), 0.5f * (lo.z + hi.z)};
    float size[3] = {0.5f * (hi.x - lo.x), 0.5f * (hi.y - lo.y), 0.5f * (hi.z - lo.z)};
    for (int k = 0; k < 3; k++) {
        if (size[k] == 0.0f)
            size[k] = 1.0f;
        else if (size[k] > 0.0f && size[k] < 1e-5f)
            size[k] = 1e-5f;
        m->texspace_location[k] = loc[k];
        m->texspace_size[k] = size[k];
    }
}

/* Whether Embree can trace rays through an instance: it maps each ray
 * into the instance's space by the inverse transform, and a ray whose
 * origin or direction leaves ±1.8e18 there fails Embree's validity check
 * (an assertion in Debian's build: the process aborts). A singular 3×3
 * (an object scaled to zero on some axis, which Blender animations use to
 * hide things; or columns that are parallel) has no inverse; columns of
 * length outside [1e-9, 1e9] or a translation beyond 1e15 make the
 * inverse-mapped rays exceed the range for scenes of ordinary size. The
 * relative determinant det / (|c0| |c1| |c2|) is the sine-product of the
 * columns' angles: 1e-6 allows any thin but well-formed placement. */
static int instance_is_renderable(const float m[12])
{
    vec3 c0 = v3(m[0], m[4], m[8]), c1 = v3(m[1], m[5], m[9]), c2 = v3(m[2], m[6], m[10]);
    float l0 = v3_length(c0), l1 = v3_length(c1), l2 = v3_length(c2);
    if (!(l0 >= 1e-9f && l1 >= 1e-9f && l2 >= 1e-9f && l0 <= 1e9f && l1 <= 1e9f && l2 <= 1e9f))
        return 0;
    if (!(fabsf(m[3]) <= 1e15f && fabsf(m[7]) <= 1e15f && fabsf(m[11]) <= 1e15f))
        return 0;
    double det = (double)v3_dot(c0, v3_cross(c1, c2));
    return fabs(det) >= 1e-6 * (double)l0 * (double)l1 * (double)l2;
}

static void compute_bounds(scene *s)
{
    vec3 lo = v3s(INFINITY), hi = v3s(-INFINITY);
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const instance *inst = &s->instances[i];
        const mesh *m = &s->meshes[inst->mesh_id];
        if (m->triangle_count == 0 || inst->hidden)
            continue;
        for (uint32_t v = 0; v < m->vertex_count; v++) {
            vec3 p = xform_point(inst->transform, v3_load(m->positions + 3 * (size_t)v));
            lo = v3_min(lo, p);
            hi = v3_max(hi, p);
        }
    }
    /* Lamps count too, so that a sun's disk covers a scene of lamps only. */
    for (uint32_t i = 0; i < s->light_desc_count; i++) {
        if (s->light_descs[i].type == PHOS_LIGHT_SUN)
            continue;
        vec3 p = v3_load(s->light_descs[i].position);
        lo = v3_min(lo, p);
        hi = v3_max(hi, p);
    }
    if (lo.x > hi.x) {
        lo = v3s(-1.0f);
        hi = v3s(1.0f);
    }
    s->bounds_min = lo;
    s->bounds_max = hi;
}

void scene_prepare(scene *s)
{
    s->has_transparency = 0;
    for (uint32_t i = 0; i < s->instance_count; i++) {
        normal_matrix(s->instances[i].transform, s->instances[i].normal_matrix);
        affine_inverse(s->instances[i].transform, s->instances[i].inverse);
        s->instances[i].hidden = !instance_is_renderable(s->instances[i].transform);
    }
    for (uint32_t i = 0; i < s->material_count; i++) {
        material *m = &s->materials[i];
        m->emissive = m->transparent = m->transmits = m->holdout = 0;
        for (uint32_t k = 0; k < m->closure_count; k++) {
            if (m->closures[k].type == PHOS_CLOSURE_EMISSION)
                m->emissive = 1;
            if (m->closures[k].type == PHOS_CLOSURE_TRANSPARENT)
                m->transparent = 1;
            if (m->closures[k].type == PHOS_CLOSURE_REFRACTION || m->closures[k].type == PHOS_CLOSURE_GLASS ||
                m->closures[k].type == PHOS_CLOSURE_TRANSLUCENT)
                m->transmits = 1;
            if (m->closures[k].type == PHOS_CLOSURE_HOLDOUT)
                m->holdout = 1;
        }
        if (m->transparent)
            s->has_transparency = 1;
    }
    compute_bounds(s);
    for (uint32_t i = 0; i < s->mesh_count; i++)
        auto_texture_space(&s->meshes[i]);
    affine_inverse(s->camera.transform, s->world_to_camera);
    s->bump_offset = 1e-4f * fmaxf(v3_length(v3_sub(s->bounds_max, s->bounds_min)), 1e-3f);
}

void mesh_free(mesh *m)
{
    free(m->positions);
    free(m->indices);
    free(m->normals);
    free(m->uvs);
    free(m->slots);
    free(m->tangents);
    for (uint32_t k = 0; k < m->attribute_count; k++)
        free(m->attributes[k].values);
    free(m->attributes);
    memset(m, 0, sizeof(*m));
}

static void scene_free(scene *s)
{
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        mesh_free(&s->meshes[i]);
    }
    for (uint32_t i = 0; i < s->material_count; i++)
        shader_program_free(&s->materials[i].program);
    for (uint32_t i = 0; i < s->instance_count; i++) {
        free(s->instances[i].materials);
        free(s->instances[i].emitter_of_triangle);
    }
    for (uint32_t i = 0; i < s->image_count; i++)
        free(s->images[i].pixels);
    free(s->meshes);
    free(s->instances);
    free(s->materials);
    free(s->images);
    free(s->light_descs);
    embree_bvh_destroy(s->bvh);
    light_table_free(&s->lights);
    free(s);
}

void scene_release(scene *s)
{
    if (s && atomic_fetch_sub(&s->refcount, 1) == 1)
        scene_free(s);
}
