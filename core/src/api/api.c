/*
 * api.c — the public functions of phos.h, and the only place that
 * validates what callers pass in. Everything past this file may assume
 * valid, finite input. A failure never ends the process: it returns a
 * status and leaves a message on the handle.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "lights/environment.h"
#include "lights/light.h"
#include "scene/embree.h"
#include "render/film.h"
#include "render/memory.h"
#include "phos.h"
#include "render/render.h"
#include "render/stages.h"
#include "scene/scene.h"

/* ------------------------------------------------------------- general */

uint32_t phos_version(void) { return PHOS_VERSION; }

const char *phos_status_string(phos_status status)
{
    switch (status) {
    case PHOS_OK: return "ok";
    case PHOS_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case PHOS_ERROR_INVALID_STATE: return "invalid state";
    case PHOS_ERROR_OUT_OF_MEMORY: return "out of memory";
    case PHOS_ERROR_EMBREE: return "ray-tracing kernel error";
    case PHOS_ERROR_CANCELLED: return "cancelled";
    case PHOS_ERROR_TIMEOUT: return "timed out";
    case PHOS_ERROR_INTERNAL: return "internal error";
    }
    return "unknown status";
}

static int all_finite(const float *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

static int all_finite_nonnegative(const float *v, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(v[i]) || v[i] < 0.0f)
            return 0;
    return 1;
}

/* Grows a dynamic array of `count` elements to hold one more. */
static int grow(void **items, uint32_t count, uint32_t *capacity, size_t elem)
{
    if (count < *capacity)
        return 1;
    if (count == UINT32_MAX)
        return 0;
    uint32_t cap = *capacity ? *capacity * 2 : 8;
    if (cap < *capacity)
        cap = UINT32_MAX;
    void *n = realloc(*items, elem * cap);
    if (!n)
        return 0;
    *items = n;
    *capacity = cap;
    return 1;
}

#define FAIL(s, status, ...)              \
    do {                                  \
        scene_set_error((s), __VA_ARGS__); \
        return (status);                  \
    } while (0)

/* Common checks of every scene-changing call: a committed scene that a
 * render holds cannot change (phos.h, scene updates). */
#define CHECK_EDITABLE(s, what, ptr)                                                            \
    do {                                                                                        \
        if (!(s))                                                                               \
            return PHOS_ERROR_INVALID_ARGUMENT;                                                 \
        (s)->error[0] = 0;                                                                      \
        if ((s)->committed && atomic_load(&(s)->refcount) > 1)                                  \
            FAIL((s), PHOS_ERROR_INVALID_STATE,                                                 \
                 "%s: a render holds the committed scene; destroy it before changing the scene", what); \
        if (!(ptr))                                                                             \
            FAIL((s), PHOS_ERROR_INVALID_ARGUMENT, "%s: the description is NULL", what);        \
    } while (0)

/* An update names something the scene has (phos_scene_update_*). */
#define CHECK_EXISTS(s, kind, id, count)                                                        \
    do {                                                                                        \
        if ((id) >= (count))                                                                    \
            FAIL((s), PHOS_ERROR_INVALID_ARGUMENT, "%s: %u does not exist (the scene has %u)",  \
                 kind, (id), (count));                                                          \
    } while (0)

/* A change accepted: the scene needs a commit again, which rebuilds what
 * depends on `what` (enum phos_scene_change). */
static void scene_changed(scene *s, uint32_t what)
{
    s->changed |= what;
    if (what & ~PHOS_CHANGE_CAMERA)
        s->version++;
    s->committed = 0;
}

/* ------------------------------------------------------------ defaults */

void phos_image_desc_init(phos_image_desc *d)
{
    if (!d)
        return;
    memset(d, 0, sizeof(*d));
}

void phos_closure_desc_init(phos_closure_desc *d)
{
    if (!d)
        return;
    memset(d, 0, sizeof(*d));
    d->type = PHOS_CLOSURE_DIFFUSE;
    d->weight[0] = d->weight[1] = d->weight[2] = 0.8f;
    d->roughness = 0.5f;
    d->ior = 1.45f;
    d->specular_color[0] = d->specular_color[1] = d->specular_color[2] = 0.04f;
    d->glass_fresnel = PHOS_GLASS_FRESNEL_MACRO;
    d->transmission_tint[0] = d->transmission_tint[1] = d->transmission_tint[2] = 1.0f;
    d->transmission_roughness = -1.0f;
    d->microfacet = PHOS_MICROFACET_GGX_SEPARABLE;
    for (int k = 0; k < 3; k++) {
        d->multiscatter_fresnel[k] = 1.0f;
        d->specular_tint[k] = 1.0f;
        d->layer_weight[k] = 1.0f;
        d->layer_tint[k] = 1.0f;
    }
    d->thin_film_ior = 1.33f;
    d->roughness_y = -1.0f; /* isotropic */
}

void phos_material_desc_init(phos_material_desc *d)
{
    if (d)
        memset(d, 0, sizeof(*d));
}

void phos_mesh_desc_init(phos_mesh_desc *d)
{
    if (d)
        memset(d, 0, sizeof(*d));
}

static void identity_3x4(float m[12])
{
    memset(m, 0, sizeof(float) * 12);
    m[0] = m[5] = m[10] = 1.0f;
}

void phos_instance_desc_init(phos_instance_desc *d)
{
    if (!d)
        return;
    memset(d, 0, sizeof(*d));
    identity_3x4(d->transform);
}

void phos_light_desc_init(phos_light_desc *d)
{
    if (!d)
        return;
    memset(d, 0, sizeof(*d));
    d->type = PHOS_LIGHT_POINT;
    d->color[0] = d->color[1] = d->color[2] = 1.0f;
    d->direction[2] = -1.0f;
    d->axis_u[0] = 1.0f;
    d->axis_v[1] = 1.0f;
    d->area_shape = PHOS_AREA_RECTANGLE;
    d->point_shape = PHOS_POINT_DISK;
    d->spot_angle = 0.785398163f; /* 45°, Blender's default */
    d->spot_blend = 0.15f;
    d->spot_cosine = 0;
    d->camera_visible = 1;
}

void phos_world_desc_init(phos_world_desc *d)
{
    if (!d)
        return;
    memset(d, 0, sizeof(*d));
    d->material = PHOS_WORLD_NO_MATERIAL;
}

void phos_camera_desc_init(phos_camera_desc *d)
{
    if (!d)
        return;
    memset(d, 0, sizeof(*d));
    d->type = PHOS_CAMERA_PERSPECTIVE;
    identity_3x4(d->transform);
    /* 50 mm lens on a 36 mm sensor, square frame. */
    d->frame_min[0] = d->frame_min[1] = -0.36f;
    d->frame_max[0] = d->frame_max[1] = 0.36f;
    d->focus_distance = 10.0f;
    d->clip_start = 0.1f;
    d->clip_end = 1000.0f;
}

void phos_render_settings_init(phos_render_settings *s)
{
    if (!s)
        return;
    memset(s, 0, sizeof(*s));
#define SETTING_DEFAULT(type, name, def, ...) s->name = (def);
    PHOS_RENDER_SETTINGS(SETTING_DEFAULT, SETTING_DEFAULT)
#undef SETTING_DEFAULT
}

/* --------------------------------------------------------------- scene */

phos_scene *phos_scene_create(void)
{
    scene *s = calloc(1, sizeof(scene));
    if (!s)
        return NULL;
    static atomic_uint_fast64_t scenes_created;
    s->id = atomic_fetch_add(&scenes_created, 1) + 1;
    atomic_init(&s->refcount, 1);
    atomic_init(&s->cancel, 0);
    s->lights.world = -1;
    phos_world_desc_init(&s->world);
    s->camera.type = PHOS_CAMERA_PERSPECTIVE;
    phos_camera_desc_init(&s->camera);
    return s;
}

void phos_scene_destroy(phos_scene *s) { scene_release(s); }

const char *phos_scene_error(const phos_scene *s) { return s ? s->error : "the scene handle is NULL"; }

phos_status phos_scene_add_image(phos_scene *s, const phos_image_desc *d, uint32_t *out_id)
{
    CHECK_EDITABLE(s, "phos_scene_add_image", d);
    if (d->width == 0 || d->height == 0 || d->width > 65536 || d->height > 65536)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "image: size %ux%u must be between 1 and 65536 per side", d->width,
             d->height);
    if (!d->pixels)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "image: pixels are NULL");
    size_t n = (size_t)d->width * d->height * 4;
    if (!all_finite(d->pixels, n))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "image: pixel values must be finite (found NaN or infinity)");
    if (!grow((void **)&s->images, s->image_count, &s->image_capacity, sizeof(image)))
        FAIL(s, PHOS_ERROR_OUT_OF_MEMORY, "image: out of memory");
    image *img = &s->images[s->image_count];
    memset(img, 0, sizeof(*img));
    img->pixels = malloc(n * sizeof(float));
    if (!img->pixels)
        FAIL(s, PHOS_ERROR_OUT_OF_MEMORY, "image: out of memory for %ux%u pixels", d->width, d->height);
    memcpy(img->pixels, d->pixels, n * sizeof(float));
    img->width = d->width;
    img->height = d->height;
    if (out_id)
        *out_id = s->image_count;
    s->image_count++;
    scene_changed(s, PHOS_CHANGE_MATERIALS);
    return PHOS_OK;
}

static int closure_needs_ior(uint32_t type)
{
    return type == PHOS_CLOSURE_GLASS || type == PHOS_CLOSURE_REFRACTION || type == PHOS_CLOSURE_REFLECTION_FRESNEL;
}

static int all_finite_in(const float *v, int n, float lo, float hi)
{
    for (int k = 0; k < n; k++)
        if (!isfinite(v[k]) || v[k] < lo || v[k] > hi)
            return 0;
    return 1;
}

static phos_status validate_closure(scene *s, const phos_closure_desc *c, uint32_t i)
{
    if (c->type >= PHOS_CLOSURE_TYPE_COUNT)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u has unknown type %u", i, c->type);
    if (!all_finite_nonnegative(c->weight, 3))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u weight must be finite and >= 0", i);
    if (!isfinite(c->roughness) || c->roughness < 0.0f || c->roughness > 1.0f)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u roughness %g must be in [0, 1]", i,
             (double)c->roughness);
    if (closure_needs_ior(c->type) && (!isfinite(c->ior) || c->ior <= 0.0f))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u IOR %g must be finite and > 0", i, (double)c->ior);
    if (!all_finite_nonnegative(c->specular_color, 3))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u specular colour must be finite and >= 0", i);
    if (!all_finite_nonnegative(c->transmission_tint, 3))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u transmission tint must be finite and >= 0", i);
    if (!isfinite(c->transmission_roughness) || c->transmission_roughness > 1.0f)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u transmission roughness %g must be <= 1", i,
             (double)c->transmission_roughness);
    if (c->microfacet > PHOS_MICROFACET_ASHIKHMIN_SHIRLEY)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u has unknown microfacet model %u", i,
             c->microfacet);
    if (!all_finite_in(c->multiscatter_fresnel, 3, 0.0f, 1.0f))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u multiscatter Fresnel must be in [0, 1]", i);
    if (!all_finite_in(c->specular_tint, 3, 0.0f, 1.0f))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u specular tint must be in [0, 1]", i);
    if (!isfinite(c->thin_film_thickness) || c->thin_film_thickness < 0.0f || c->thin_film_thickness > 1e6f)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u thin film thickness %g nm must be in [0, 1e6]",
             i, (double)c->thin_film_thickness);
    if (!isfinite(c->thin_film_ior) || c->thin_film_ior <= 0.0f)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u thin film IOR %g must be finite and > 0", i,
             (double)c->thin_film_ior);
    if (!all_finite_nonnegative(c->layer_weight, 3) || !all_finite_nonnegative(c->layer_tint, 3) ||
        !isfinite(c->layer_tint_weight) || c->layer_tint_weight < 0.0f)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u layer weight and tint must be finite and >= 0",
             i);
    if (c->glass_fresnel > PHOS_GLASS_FRESNEL_MICROFACET)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u has unknown glass Fresnel mode %u", i,
             c->glass_fresnel);
    if (!isfinite(c->roughness_y) || c->roughness_y > 1.0f)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT,
             "material: closure %u roughness across the tangent %g must be <= 1 (< 0: isotropic)", i,
             (double)c->roughness_y);
    if (!isfinite(c->tangent_rotation))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u tangent rotation must be finite", i);
    if (c->normal_correction > PHOS_NORMAL_CORRECTION_ONE_ROOT)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u has unknown normal correction %u", i,
             c->normal_correction);
    return PHOS_OK;
}

/* A material from its description, validated (m's program is its own;
 * nothing is changed on failure). */
static phos_status material_from_desc(scene *s, const phos_material_desc *d, material *m)
{
    if (d->closure_count > PHOS_MAX_CLOSURES)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: %u closures, at most %d are supported", d->closure_count,
             PHOS_MAX_CLOSURES);
    if (d->closure_count > 0 && !d->closures)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closures are NULL");
    for (uint32_t i = 0; i < d->closure_count; i++) {
        phos_status st = validate_closure(s, &d->closures[i], i);
        if (st != PHOS_OK)
            return st;
        if (d->closures[i].layer_span > d->closure_count - 1 - i)
            FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "material: closure %u lies over %u closures, but only %u follow it",
                 i, d->closures[i].layer_span, d->closure_count - 1 - i);
    }
    shader_program program;
    memset(&program, 0, sizeof(program));
    if (d->program) {
        char msg[256];
        const char *bad = shader_program_create(d->program, d->closure_count, s->image_count, &program, msg,
                                                sizeof(msg));
        if (bad)
            FAIL(s, strcmp(bad, "out of memory") ? PHOS_ERROR_INVALID_ARGUMENT : PHOS_ERROR_OUT_OF_MEMORY,
                 "material: shader program: %s", bad);
    }
    memset(m, 0, sizeof(*m));
    m->closure_count = d->closure_count;
    if (d->closure_count)
        memcpy(m->closures, d->closures, sizeof(phos_closure_desc) * d->closure_count);
    if (d->program)
        material_set_program(s, m, &program);
    return PHOS_OK;
}

phos_status phos_scene_add_material(phos_scene *s, const phos_material_desc *d, uint32_t *out_id)
{
    CHECK_EDITABLE(s, "phos_scene_add_material", d);
    if (!grow((void **)&s->materials, s->material_count, &s->material_capacity, sizeof(material)))
        FAIL(s, PHOS_ERROR_OUT_OF_MEMORY, "material: out of memory");
    phos_status st = material_from_desc(s, d, &s->materials[s->material_count]);
    if (st != PHOS_OK)
        return st;
    if (out_id)
        *out_id = s->material_count;
    s->material_count++;
    scene_changed(s, PHOS_CHANGE_MATERIALS);
    return PHOS_OK;
}

phos_status phos_scene_update_material(phos_scene *s, uint32_t id, const phos_material_desc *d)
{
    CHECK_EDITABLE(s, "phos_scene_update_material", d);
    CHECK_EXISTS(s, "material", id, s->material_count);
    material m;
    phos_status st = material_from_desc(s, d, &m);
    if (st != PHOS_OK)
        return st;
    shader_program_free(&s->materials[id].program);
    s->materials[id] = m;
    scene_changed(s, PHOS_CHANGE_MATERIALS);
    return PHOS_OK;
}

static void *copy_array(const void *src, size_t bytes)
{
    void *p = malloc(bytes ? bytes : 1);
    if (p && bytes)
        memcpy(p, src, bytes);
    return p;
}

/* Why a mesh's attributes are refused, or NULL: at most
 * PHOS_MAX_MESH_ATTRIBUTES, each of a known type, with finite values and an
 * id no other attribute of the mesh has (an instruction reads one). */
static const char *mesh_attributes_invalid(const phos_mesh_desc *d, char *msg, size_t n)
{
    if (d->attribute_count > PHOS_MAX_MESH_ATTRIBUTES)
        return (snprintf(msg, n, "%u attributes, at most %d", d->attribute_count, PHOS_MAX_MESH_ATTRIBUTES), msg);
    if (d->attribute_count && !d->attributes)
        return "attributes are NULL";
    size_t floats = 12 * (size_t)d->triangle_count;
    for (uint32_t k = 0; k < d->attribute_count; k++) {
        const phos_mesh_attribute *a = &d->attributes[k];
        if (a->type >= PHOS_ATTRIBUTE_TYPE_COUNT)
            return (snprintf(msg, n, "attribute %u has unknown type %u", k, a->type), msg);
        if (floats && !a->values)
            return (snprintf(msg, n, "attribute %u has no values", k), msg);
        if (floats && !all_finite(a->values, floats))
            return (snprintf(msg, n, "attribute %u (id %u) must be finite", k, a->id), msg);
        for (uint32_t j = 0; j < k; j++)
            if (d->attributes[j].id == a->id)
                return (snprintf(msg, n, "attributes %u and %u have the same id %u", j, k, a->id), msg);
    }
    return NULL;
}

/* Copies the desc's attributes into the mesh; 0 when memory runs out
 * (what was copied is the mesh's, for mesh_free). */
static int mesh_copy_attributes(mesh *m, const phos_mesh_desc *d)
{
    if (!d->attribute_count)
        return 1;
    m->attributes = calloc(d->attribute_count, sizeof(mesh_attribute));
    if (!m->attributes)
        return 0;
    size_t bytes = sizeof(float) * 12 * (size_t)d->triangle_count;
    for (uint32_t k = 0; k < d->attribute_count; k++) {
        mesh_attribute *a = &m->attributes[m->attribute_count];
        a->id = d->attributes[k].id;
        a->type = d->attributes[k].type;
        a->values = copy_array(d->attributes[k].values, bytes);
        if (!a->values)
            return 0;
        m->attribute_count++;
    }
    return 1;
}

/* A mesh from its description, validated and copied (nothing is changed
 * on failure). */
static phos_status mesh_from_desc(scene *s, const phos_mesh_desc *d, mesh *out)
{
    if (d->vertex_count > (1u << 30) || d->triangle_count > (1u << 30))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "mesh: %u vertices / %u triangles exceed the limit of 2^30",
             d->vertex_count, d->triangle_count);
    if (d->triangle_count > 0 && (!d->positions || !d->indices || d->vertex_count == 0))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "mesh: positions or indices are NULL");
    if (d->vertex_count > 0 && !d->positions)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "mesh: positions are NULL");
    size_t nv = (size_t)d->vertex_count, nt = (size_t)d->triangle_count;
    for (size_t v = 0; v < nv; v++)
        if (!all_finite(d->positions + 3 * v, 3))
            FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "mesh: vertex %zu has a non-finite coordinate", v);
    for (size_t t = 0; t < 3 * nt; t++)
        if (d->indices[t] >= d->vertex_count)
            FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "mesh: triangle %zu uses vertex %u, but there are only %u vertices",
                 t / 3, d->indices[t], d->vertex_count);
    if (d->normals && !all_finite(d->normals, 9 * nt))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "mesh: normals must be finite");
    if (d->uvs && !all_finite(d->uvs, 6 * nt))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "mesh: UVs must be finite");
    if (d->tangents && !all_finite(d->tangents, 12 * nt))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "mesh: tangents must be finite");
    if (!all_finite(d->texspace_location, 3) || !all_finite_nonnegative(d->texspace_size, 3))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "mesh: the texture space must be finite, its size >= 0");
    char msg[160];
    const char *bad_attribute = mesh_attributes_invalid(d, msg, sizeof(msg));
    if (bad_attribute)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "mesh: %s", bad_attribute);
    mesh m;
    memset(&m, 0, sizeof(m));
    m.vertex_count = d->vertex_count;
    m.triangle_count = d->triangle_count;
    m.positions = copy_array(d->positions, sizeof(float) * 3 * nv);
    m.indices = copy_array(d->indices, sizeof(uint32_t) * 3 * nt);
    m.normals = d->normals ? copy_array(d->normals, sizeof(float) * 9 * nt) : NULL;
    m.uvs = d->uvs ? copy_array(d->uvs, sizeof(float) * 6 * nt) : NULL;
    m.slots = d->material_slots ? copy_array(d->material_slots, sizeof(uint32_t) * nt) : NULL;
    m.tangents = d->tangents ? copy_array(d->tangents, sizeof(float) * 12 * nt) : NULL;
    memcpy(m.texspace_location, d->texspace_location, sizeof(m.texspace_location));
    memcpy(m.texspace_size, d->texspace_size, sizeof(m.texspace_size));
    int attributes_copied = mesh_copy_attributes(&m, d);
    if (!m.positions || !m.indices || (d->normals && !m.normals) || (d->uvs && !m.uvs) ||
        (d->material_slots && !m.slots) || (d->tangents && !m.tangents) || !attributes_copied) {
        mesh_free(&m);
        FAIL(s, PHOS_ERROR_OUT_OF_MEMORY, "mesh: out of memory for %u triangles", d->triangle_count);
    }
    m.changed = 1;
    *out = m;
    return PHOS_OK;
}

phos_status phos_scene_add_mesh(phos_scene *s, const phos_mesh_desc *d, uint32_t *out_id)
{
    CHECK_EDITABLE(s, "phos_scene_add_mesh", d);
    if (!grow((void **)&s->meshes, s->mesh_count, &s->mesh_capacity, sizeof(mesh)))
        FAIL(s, PHOS_ERROR_OUT_OF_MEMORY, "mesh: out of memory");
    phos_status st = mesh_from_desc(s, d, &s->meshes[s->mesh_count]);
    if (st != PHOS_OK)
        return st;
    if (out_id)
        *out_id = s->mesh_count;
    s->mesh_count++;
    scene_changed(s, PHOS_CHANGE_GEOMETRY);
    return PHOS_OK;
}

/* The instances of a replaced mesh keep their slots, which may now name
 * slots it does not have: they take the default material, as a slot past
 * an instance's list does (scene_instance_material). */
phos_status phos_scene_update_mesh(phos_scene *s, uint32_t id, const phos_mesh_desc *d)
{
    CHECK_EDITABLE(s, "phos_scene_update_mesh", d);
    CHECK_EXISTS(s, "mesh", id, s->mesh_count);
    mesh m;
    phos_status st = mesh_from_desc(s, d, &m);
    if (st != PHOS_OK)
        return st;
    mesh_free(&s->meshes[id]);
    s->meshes[id] = m;
    scene_changed(s, PHOS_CHANGE_GEOMETRY);
    return PHOS_OK;
}

/* An instance from its description, validated (nothing is changed on
 * failure). */
static phos_status instance_from_desc(scene *s, const phos_instance_desc *d, instance *inst)
{
    if (d->mesh_id >= s->mesh_count)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "instance: mesh %u does not exist (the scene has %u meshes)", d->mesh_id,
             s->mesh_count);
    if (!all_finite(d->transform, 12))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "instance: the transform must be finite");
    if (d->material_count > 0 && !d->materials)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "instance: materials are NULL");
    if (!isfinite(d->random) || !isfinite(d->pass_index))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "instance: random and pass index must be finite");
    for (uint32_t i = 0; i < d->material_count; i++)
        if (d->materials[i] >= s->material_count)
            FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "instance: slot %u uses material %u, but the scene has %u materials", i,
                 d->materials[i], s->material_count);
    memset(inst, 0, sizeof(*inst));
    inst->mesh_id = d->mesh_id;
    memcpy(inst->transform, d->transform, sizeof(inst->transform));
    inst->random = d->random;
    inst->pass_index = d->pass_index;
    inst->material_count = d->material_count;
    inst->materials = copy_array(d->materials, sizeof(uint32_t) * d->material_count);
    if (!inst->materials)
        FAIL(s, PHOS_ERROR_OUT_OF_MEMORY, "instance: out of memory");
    return PHOS_OK;
}

phos_status phos_scene_add_instance(phos_scene *s, const phos_instance_desc *d, uint32_t *out_id)
{
    CHECK_EDITABLE(s, "phos_scene_add_instance", d);
    if (!grow((void **)&s->instances, s->instance_count, &s->instance_capacity, sizeof(instance)))
        FAIL(s, PHOS_ERROR_OUT_OF_MEMORY, "instance: out of memory");
    phos_status st = instance_from_desc(s, d, &s->instances[s->instance_count]);
    if (st != PHOS_OK)
        return st;
    if (out_id)
        *out_id = s->instance_count;
    s->instance_count++;
    scene_changed(s, PHOS_CHANGE_GEOMETRY);
    return PHOS_OK;
}

/* Instance k of a bulk description as a single one (materials pointing
 * into the shared list). */
static phos_instance_desc instance_of_bulk(const phos_instances_desc *d, uint32_t k)
{
    phos_instance_desc one;
    phos_instance_desc_init(&one);
    one.mesh_id = d->mesh_ids[k];
    memcpy(one.transform, d->transforms + 12 * (size_t)k, sizeof(one.transform));
    one.material_count = d->material_offsets[k + 1] - d->material_offsets[k];
    one.materials = one.material_count ? d->materials + d->material_offsets[k] : NULL;
    one.random = d->randoms ? d->randoms[k] : 0.0f;
    one.pass_index = d->pass_indices ? d->pass_indices[k] : 0.0f;
    return one;
}

phos_status phos_scene_add_instances(phos_scene *s, const phos_instances_desc *d, uint32_t *out_first_id)
{
    CHECK_EDITABLE(s, "phos_scene_add_instances", d);
    if (d->count == 0) {
        if (out_first_id)
            *out_first_id = s->instance_count;
        return PHOS_OK;
    }
    if (!d->mesh_ids || !d->transforms || !d->material_offsets)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "instances: mesh ids, transforms or material offsets are NULL");
    if (d->count > UINT32_MAX - s->instance_count)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "instances: %u more would pass 2^32", d->count);
    if (d->material_offsets[0] != 0)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "instances: material offsets must start at 0");
    for (uint32_t k = 0; k < d->count; k++)
        if (d->material_offsets[k + 1] < d->material_offsets[k])
            FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "instances: material offsets decrease at instance %u", k);
    if (d->material_offsets[d->count] > 0 && !d->materials)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "instances: materials are NULL");
    /* Every instance checked before any is added. */
    uint32_t capacity = s->instance_count + d->count;
    if (capacity > s->instance_capacity) {
        instance *grown = realloc(s->instances, sizeof(instance) * capacity);
        if (!grown)
            FAIL(s, PHOS_ERROR_OUT_OF_MEMORY, "instances: out of memory for %u instances", capacity);
        s->instances = grown;
        s->instance_capacity = capacity;
    }
    for (uint32_t k = 0; k < d->count; k++) {
        phos_instance_desc one = instance_of_bulk(d, k);
        phos_status st = instance_from_desc(s, &one, &s->instances[s->instance_count + k]);
        if (st != PHOS_OK) {
            for (uint32_t j = 0; j < k; j++)
                free(s->instances[s->instance_count + j].materials);
            char msg[sizeof(s->error)];
            snprintf(msg, sizeof(msg), "%s", s->error);
            FAIL(s, st, "instance %u of %u: %s", k, d->count, msg);
        }
    }
    if (out_first_id)
        *out_first_id = s->instance_count;
    s->instance_count += d->count;
    scene_changed(s, PHOS_CHANGE_GEOMETRY);
    return PHOS_OK;
}

phos_status phos_scene_update_instance(phos_scene *s, uint32_t id, const phos_instance_desc *d)
{
    CHECK_EDITABLE(s, "phos_scene_update_instance", d);
    CHECK_EXISTS(s, "instance", id, s->instance_count);
    instance inst;
    phos_status st = instance_from_desc(s, d, &inst);
    if (st != PHOS_OK)
        return st;
    free(s->instances[id].materials);
    free(s->instances[id].emitter_of_triangle);
    s->instances[id] = inst;
    scene_changed(s, PHOS_CHANGE_GEOMETRY);
    return PHOS_OK;
}

static int nonzero3(const float *v) { return v[0] != 0.0f || v[1] != 0.0f || v[2] != 0.0f; }

static phos_status validate_light(scene *s, const phos_light_desc *d)
{
    if (d->type > PHOS_LIGHT_PORTAL)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "light: unknown type %u", d->type);
    if (!all_finite_nonnegative(d->color, 3))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "light: colour must be finite and >= 0");
    if (!all_finite(d->position, 3) || !all_finite(d->direction, 3) || !all_finite(d->axis_u, 3) ||
        !all_finite(d->axis_v, 3))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "light: position, direction and axes must be finite");
    if (d->type != PHOS_LIGHT_POINT && !nonzero3(d->direction))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "light: the direction must not be zero");
    if (d->type == PHOS_LIGHT_AREA || d->type == PHOS_LIGHT_PORTAL) {
        if (d->area_shape > PHOS_AREA_ELLIPSE)
            FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "light: unknown area shape %u", d->area_shape);
        float c[3] = {d->axis_u[1] * d->axis_v[2] - d->axis_u[2] * d->axis_v[1],
                      d->axis_u[2] * d->axis_v[0] - d->axis_u[0] * d->axis_v[2],
                      d->axis_u[0] * d->axis_v[1] - d->axis_u[1] * d->axis_v[0]};
        if (!(c[0] * c[0] + c[1] * c[1] + c[2] * c[2] > 0.0f))
            FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "light: an area light needs a nonzero size along both axes");
    }
    if (!isfinite(d->radius) || d->radius < 0.0f)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "light: radius %g must be finite and >= 0", (double)d->radius);
    if (d->point_shape > PHOS_POINT_SPHERE)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "light: unknown point shape %u", d->point_shape);
    if (d->type == PHOS_LIGHT_SPOT) {
        if (!(d->spot_angle > 0.0f && d->spot_angle <= 3.14159266f))
            FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "light: spot angle %g must be in (0, π]", (double)d->spot_angle);
        if (!(d->spot_blend >= 0.0f && d->spot_blend <= 1.0f))
            FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "light: spot blend %g must be in [0, 1]", (double)d->spot_blend);
    }
    if (d->type == PHOS_LIGHT_SUN && !(d->sun_angle >= 0.0f && d->sun_angle < 3.14159265f))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "light: sun angle %g must be in [0, π)", (double)d->sun_angle);
    return PHOS_OK;
}

phos_status phos_scene_add_light(phos_scene *s, const phos_light_desc *d, uint32_t *out_id)
{
    CHECK_EDITABLE(s, "phos_scene_add_light", d);
    phos_status st = validate_light(s, d);
    if (st != PHOS_OK)
        return st;
    if (!grow((void **)&s->light_descs, s->light_desc_count, &s->light_desc_capacity, sizeof(phos_light_desc)))
        FAIL(s, PHOS_ERROR_OUT_OF_MEMORY, "light: out of memory");
    s->light_descs[s->light_desc_count] = *d;
    if (out_id)
        *out_id = s->light_desc_count;
    s->light_desc_count++;
    scene_changed(s, PHOS_CHANGE_LIGHTS);
    return PHOS_OK;
}

phos_status phos_scene_update_light(phos_scene *s, uint32_t id, const phos_light_desc *d)
{
    CHECK_EDITABLE(s, "phos_scene_update_light", d);
    CHECK_EXISTS(s, "light", id, s->light_desc_count);
    phos_status st = validate_light(s, d);
    if (st != PHOS_OK)
        return st;
    s->light_descs[id] = *d;
    scene_changed(s, PHOS_CHANGE_LIGHTS);
    return PHOS_OK;
}

phos_status phos_scene_set_world(phos_scene *s, const phos_world_desc *d)
{
    CHECK_EDITABLE(s, "phos_scene_set_world", d);
    if (!all_finite_nonnegative(d->color, 3))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "world: colour must be finite and >= 0");
    if (d->material != PHOS_WORLD_NO_MATERIAL && d->material >= s->material_count)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "world: material %u does not exist (%u materials added)", d->material,
             s->material_count);
    s->world = *d;
    scene_changed(s, PHOS_CHANGE_LIGHTS);
    return PHOS_OK;
}

/* What is wrong with a camera, or NULL: for the scene's camera and a
 * render's further views alike. */
static const char *camera_problem(const phos_camera_desc *d)
{
    if (d->type > PHOS_CAMERA_ORTHOGRAPHIC)
        return "unknown type";
    if (!all_finite(d->transform, 12))
        return "the transform must be finite";
    const float *m = d->transform;
    float det = m[0] * (m[5] * m[10] - m[6] * m[9]) - m[1] * (m[4] * m[10] - m[6] * m[8]) +
                m[2] * (m[4] * m[9] - m[5] * m[8]);
    if (!(fabsf(det) > 1e-12f))
        return "the transform is singular (zero scale?)";
    if (!all_finite(d->frame_min, 2) || !all_finite(d->frame_max, 2) || !(d->frame_min[0] < d->frame_max[0]) ||
        !(d->frame_min[1] < d->frame_max[1]))
        return "the frame must be finite with min < max";
    if (!isfinite(d->aperture_radius) || d->aperture_radius < 0.0f)
        return "aperture radius must be finite and >= 0";
    if (d->aperture_radius > 0.0f && !(isfinite(d->focus_distance) && d->focus_distance > 0.0f))
        return "focus distance must be > 0 with depth of field";
    if (!(isfinite(d->clip_start) && d->clip_start >= 0.0f) || !(d->clip_end > d->clip_start))
        return "clipping needs 0 <= start < end";
    return NULL;
}

phos_status phos_scene_set_camera(phos_scene *s, const phos_camera_desc *d)
{
    CHECK_EDITABLE(s, "phos_scene_set_camera", d);
    const char *problem = camera_problem(d);
    if (problem)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "camera: %s", problem);
    s->camera = *d;
    s->has_camera = 1;
    scene_changed(s, PHOS_CHANGE_CAMERA);
    return PHOS_OK;
}

/* A world that varies with direction gets a sampling map at commit
 * (lights/environment.h), of bounded size whatever its image's: refused,
 * as a render is (render/memory.h), when even that cannot fit. */
static phos_status check_environment_memory(phos_scene *s)
{
    if (s->world.material == PHOS_WORLD_NO_MATERIAL || !s->materials[s->world.material].has_program)
        return PHOS_OK;
    uint32_t rows, columns;
    environment_resolution(s, &s->materials[s->world.material], &rows, &columns);
    uint64_t need = environment_bytes(rows, columns), available = memory_available();
    if (need > available)
        FAIL(s, PHOS_ERROR_OUT_OF_MEMORY,
             "commit: the world's sampling map needs %.1f MiB but %.1f MiB is available", (double)need / 1048576.0,
             (double)available / 1048576.0);
    return PHOS_OK;
}

/* What a failed commit built is freed, and every mesh marked changed: the
 * next commit builds everything again. */
static void commit_undo(scene *s)
{
    embree_bvh_destroy(s->bvh);
    s->bvh = NULL;
    light_table_free(&s->lights);
    for (uint32_t i = 0; i < s->instance_count; i++) {
        free(s->instances[i].emitter_of_triangle);
        s->instances[i].emitter_of_triangle = NULL;
    }
    for (uint32_t i = 0; i < s->mesh_count; i++)
        s->meshes[i].changed = 1;
}

/* The BVH: built whole the first time, then only where geometry changed
 * (embree_bvh_update). */
static phos_status commit_bvh(scene *s)
{
    if (!s->bvh)
        return embree_bvh_build(s->meshes, s->mesh_count, s->instances, s->instance_count, &s->cancel, &s->bvh,
                                s->error, sizeof(s->error));
    if (!(s->changed & PHOS_CHANGE_GEOMETRY))
        return PHOS_OK;
    return embree_bvh_update(s->bvh, s->meshes, s->mesh_count, s->instances, s->instance_count, s->error,
                             sizeof(s->error));
}

/* The light table, which reads the lights, the world, the emissive
 * materials and the triangles they cover: rebuilt when any of them changed. */
static phos_status commit_lights(scene *s)
{
    const uint32_t depends = PHOS_CHANGE_GEOMETRY | PHOS_CHANGE_MATERIALS | PHOS_CHANGE_LIGHTS;
    if (s->light_table_builds > 0 && !(s->changed & depends))
        return PHOS_OK;
    light_table_free(&s->lights);
    for (uint32_t i = 0; i < s->instance_count; i++) {
        free(s->instances[i].emitter_of_triangle);
        s->instances[i].emitter_of_triangle = NULL;
    }
    s->light_table_builds++;
    return light_table_build(s);
}

phos_status phos_scene_commit(phos_scene *s)
{
    if (!s)
        return PHOS_ERROR_INVALID_ARGUMENT;
    s->error[0] = 0;
    if (s->committed)
        FAIL(s, PHOS_ERROR_INVALID_STATE, "commit: the scene is already committed");
    int first = s->bvh == NULL;
    /* Scene data first, then what is derived from it: the BVH, the light table. */
    scene_prepare(s);
    phos_status st = check_environment_memory(s);
    if (st != PHOS_OK)
        return st;
    st = commit_bvh(s);
    if (st == PHOS_OK) {
        st = commit_lights(s);
        if (st == PHOS_ERROR_CANCELLED)
            scene_set_error(s, "commit: cancelled");
        else if (st != PHOS_OK)
            scene_set_error(s, "out of memory while building the light table");
    } else if (st == PHOS_ERROR_CANCELLED) {
        scene_set_error(s, "commit: cancelled");
    } else if (!s->error[0]) {
        scene_set_error(s, "could not build the ray-tracing acceleration structure");
    }
    atomic_store(&s->cancel, 0);
    if (st != PHOS_OK) {
        /* Uncommitted again: what was built is freed, a commit may retry. */
        commit_undo(s);
        return st;
    }
    for (uint32_t i = 0; i < s->mesh_count; i++)
        s->meshes[i].changed = 0;
    s->last_changes = first ? (PHOS_CHANGE_GEOMETRY | PHOS_CHANGE_MATERIALS | PHOS_CHANGE_LIGHTS | PHOS_CHANGE_CAMERA)
                            : s->changed;
    s->changed = 0;
    s->committed = 1;
    return PHOS_OK;
}

uint32_t phos_scene_changes(const phos_scene *s) { return s ? s->last_changes : 0; }

void phos_scene_cancel(phos_scene *s)
{
    if (s)
        atomic_store(&s->cancel, 1);
}

/* -------------------------------------------------------------- render */

static void render_set_error(render *r, phos_status st, const char *msg)
{
    pthread_mutex_lock(&r->lock);
    snprintf(r->error, sizeof(r->error), "%s", msg);
    (void)st;
    pthread_mutex_unlock(&r->lock);
}

/* One setting against the range of its row in PHOS_RENDER_SETTINGS (every
 * uint32_t and float is exact as a double). */
static phos_status check_setting(scene *s, const char *name, double v, double lo, double hi, int is_float)
{
    if (isfinite(v) && v >= lo && v <= hi)
        return PHOS_OK;
    const char *finite = is_float ? "finite and " : "";
    if (hi >= (is_float ? (double)FLT_MAX : (double)UINT32_MAX))
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "render: %s %.10g must be %s>= %.10g", name, v, finite, lo);
    FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "render: %s %.10g must be %sbetween %.10g and %.10g", name, v, finite, lo,
         hi);
}

static phos_status validate_settings(scene *s, const phos_render_settings *rs)
{
    phos_status st = PHOS_OK;
#define CHECK_SETTING(type, name, def, lo, hi, ...)                                                          \
    if (st == PHOS_OK)                                                                                      \
        st = check_setting(s, #name, (double)rs->name, (double)(lo), (double)(hi),                          \
                           _Generic(rs->name, float: 1, default: 0));
    PHOS_RENDER_SETTINGS(CHECK_SETTING, CHECK_SETTING)
#undef CHECK_SETTING
    if (st != PHOS_OK)
        return st;
    /* What one row cannot say. */
    if (rs->ic_min_spacing > rs->ic_max_spacing)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "render: ic_min_spacing %g must not exceed ic_max_spacing %g",
             (double)rs->ic_min_spacing, (double)rs->ic_max_spacing);
    if (rs->region_width || rs->region_height) {
        if (rs->region_width == 0 || rs->region_height == 0 || rs->region_x >= rs->width ||
            rs->region_y >= rs->height || rs->region_width > rs->width - rs->region_x ||
            rs->region_height > rs->height - rs->region_y)
            FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "render: region %u,%u %ux%u does not lie inside the %ux%u frame",
                 rs->region_x, rs->region_y, rs->region_width, rs->region_height, rs->width, rs->height);
    }
    return PHOS_OK;
}

phos_status phos_render_create(phos_scene *s, const phos_render_settings *rs, phos_render **out)
{
    if (!s)
        return PHOS_ERROR_INVALID_ARGUMENT;
    s->error[0] = 0;
    if (!out)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "render: the output pointer is NULL");
    *out = NULL;
    if (!rs)
        FAIL(s, PHOS_ERROR_INVALID_ARGUMENT, "render: the settings are NULL");
    if (!s->committed)
        FAIL(s, PHOS_ERROR_INVALID_STATE, "render: the scene must be committed first");
    if (!s->has_camera)
        FAIL(s, PHOS_ERROR_INVALID_STATE, "render: the scene has no camera");
    phos_status st = validate_settings(s, rs);
    if (st != PHOS_OK)
        return st;
    /* Refused before anything is allocated (render/memory.h). */
    memory_estimate need;
    render_memory_estimate(rs, &need);
    if (!render_memory_fits(&need, memory_available(), s->error, sizeof(s->error)))
        return PHOS_ERROR_OUT_OF_MEMORY;

    render *r = calloc(1, sizeof(render));
    if (!r)
        FAIL(s, PHOS_ERROR_OUT_OF_MEMORY, "render: out of memory");
    r->settings = *rs;
    if (!rs->region_width) {
        r->settings.region_x = r->settings.region_y = 0;
        r->settings.region_width = rs->width;
        r->settings.region_height = rs->height;
    }
    pthread_mutex_init(&r->lock, NULL);
    pthread_cond_init(&r->finished_cond, NULL);
    atomic_init(&r->cancel, 0);
    atomic_init(&r->tiles_done, 0u);
    atomic_init(&r->samples_done, 0u);
    atomic_init(&r->work_done, 0u);
    atomic_init(&r->rays_traced, 0u);
    atomic_init(&r->cache_lookups, 0u);
    atomic_init(&r->cache_hits, 0u);
    atomic_init(&r->cache_rays, 0u);
    atomic_init(&r->gather_rays, 0u);
    atomic_init(&r->cache_passes_done, 0u);
    atomic_init(&r->stage_index, 0u);
    atomic_init(&r->photon_progress.emitted, 0u);
    atomic_init(&r->photon_progress.stored, 0u);
    atomic_init(&r->photon_progress.map, PHOS_MAP_GLOBAL);
    r->state = PHOS_STATE_IDLE;
    r->status = PHOS_OK;
    r->stage_started = -1.0;
    r->scene = s;
    atomic_fetch_add(&s->refcount, 1);
    if (!render_prepare(r)) {
        uint32_t w = r->settings.region_width, h = r->settings.region_height;
        phos_render_destroy(r);
        FAIL(s, PHOS_ERROR_OUT_OF_MEMORY, "render: out of memory for a %ux%u film", w, h);
    }
    *out = r;
    return PHOS_OK;
}

void phos_render_destroy(phos_render *r)
{
    if (!r)
        return;
    atomic_store(&r->cancel, 1);
    render_join(r);
    render_free(r);
    pthread_mutex_destroy(&r->lock);
    pthread_cond_destroy(&r->finished_cond);
    if (r->scene)
        scene_release(r->scene);
    free(r);
}

const char *phos_render_error(const phos_render *r) { return r ? r->error : "the render handle is NULL"; }

static phos_status render_refuse(render *r, phos_status st, const char *msg)
{
    render_set_error(r, st, msg);
    return st;
}

phos_status phos_render_set_cache_file(phos_render *r, uint32_t kind, const char *path, uint32_t mode)
{
    if (!r)
        return PHOS_ERROR_INVALID_ARGUMENT;
    if (kind >= PHOS_CACHE_KIND_COUNT)
        return render_refuse(r, PHOS_ERROR_INVALID_ARGUMENT, "set_cache_file: unknown cache kind");
    if (mode > PHOS_CACHE_FILE_LOAD)
        return render_refuse(r, PHOS_ERROR_INVALID_ARGUMENT, "set_cache_file: unknown mode");
    if (mode != PHOS_CACHE_FILE_NONE && (!path || !path[0]))
        return render_refuse(r, PHOS_ERROR_INVALID_ARGUMENT, "set_cache_file: no file name");
    if (path && strlen(path) >= sizeof(r->cache_path[0]))
        return render_refuse(r, PHOS_ERROR_INVALID_ARGUMENT, "set_cache_file: the file name is longer than 1023 bytes");
    pthread_mutex_lock(&r->lock);
    int started = r->started;
    pthread_mutex_unlock(&r->lock);
    if (started)
        return render_refuse(r, PHOS_ERROR_INVALID_STATE, "set_cache_file: the render has started");
    if (kind == PHOS_CACHE_PHOTON_MAPS && mode != PHOS_CACHE_FILE_NONE && r->maps_given)
        return render_refuse(r, PHOS_ERROR_INVALID_STATE,
                                "set_cache_file: the render was given photon maps (phos_render_use_photon_maps)");
    snprintf(r->cache_path[kind], sizeof(r->cache_path[kind]), "%s", mode != PHOS_CACHE_FILE_NONE ? path : "");
    r->cache_file_mode[kind] = mode;
    return PHOS_OK;
}

phos_status phos_render_add_view(phos_render *r, const phos_camera_desc *camera)
{
    if (!r)
        return PHOS_ERROR_INVALID_ARGUMENT;
    if (!camera)
        return render_refuse(r, PHOS_ERROR_INVALID_ARGUMENT, "add_view: the camera is NULL");
    char msg[128];
    const char *problem = camera_problem(camera);
    if (problem) {
        snprintf(msg, sizeof(msg), "add_view: %s", problem);
        return render_refuse(r, PHOS_ERROR_INVALID_ARGUMENT, msg);
    }
    pthread_mutex_lock(&r->lock);
    int started = r->started;
    pthread_mutex_unlock(&r->lock);
    if (started)
        return render_refuse(r, PHOS_ERROR_INVALID_STATE, "add_view: the render has started");
    if (r->view_count >= PHOS_MAX_VIEWS)
        return render_refuse(r, PHOS_ERROR_INVALID_ARGUMENT, "add_view: more than 16384 views");
    phos_camera_desc *views = realloc(r->views, sizeof(*views) * (r->view_count + 1u));
    if (!views)
        return render_refuse(r, PHOS_ERROR_OUT_OF_MEMORY, "add_view: out of memory");
    views[r->view_count++] = *camera;
    r->views = views;
    r->cache_fill.views = r->photon_settings.views = views;
    r->cache_fill.view_count = r->photon_settings.view_count = r->view_count;
    return PHOS_OK;
}

/* ------------------------------------------------- photon maps kept */

static int render_started(render *r)
{
    pthread_mutex_lock(&r->lock);
    int started = r->started;
    pthread_mutex_unlock(&r->lock);
    return started;
}

phos_status phos_render_keep_photon_maps(phos_render *r, phos_photon_maps **out)
{
    if (!r)
        return PHOS_ERROR_INVALID_ARGUMENT;
    if (!out)
        return render_refuse(r, PHOS_ERROR_INVALID_ARGUMENT, "keep_photon_maps: the output pointer is NULL");
    *out = NULL;
    if (!r->use_maps)
        return render_refuse(r, PHOS_ERROR_INVALID_STATE, "keep_photon_maps: this render uses no photon maps");
    if (!atomic_load(&r->maps_complete))
        return render_refuse(r, PHOS_ERROR_INVALID_STATE, "keep_photon_maps: the photon maps are not built yet");
    shared_maps_retain(r->shared);
    *out = r->shared;
    return PHOS_OK;
}

void phos_photon_maps_release(phos_photon_maps *maps) { shared_maps_release(maps); }

phos_status phos_render_use_photon_maps(phos_render *r, phos_photon_maps *maps, uint32_t any_view)
{
    if (!r)
        return PHOS_ERROR_INVALID_ARGUMENT;
    if (!maps)
        return render_refuse(r, PHOS_ERROR_INVALID_ARGUMENT, "use_photon_maps: the maps are NULL");
    if (render_started(r))
        return render_refuse(r, PHOS_ERROR_INVALID_STATE, "use_photon_maps: the render has started");
    if (!r->use_maps)
        return render_refuse(r, PHOS_ERROR_INVALID_STATE, "use_photon_maps: this render uses no photon maps");
    if (r->cache_file_mode[PHOS_CACHE_PHOTON_MAPS] != PHOS_CACHE_FILE_NONE)
        return render_refuse(r, PHOS_ERROR_INVALID_STATE,
                                "use_photon_maps: this render reads or writes its photon maps' file");
    if (maps == r->shared)
        return PHOS_OK;
    char detail[160], msg[256];
    const char *why = shared_maps_mismatch(maps, r->scene, &r->photon_settings,
                                           stage_plan_has(&r->plan, PHOS_STAGE_PRECOMPUTING_RADIANCE),
                                           any_view != 0, detail, sizeof(detail));
    if (why) {
        snprintf(msg, sizeof(msg), "use_photon_maps: %s", why);
        return render_refuse(r, PHOS_ERROR_INVALID_ARGUMENT, msg);
    }
    shared_maps_retain(maps);
    shared_maps_release(r->shared);
    r->shared = maps;
    r->maps = &maps->maps;
    r->maps_given = 1;
    atomic_store(&r->maps_complete, 1);
    stage_plan_drop_photon_stages(&r->plan);
    atomic_store(&r->photon_progress.stored, r->maps->global.count + r->maps->caustic.count);
    atomic_store(&r->photon_progress.emitted, r->maps->global_emitted + r->maps->caustic_emitted);
    return PHOS_OK;
}

phos_status phos_render_start(phos_render *r)
{
    if (!r)
        return PHOS_ERROR_INVALID_ARGUMENT;
    pthread_mutex_lock(&r->lock);
    int started = r->started;
    pthread_mutex_unlock(&r->lock);
    if (started) {
        render_set_error(r, PHOS_ERROR_INVALID_STATE, "start: the render was already started");
        return PHOS_ERROR_INVALID_STATE;
    }
    phos_status st = render_start(r);
    if (st != PHOS_OK && !r->error[0])
        render_set_error(r, st, "start: could not start the render threads");
    return st;
}

phos_status phos_render_progress(phos_render *r, phos_progress *out)
{
    if (!r || !out)
        return PHOS_ERROR_INVALID_ARGUMENT;
    memset(out, 0, sizeof(*out));
    pthread_mutex_lock(&r->lock);
    out->state = r->state;
    memcpy(out->stage_seconds, r->stage_seconds, sizeof(out->stage_seconds));
    if (r->stage_started >= 0.0) /* a stage is running */
        out->stage_seconds[r->plan.stages[atomic_load(&r->stage_index)]] += monotonic_seconds() - r->stage_started;
    pthread_mutex_unlock(&r->lock);
    out->tiles_total = r->tile_count * r->pass_count;
    out->tiles_done = atomic_load(&r->tiles_done);
    out->rays_traced = atomic_load(&r->rays_traced);
    out->samples = r->settings.samples;
    out->samples_done = atomic_load(&r->samples_done);
    out->stage_index = atomic_load(&r->stage_index);
    out->stage_id = r->plan.stages[out->stage_index];
    out->photons_stored = atomic_load(&r->photon_progress.stored);
    out->photons_emitted = atomic_load(&r->photon_progress.emitted);
    out->photon_map = atomic_load(&r->photon_progress.map);
    if (out->stage_id >= PHOS_STAGE_FILLING_IRRADIANCE_CACHE) {
        out->global_photons = r->maps->global.count;
        out->caustic_photons = r->maps->caustic.count;
        out->photon_maps_short = r->maps->short_maps;
    }
    if (out->stage_id >= PHOS_STAGE_RENDERING)
        out->cache_records = r->cache.count;
    out->cache_lookups = atomic_load(&r->cache_lookups);
    out->cache_interpolated = atomic_load(&r->cache_hits);
    out->cache_rays_traced = atomic_load(&r->cache_rays);
    out->gather_rays = atomic_load(&r->gather_rays);
    /* How far through its stage it is; the plan gives each stage its
     * share of the bar. The tiles' part: pixel samples done, over all
     * passes; the photons' part: photons stored over the maps it traces
     * (no global map for the path-traced gather). */
    uint64_t work_total = (uint64_t)r->film.width * r->film.height * r->settings.samples;
    float tiles = work_total ? (float)((double)atomic_load(&r->work_done) / (double)work_total) : 1.0f;
    float photons_target = (float)r->photon_settings.global_photons + (float)r->photon_settings.caustic_photons;
    float within = 0.0f;
    if (out->stage_id == PHOS_STAGE_TRACING_PHOTONS)
        within = photons_target > 0.0f ? (float)out->photons_stored / photons_target : 1.0f;
    else if (out->stage_id == PHOS_STAGE_FILLING_IRRADIANCE_CACHE) {
        uint32_t cache_passes = irradiance_cache_fill_passes(&r->cache_fill);
        within = (float)atomic_load(&r->cache_passes_done) / (float)(cache_passes ? cache_passes : 1);
    } else if (out->stage_id == PHOS_STAGE_RENDERING)
        within = tiles;
    out->fraction = stage_plan_fraction(&r->plan, out->stage_index, within);
    const char *stage = stage_name(out->stage_id, r->settings.integrator);
    if (out->state == PHOS_STATE_CANCELLED)
        stage = "Cancelled";
    else if (out->state == PHOS_STATE_FAILED)
        stage = "Failed";
    snprintf(out->stage, sizeof(out->stage), "%s", stage);
    return PHOS_OK;
}

phos_status phos_render_stages(const phos_render *r, phos_stage_info *out, uint32_t max, uint32_t *out_count)
{
    if (!r || !out_count || (max && !out))
        return PHOS_ERROR_INVALID_ARGUMENT;
    *out_count = r->plan.count;
    for (uint32_t i = 0; i < r->plan.count && i < max; i++) {
        memset(&out[i], 0, sizeof(out[i]));
        out[i].id = r->plan.stages[i];
        snprintf(out[i].name, sizeof(out[i].name), "%s", stage_name(r->plan.stages[i], r->settings.integrator));
    }
    return PHOS_OK;
}

phos_status phos_settings_stages(const phos_render_settings *rs, uint32_t *stage_ids, uint32_t max,
                                 uint32_t *out_count)
{
    if (!rs || !out_count || (max && !stage_ids))
        return PHOS_ERROR_INVALID_ARGUMENT;
    stage_plan plan;
    stage_plan_make(rs, &plan);
    *out_count = plan.count;
    for (uint32_t i = 0; i < plan.count && i < max; i++)
        stage_ids[i] = plan.stages[i];
    return PHOS_OK;
}

phos_status phos_render_next_tile(phos_render *r, phos_tile *out, uint32_t *out_count)
{
    if (!r || !out || !out_count)
        return PHOS_ERROR_INVALID_ARGUMENT;
    *out_count = 0;
    pthread_mutex_lock(&r->lock);
    if (r->finished_read < r->finished_count) {
        *out = r->tiles[r->finished[r->finished_read++]];
        *out_count = 1;
    }
    pthread_mutex_unlock(&r->lock);
    return PHOS_OK;
}

phos_status phos_render_read(phos_render *r, uint32_t pass, uint32_t x, uint32_t y, uint32_t w, uint32_t h,
                             float *dst, size_t dst_count)
{
    if (!r)
        return PHOS_ERROR_INVALID_ARGUMENT;
    char msg[256];
    const film *f = &r->film;
    if (pass >= PHOS_PASS_COUNT || !f->planes[pass]) {
        snprintf(msg, sizeof(msg), "read: pass %u is not enabled in this render", pass);
        render_set_error(r, PHOS_ERROR_INVALID_ARGUMENT, msg);
        return PHOS_ERROR_INVALID_ARGUMENT;
    }
    if (w == 0 || h == 0 || x < f->x0 || y < f->y0 || x - f->x0 > f->width - w || w > f->width ||
        y - f->y0 > f->height - h || h > f->height) {
        snprintf(msg, sizeof(msg), "read: rectangle %u,%u %ux%u is not inside the region %u,%u %ux%u", x, y, w, h,
                 f->x0, f->y0, f->width, f->height);
        render_set_error(r, PHOS_ERROR_INVALID_ARGUMENT, msg);
        return PHOS_ERROR_INVALID_ARGUMENT;
    }
    uint32_t ch = phos_pass_channels(pass);
    if (!dst || dst_count < (size_t)w * h * ch) {
        snprintf(msg, sizeof(msg), "read: the buffer holds %zu floats, %zu are needed", dst_count,
                 (size_t)w * h * ch);
        render_set_error(r, PHOS_ERROR_INVALID_ARGUMENT, msg);
        return PHOS_ERROR_INVALID_ARGUMENT;
    }
    for (uint32_t j = 0; j < h; j++)
        memcpy(dst + (size_t)j * w * ch, film_pixel(f, pass, x, y + j), sizeof(float) * w * ch);
    return PHOS_OK;
}

void phos_render_cancel(phos_render *r)
{
    if (r)
        atomic_store(&r->cancel, 1);
}

phos_status phos_render_wait(phos_render *r, double timeout_seconds)
{
    if (!r)
        return PHOS_ERROR_INVALID_ARGUMENT;
    pthread_mutex_lock(&r->lock);
    if (!r->started) {
        pthread_mutex_unlock(&r->lock);
        render_set_error(r, PHOS_ERROR_INVALID_STATE, "wait: the render was not started");
        return PHOS_ERROR_INVALID_STATE;
    }
    if (timeout_seconds < 0.0) {
        while (r->running)
            pthread_cond_wait(&r->finished_cond, &r->lock);
    } else {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        double whole = floor(timeout_seconds);
        ts.tv_sec += (time_t)whole;
        ts.tv_nsec += (long)((timeout_seconds - whole) * 1e9);
        if (ts.tv_nsec >= 1000000000L) {
            ts.tv_sec += 1;
            ts.tv_nsec -= 1000000000L;
        }
        while (r->running)
            if (pthread_cond_timedwait(&r->finished_cond, &r->lock, &ts) == ETIMEDOUT)
                break;
    }
    int running = r->running;
    phos_status st = r->status;
    pthread_mutex_unlock(&r->lock);
    if (running)
        return PHOS_ERROR_TIMEOUT;
    render_join(r);
    return st;
}
