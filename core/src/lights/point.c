/*
 * point.c — point lamps, and the lamp shape spots share (lamp_shape.h).
 *
 * Radius 0: a delta light of intensity I (W/sr). Otherwise a disk facing
 * the receiver (Cycles < 4.0) or a sphere (Cycles 4.0+) of radius r; either
 * way its radiance is I/(πr²) (W/(m²·sr)), so that it has intensity I seen
 * from afar. The disk is sampled uniformly by area (concentric map, Shirley
 * & Chiu 1997) and converted to solid angle, pdf_ω = d² / (πr²·|cos θ_l|);
 * the sphere uniformly in the cone it subtends, pdf_ω = 1/(2π(1 − cos θ_max))
 * (pbrt-v4's sphere sampling). A point emits uniformly over the sphere of
 * directions: Φ = 4πI. What the add-on passes is in Cycles' units converted
 * to these (docs/blender.md §1).
 */
#include "lights/lamp_shape.h"
#include "lights/light_kind.h"
#include "sampling/warp.h"

float lamp_unattenuated(const light *l, vec3 dir_from_light) { return 1.0f; }

int lamp_hittable(const light *l) { return l->radius > 0.0f; }

/* Radius 0: the lamp's centre, a delta direction. */
static int sample_delta(const light *l, vec3 axis, float d, float d2, lamp_attenuation attenuation,
                        light_sample *out)
{
    float a = attenuation(l, v3_neg(axis));
    out->wi = axis;
    out->distance = d;
    out->radiance = v3_scale(l->color, a / d2);
    out->pdf = 1.0f;
    out->delta = 1;
    return a > 0.0f;
}

/* Uniform in the cone the sphere subtends from p. */
static int sample_sphere(const light *l, vec3 to_light, vec3 axis, float d, float d2, float2 u,
                         lamp_attenuation attenuation, light_sample *out)
{
    float r = l->radius;
    if (d <= r)
        return 0;
    vec3 L = v3_scale(l->color, 1.0f / (PHOS_PI * r * r));
    float sin2 = (r * r) / d2;
    float cos_max = safe_sqrtf(1.0f - sin2);
    vec3 wi = warp_cone(axis, cos_max, u);
    /* Distance to the sphere along wi. */
    float b = v3_dot(wi, to_light);
    float disc = b * b - (d2 - r * r);
    float t = b - safe_sqrtf(disc);
    out->wi = wi;
    out->distance = maxf(t, 0.0f);
    out->pdf = 1.0f / cone_solid_angle(cos_max);
    out->delta = 0;
    /* A sphere spot (Cycles 4) shapes its beam by the direction of each
     * ray leaving it, not by where p lies from its centre. */
    float a = attenuation(l, v3_neg(wi));
    out->radiance = v3_scale(L, a);
    return a > 0.0f && out->pdf > 0.0f && isfinite(out->pdf);
}

/* Uniform on the disk of radius r centred on the light, facing p. */
static int sample_disk(const light *l, vec3 p, vec3 axis, float2 u, lamp_attenuation attenuation,
                       light_sample *out)
{
    float r = l->radius;
    vec3 L = v3_scale(l->color, 1.0f / (PHOS_PI * r * r));
    frame f = frame_from_normal(v3_neg(axis));
    float2 dk = warp_disk_concentric(u);
    vec3 x = v3_add(l->position, v3_add(v3_scale(f.t, dk.x * r), v3_scale(f.b, dk.y * r)));
    vec3 to_x = v3_sub(x, p);
    float dist2 = v3_length2(to_x);
    float dist = sqrtf(dist2);
    vec3 wi = v3_scale(to_x, 1.0f / dist);
    float cos_l = fabsf(v3_dot(wi, axis));
    if (!(cos_l > 0.0f))
        return 0;
    float a = attenuation(l, v3_neg(wi));
    out->wi = wi;
    out->distance = dist;
    out->pdf = dist2 / (PHOS_PI * r * r * cos_l);
    out->radiance = v3_scale(L, a);
    out->delta = 0;
    return a > 0.0f;
}

int lamp_sample(const light *l, vec3 p, float2 u, lamp_attenuation attenuation, light_sample *out)
{
    vec3 to_light = v3_sub(l->position, p);
    float d2 = v3_length2(to_light);
    float d = sqrtf(d2);
    if (!(d > 0.0f))
        return 0;
    vec3 axis = v3_scale(to_light, 1.0f / d);
    if (l->radius <= 0.0f)
        return sample_delta(l, axis, d, d2, attenuation, out);
    if (l->point_shape == PHOS_POINT_SPHERE)
        return sample_sphere(l, to_light, axis, d, d2, u, attenuation, out);
    return sample_disk(l, p, axis, u, attenuation, out);
}

/* The sphere along the ray from o (outside it, at squared distance dist2
 * from its centre): the distance t and the solid-angle pdf of sampling d. */
static int intersect_sphere(const light *l, vec3 oc, float dist2, vec3 d, float *t, float *pdf)
{
    float r = l->radius;
    float b = v3_dot(d, oc);
    float disc = b * b - (dist2 - r * r);
    if (disc < 0.0f)
        return 0;
    *t = b - sqrtf(disc);
    float cos_max = safe_sqrtf(1.0f - r * r / dist2);
    *pdf = 1.0f / cone_solid_angle(cos_max);
    return 1;
}

/* The disk through the centre, facing the ray origin o. */
static int intersect_disk(const light *l, vec3 o, vec3 oc, float dist2, vec3 d, float *t, float *pdf)
{
    float r = l->radius;
    float dist = sqrtf(dist2);
    vec3 n = v3_scale(oc, -1.0f / dist);
    float denom = v3_dot(d, n);
    if (denom >= 0.0f)
        return 0;
    *t = v3_dot(v3_sub(l->position, o), n) / denom;
    vec3 x = v3_madd(o, d, *t);
    if (v3_length2(v3_sub(x, l->position)) > r * r)
        return 0;
    *pdf = *t * *t / (PHOS_PI * r * r * -denom);
    return 1;
}

int lamp_intersect(const light *l, vec3 o, vec3 d, float tmax, lamp_attenuation attenuation, light_hit *out)
{
    if (l->radius <= 0.0f)
        return 0;
    float r = l->radius;
    vec3 oc = v3_sub(l->position, o);
    float dist2 = v3_length2(oc);
    if (dist2 <= r * r)
        return 0;
    float t;
    float pdf;
    int hit = l->point_shape == PHOS_POINT_SPHERE ? intersect_sphere(l, oc, dist2, d, &t, &pdf)
                                                  : intersect_disk(l, o, oc, dist2, d, &t, &pdf);
    if (!hit || !(t > 0.0f) || t >= tmax)
        return 0;
    /* Either shape, as lamp_sample: the beam by the ray's own direction. */
    float a = attenuation(l, v3_neg(d));
    out->t = t;
    out->radiance = v3_scale(l->color, a / (PHOS_PI * r * r));
    out->pdf = pdf;
    return 1;
}

int lamp_emit_toward(const light *l, vec3 d, lamp_attenuation attenuation, vec3 *origin, vec3 *intensity)
{
    float a = attenuation(l, d);
    /* A lamp of radius r emits the same flux from its surface; start the
     * photon there so it is not born inside nearby geometry. */
    *origin = l->radius > 0.0f ? v3_madd(l->position, d, l->radius) : l->position;
    *intensity = v3_scale(l->color, a); /* I·a */
    return a > 0.0f;
}

/* ------------------------------------------------------------ point lamp */

static float point_power(const light *l, float scene_radius)
{
    return 4.0f * PHOS_PI * light_mean_color(l); /* Φ = 4πI */
}

static int point_sample(const scene *s, const light *l, const light_context *c, float2 u, light_sample *out)
{
    return lamp_sample(l, c->p, u, lamp_unattenuated, out);
}

static int point_intersect(const light *l, vec3 o, vec3 d, float tmax, light_hit *out)
{
    return lamp_intersect(l, o, d, tmax, lamp_unattenuated, out);
}

/* Uniform over the sphere of directions. */
static vec3 point_emission_direction(const light *l, float2 u, float *pdf)
{
    *pdf = PHOS_INV_4PI;
    return warp_uniform_sphere(u);
}

static int point_emit_toward(const scene *s, const light *l, vec3 d, float2 u, vec3 *origin, vec3 *intensity)
{
    return lamp_emit_toward(l, d, lamp_unattenuated, origin, intensity);
}

const light_kind_ops light_point_ops = {
    .name = "point",
    .desc_type = PHOS_LIGHT_POINT,
    .from_desc = NULL, /* nothing beyond the common fields */
    .power = point_power,
    .hittable = lamp_hittable,
    .sample = point_sample,
    .intersect = point_intersect,
    .emission_direction = point_emission_direction,
    .emit_toward = point_emit_toward,
};
