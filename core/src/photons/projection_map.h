/*
 * projection_map.h — caustic photons aimed at the objects that can make
 * caustics (Jensen 1996, "Global Illumination using Photon Maps", §2.1;
 * Jensen 2001 §5.1.5 "projection maps").
 *
 * A caustic photon must reach a delta-scattering surface first (L S+ D), so
 * emitting it anywhere else is wasted work. Each light group (a lamp, or
 * the emissive triangles of an instance) emits its caustic photons only
 * into the cones of directions that can reach the bounding sphere of an
 * object with a delta-scattering material; a sun only from the cells of
 * the plane its photons start on that lie in such an object's shadow, and
 * the world likewise, from a plane per bin of its directions. The photon's
 * power divides by that density, so the map is the same in expectation:
 * every direction that can start a caustic path is still sampled.
 *
 * The global map uses the same cells for the distant lights (suns and the
 * world), weighted by pilot photons toward what the camera reads, and
 * cones for the local lights toward every object that can receive a
 * photon, so that no photon is emitted into empty space
 * (projection_map_build_global, projection_map_set_weights).
 */
#ifndef PHOS_PROJECTION_MAP_H
#define PHOS_PROJECTION_MAP_H

#include <stdint.h>

#include "phos.h"
#include "sampling/distribution.h"
#include "sampling/sampler.h"
#include "scene/scene.h"

typedef struct projection_cone {
    vec3 axis;                  /* unit, from the light toward the object */
    float cos_max;              /* cos of the half angle */
    float omega;                /* sr, 2π(1 − cos_max) */
    float cdf_end;              /* the group's cones picked by solid angle: cumulative share */
} projection_cone;

typedef struct projection_group {
    uint32_t first, count;      /* distant: projection_map.cells[first ..]; others: cones[first ..] */
    uint32_t distant;           /* a sun or the world: plane cells */
    uint32_t discs;             /* the world (caustic map): a direction from the world, then a point on
                                   the disc of a target sphere across it (projection_map.c) */
    uint32_t all;               /* 1: no projection (the light sits among the specular objects,
                                   or covering every direction), emitted as for the global map */
    float power;                /* W a local group sends into its cones, roughly: its pick weight */
} projection_group;

typedef struct projection_map {
    projection_group *groups;   /* one per light group (light_table.groups) */
    uint32_t group_count;
    uint32_t *cells;            /* the distant lights' marked plane cells: bin · grid² + cell */
    float *cell_cum;            /* their weights, cumulative within each group (the caustic map's
                                   are all 1; the global map's come from pilot photons) */
    projection_cone *cones;
    distribution pick;          /* groups by the power they send into their marked cells */
    float marked_fraction;      /* of all power, the share sent into marked cells (diagnostics) */
    float *targets;             /* the target spheres, 4 floats each (centre, radius), for the discs */
    uint32_t target_count;
    float *target_cdf;          /* cumulative r², normalised: a target picked by its cross-section */
} projection_map;

/* Marks the cells of every light group against the bounding spheres of
 * the instances whose materials carry caustics (delta scattering, or glossy
 * below max_roughness: material_can_scatter_caustic). Returns 0 when memory is
 * exhausted; a scene without such instances gets an empty map (every
 * group `all`). */
int projection_map_build(projection_map *pm, const scene *s, float max_roughness);
void projection_map_free(projection_map *pm);

/* For the global map: every distant light's cells over the scene's
 * bounds, each of weight 1 until projection_map_set_weights; every local
 * light's cones toward the bounding boxes of the visible instances (those
 * with triangles), none where the light sits among them or they surround
 * it. Returns 0 when memory is exhausted. */
int projection_map_build_global(projection_map *pm, const scene *s);

/* A photon's origin and direction through cell k of distant group g (u:
 * the point in the cell, ud: the direction in the sun's cone or the
 * world's bin), for pilots. */
void projection_map_cell_ray(const scene *s, const projection_map *pm, uint32_t g, uint32_t k, float2 u, float2 ud,
                             vec3 *origin, vec3 *direction);

/* A pilot photon's origin and direction through cone k of local group g:
 * a light of the group by power (u_light), a uniform direction in the
 * cone (ud), its origin on the light (uo); 0 if the light sends nothing
 * that way (a spot's back). */
int projection_map_cone_ray(const scene *s, const projection_map *pm, uint32_t g, uint32_t k, float u_light,
                            float2 uo, float2 ud, vec3 *origin, vec3 *direction);

/* Weighs the cones of every local group (weights[first + k] as listed,
 * each > 0): a cone is picked in proportion to weight × solid angle, and
 * the mixture density of projection_map_emit follows. 0 on a zero total. */
int projection_map_set_cone_weights(projection_map *pm, const float *weights);

/* Sets the weights of the cells of every distant group (weights[first + k] as
 * listed, each > 0) and the groups' pick weights to match. */
int projection_map_set_weights(projection_map *pm, const scene *s, const float *weights);

/* A caustic photon leaving a light toward its marked cells: as
 * light_sample_emission, with the same five numbers and the flux divided
 * by the projected densities. */
int projection_map_emit(const scene *s, const projection_map *pm, const float u[5], vec3 *origin, vec3 *direction,
                        vec3 *power);

#endif /* PHOS_PROJECTION_MAP_H */
