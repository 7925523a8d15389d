/*
 * fingerprint.c — the scene's hashes (fingerprint.h).
 */
#include "cache/fingerprint.h"

#include <math.h>
#include <string.h>

#define FNV_OFFSET 0xcbf29ce484222325ull
#define FNV_PRIME 0x100000001b3ull

static uint64_t hash_u32(uint64_t h, uint32_t v)
{
    for (int b = 0; b < 4; b++) {
        h ^= (v >> (8 * b)) & 0xffu;
        h *= FNV_PRIME;
    }
    return h;
}

/* 32-bit words: uint32_t, int32_t and float alike (a float by its bits). */
static uint64_t hash_words(uint64_t h, const void *p, size_t words)
{
    const unsigned char *c = p;
    for (size_t i = 0; i < words; i++) {
        uint32_t v;
        memcpy(&v, c + 4 * i, 4);
        h = hash_u32(h, v);
    }
    return h;
}

/* Normals rounded to 1/1024: Blender's smooth normals of one mesh vary in
 * their last bits between two evaluations (seen: 128 of 35 712 values by
 * up to 1.2·10⁻⁹), which must not make a saved cache look stale, while
 * smoothing or flattening a surface still changes the hash. A value
 * within the jitter of a rounding boundary would still flip it (odds of
 * about 10⁻⁶ per value). */
static uint64_t hash_normals(uint64_t h, const float *n, size_t count)
{
    h = hash_u32(h, n != NULL);
    for (size_t i = 0; n && i < count; i++)
        h = hash_u32(h, (uint32_t)(int32_t)lrintf(n[i] * 1024.0f));
    return h;
}

/* An optional array: its presence counts too. */
/* A material's program as the core keeps it (folded): its words. */
static uint64_t hash_program(uint64_t h, const shader_program *p)
{
    h = hash_u32(h, p != NULL);
    if (!p)
        return h;
    h = hash_u32(hash_u32(h, p->register_count), p->constant_count);
    h = hash_words(h, p->constants, p->constant_count);
    h = hash_u32(h, p->instruction_count);
    h = hash_words(h, p->instructions, p->instruction_count * (sizeof(phos_shader_instruction) / 4));
    h = hash_u32(h, p->table_size);
    h = hash_words(h, p->table, p->table_size);
    h = hash_u32(h, p->binding_count);
    return hash_words(h, p->bindings, p->binding_count * (sizeof(phos_shader_binding) / 4));
}

static uint64_t hash_array(uint64_t h, const void *p, size_t words)
{
    h = hash_u32(h, p != NULL);
    return p ? hash_words(h, p, words) : h;
}

scene_fingerprint scene_fingerprint_of(const scene *s)
{
    scene_fingerprint f = {FNV_OFFSET, FNV_OFFSET, FNV_OFFSET};
    for (uint32_t i = 0; i < s->mesh_count; i++) {
        const mesh *m = &s->meshes[i];
        f.geometry = hash_u32(hash_u32(f.geometry, m->vertex_count), m->triangle_count);
        f.geometry = hash_words(f.geometry, m->positions, 3 * (size_t)m->vertex_count);
        f.geometry = hash_words(f.geometry, m->indices, 3 * (size_t)m->triangle_count);
        f.geometry = hash_normals(f.geometry, m->normals, 9 * (size_t)m->triangle_count);
        f.geometry = hash_array(f.geometry, m->uvs, 6 * (size_t)m->triangle_count);
        f.geometry = hash_array(f.geometry, m->slots, m->triangle_count);
        f.geometry = hash_array(f.geometry, m->tangents, 12 * (size_t)m->triangle_count);
        f.geometry = hash_words(f.geometry, m->texspace_location, 3);
        f.geometry = hash_words(f.geometry, m->texspace_size, 3);
        f.geometry = hash_u32(f.geometry, m->attribute_count);
        for (uint32_t k = 0; k < m->attribute_count; k++) {
            const mesh_attribute *a = &m->attributes[k];
            f.geometry = hash_u32(hash_u32(f.geometry, a->id), a->type);
            f.geometry = hash_words(f.geometry, a->values, 12 * (size_t)m->triangle_count);
        }
    }
    for (uint32_t i = 0; i < s->instance_count; i++) {
        const instance *in = &s->instances[i];
        f.geometry = hash_u32(f.geometry, in->mesh_id);
        f.geometry = hash_words(f.geometry, in->transform, 12);
        f.geometry = hash_u32(f.geometry, in->material_count);
        f.geometry = hash_words(f.geometry, in->materials, in->material_count);
        f.geometry = hash_words(hash_words(f.geometry, &in->random, 1), &in->pass_index, 1);
    }
    /* phos_closure_desc and phos_light_desc hold 32-bit fields only. */
    for (uint32_t i = 0; i < s->material_count; i++) {
        const material *m = &s->materials[i];
        f.materials = hash_u32(f.materials, m->closure_count);
        f.materials = hash_words(f.materials, m->closures, m->closure_count * (sizeof(phos_closure_desc) / 4));
        f.materials = hash_program(f.materials, m->has_program ? &m->program : NULL);
    }
    for (uint32_t i = 0; i < s->image_count; i++) {
        const image *im = &s->images[i];
        f.materials = hash_u32(hash_u32(f.materials, im->width), im->height);
        f.materials = hash_words(f.materials, im->pixels, 4 * (size_t)im->width * im->height);
    }
    for (uint32_t i = 0; i < s->light_desc_count; i++)
        f.lights = hash_words(f.lights, &s->light_descs[i], sizeof(phos_light_desc) / 4);
    f.lights = hash_words(f.lights, &s->world, sizeof(phos_world_desc) / 4);
    return f;
}

_Static_assert(sizeof(phos_closure_desc) % 4 == 0 && sizeof(phos_light_desc) % 4 == 0 &&
                   sizeof(phos_world_desc) % 4 == 0 && sizeof(phos_shader_instruction) % 4 == 0 &&
                   sizeof(phos_shader_binding) % 4 == 0,
               "the fingerprint hashes these structs as 32-bit words");
