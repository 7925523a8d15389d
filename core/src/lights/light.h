/*
 * light.h — every emitter of the scene in one table: lamps (point, spot,
 * area, sun), emissive triangles and the world background. Next-event
 * estimation picks among them by what each can give the shading point
 * (light_pick.c); photons leave them in proportion to their power. Each
 * kind is implemented in its own file behind light_kind.h; these functions
 * dispatch to it (light.c).
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

#include "lights/light_table.h"
#include "phos.h"
#include "sampling/sampler.h"
#include "scene/scene.h"
#include "shading/material.h"

/* Groups evaluated per shading point; scenes with more pick by power. */
#define LIGHT_PICK_MAX_GROUPS 64

/* The receiver a light is picked for: a surface point with its normals,
 * and whether its material scatters light to the other side. A path vertex
 * builds one and uses it both for its light sample and for the MIS weights
 * of what its rays find, so the two always agree. */
typedef struct light_context {
    vec3 p, ng, ns;
    int two_sided;
    int no_normal;              /* no orientation to test (a point in space) */
} light_context;

static inline light_context light_context_at(const surface *sf)
{
    light_context c = {sf->p, sf->ng, sf->ns, sf->mat->transmits, 0};
    return c;
}

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


/* Builds the table from the scene's lamp descriptions, emissive triangles
 * and world; needs the scene bounds. */
phos_status light_table_build(scene *s);

/* Groups of lights for picking (light_pick.c), from each light's power. */
phos_status light_groups_build(light_table *t, const float *power);

/* Picks the light a next-event estimate at c samples, with probability
 * *pdf (0: nothing can light c). c NULL: by power. */
uint32_t light_pick(const light_table *t, const light_context *c, float u, float *pdf);

/* Whether the world is sampled apart at c (one sample of its own
 * besides the picked light's, light_sample_world) rather than picked: the
 * uniform world always, one that varies with direction beside other lights. */
int light_world_apart(const light_table *t, const light_context *c);
int light_world_sampled_apart(const light_table *t); /* the same, for next-event estimation anywhere */

/* A sample of the world alone (pick pdf 1), for a world sampled apart. */
int light_sample_world(const scene *s, const light_context *c, float2 u, light_sample *out);

/* The probability with which light_pick chooses `light` at c (1 for a
 * world sampled apart). */
float light_pick_pdf(const light_table *t, const light_context *c, uint32_t light);

/* Picks a light for the receiver c and samples a direction toward it from
 * c->p. Returns 0 when the sample carries nothing (e.g. behind a one-sided
 * light). */
int light_sample_pick(const scene *s, const light_context *c, float u_pick, float2 u, light_sample *out);

/* Solid-angle pdf of the world's light sample toward wi at c (pick not
 * included): cosine-weighted about the shading normal, or uniform over the
 * sphere at surfaces that transmit and at points without a normal. */
float light_world_pdf(const light_context *c, vec3 wi);

/* pdf (solid angle, pick included) with which light_sample_pick at c would
 * have chosen the emissive triangle `index` at point x with geometric
 * normal ng. */
float light_pdf_triangle(const scene *s, int32_t index, const light_context *c, vec3 x, vec3 ng);

/* Nearest lamp (point, spot, area) along the ray within (tmin, tmax);
 * camera rays skip lamps hidden from the camera. A ray that passed
 * through transparent surfaces keeps its origin and moves tmin past each
 * of them, so lamps before them are not found again. `from` is the vertex
 * the ray left, for the light-sample pdf (NULL for camera rays, which
 * take emission unweighted). */
int lights_intersect(const scene *s, const light_context *from, vec3 o, vec3 d, float tmin, float tmax,
                     int camera_ray, light_hit *out);

/* Radiance of the distant lights (world, suns with an angle) seen along an
 * escaping ray from the vertex `from`, each weighted for MIS against a
 * BSDF sample of pdf bsdf_pdf (no weighting if bsdf_delta or from NULL). */
vec3 lights_escape(const scene *s, const light_context *from, vec3 d, float bsdf_pdf, int bsdf_delta,
                   int camera_ray);

/* A photon leaving a light (Jensen 2001 §5.1; pbrt-v4 SampleLe): picks a
 * light in proportion to its power and samples an origin and direction.
 * `power` is the flux the photon carries if it were the only one emitted,
 * Φ = L_e·|cos θ| / (p_light · p_A · p_ω) in W; divide by the number of
 * photons emitted. Points emit uniformly over the sphere (spots over their
 * cone), area lights and emissive triangles cosine-weighted from a uniform
 * point, suns and the world from a disk covering the scene's bounding
 * sphere. Returns 0 if the sample carries nothing. */
int light_sample_emission(const scene *s, const float u[5], vec3 *origin, vec3 *direction,
                          vec3 *power);

/* A photon of light `index` alone (no pick): origin, direction and the
 * flux Φ = L_e·|cos θ| / (p_A · p_ω) it carries (W), from four numbers
 * (origin 0–1, direction 2–3). Returns 0 if it carries nothing. */
int light_emit(const scene *s, uint32_t index, const float u[4], vec3 *origin, vec3 *direction, vec3 *flux);

/* For a local light (point, spot, area, emissive triangle) and a direction
 * d chosen by the caller: an origin on the light from u and the radiant
 * intensity it stands for along d, I = L_e·A·|cos θ| (W/sr; a point's I·a),
 * so that a photon of direction density p_ω carries I/p_ω. Returns 0 if
 * the light sends nothing along d. */
int light_emit_toward(const scene *s, uint32_t index, vec3 d, float2 u, vec3 *origin, vec3 *intensity);

/* pdf (solid angle, pick not included) with which the distant light
 * `index` (sun, world, environment) is sampled along d from c; 0 if d
 * misses it or it is a local light. */
float light_escape_pdf(const scene *s, const light_context *c, uint32_t index, vec3 d);

/* Spot attenuation for the direction from the light toward the point. */
float light_spot_attenuation(const light *l, vec3 dir_from_light);
/* The same for a direction at cosine c to the spot's axis; it never falls
 * as c grows (light_pick.c bounds a spot with a radius by it). */
float light_spot_attenuation_cos(const light *l, float c);

/* Emitted power (W), the channels' mean: the flux its photons carry. */
float light_power(const light *l, float scene_radius);

#endif /* PHOS_LIGHT_H */
