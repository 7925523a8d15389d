/*
 * area.c — area lamps: a square, rectangle, disk or ellipse with edges
 * axis_u, axis_v about its centre, of uniform radiance L (W/(m²·sr)),
 * one-sided: it emits toward +direction only.
 *
 * Sampled uniformly by area and converted to solid angle, pdf_ω =
 * d² / (A·|cos θ_l|) (pbrt-v4's area lights); the disk and ellipse by the
 * concentric map (Shirley & Chiu 1997). Photons leave a uniform point
 * cosine-weighted about the emitting side, each carrying L·A·cos θ /
 * (cos θ/π) = πAL = Φ (Jensen 2001 §5.1).
 */
#include "lights/light_kind.h"
#include "sampling/warp.h"

void light_area_from_desc(const phos_light_desc *d, light *l)
{
    l->axis_u = v3_load(d->axis_u);
    l->axis_v = v3_load(d->axis_v);
    l->area_shape = d->area_shape;
    l->area = v3_length(v3_cross(l->axis_u, l->axis_v));
    if (d->area_shape == PHOS_AREA_ELLIPSE)
        l->area *= PHOS_PI * 0.25f;
}

static float area_power(const light *l, float scene_radius)
{
    return PHOS_PI * l->area * light_mean_color(l); /* Φ = πAL, one-sided */
}

static int area_hittable(const light *l) { return 1; }

/* Uniform on the shape. */
vec3 light_area_point(const light *l, float2 u)
{
    float a, b;
    if (l->area_shape == PHOS_AREA_ELLIPSE) {
        float2 dk = warp_disk_concentric(u);
        a = 0.5f * dk.x;
        b = 0.5f * dk.y;
    } else {
        a = u.x - 0.5f;
        b = u.y - 0.5f;
    }
    return v3_add(l->position, v3_add(v3_scale(l->axis_u, a), v3_scale(l->axis_v, b)));
}

static int area_sample(const scene *s, const light *l, const light_context *c, float2 u, light_sample *out)
{
    vec3 wi;
    float d, d2;
    if (!light_direction_to(c->p, light_area_point(l, u), &wi, &d, &d2))
        return 0;
    float cos_l = -v3_dot(wi, l->direction);
    if (cos_l <= 0.0f)
        return 0;
    out->wi = wi;
    out->distance = d;
    out->radiance = l->color;
    out->pdf = d2 / (l->area * cos_l);
    out->delta = 0;
    return 1;
}

/* Whether the point x, relative to the centre, lies on the shape. */
static int area_contains(const light *l, vec3 x)
{
    float lu2 = v3_length2(l->axis_u), lv2 = v3_length2(l->axis_v);
    float a = v3_dot(x, l->axis_u) / lu2; /* in [−0.5, 0.5] inside */
    float b = v3_dot(x, l->axis_v) / lv2;
    return l->area_shape == PHOS_AREA_ELLIPSE ? (a * a + b * b <= 0.25f) : (fabsf(a) <= 0.5f && fabsf(b) <= 0.5f);
}

int light_area_crossing(const light *l, vec3 o, vec3 d, float tmax, float *t_out, float *pdf)
{
    float denom = v3_dot(d, l->direction);
    if (denom >= 0.0f) /* one-sided: only the emitting face is seen */
        return 0;
    float t = v3_dot(v3_sub(l->position, o), l->direction) / denom;
    if (!(t > 0.0f) || t >= tmax)
        return 0;
    if (!area_contains(l, v3_sub(v3_madd(o, d, t), l->position)))
        return 0;
    *t_out = t;
    *pdf = t * t / (l->area * -denom);
    return 1;
}

static int area_intersect(const light *l, vec3 o, vec3 d, float tmax, light_hit *out)
{
    if (!light_area_crossing(l, o, d, tmax, &out->t, &out->pdf))
        return 0;
    out->radiance = l->color;
    return 1;
}

/* Cosine-weighted about the emitting side. */
static vec3 area_emission_direction(const light *l, float2 u, float *pdf)
{
    vec3 d = warp_cosine_about(l->direction, u);
    *pdf = maxf(v3_dot(d, l->direction), 0.0f) * PHOS_INV_PI;
    return d;
}

static int area_emit_toward(const scene *s, const light *l, vec3 d, float2 u, vec3 *origin, vec3 *intensity)
{
    float c = v3_dot(d, l->direction);
    *origin = light_area_point(l, u);
    *intensity = v3_scale(l->color, l->area * maxf(c, 0.0f)); /* L·A·cos, one-sided */
    return c > 0.0f;
}

const light_kind_ops light_area_ops = {
    .name = "area",
    .desc_type = PHOS_LIGHT_AREA,
    .from_desc = light_area_from_desc,
    .power = area_power,
    .hittable = area_hittable,
    .sample = area_sample,
    .intersect = area_intersect,
    .emission_direction = area_emission_direction,
    .emit_toward = area_emit_toward,
};
