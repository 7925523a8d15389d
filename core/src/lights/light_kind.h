/*
 * light_kind.h — what each kind of light provides, inside lights/: one
 * table of operations per kind, filled in the kind's own file (point.c,
 * spot.c, area.c, sun.c, mesh_emitter.c, world.c) and found by light.kind
 * in light_kinds[]. light.c builds the light table and dispatches light.h's
 * functions through these tables, so a new kind is its own file, a value
 * of enum light_kind (light_table.h) and an entry of light_kinds[].
 *
 * Units and conventions are light.h's: radiance W/(m²·sr), intensity W/sr,
 * flux W, pdfs per steradian.
 */
#ifndef PHOS_LIGHT_KIND_H
#define PHOS_LIGHT_KIND_H

#include "lights/light.h"

typedef struct light_kind_ops {
    const char *name;

    /* Lamps: the phos_light_type they are described by, and their own
     * fields of l from d (light.c has filled the common ones; NULL: none).
     * Kinds the table builds from the scene (emissive triangles, the
     * world): −1 and NULL. */
    int desc_type;
    void (*from_desc)(const phos_light_desc *d, light *l);

    /* Emitted flux (W): light_power. */
    float (*power)(const light *l, float scene_radius);

    /* Whether rays can find the light in lights_intersect (a lamp with a
     * surface) or lights_escape (a distant light of nonzero solid angle);
     * NULL: never (emissive triangles are found by the BVH). */
    int (*hittable)(const light *l);

    /* A direction toward the light from the receiver c, as light_sample_pick
     * but with the pdf of this light alone. Returns 0 if it carries nothing. */
    int (*sample)(const scene *s, const light *l, const light_context *c, float2 u, light_sample *out);

    /* Local lights rays can hit: the hit along o + t·d, 0 < t < tmax, with
     * the pdf of sample() producing d (pick not included). NULL: none. */
    int (*intersect)(const light *l, vec3 o, vec3 d, float tmax, light_hit *out);

    /* Distant lights: the radiance (W/(m²·sr)) an escaping ray of
     * direction d finds, and the pdf of sample() at `from` producing d
     * (from may be NULL). Returns 0 if the ray misses it or, for camera
     * rays, it is hidden from the camera. NULL for local lights. */
    int (*escape)(const scene *s, const light *l, const light_context *from, vec3 d, int camera_ray,
                  vec3 *radiance, float *pdf);

    /* Local lights' photons: a direction of emission with its density
     * (sr⁻¹), and for a direction d an origin on the light and the
     * intensity (W/sr) it stands for (light_emit_toward). NULL for distant
     * lights. */
    vec3 (*emission_direction)(const light *l, float2 u, float *pdf);
    int (*emit_toward)(const scene *s, const light *l, vec3 d, float2 u, vec3 *origin, vec3 *intensity);

    /* Distant lights' photons: origin, direction and flux (W), as
     * light_emit. NULL for local lights, which light_emit builds from
     * emission_direction and emit_toward. */
    int (*emit)(const scene *s, const light *l, float2 u_origin, float2 u_direction, vec3 *origin,
                vec3 *direction, vec3 *flux);
} light_kind_ops;

extern const light_kind_ops light_point_ops, light_spot_ops, light_area_ops, light_sun_ops, light_mesh_ops,
    light_world_ops, light_environment_ops;

/* Indexed by enum light_kind (light.c). */
extern const light_kind_ops *const light_kinds[LIGHT_KIND_COUNT];

static inline const light_kind_ops *light_ops(const light *l) { return light_kinds[l->kind]; }

/* Mean of the colour's channels, never negative: the scalar the powers
 * (W) are computed from. */
static inline float light_mean_color(const light *l) { return maxf(v3_average(l->color), 0.0f); }

/* The unit direction *wi from p toward a point x on a light, with the
 * distance *d (m) and its square *d2; 0 if x is p. */
static inline int light_direction_to(vec3 p, vec3 x, vec3 *wi, float *d, float *d2)
{
    vec3 to_x = v3_sub(x, p);
    *d2 = v3_length2(to_x);
    *d = sqrtf(*d2);
    if (!(*d > 0.0f))
        return 0;
    *wi = v3_scale(to_x, 1.0f / *d);
    return 1;
}

/* Appends l to the table being built, whose array holds *capacity
 * lights. Returns 0 out of memory (light.c). */
int light_table_append(light_table *t, uint32_t *capacity, const light *l);

/* Table builders of the kinds not described by phos_light_desc: every
 * emissive triangle of the visible instances, consecutive per instance
 * (mesh_emitter.c), and the world light if the world is not black: a
 * uniform world (world.c) or one that varies with direction
 * (environment.c). */
phos_status light_mesh_emitters_add(scene *s, light_table *t, uint32_t *capacity);
phos_status light_world_add(const scene *s, light_table *t, uint32_t *capacity);
phos_status light_environment_add(const scene *s, light_table *t, uint32_t *capacity, const material *world);

/* The Sky Texture's sun as a sun light, when the world's program allows
 * (sky_sun.c); *added tells whether it did, and then the world's radiance
 * is to be read without the disc (SHADER_RAY_SKY_SUN_AS_LIGHT). */
phos_status light_sky_sun_add(const scene *s, light_table *t, uint32_t *capacity, const material *world,
                              int *added);

/* The shape of area lamps, which portals share (area.c): the fields of an
 * AREA or PORTAL desc; a uniform point on the shape; the crossing of the
 * ray o + t·d, 0 < t < tmax, with its emitting face (the side
 * `direction` points to), and the solid-angle pdf of light_area_point
 * producing d from o, t²/(A·|cos θ|). */
void light_area_from_desc(const phos_light_desc *d, light *l);
vec3 light_area_point(const light *l, float2 u);
int light_area_crossing(const light *l, vec3 o, vec3 d, float tmax, float *t, float *pdf);

/* A world's own way of drawing a direction toward it from c, and its pdf;
 * portal.c mixes it with draws through the portals. */
typedef struct world_sampling {
    vec3 (*sample)(const scene *s, const light_context *c, float2 u, float *pdf);
    float (*pdf)(const scene *s, const light_context *c, vec3 wi);
} world_sampling;

/* The share of a world light sample at c drawn through the portals: ½
 * where c lies on the inner side of a portal, else 0 (portal.c). */
float portal_share(const light_table *t, const light_context *c);

/* A direction from c by the mixture of portals (share portal_share) and
 * the world's own sampling, with the mixture's pdf; the pdf alone. */
int portal_mix_sample(const scene *s, const light_context *c, const world_sampling *own, float2 u, vec3 *wi,
                      float *pdf);
float portal_mix_pdf(const scene *s, const light_context *c, const world_sampling *own, vec3 wi);

/* Distant lights (sun, world) emit photons from the disk of the scene's
 * bounding sphere (radius R, light_table.center and .radius) that faces
 * them (light.c). */

/* Its area πR² (m²): the cross-section their power is computed over. */
float distant_disk_area(float scene_radius);

/* An origin on that disk for a photon travelling along d; returns the
 * disk's area (m²). */
float distant_origin(const light_table *t, vec3 d, float2 u, vec3 *origin);

#endif /* PHOS_LIGHT_KIND_H */
