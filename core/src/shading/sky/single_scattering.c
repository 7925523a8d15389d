/*
 * single_scattering.c — Blender's "Nishita" sky (before 5.0; "Single
 * Scattering" from 5.0): Nishita, Sirai, Tadamura and Nakamae 1993,
 * "Display of the Earth taking into account atmospheric scattering", with
 * the parameters Blender's Sky Texture gives it (docs/algorithms.md §11.1).
 *
 * A spherical Earth (6360 km) under 60 km of air whose molecules
 * (Rayleigh, scale height 8 km) and aerosols (Mie, 1.2 km, the
 * Cornette-Shanks phase function with g = 0.76) scatter sunlight once
 * toward the viewer, and whose ozone (a tent from 10 to 40 km, densest at
 * 25 km) absorbs it; 21 wavelengths from 380 to 780 nm, integrated against
 * the CIE 1931 colour matching functions. The sky is computed into the
 * texture of sky.h; below the horizon it fades to black.
 */
#include <stdlib.h>
#include <string.h>

#include "shading/color_space.h"
#include "shading/sky/sky.h"
#include "util/parallel.h"

#define WAVELENGTHS 21       /* 380, 400, …, 780 nm */
#define LAMBDA_STEP 20.0f    /* nm */
#define EARTH_RADIUS 6360e3f /* m */
#define ATMOSPHERE_RADIUS 6420e3f
#define RAYLEIGH_SCALE 8e3f  /* m */
#define MIE_SCALE 1.2e3f     /* m */
#define MIE_SCATTERING 2e-5f /* m⁻¹ at sea level */
#define MIE_EXTINCTION (1.11f * MIE_SCATTERING)
#define MIE_G 0.76f
#define VIEW_STEPS 32        /* midpoint segments along the view ray */
#define MAX_ALTITUDE 59999.0f

/* The CIE 1931 2° standard observer x̄, ȳ, z̄ at 20 nm from 380 nm
 * (CIE 15:2004, Table T.4). */
static const float CMF[WAVELENGTHS][3] = {
    {0.001368f, 0.000039f, 0.006450001f}, {0.01431f, 0.000396f, 0.06785001f}, {0.13438f, 0.004f, 0.6456f},
    {0.34828f, 0.023f, 1.74706f},         {0.2908f, 0.06f, 1.6692f},          {0.09564f, 0.13902f, 0.8129501f},
    {0.0049f, 0.323f, 0.272f},            {0.06327f, 0.71f, 0.07824999f},     {0.2904f, 0.954f, 0.0203f},
    {0.5945f, 0.995f, 0.0039f},           {0.9163f, 0.87f, 0.001650001f},     {1.0622f, 0.631f, 0.0008f},
    {0.8544499f, 0.381f, 0.00019f},       {0.4479f, 0.175f, 0.00002f},        {0.1649f, 0.061f, 0.0f},
    {0.04677f, 0.017f, 0.0f},             {0.01135916f, 0.004102f, 0.0f},     {0.002899327f, 0.001047f, 0.0f},
    {0.0006900786f, 0.0002492f, 0.0f},    {0.0001661505f, 0.00006f, 0.0f},    {0.00004150994f, 0.00001499f, 0.0f},
};

/* Ozone's absorption coefficient at the tent's peak (m⁻¹): the model's
 * number density times the cross-sections measured by Serdyuchenko et al.
 * (2014) at 293 K, as Blender's Sky Texture sets them. */
static const float OZONE_ABSORPTION[WAVELENGTHS] = {
    3.25126849861e-9f, 5.85395365047e-9f, 1.977191155085e-8f, 7.309568762914e-8f, 2.0084561514287e-7f,
    4.0383958096161e-7f, 6.3551335912363e-7f, 9.670704118097e-7f, 1.5479740042441e-6f, 2.09038647223331e-6f,
    2.46128056164565e-6f, 2.73551299461512e-6f, 2.15125863128643e-6f, 1.59051840791988e-6f, 1.12356197979857e-6f,
    7.3527551487574e-7f, 4.6450130357806e-7f, 3.3096079921048e-7f, 2.2512612292678e-7f, 1.487912926649e-7f,
    1.6828623364192e-7f,
};

/* Gauss-Laguerre quadrature of 8 nodes for the optical depth toward the
 * sun, ∫ f(x) e^{−x} dx, with the nodes scaled so that the last lies
 * within the atmosphere (x/25) and e^{x} folded into the weights: the
 * densities fall off roughly exponentially along the ray. */
static const float LAGUERRE_NODE[8] = {0.006811185292f, 0.03614807107f, 0.09004346519f, 0.1706680068f,
                                       0.2818362161f,   0.4303406404f,  0.6296271457f,  0.9145252695f};
static const float LAGUERRE_WEIGHT[8] = {0.01750893642f, 0.04135477391f, 0.06678839063f, 0.09507698807f,
                                         0.1283416365f,  0.1707430204f,  0.2327233347f,  0.3562490486f};

typedef struct spectrum {
    float v[WAVELENGTHS];
} spectrum;

typedef struct atmosphere {
    float solar[WAVELENGTHS];    /* the sun's spectral irradiance above the air, W/(m²·nm) */
    float rayleigh[WAVELENGTHS]; /* molecules' scattering coefficient at sea level, m⁻¹ */
    float air, aerosol, ozone;   /* the node's density multipliers */
    float altitude;              /* m */
} atmosphere;

/* The sun as a black body of 5778 K (W/(m²·sr·m) by Planck's law), seen
 * under the solid angle of its disc at 1 AU: E(λ) = π B(λ, T) (R☉/d)². */
static float solar_irradiance(float lambda_nm)
{
    const double h = 6.62607015e-34, c = 2.99792458e8, k = 1.380649e-23, t = 5778.0;
    const double r_sun = 6.957e8, au = 1.495978707e11;
    double l = lambda_nm * 1e-9;
    double b = 2.0 * h * c * c / (l * l * l * l * l) / expm1(h * c / (l * k * t));
    return (float)((double)PHOS_PI * b * (r_sun / au) * (r_sun / au) * 1e-9);
}

/* Rayleigh's scattering coefficient of air at sea level,
 * β(λ) = 8π³(n² − 1)² / (3Nλ⁴), n = 1.0002926 and N = 2.504·10²⁵ m⁻³
 * (Nishita et al. 1993, eq. 2 integrated over the phase function). */
static float rayleigh_scattering(float lambda_nm)
{
    const double n = 1.0002926, molecules = 2.504e25, pi = (double)PHOS_PI;
    double l = lambda_nm * 1e-9, n2 = n * n - 1.0;
    return (float)(8.0 * pi * pi * pi * n2 * n2 / (3.0 * molecules * l * l * l * l));
}

static atmosphere make_atmosphere(const phos_sky_desc *d)
{
    atmosphere a;
    for (int i = 0; i < WAVELENGTHS; i++) {
        float lambda = 380.0f + LAMBDA_STEP * (float)i;
        a.solar[i] = solar_irradiance(lambda);
        a.rayleigh[i] = rayleigh_scattering(lambda);
    }
    a.air = d->air_density;
    a.aerosol = d->aerosol_density;
    a.ozone = d->ozone_density;
    a.altitude = clampf(d->altitude, 1.0f, MAX_ALTITUDE);
    return a;
}

/* Relative densities (1 at their peak) at height h above sea level (m):
 * molecules, aerosols and ozone. */
static vec3 densities(float h)
{
    return v3(expf(-h / RAYLEIGH_SCALE), expf(-h / MIE_SCALE), maxf(0.0f, 1.0f - fabsf(h - 25e3f) / 15e3f));
}

/* Distance from p along the unit d to the top of the atmosphere. */
static float to_top(vec3 p, vec3 d)
{
    float b = v3_dot(p, d), c = v3_length2(p) - ATMOSPHERE_RADIUS * ATMOSPHERE_RADIUS;
    return -b + sqrtf(maxf(b * b - c, 0.0f));
}

/* Whether the ray from p along d meets the Earth. */
static int hits_earth(vec3 p, vec3 d)
{
    float b = v3_dot(p, d);
    return b < 0.0f && b * b - (v3_length2(p) - EARTH_RADIUS * EARTH_RADIUS) >= 0.0f;
}

/* ∫ density ds from p to the top of the atmosphere along d, per kind (m). */
static vec3 optical_length(vec3 p, vec3 d)
{
    float length = to_top(p, d);
    vec3 sum = v3s(0.0f);
    for (int i = 0; i < 8; i++) {
        vec3 q = v3_madd(p, d, LAGUERRE_NODE[i] * length);
        sum = v3_madd(sum, densities(v3_length(q) - EARTH_RADIUS), LAGUERRE_WEIGHT[i]);
    }
    return v3_scale(sum, length);
}

/* Cornette and Shanks 1992. */
static float phase_mie(float mu)
{
    const float g2 = MIE_G * MIE_G;
    return 3.0f * (1.0f - g2) * (1.0f + mu * mu) /
           (8.0f * PHOS_PI * (2.0f + g2) * powf(1.0f + g2 - 2.0f * MIE_G * mu, 1.5f));
}

static float extinction(const atmosphere *a, vec3 length, int i)
{
    return a->rayleigh[i] * length.x + MIE_EXTINCTION * length.y + OZONE_ABSORPTION[i] * length.z;
}

/* The radiance scattered once toward a viewer at `origin` looking along
 * view (W/(m²·sr·nm) per wavelength): the view ray is cut into
 * VIEW_STEPS segments, each lit through the air above it where the Earth
 * does not shadow it: L = Σ T(viewer, x) T(x, sun) σ_s(x) p(μ) E Δs. */
static spectrum single_scattering(const atmosphere *a, vec3 origin, vec3 view, vec3 sun)
{
    spectrum out;
    memset(&out, 0, sizeof(out));
    float step = to_top(origin, view) / VIEW_STEPS;
    float mu = v3_dot(view, sun);
    float p_r = sky_phase_rayleigh(mu), p_m = phase_mie(mu);
    vec3 scale = v3(a->air, a->aerosol, a->ozone);
    vec3 viewed = v3s(0.0f); /* density × length from the viewer, per kind */
    for (int s = 0; s < VIEW_STEPS; s++) {
        vec3 x = v3_madd(origin, view, ((float)s + 0.5f) * step);
        vec3 rho = v3_mul(densities(v3_length(x) - EARTH_RADIUS), scale);
        viewed = v3_madd(viewed, rho, step);
        if (hits_earth(x, sun))
            continue;
        vec3 length = v3_add(viewed, v3_mul(optical_length(x, sun), scale));
        for (int i = 0; i < WAVELENGTHS; i++) {
            float scattered = (a->rayleigh[i] * rho.x * p_r + MIE_SCATTERING * rho.y * p_m) * step;
            out.v[i] += expf(-extinction(a, length, i)) * scattered * a->solar[i];
        }
    }
    return out;
}

/* CIE XYZ of a spectrum sampled at the WAVELENGTHS, then linear Rec. 709. */
static vec3 spectrum_to_rgb(const spectrum *s)
{
    vec3 xyz = v3s(0.0f);
    for (int i = 0; i < WAVELENGTHS; i++)
        xyz = v3_madd(xyz, v3_load(CMF[i]), s->v[i]);
    return xyz_to_rec709(v3_scale(xyz, LAMBDA_STEP));
}

/* The sun's disc seen along d: its irradiance through the air (molecules
 * and aerosols; the model leaves ozone out of the direct beam) spread
 * evenly over the disc's solid angle. */
static vec3 sun_radiance(const atmosphere *a, vec3 d, float solid_angle)
{
    vec3 origin = v3(0.0f, 0.0f, EARTH_RADIUS + a->altitude);
    vec3 length = optical_length(origin, d);
    spectrum s;
    for (int i = 0; i < WAVELENGTHS; i++)
        s.v[i] = a->solar[i] * expf(-(a->rayleigh[i] * length.x * a->air +
                                      MIE_EXTINCTION * length.y * a->aerosol)) / solid_angle;
    return spectrum_to_rgb(&s);
}

/* ------------------------------------------------------------------ bake */

typedef struct bake_job {
    const atmosphere *a;
    vec3 sun;                   /* in the texels' frame */
    uint32_t layout;
    float *pixels;
} bake_job;

/* A row of the sky above the horizon (the left half, mirrored). */
static void bake_row(void *ctx, uint32_t row, uint32_t thread)
{
    (void)thread;
    const bake_job *job = ctx;
    vec3 origin = v3(0.0f, 0.0f, EARTH_RADIUS + job->a->altitude);
    uint32_t first = job->layout == PHOS_SKY_LAYOUT_SPHERE ? sky_texture_height(job->layout) / 2 : 0;
    for (uint32_t column = 0; column < SKY_TEXTURE_WIDTH / 2; column++) {
        float e;
        vec3 d = sky_texel_direction(job->layout, 0, column, first + row, &e);
        spectrum s = single_scattering(job->a, origin, d, job->sun);
        sky_store_texel(job->pixels, column, first + row, spectrum_to_rgb(&s));
    }
}

/* The sphere layout's rows below the horizon: its fade (sky.h). */
static void fill_ground(float *pixels)
{
    const uint32_t half = sky_texture_height(PHOS_SKY_LAYOUT_SPHERE) / 2;
    const float *horizon = pixels + (size_t)half * SKY_TEXTURE_WIDTH * 4;
    for (uint32_t row = 0; row < half; row++) {
        float e;
        sky_texel_direction(PHOS_SKY_LAYOUT_SPHERE, 0, 0, row, &e);
        float fade = sky_ground_fade(e);
        float *p = pixels + (size_t)row * SKY_TEXTURE_WIDTH * 4;
        for (uint32_t k = 0; k < SKY_TEXTURE_WIDTH * 4; k++)
            p[k] = (k & 3u) == 3u ? 1.0f : horizon[k] * fade;
    }
}

phos_status sky_single_scattering_bake(const phos_sky_desc *d, float *pixels, float *data)
{
    atmosphere a = make_atmosphere(d);
    float half = 0.5f * d->sun_size, solid_angle = sky_disc_solid_angle(d->sun_size);
    float bottom = maxf(d->sun_elevation - half, 0.0f), top = maxf(d->sun_elevation + half, 0.0f);
    vec3 low = v3s(0.0f), high = v3s(0.0f);
    if (top > 0.0f && solid_angle > 0.0f) {
        low = sun_radiance(&a, v3(cosf(bottom), 0.0f, sinf(bottom)), solid_angle);
        high = sun_radiance(&a, v3(cosf(top), 0.0f, sinf(top)), solid_angle);
    }
    sky_write_sun(d, low, high, -acosf(EARTH_RADIUS / (EARTH_RADIUS + a.altitude)), data);
    if (!pixels)
        return PHOS_OK;
    bake_job job = {&a, v3(cosf(d->sun_elevation), 0.0f, sinf(d->sun_elevation)), d->layout, pixels};
    uint32_t rows = sky_texture_height(d->layout);
    if (d->layout == PHOS_SKY_LAYOUT_SPHERE)
        rows /= 2;
    if (!parallel_for(rows, parallel_thread_count(0), bake_row, &job, NULL))
        return PHOS_ERROR_OUT_OF_MEMORY;
    if (d->layout == PHOS_SKY_LAYOUT_SPHERE)
        fill_ground(pixels);
    return PHOS_OK;
}
