/*
 * photon_importance.h — where the camera will read photons, so that photon
 * emission can be spent there (docs/algorithms.md §3.1, "Global photons
 * aimed at what the camera sees").
 *
 * A pilot of camera rays finds the first diffuse surfaces the camera sees
 * (through specular ones, as the debug passes do) and, from each, the
 * surfaces a gather there reaches. Their positions are marked in a voxel
 * grid over the scene's bounds, one bit per voxel and facing (the
 * dominant axis and sign of the surface normal, on the side the ray
 * arrived from), dilated by one voxel. A photon stored at a marked voxel
 * and facing can enter an estimate the camera reads; the outside of a
 * thin wall, whose photons face away, cannot. The grid only steers where
 * photons are emitted, never which are kept, so it cannot bias a map.
 */
#ifndef PHOS_PHOTON_IMPORTANCE_H
#define PHOS_PHOTON_IMPORTANCE_H

#include <stdint.h>

#include "scene/scene.h"

typedef struct photon_importance {
    uint8_t *bits;              /* (voxel · 6 + facing) bits */
    vec3 lo;                    /* grid origin (m) */
    float inv_voxel;            /* voxels per metre */
    uint32_t n;                 /* voxels per axis */
    uint32_t gather_hits;       /* the pilot's gather rays that found a surface: 0, no gather from
                                   what the camera sees reads a global photon */
} photon_importance;

/* Marks what the camera sees and its gathers reach, and likewise for each
 * of `view_count` further views (a render farm's cache job aims one map at
 * a whole camera path, phos_render_add_view). Returns 0 when memory is
 * exhausted or the scene has no camera (then nothing is marked). */
int photon_importance_build(photon_importance *imp, const scene *s, const phos_camera_desc *views,
                            uint32_t view_count);
void photon_importance_free(photon_importance *imp);

/* Whether a photon stored at p with normal n (facing the side it arrived
 * from) lies where the camera reads photons. */
int photon_importance_marked(const photon_importance *imp, vec3 p, vec3 n);

#endif /* PHOS_PHOTON_IMPORTANCE_H */
