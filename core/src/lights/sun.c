/*
 * sun.c — suns: a distant light of irradiance E (W/m²) at normal
 * incidence, arriving along −direction. Angle 0: a delta direction.
 * Otherwise a disk of half angle α = sun_angle/2 seen uniformly bright, of
 * radiance L = E/(π sin²α) (W/(m²·sr)) so that its irradiance at normal
 * incidence is E, sampled uniformly in its cone, pdf_ω = 1/Ω with
 * Ω = 2π(1 − cos α) (pbrt-v4's distant light, widened to a cone).
 *
 * Photons start on the disk of the scene's bounding sphere that faces the
 * sun (light_kind.h, distant_origin) and carry E·πR², or L·Ω·πR² with an
 * angle (docs/algorithms.md §3.1).
 */
#include "lights/light_kind.h"
#include "sampling/warp.h"

static int has_angle(const light *l) { return l->sun_cos_half < 1.0f; }

static void sun_from_desc(const phos_light_desc *d, light *l)
{
    if (d->sun_angle > 0.0f) {
        /* Uniform radiance over the cone gives irradiance L·π·sin²α at
         * normal incidence; choose L so that it equals E. */
        float s = sinf(0.5f * d->sun_angle);
        l->sun_cos_half = cosf(0.5f * d->sun_angle);
        l->sun_radiance = v3_scale(l->color, 1.0f / (PHOS_PI * s * s));
    }
}

/* Φ = E·πR², or L·Ω·πR² with an angle (sun_emit). Ω is written out:
 * disk·L·cone_solid_angle() would round differently and move the photons'
 * pick probabilities by an ulp. */
static float sun_power(const light *l, float scene_radius)
{
    float disk = distant_disk_area(scene_radius);
    if (!has_angle(l))
        return disk * light_mean_color(l);
    return disk * maxf(v3_average(l->sun_radiance), 0.0f) * 2.0f * PHOS_PI * (1.0f - l->sun_cos_half);
}

static int sun_sample(const scene *s, const light *l, const light_context *c, float2 u, light_sample *out)
{
    vec3 to_sun = v3_neg(l->direction);
    out->distance = INFINITY;
    if (!has_angle(l)) {
        out->wi = to_sun;
        out->radiance = l->color;
        out->pdf = 1.0f;
        out->delta = 1;
        return 1;
    }
    out->wi = warp_cone(to_sun, l->sun_cos_half, u);
    out->radiance = l->sun_radiance;
    out->pdf = 1.0f / cone_solid_angle(l->sun_cos_half);
    out->delta = 0;
    return 1;
}

/* Rays find only a sun with an angle, within its cone. */
static int sun_escape(const scene *s, const light *l, const light_context *from, vec3 d, int camera_ray, vec3 *radiance,
                      float *pdf)
{
    if ((camera_ray && !l->camera_visible) || !has_angle(l))
        return 0;
    if (-v3_dot(d, l->direction) < l->sun_cos_half)
        return 0;
    *radiance = l->sun_radiance;
    *pdf = 1.0f / cone_solid_angle(l->sun_cos_half);
    return 1;
}

/* A photon per direction of the cone carries L·Ω·πR² (Ω the cone's solid
 * angle), not E·πR²: E = ∫ L cos θ dω = L·π sin²α is less than L·Ω by
 * (1 + cos α)/2 (α the half angle). */
static int sun_emit(const scene *s, const light *l, float2 u_origin, float2 u_direction, vec3 *origin,
                    vec3 *direction, vec3 *flux)
{
    vec3 d = has_angle(l) ? warp_cone(l->direction, l->sun_cos_half, u_direction) : l->direction;
    float area = distant_origin(&s->lights, d, u_origin, origin);
    *direction = d;
    *flux = has_angle(l) ? v3_scale(l->sun_radiance, cone_solid_angle(l->sun_cos_half) * area)
                         : v3_scale(l->color, area); /* E · πR² */
    return 1;
}

const light_kind_ops light_sun_ops = {
    .name = "sun",
    .desc_type = PHOS_LIGHT_SUN,
    .from_desc = sun_from_desc,
    .power = sun_power,
    .hittable = has_angle,
    .sample = sun_sample,
    .escape = sun_escape,
    .emit = sun_emit,
};
