/*
 * world.c — the uniform world: radiance L (W/(m²·sr)) arriving from every
 * direction, found by every ray that escapes the scene. A world whose
 * radiance varies with direction is environment.c's.
 *
 * Its light sample is cosine-weighted about the shading normal (Malley's
 * method, pdf cos θ/π) where only light from above the surface can be
 * reflected, so that a diffuse surface gets its irradiance with no
 * variance but that of occlusion; uniform over the sphere (pdf 1/(4π))
 * where the surface also transmits and at points without a normal.
 *
 * Photons come from a direction uniform over the sphere and start on the
 * disk of the scene's bounding sphere that faces it (light_kind.h,
 * distant_origin), each carrying L·πR²/(1/(4π)); its power is 4π·L·πR²
 * (pbrt-v4's uniform infinite light; docs/algorithms.md §3.1).
 */
#include "lights/light_kind.h"

#include <string.h>

#include "sampling/warp.h"
#include "shading/material.h"

phos_status light_world_add(const scene *s, light_table *t, uint32_t *capacity)
{
    vec3 world = v3_load(s->world.color);
    if (s->world.material != PHOS_WORLD_NO_MATERIAL) {
        const material *m = &s->materials[s->world.material];
        if (m->has_program)
            return light_environment_add(s, t, capacity, m);
        world = material_background(s, m, v3(0.0f, 0.0f, 1.0f), 0); /* folded: the same every way */
    }
    if (v3_is_zero(world))
        return PHOS_OK;
    light l;
    memset(&l, 0, sizeof(l));
    l.kind = LIGHT_WORLD;
    l.color = world;
    t->world = (int32_t)t->count;
    return light_table_append(t, capacity, &l) ? PHOS_OK : PHOS_ERROR_OUT_OF_MEMORY;
}

static float world_power(const light *l, float scene_radius)
{
    /* L·πR² per steradian, from every direction */
    return 4.0f * PHOS_PI * light_mean_color(l) * distant_disk_area(scene_radius);
}

static int world_hittable(const light *l) { return 1; }

/* Where only light from above the shading normal can be reflected
 * (bsdf.c: a reflected wi lies above both normals). */
static int world_samples_hemisphere(const light_context *c) { return !c->no_normal && !c->two_sided; }

float light_world_pdf(const light_context *c, vec3 wi)
{
    if (!c || !world_samples_hemisphere(c))
        return PHOS_INV_4PI;
    return maxf(v3_dot(wi, c->ns), 0.0f) * PHOS_INV_PI;
}

static vec3 own_sample(const scene *s, const light_context *c, float2 u, float *pdf)
{
    vec3 wi = world_samples_hemisphere(c) ? warp_cosine_about(c->ns, u) : warp_uniform_sphere(u);
    *pdf = light_world_pdf(c, wi);
    return wi;
}

static float own_pdf(const scene *s, const light_context *c, vec3 wi) { return light_world_pdf(c, wi); }

static const world_sampling uniform_world_sampling = {own_sample, own_pdf};

static int world_sample(const scene *s, const light *l, const light_context *c, float2 u, light_sample *out)
{
    if (!portal_mix_sample(s, c, &uniform_world_sampling, u, &out->wi, &out->pdf))
        return 0;
    out->distance = INFINITY;
    out->radiance = l->color;
    out->delta = 0;
    return 1;
}

/* Every escaping ray finds the world, camera rays included. */
static int world_escape(const scene *s, const light *l, const light_context *from, vec3 d, int camera_ray,
                        vec3 *radiance, float *pdf)
{
    *radiance = l->color;
    *pdf = portal_mix_pdf(s, from, &uniform_world_sampling, d);
    return 1;
}

static int world_emit(const scene *s, const light *l, float2 u_origin, float2 u_direction, vec3 *origin,
                      vec3 *direction, vec3 *flux)
{
    vec3 d = v3_neg(warp_uniform_sphere(u_direction)); /* away from where the light comes from */
    float area = distant_origin(&s->lights, d, u_origin, origin);
    *direction = d;
    *flux = v3_scale(l->color, area / PHOS_INV_4PI); /* L · πR² / p_ω */
    return 1;
}

const light_kind_ops light_world_ops = {
    .name = "world",
    .desc_type = -1,
    .power = world_power,
    .hittable = world_hittable,
    .sample = world_sample,
    .escape = world_escape,
    .emit = world_emit,
};
