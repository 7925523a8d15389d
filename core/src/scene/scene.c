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
    for (uint32_t i = 0; i < s->instance_count; i++) {
        normal_matrix(s->instances[i].transform, s->instances[i].normal_matrix);
        s->instances[i].hidden = !instance_is_renderable(s->instances[i].transform);
    }
    for (uint32_t i = 0; i < s->material_count; i++) {
        material *m = &s->materials[i];
        m->emissive = m->transparent = m->transmits = 0;
        for (uint32_t k = 0; k < m->closure_count; k++) {
            if (m->closures[k].type == PHOS_CLOSURE_EMISSION)
                m->emissive = 1;
            if (m->closures[k].type == PHOS_CLOSURE_TRANSPARENT)
                m->transparent = 1;
            if (m->closures[k].type == PHOS_CLOSURE_REFRACTION || m->closures[k].type == PHOS_CLOSURE_GLASS)
                m->transmits = 1;
        }
        if (m->transparent)
            s->has_transparency = 1;
    }
    compute_bounds(s);
}

static void scene_free(scene *s)
{
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        mesh *m = &s->meshes[i];
        free(m->positions);
        free(m->indices);
        free(m->normals);
        free(m->uvs);
        free(m->slots);
    }
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
