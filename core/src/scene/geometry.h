/*
 * geometry.h — triangle meshes and their placements, as the scene holds
 * them: what the ray-tracing kernel (embree.c) builds its BVHs from.
 */
#ifndef PHOS_GEOMETRY_H
#define PHOS_GEOMETRY_H

#include <stddef.h>
#include <stdint.h>

/* A per-corner attribute (phos.h, phos_mesh_attribute). */
typedef struct mesh_attribute {
    uint32_t id, type;          /* the number programs read it by; enum phos_attribute_type */
    float *values;              /* triangle_count*12: 4 floats per corner */
} mesh_attribute;

typedef struct mesh {
    uint32_t vertex_count, triangle_count;
    float *positions;           /* vertex_count*3, object space */
    uint32_t *indices;          /* triangle_count*3 */
    float *normals;             /* triangle_count*9 per-corner, or NULL */
    float *uvs;                 /* triangle_count*6, or NULL */
    uint32_t *slots;            /* triangle_count, or NULL */
    float *tangents;            /* triangle_count*12 per-corner MikkTSpace (tangent xyz, sign), or NULL */
    float texspace_location[3], texspace_size[3]; /* the texture space Generated coordinates map to [0,1]³ */
    uint32_t attribute_count;
    mesh_attribute *attributes;
    int changed;                /* added or replaced since the last commit: its BVH is built anew */
} mesh;

/* The mesh's attribute of that id, or NULL. */
static inline const mesh_attribute *mesh_find_attribute(const mesh *m, uint32_t id)
{
    for (uint32_t k = 0; k < m->attribute_count; k++)
        if (m->attributes[k].id == id)
            return &m->attributes[k];
    return NULL;
}

void mesh_free(mesh *m);

typedef struct instance {
    uint32_t mesh_id;
    float transform[12];        /* object → world */
    float normal_matrix[9];     /* inverse transpose of the 3x3 part, row-major */
    float inverse[12];          /* world → object */
    float random;               /* Object Info's Random, [0,1) */
    float pass_index;           /* Object Info's Object Index */
    uint32_t material_count;
    uint32_t *materials;
    int32_t *emitter_of_triangle; /* light index per triangle, or NULL if nothing emits */
    int hidden;                 /* 1: a transform Embree cannot use (scene.c, instance_is_renderable):
                                   nothing of the instance renders, as of an object scaled to zero */
} instance;

static inline uint32_t mesh_triangle_slot(const mesh *m, uint32_t prim)
{
    return m->slots ? m->slots[prim] : 0;
}

#endif /* PHOS_GEOMETRY_H */
