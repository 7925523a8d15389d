/*
 * embree.h — the ray-tracing kernel behind one small interface. All Embree
 * calls live in embree.c, which builds against Embree 3 or Embree 4.
 */
#ifndef PHOS_EMBREE_H
#define PHOS_EMBREE_H

#include "scene.h"

typedef struct ray_hit {
    float t;
    uint32_t instance, prim;
    float b1, b2;           /* barycentric weights of corners 1 and 2 */
} ray_hit;

/* One BVH per mesh, shared by its instances, under a top-level BVH of
 * instances. The message of a failure is written to the scene. */
phos_status embree_bvh_build(scene *s);
void embree_bvh_destroy(struct embree_bvh *bvh);

/* Closest hit with t in (tmin, tmax); coherent marks camera rays. */
int embree_intersect(const struct embree_bvh *bvh, vec3 o, vec3 d, float tmin, float tmax, int coherent,
                     ray_hit *hit);
/* Whether anything lies on the segment t in (tmin, tmax). */
int embree_occluded(const struct embree_bvh *bvh, vec3 o, vec3 d, float tmin, float tmax);

/* The version of the Embree library in use, e.g. "3.13.5". */
const char *embree_version(void);

#endif /* PHOS_EMBREE_H */
