/*
 * spot.c — spot lamps: a point lamp's shape (lamp_shape.h, point.c) whose
 * intensity I (W/sr) is shaped by Cycles' spot attenuation a(ω): zero
 * outside the cone of half angle θs, a smoothstep over the blend's width
 * in cos θ at its edge, times cos θ when the spot's cosine falloff is on.
 * Its flux is Φ = I ∫ a dω over the cone, integrated numerically; photons
 * leave uniformly within the cone, pdf_ω = 1/(2π(1 − cos θs)), each
 * carrying I·a(ω)/pdf_ω (docs/algorithms.md §3.1).
 */
#include "lights/lamp_shape.h"
#include "lights/light_kind.h"
#include "sampling/warp.h"

static float smoothstepf(float x)
{
    x = clampf(x, 0.0f, 1.0f);
    return x * x * (3.0f - 2.0f * x);
}

float light_spot_attenuation(const light *l, vec3 dir_from_light)
{
    return light_spot_attenuation_cos(l, v3_dot(dir_from_light, l->direction));
}

float light_spot_attenuation_cos(const light *l, float c)
{
    if (c <= l->spot_cos_half)
        return 0.0f;
    float a = l->spot_cosine ? c : 1.0f;
    float t = c - l->spot_cos_half;
    if (l->spot_smooth > 0.0f && t < l->spot_smooth)
        a *= smoothstepf(t / l->spot_smooth);
    return a;
}

/* ∫ a(ω) dω over the spot's cone (sr): 2π ∫ a dcos θ, by the midpoint
 * rule in cos θ, where the blend and the cosine make a smooth. */
static float spot_solid_angle(const light *l)
{
    const int steps = 256;
    float width = 1.0f - l->spot_cos_half, sum = 0.0f;
    for (int k = 0; k < steps; k++) {
        float c = l->spot_cos_half + width * ((float)k + 0.5f) / (float)steps;
        float sin_t = safe_sqrtf(1.0f - c * c);
        vec3 d = v3_add(v3_scale(l->direction, c), v3_scale(frame_from_normal(l->direction).t, sin_t));
        sum += light_spot_attenuation(l, d);
    }
    return 2.0f * PHOS_PI * width * sum / (float)steps;
}

static void spot_from_desc(const phos_light_desc *d, light *l)
{
    l->spot_cos_half = cosf(0.5f * d->spot_angle);
    l->spot_smooth = (1.0f - l->spot_cos_half) * d->spot_blend;
    l->spot_cosine = d->spot_cosine != 0;
}

static float spot_power(const light *l, float scene_radius)
{
    return spot_solid_angle(l) * light_mean_color(l); /* Φ = I ∫ a dω */
}

static int spot_sample(const scene *s, const light *l, const light_context *c, float2 u, light_sample *out)
{
    return lamp_sample(l, c->p, u, light_spot_attenuation, out);
}

static int spot_intersect(const light *l, vec3 o, vec3 d, float tmax, light_hit *out)
{
    return lamp_intersect(l, o, d, tmax, light_spot_attenuation, out);
}

/* Uniform within the cone. */
static vec3 spot_emission_direction(const light *l, float2 u, float *pdf)
{
    *pdf = 1.0f / cone_solid_angle(l->spot_cos_half);
    return warp_cone(l->direction, l->spot_cos_half, u);
}

static int spot_emit_toward(const scene *s, const light *l, vec3 d, float2 u, vec3 *origin, vec3 *intensity)
{
    return lamp_emit_toward(l, d, light_spot_attenuation, origin, intensity);
}

const light_kind_ops light_spot_ops = {
    .name = "spot",
    .desc_type = PHOS_LIGHT_SPOT,
    .from_desc = spot_from_desc,
    .power = spot_power,
    .hittable = lamp_hittable,
    .sample = spot_sample,
    .intersect = spot_intersect,
    .emission_direction = spot_emission_direction,
    .emit_toward = spot_emit_toward,
};
