/*
 * multiple_scattering.c — Blender 5's "Multiple Scattering" sky, the model
 * of F. García Liñán's master's thesis (2024): four
 * wavelengths (630, 560, 490, 430 nm) whose combination against fitted
 * weights gives CIE XYZ; molecules, a log-normal ozone layer and urban
 * aerosols over a 6371 km Earth under 100 km of air; single scattering
 * marched along the view ray with Hillaire's energy-conserving step
 * (2020, "A scalable and production ready sky and atmosphere rendering
 * technique"), plus a fitted term for the light scattered more than once
 * and the ground's (albedo 0.3) reflection of the sun. Lengths in km.
 */
#include <stdlib.h>
#include <string.h>

#include "shading/color_space.h"
#include "shading/sky/sky.h"
#include "util/parallel.h"

#define MS_EARTH_RADIUS 6371.0f
#define MS_THICKNESS 100.0f
#define MS_ATMOSPHERE_RADIUS (MS_EARTH_RADIUS + MS_THICKNESS)
#define MS_STEPS 64
#define MS_LUT_COS 256      /* transmittance table: cos of the sun's zenith angle over [−1, 1] */
#define MS_LUT_HEIGHT 64    /* and height over [0, MS_THICKNESS] */
#define MS_GROUND_ALBEDO 0.3f
#define MS_AEROSOL_G 0.8f

typedef struct vec4f {
    float v[4];
} vec4f;

static const vec4f MS_SUN_IRRADIANCE = {{1.679f, 1.828f, 1.986f, 1.307f}};
static const vec4f MS_MOLECULAR_SCATTERING = {{6.605e-3f, 1.067e-2f, 1.842e-2f, 3.156e-2f}}; /* km⁻¹ at sea level */
static const vec4f MS_OZONE_CROSS_SECTION = {{3.472e-25f, 3.914e-25f, 1.349e-25f, 11.03e-27f}};
static const float MS_OZONE_MEAN_DOBSON = 334.5f;
static const vec4f MS_AEROSOL_ABSORPTION = {{2.8722e-24f, 4.6168e-24f, 7.9706e-24f, 1.3578e-23f}};
static const vec4f MS_AEROSOL_SCATTERING = {{1.5908e-22f, 1.7711e-22f, 2.0942e-22f, 2.4033e-22f}};
static const float MS_AEROSOL_DENSITY = 1.3681e20f, MS_AEROSOL_BACKGROUND = 2e6f, MS_AEROSOL_SCALE = 0.73f;
/* The four samples' weights in CIE XYZ. */
static const float MS_TO_XYZ[4][3] = {
    {53.386917738564668f, 22.981337506691025f, 0.0f},
    {43.904844466369358f, 71.347795700053394f, 0.102506867965741f},
    {1.6137278251608962f, 18.422960591455485f, 31.742921188390806f},
    {20.762668673810577f, 2.3614213523314369f, 110.48009643252140f},
};

static vec4f v4s(float s) { vec4f r = {{s, s, s, s}}; return r; }
static vec4f v4_add(vec4f a, vec4f b) { for (int i = 0; i < 4; i++) a.v[i] += b.v[i]; return a; }
static vec4f v4_mul(vec4f a, vec4f b) { for (int i = 0; i < 4; i++) a.v[i] *= b.v[i]; return a; }
static vec4f v4_scale(vec4f a, float s) { for (int i = 0; i < 4; i++) a.v[i] *= s; return a; }
static vec4f v4_lerp(vec4f a, vec4f b, float t)
{
    for (int i = 0; i < 4; i++)
        a.v[i] += (b.v[i] - a.v[i]) * t;
    return a;
}

typedef struct multiple_atmosphere {
    float air, aerosol, ozone;
    vec4f transmittance[MS_LUT_HEIGHT][MS_LUT_COS];
} multiple_atmosphere;

/* Scattering and extinction (km⁻¹) at height h (km). */
static void ms_coefficients(const multiple_atmosphere *a, float h, vec4f *molecular, vec4f *aerosol,
                            vec4f *extinction)
{
    float aerosols = MS_AEROSOL_DENSITY * (expf(-h / MS_AEROSOL_SCALE) + MS_AEROSOL_BACKGROUND / MS_AEROSOL_DENSITY) *
                     a->aerosol;
    float log_h = logf(fmaxf(h, 1e-4f));
    float ozone = 3.78547397e20f * expf(-sqr(log_h - 3.22261f) * 5.55555555f - log_h) * MS_OZONE_MEAN_DOBSON *
                  a->ozone;
    *molecular = v4_scale(MS_MOLECULAR_SCATTERING, expf(-0.07771971f * powf(h, 1.16364243f)) * a->air);
    *aerosol = v4_scale(MS_AEROSOL_SCATTERING, aerosols);
    *extinction = v4_add(v4_add(*molecular, *aerosol),
                         v4_add(v4_scale(MS_AEROSOL_ABSORPTION, aerosols), v4_scale(MS_OZONE_CROSS_SECTION, ozone)));
}

/* The distance from o along the unit d to the sphere of radius r: the
 * nearest crossing ahead, or −1 if there is none. */
static float ms_sphere(vec3 o, vec3 d, float r)
{
    float b = v3_dot(o, d), c = v3_length2(o) - r * r, disc = b * b - c;
    if (disc < 0.0f)
        return -1.0f;
    float q = sqrtf(disc), t0 = -b - q, t1 = -b + q;
    return t0 >= 0.0f ? t0 : t1 >= 0.0f ? t1 : -1.0f;
}

/* Transmittance toward the sun from height fraction `height` of the air,
 * the sun at cos_zenith: midpoint quadrature of the extinction. */
static vec4f ms_transmittance_to_sun(const multiple_atmosphere *a, float cos_zenith, float height)
{
    vec3 sun = v3(safe_sqrtf(1.0f - cos_zenith * cos_zenith), 0.0f, cos_zenith);
    vec3 o = v3(0.0f, 0.0f, MS_EARTH_RADIUS + height * MS_THICKNESS);
    float step = ms_sphere(o, sun, MS_ATMOSPHERE_RADIUS) / MS_STEPS;
    vec4f depth = v4s(0.0f);
    for (int i = 0; i < MS_STEPS; i++) {
        vec3 x = v3_madd(o, sun, ((float)i + 0.5f) * step);
        vec4f molecular, aerosol, extinction;
        ms_coefficients(a, fmaxf(v3_length(x) - MS_EARTH_RADIUS, 0.0f), &molecular, &aerosol, &extinction);
        depth = v4_add(depth, v4_scale(extinction, step));
    }
    for (int i = 0; i < 4; i++)
        depth.v[i] = expf(-depth.v[i]);
    return depth;
}

static vec4f ms_lookup(const multiple_atmosphere *a, float cos_zenith, float height)
{
    float x = (float)(MS_LUT_COS - 1) * clampf(cos_zenith * 0.5f + 0.5f, 0.0f, 1.0f);
    float y = (float)(MS_LUT_HEIGHT - 1) * clampf(height, 0.0f, 1.0f);
    int x0 = (int)x, y0 = (int)y;
    int x1 = x0 + 1 < MS_LUT_COS ? x0 + 1 : x0, y1 = y0 + 1 < MS_LUT_HEIGHT ? y0 + 1 : y0;
    vec4f lo = v4_lerp(a->transmittance[y0][x0], a->transmittance[y0][x1], x - (float)x0);
    vec4f hi = v4_lerp(a->transmittance[y1][x0], a->transmittance[y1][x1], x - (float)x0);
    return v4_lerp(lo, hi, y - (float)y0);
}

/* Light scattered more than once arriving at a point at distance r from
 * the Earth's centre (height fraction `height`), the sun at cos_zenith:
 * the model's fit for the air, plus the sunlit ground (a Lambertian disc
 * of the solid angle the Earth subtends) scattered isotropically. */
static vec4f ms_multiple(const multiple_atmosphere *a, float cos_zenith, float height, float r)
{
    static const vec4f fit = {{0.217f, 0.347f, 0.594f, 1.0f}};
    /* r can fall a rounding error below the Earth's radius on a ray that
     * grazes it (its distance is found in float). */
    float omega = 2.0f * PHOS_PI * (1.0f - safe_sqrtf(1.0f - sqr(MS_EARTH_RADIUS / fmaxf(r, MS_EARTH_RADIUS))));
    vec4f ground_to_sun = ms_lookup(a, cos_zenith, 0.0f);
    vec4f from_ground = ms_lookup(a, 1.0f, 0.0f), above = ms_lookup(a, 1.0f, height);
    vec4f ground = v4s(0.0f);
    for (int i = 0; i < 4; i++)
        ground.v[i] = above.v[i] > 0.0f ? PHOS_INV_4PI * omega * MS_GROUND_ALBEDO * PHOS_INV_PI *
                                              ground_to_sun.v[i] * (from_ground.v[i] / above.v[i]) * cos_zenith
                                        : 0.0f; /* the sun's light never gets this deep */
    return v4_add(v4_scale(fit, 0.02f / (1.0f + 5.0f * expf(-17.92f * cos_zenith))), ground);
}

static vec3 ms_to_rgb(vec4f l)
{
    vec3 xyz = v3s(0.0f);
    for (int i = 0; i < 4; i++)
        xyz = v3_madd(xyz, v3_load(MS_TO_XYZ[i]), l.v[i]);
    return xyz_to_rec709(xyz);
}

/* The radiance reaching a viewer at height `altitude` (km) along view,
 * the sun along sun: up to the ground or the top of the air. */
static vec3 ms_sky(const multiple_atmosphere *a, float altitude, vec3 view, vec3 sun)
{
    vec3 o = v3(0.0f, 0.0f, MS_EARTH_RADIUS + altitude);
    float ground = ms_sphere(o, view, MS_EARTH_RADIUS);
    float length = ground >= 0.0f ? ground : ms_sphere(o, view, MS_ATMOSPHERE_RADIUS);
    float cos_theta = -v3_dot(view, sun);
    float den = 1.0f + MS_AEROSOL_G * MS_AEROSOL_G + 2.0f * MS_AEROSOL_G * cos_theta;
    float p_molecular = sky_phase_rayleigh(cos_theta);
    float p_aerosol = PHOS_INV_4PI * (1.0f - MS_AEROSOL_G * MS_AEROSOL_G) / (den * sqrtf(den));
    float dt = length / MS_STEPS;
    vec4f radiance = v4s(0.0f), transmittance = v4s(1.0f);
    for (int i = 0; i < MS_STEPS; i++) {
        vec3 x = v3_madd(o, view, ((float)i + 0.5f) * dt);
        float r = v3_length(x), h = fmaxf(r - MS_EARTH_RADIUS, 0.0f), height = h / MS_THICKNESS;
        float cos_zenith = v3_dot(v3_scale(x, 1.0f / r), sun);
        vec4f molecular, aerosol, extinction;
        ms_coefficients(a, h, &molecular, &aerosol, &extinction);
        vec4f to_sun = ms_lookup(a, cos_zenith, height), more = ms_multiple(a, cos_zenith, height, r);
        for (int k = 0; k < 4; k++) {
            float source = MS_SUN_IRRADIANCE.v[k] * (molecular.v[k] * (p_molecular * to_sun.v[k] + more.v[k]) +
                                                     aerosol.v[k] * (p_aerosol * to_sun.v[k] + more.v[k]));
            /* ∫ over the step of S e^{−σt} dt = S (1 − e^{−σΔt}) / σ. */
            float step = expf(-dt * extinction.v[k]);
            radiance.v[k] += transmittance.v[k] * source * (1.0f - step) / fmaxf(extinction.v[k], 1e-7f);
            transmittance.v[k] *= step;
        }
    }
    return ms_to_rgb(radiance);
}

typedef struct ms_job {
    multiple_atmosphere *a;
    float altitude;
    vec3 sun;
    float *pixels;
} ms_job;

static void ms_lut_row(void *ctx, uint32_t row, uint32_t thread)
{
    (void)thread;
    multiple_atmosphere *a = ((ms_job *)ctx)->a;
    for (int x = 0; x < MS_LUT_COS; x++)
        a->transmittance[row][x] = ms_transmittance_to_sun(a, 2.0f * (float)x / (MS_LUT_COS - 1) - 1.0f,
                                                           (float)row / (MS_LUT_HEIGHT - 1));
}

static void ms_bake_row(void *ctx, uint32_t row, uint32_t thread)
{
    (void)thread;
    const ms_job *job = ctx;
    for (uint32_t column = 0; column < SKY_TEXTURE_WIDTH / 2; column++) {
        float e;
        vec3 d = sky_texel_direction(PHOS_SKY_LAYOUT_SPHERE, 1, column, row, &e);
        sky_store_texel(job->pixels, column, row, ms_sky(job->a, job->altitude, d, job->sun));
    }
}

/* The sun's disc seen at `elevation`: its irradiance through the air
 * over the disc's solid angle. */
static vec3 ms_sun(const multiple_atmosphere *a, float elevation, float height, float solid_angle)
{
    vec4f t = ms_transmittance_to_sun(a, sinf(elevation), height);
    return ms_to_rgb(v4_scale(v4_mul(MS_SUN_IRRADIANCE, t), 1.0f / solid_angle));
}

phos_status sky_multiple_scattering_bake(const phos_sky_desc *d, float *pixels, float *data)
{
    multiple_atmosphere *a = malloc(sizeof(multiple_atmosphere));
    if (!a)
        return PHOS_ERROR_OUT_OF_MEMORY;
    a->air = d->air_density;
    a->aerosol = d->aerosol_density;
    a->ozone = d->ozone_density;
    float altitude = clampf(d->altitude, 1.0f, 99999.0f) * 1e-3f; /* km */
    float half = 0.5f * d->sun_size, solid_angle = sky_disc_solid_angle(d->sun_size);
    vec3 low = v3s(0.0f), high = v3s(0.0f);
    if (solid_angle > 0.0f) {
        low = ms_sun(a, d->sun_elevation - half, altitude / MS_THICKNESS, solid_angle);
        high = ms_sun(a, d->sun_elevation + half, altitude / MS_THICKNESS, solid_angle);
    }
    sky_write_sun(d, low, high, -acosf(MS_EARTH_RADIUS / (MS_EARTH_RADIUS + altitude)), data);
    int ok = 1;
    if (pixels) {
        /* The sun at azimuth π, the texture's middle column, as in the single-scattering texture. */
        ms_job job = {a, altitude, v3(-cosf(d->sun_elevation), 0.0f, sinf(d->sun_elevation)), pixels};
        uint32_t threads = parallel_thread_count(0);
        ok = parallel_for(MS_LUT_HEIGHT, threads, ms_lut_row, &job, NULL) &&
             parallel_for(sky_texture_height(PHOS_SKY_LAYOUT_SPHERE), threads, ms_bake_row, &job, NULL);
    }
    free(a);
    return ok ? PHOS_OK : PHOS_ERROR_OUT_OF_MEMORY;
}
