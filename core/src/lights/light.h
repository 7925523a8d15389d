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

#include "lights/light_table.h"
#include "phos.h"
#include "sampling/sampler.h"
#include "scene/scene.h"

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

/* Picks a light and samples a direction toward it from p. Returns 0 when
 * the sample carries nothing (e.g. behind a one-sided light). */
int light_sample_pick(const scene *s, vec3 p, float u_pick, float2 u, light_sample *out);

/* pdf (solid angle, pick included) with which light_sample_pick would have
 * chosen the emissive triangle `index` seen from p at point x with
 * geometric normal ng. */
float light_pdf_triangle(const scene *s, int32_t index, vec3 p, vec3 x, vec3 ng);

/* Nearest lamp (point, spot, area) along the ray within (tmin, tmax);
 * camera rays skip lamps hidden from the camera. A ray that passed
 * through transparent surfaces keeps its origin and moves tmin past each
 * of them, so lamps before them are not found again. */
int lights_intersect(const scene *s, vec3 o, vec3 d, float tmin, float tmax, int camera_ray, light_hit *out);

/* Radiance of the distant lights (world, suns with an angle) seen along an
 * escaping ray, each weighted for MIS against a BSDF sample of pdf
 * bsdf_pdf (no weighting if bsdf_delta). */
vec3 lights_escape(const scene *s, vec3 d, float bsdf_pdf, int bsdf_delta, int camera_ray);

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

/* Spot attenuation for the direction from the light toward the point. */
float light_spot_attenuation(const light *l, vec3 dir_from_light);

/* Estimated emitted power (W), luminance-weighted, for picking. */
float light_power(const light *l, float scene_radius);

#endif /* PHOS_LIGHT_H */
