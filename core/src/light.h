/*
 * light.h — every emitter of the scene in one table: lamps (point, spot,
 * area, sun), emissive triangles and the world background, picked in
 * proportion to their power for next-event estimation.
 *
 * Radiometric conventions: a sample carries the radiance arriving at the
 * shading point along −wi (W/(m²·sr)) and the solid-angle pdf of having
 * produced wi (light pick included), so that the estimate of reflected
 * radiance is f·cos·radiance/pdf. Delta lights (points, spots of radius 0,
 * suns of angle 0) set `delta` and give in `radiance` their irradiance at
 * normal incidence (W/m²) with pdf = the pick probability.
 */
#ifndef PHOS_LIGHT_H
#define PHOS_LIGHT_H

#include "distribution.h"
#include "phos.h"
#include "sampler.h"
#include "vec.h"

enum light_kind {
    LIGHT_POINT = 0,
    LIGHT_SPOT,
    LIGHT_AREA,
    LIGHT_SUN,
    LIGHT_TRIANGLE,
    LIGHT_WORLD
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
} light;

typedef struct light_table {
    light *lights;
    uint32_t count;
    distribution pick;          /* by estimated power */
    int32_t world;              /* index of the world light, −1 if black */
    uint32_t *shapes;           /* indices of lights a ray can hit: lamps with area, suns with an angle, world */
    uint32_t shape_count;
    vec3 center;                /* bounding sphere of the scene, for distant lights */
    float radius;
} light_table;

typedef struct light_sample {
    vec3 wi;                    /* toward the light */
    float distance;             /* to the sampled point; INFINITY for distant lights */
    vec3 radiance;              /* see the header comment */
    float pdf;
    int delta;
} light_sample;

/* A lamp or distant light hit by a ray (not the BVH's emissive triangles). */
typedef struct light_hit {
    float t;
    vec3 radiance;              /* W/(m²·sr) toward the ray origin */
    float pdf;                  /* solid-angle pdf of light_sample producing this direction */
} light_hit;

struct phos_scene;

/* Builds the table from the scene's lamp descriptions, emissive triangles
 * and world; needs the scene bounds. */
phos_status light_table_build(struct phos_scene *s);
void light_table_free(light_table *t);

/* Picks a light and samples a direction toward it from p. Returns 0 when
 * the sample carries nothing (e.g. behind a one-sided light). */
int light_sample_pick(const struct phos_scene *s, vec3 p, float u_pick, float2 u, light_sample *out);

/* pdf (solid angle, pick included) with which light_sample_pick would have
 * chosen the emissive triangle `index` seen from p at point x with
 * geometric normal ng. */
float light_pdf_triangle(const struct phos_scene *s, int32_t index, vec3 p, vec3 x, vec3 ng);

/* Nearest lamp (point, spot, area) along the ray within (0, tmax);
 * camera rays skip lamps hidden from the camera. */
int lights_intersect(const struct phos_scene *s, vec3 o, vec3 d, float tmax, int camera_ray, light_hit *out);

/* Radiance of the distant lights (world, suns with an angle) seen along an
 * escaping ray, each weighted for MIS against a BSDF sample of pdf
 * bsdf_pdf (no weighting if bsdf_delta). */
vec3 lights_escape(const struct phos_scene *s, vec3 d, float bsdf_pdf, int bsdf_delta, int camera_ray);

/* A photon leaving a light (Jensen 2001 §5.1; pbrt-v4 SampleLe): picks a
 * light in proportion to its power and samples an origin and direction.
 * `power` is the flux the photon carries if it were the only one emitted,
 * Φ = L_e·|cos θ| / (p_light · p_A · p_ω) in W; divide by the number of
 * photons emitted. Points emit uniformly over the sphere (spots over their
 * cone), area lights and emissive triangles cosine-weighted from a uniform
 * point, suns and the world from a disk covering the scene's bounding
 * sphere. Returns 0 if the sample carries nothing. */
int light_sample_emission(const struct phos_scene *s, const float u[5], vec3 *origin, vec3 *direction,
                          vec3 *power);

/* Spot attenuation for the direction from the light toward the point. */
float light_spot_attenuation(const light *l, vec3 dir_from_light);

/* Estimated emitted power (W), luminance-weighted, for picking. */
float light_power(const light *l, float scene_radius);

#endif /* PHOS_LIGHT_H */
