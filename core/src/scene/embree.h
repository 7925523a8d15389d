/*
 * embree.h — the ray-tracing kernel behind one small interface. All Embree
 * calls live in embree.c, which builds against Embree 3 or Embree 4.
 */
#ifndef PHOS_EMBREE_H
#define PHOS_EMBREE_H

#include <stdatomic.h>
#include <stddef.h>

#include "phos.h"
#include "scene/geometry.h"
#include "util/vec.h"

typedef struct ray_hit {
    float t;
    uint32_t instance, prim;
    float b1, b2;           /* barycentric weights of corners 1 and 2 */
} ray_hit;

struct embree_bvh;

/* One BVH per mesh, shared by its instances, under a top-level BVH of
 * instances. *out is set before anything can fail, so that the caller frees
 * a partial build with embree_bvh_destroy; the message of a failure is
 * written to error (error_size bytes). When *cancel becomes nonzero the
 * build stops (Embree's build progress callback says no) and returns
 * PHOS_ERROR_CANCELLED. */
phos_status embree_bvh_build(const mesh *meshes, uint32_t mesh_count, const instance *instances,
                             uint32_t instance_count, atomic_int *cancel, struct embree_bvh **out, char *error,
                             size_t error_size);
void embree_bvh_destroy(struct embree_bvh *bvh);

/* After scene updates (docs/architecture.md, "Scene updates"): rebuilds the
 * BVHs of the meshes marked `changed` and of those added since, then the
 * top level. A failure leaves bvh to embree_bvh_destroy. */
phos_status embree_bvh_update(struct embree_bvh *bvh, const mesh *meshes, uint32_t mesh_count,
                              const instance *instances, uint32_t instance_count, char *error, size_t error_size);

/* How many mesh BVHs and top levels bvh has built, for the tests of scene
 * updates. */
void embree_bvh_build_counts(const struct embree_bvh *bvh, uint32_t *mesh_builds, uint32_t *top_builds);

/* The configuration string of the Embree devices built from now on (NULL:
 * Embree's defaults), e.g. "threads=1": lets tests/c/test_determinism.c
 * build the same BVH with another number of build threads. Not thread-safe;
 * not part of the public API. */
void embree_set_device_config(const char *config);

/* Closest hit with t in (tmin, tmax); coherent marks camera rays. */
int embree_intersect(const struct embree_bvh *bvh, vec3 o, vec3 d, float tmin, float tmax, int coherent,
                     ray_hit *hit);
/* Whether anything lies on the segment t in (tmin, tmax). */
int embree_occluded(const struct embree_bvh *bvh, vec3 o, vec3 d, float tmin, float tmax);

/* Rays this thread has cast through embree_intersect and embree_occluded
 * since it started (a counter per thread, so counting costs no sharing). */
uint64_t embree_thread_rays(void);

/* For the ray-throughput benchmark only: when set, every ray any thread
 * casts is passed to fn first (occlusion: hit == NULL). NULL turns it off. */
typedef void (*embree_ray_recorder)(void *ctx, vec3 o, vec3 d, float tmin, float tmax, int coherent, int occlusion);
void embree_set_ray_recorder(embree_ray_recorder fn, void *ctx);
/* The top-level RTCScene, for the benchmark's raw Embree loop. */
void *embree_bvh_scene(const struct embree_bvh *bvh);

/* The version of the Embree library in use, e.g. "3.13.5". */
const char *embree_version(void);

#endif /* PHOS_EMBREE_H */
