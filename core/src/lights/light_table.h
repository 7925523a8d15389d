/*
 * light_table.h — the data of the scene's emitters, built at commit
 * (light.c) and held by the scene; light.h has the functions that build,
 * sample and intersect it.
 */
#ifndef PHOS_LIGHT_TABLE_H
#define PHOS_LIGHT_TABLE_H

#include <stdlib.h>
#include <string.h>

#include "sampling/distribution.h"
#include "util/vec.h"

enum light_kind {
    LIGHT_POINT = 0,
    LIGHT_SPOT,
    LIGHT_AREA,
    LIGHT_SUN,
    LIGHT_TRIANGLE,
    LIGHT_WORLD,                /* uniform: one radiance from every direction */
    LIGHT_ENVIRONMENT,          /* the world varying with direction (lights/environment.h) */
    LIGHT_KIND_COUNT            /* each kind's operations: light_kinds[] (light_kind.h) */
};

typedef struct light {
    uint32_t kind;
    vec3 color;                 /* intensity W/sr, radiance W/(m²·sr) or irradiance W/m² (phos_light_desc) */
    vec3 position, direction;   /* as phos_light_desc; direction unit length */
    vec3 axis_u, axis_v;        /* AREA edges */
    float area;                 /* AREA and TRIANGLE: m² */
    uint32_t area_shape;
    float radius;
    uint32_t point_shape;
    float spot_cos_half;        /* cos(spot_angle / 2) */
    float spot_smooth;          /* (1 − spot_cos_half)·blend: width of the smooth edge in cos */
    int spot_cosine;
    float sun_cos_half;         /* cos(sun_angle / 2); 1 for a delta sun */
    vec3 sun_radiance;          /* W/(m²·sr) inside the sun's cone when sun_angle > 0 */
    int camera_visible;         /* lamps: seen by camera rays */
    uint32_t instance, prim;    /* TRIANGLE */
    vec3 p0, p1, p2;            /* TRIANGLE corners, world space */
    uint32_t group;             /* index into light_table.groups */
} light;

/* Lights picked together for next-event estimation (light_pick.c): each
 * lamp, sun and the world alone, the emissive triangles of one instance
 * together. A group is chosen by its estimated irradiance at the shading
 * point, a light within it by power. */
typedef struct light_group {
    uint32_t first, count;      /* lights[first .. first + count) */
    float power;                /* W, the sum of light_power */
    vec3 center;                /* m: bounding sphere (lamps: position and radius) */
    float radius;
    distribution within;        /* count > 1: by power */
} light_group;

typedef struct light_table {
    light *lights;
    uint32_t count;
    distribution pick;          /* by power: photon emission */
    distribution pick_nee;      /* by power without the uniform world, which is sampled apart
                                   (light_pick.c): next-event estimation in scenes with more than
                                   LIGHT_PICK_MAX_GROUPS groups */
    light_group *groups;
    uint32_t group_count;
    int32_t world;              /* index of the world light (uniform or environment), −1 if black */
    struct environment *env;    /* the world's sampling map when it varies with direction, else NULL */
    light *portals;             /* PORTAL descs, shaped as AREA lights (portal.c); no light of their own */
    uint32_t portal_count;
    uint32_t *shapes;           /* indices of lights a ray can hit: lamps with area, suns with an angle, world */
    uint32_t shape_count;
    vec3 center;                /* bounding sphere of the scene, for distant lights */
    float radius;
} light_table;

/* Whether l is the world, uniform or not: the distant light from every
 * direction. */
static inline int light_is_world(const light *l) { return l->kind == LIGHT_WORLD || l->kind == LIGHT_ENVIRONMENT; }

/* Suns and the world: lights at infinity, whose photons start on a plane
 * or disk across the scene. */
static inline int light_is_distant(const light *l) { return l->kind == LIGHT_SUN || light_is_world(l); }

void environment_destroy(struct environment *e); /* lights/environment.c */

static inline void light_table_free(light_table *t)
{
    environment_destroy(t->env);
    free(t->portals);
    free(t->lights);
    free(t->shapes);
    distribution_free(&t->pick);
    distribution_free(&t->pick_nee);
    for (uint32_t g = 0; g < t->group_count; g++)
        distribution_free(&t->groups[g].within);
    free(t->groups);
    memset(t, 0, sizeof(*t));
    t->world = -1;
}

#endif /* PHOS_LIGHT_TABLE_H */
