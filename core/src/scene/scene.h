/*
 * scene.h — the scene as the core holds it: copies of the caller's meshes,
 * instances, materials, images, lights, world and camera, and what
 * phos_scene_commit derives from them (the ray-tracing BVH and the light
 * table). After commit the scene is read-only and shared by renders; once
 * no render holds it, it may be changed and committed again, and commit
 * then rebuilds only what the changes touched (docs/architecture.md,
 * "Scene updates").
 */
#ifndef PHOS_SCENE_H
#define PHOS_SCENE_H

#include <stdatomic.h>
#include <stddef.h>

#include "lights/light_table.h"
#include "phos.h"
#include "scene/geometry.h"
#include "shading/shader_program.h"
#include "util/vec.h"

typedef struct material {
    uint32_t closure_count;
    phos_closure_desc closures[PHOS_MAX_CLOSURES];
    int has_program;            /* closures' fields vary over the surface: program sets them */
    shader_program program;
    int emissive;               /* has an EMISSION closure */
    int transparent;            /* has a TRANSPARENT closure */
    int transmits;              /* has a REFRACTION, GLASS or TRANSLUCENT closure: scatters light to its
                                   other side */
    int holdout;                /* has a HOLDOUT closure */
} material;

typedef struct image {
    uint32_t width, height;
    float *pixels;              /* width*height*4, linear RGBA, rows bottom-up */
} image;

struct embree_bvh;

struct phos_scene {
    char error[512];
    atomic_int refcount;        /* the caller's reference plus one per render */
    atomic_int cancel;          /* phos_scene_cancel: stop the commit running */
    int committed;
    uint32_t changed;           /* enum phos_scene_change: what changed since the last commit */
    uint32_t last_changes;      /* what had changed before the last commit (phos_scene_changes) */
    uint32_t light_table_builds; /* light tables built so far, for the tests of scene updates */
    /* Which scene, and which version of everything but its camera: what
     * photon maps kept between renders were made from (photons/shared_maps.h). */
    uint64_t id;
    uint64_t version;

    mesh *meshes;         uint32_t mesh_count, mesh_capacity;
    instance *instances;  uint32_t instance_count, instance_capacity;
    material *materials;  uint32_t material_count, material_capacity;
    image *images;        uint32_t image_count, image_capacity;
    phos_light_desc *light_descs; uint32_t light_desc_count, light_desc_capacity;
    phos_world_desc world;
    phos_camera_desc camera;
    int has_camera;
    float world_to_camera[12];     /* for shader programs (Texture Coordinate's Camera, Vector Transform) */

    /* Built by commit. */
    struct embree_bvh *bvh;
    vec3 bounds_min, bounds_max;   /* world bounds of all geometry, scene units */
    light_table lights;
    int has_transparency;          /* some material lets shadow rays through */
    float bump_offset;             /* a Bump's footprint where no pixel's ray found the point: 1e-4 of the scene's diagonal */
};

typedef struct phos_scene scene;

/* The material used where an instance has no material for a slot. */
extern const material scene_default_material;

static inline const material *scene_instance_material(const scene *s, const instance *inst,
                                                      uint32_t slot)
{
    if (slot < inst->material_count)
        return &s->materials[inst->materials[slot]];
    return &scene_default_material;
}

/* World-space triangle corners of (instance, primitive). */
void scene_triangle_vertices(const scene *s, const instance *inst, uint32_t prim, vec3 out[3]);

/* The part of commit that needs only the scene's own data: material flags
 * and world bounds. phos_scene_commit (api.c) then builds the BVH and the
 * light table from them. */
void scene_prepare(scene *s);

void scene_release(scene *s);

void scene_set_error(scene *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

#endif /* PHOS_SCENE_H */
