/*
 * sky.c — the Sky Texture's daylight models computed once per node
 * (sky.h; docs/algorithms.md §11.4), as Cycles defines them, so that a
 * sky renders as bright and as coloured in Phos as in Cycles.
 *
 * Single scattering (Blender's "Nishita" before 5.0, "Single Scattering"
 * from 5.0; Nishita, Sirai, Tadamura and Nakamae 1993, "Display of the
 * Earth taking into account atmospheric scattering"): a spherical Earth
 * (6360 km) under 60 km of air whose molecules (Rayleigh, scale height
 * 8 km) and aerosols (Mie, 1.2 km, Cornette-Shanks phase with g = 0.76)
 * scatter sunlight once toward the viewer, and whose ozone (a tent from 10
 * to 40 km, densest at 25 km) absorbs it; 21 wavelengths from 380 to
 * 780 nm, integrated against the CIE 1931 colour matching functions.
 *
 * Preetham, Shirley and Smits 1999, "A practical analytic model for
 * daylight": the Perez et al. (1993) luminance distribution with
 * coefficients linear in turbidity (the paper's Appendix A.2), and the
 * zenith's luminance and chromaticity (A.3).
 */
#include "shading/sky.h"

#include <stdlib.h>
#include <string.h>

#include "shading/color_space.h"
#include "util/parallel.h"

/* ------------------------------------------------------- single scattering */

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
    return (float)(3.14159265358979 * b * (r_sun / au) * (r_sun / au) * 1e-9);
}

/* Rayleigh's scattering coefficient of air at sea level,
 * β(λ) = 8π³(n² − 1)² / (3Nλ⁴), n = 1.0002926 and N = 2.504·10²⁵ m⁻³
 * (Nishita et al. 1993, eq. 2 integrated over the phase function). */
static float rayleigh_scattering(float lambda_nm)
{
    const double n = 1.0002926, molecules = 2.504e25, pi = 3.14159265358979;
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

static float phase_rayleigh(float mu) { return 3.0f / (16.0f * PHOS_PI) * (1.0f + mu * mu); }

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
    float p_r = phase_rayleigh(mu), p_m = phase_mie(mu);
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

/* ------------------------------------------------------------- geometry */

vec3 sky_sun_direction(float elevation, float rotation)
{
    float ce = cosf(elevation);
    return v3(ce * sinf(rotation), ce * cosf(rotation), sinf(elevation));
}

float sky_earth_angle(float altitude)
{
    float h = clampf(altitude, 1.0f, MAX_ALTITUDE);
    return -acosf(EARTH_RADIUS / (EARTH_RADIUS + h));
}

void sky_texture_coordinates(float elevation, float azimuth, uint32_t width, uint32_t height, float *u, float *v)
{
    float a = fabsf(remainderf(azimuth, 2.0f * PHOS_PI)) * PHOS_INV_PI; /* [0, 1] */
    float s = copysignf(sqrtf(fminf(fabsf(elevation) * (2.0f * PHOS_INV_PI), 1.0f)), elevation);
    *u = (a * (float)(width - 1) + 0.5f) / (float)width;
    *v = ((s + 1.0f) * 0.5f * (float)(height - 1) + 0.5f) / (float)height;
}

/* The direction of texel (column, row), in the frame where the sun's
 * azimuth is 0 (+x). */
static vec3 texel_direction(uint32_t column, uint32_t row, uint32_t width, uint32_t height, float *elevation)
{
    float s = 2.0f * (float)row / (float)(height - 1) - 1.0f;
    float e = copysignf(s * s, s) * (0.5f * PHOS_PI);
    float a = PHOS_PI * (float)column / (float)(width - 1);
    *elevation = e;
    return v3(cosf(e) * cosf(a), cosf(e) * sinf(a), sinf(e));
}

/* ------------------------------------------------------------------ bake */

typedef struct bake_job {
    const atmosphere *a;
    vec3 sun;                   /* in the texels' frame */
    uint32_t width, height;
    float *pixels;
} bake_job;

/* Below the horizon the single-scattering sky fades to black by 0.4 of the
 * way down (sin e > −0.4) as (1 + 2.5 sin e)³ times the horizon's colour:
 * the model has no ground, and this is how Cycles draws it. */
static float ground_fade(float elevation)
{
    float z = sinf(elevation);
    return z < -0.4f ? 0.0f : powf(1.0f + 2.5f * z, 3.0f);
}

static void bake_row(void *ctx, uint32_t row, uint32_t thread)
{
    (void)thread;
    const bake_job *job = ctx;
    uint32_t horizon = (job->height - 1) / 2;
    vec3 origin = v3(0.0f, 0.0f, EARTH_RADIUS + job->a->altitude);
    for (uint32_t column = 0; column < job->width; column++) {
        float e;
        vec3 d = texel_direction(column, row < horizon ? horizon : row, job->width, job->height, &e);
        spectrum s = single_scattering(job->a, origin, d, job->sun);
        vec3 rgb = spectrum_to_rgb(&s);
        if (row < horizon) {
            float below;
            texel_direction(column, row, job->width, job->height, &below);
            rgb = v3_scale(rgb, ground_fade(below));
        }
        float *p = job->pixels + ((size_t)row * job->width + column) * 4;
        p[0] = rgb.x, p[1] = rgb.y, p[2] = rgb.z, p[3] = 1.0f;
    }
}

static phos_status bake_single_scattering(const phos_sky_desc *d, uint32_t width, uint32_t height, float *pixels,
                                          float *data)
{
    atmosphere a = make_atmosphere(d);
    float half = 0.5f * d->sun_size;
    float solid_angle = 2.0f * PHOS_PI * (1.0f - cosf(half));
    float bottom = maxf(d->sun_elevation - half, 0.0f), top = maxf(d->sun_elevation + half, 0.0f);
    vec3 low = v3s(0.0f), high = v3s(0.0f);
    if (top > 0.0f && solid_angle > 0.0f) {
        low = sun_radiance(&a, v3(cosf(bottom), 0.0f, sinf(bottom)), solid_angle);
        high = sun_radiance(&a, v3(cosf(top), 0.0f, sinf(top)), solid_angle);
    }
    memcpy(data + SKY_SUN_BOTTOM, &low, sizeof(float) * 3);
    memcpy(data + SKY_SUN_TOP, &high, sizeof(float) * 3);
    data[SKY_SUN_ELEVATION] = d->sun_elevation;
    data[SKY_SUN_ROTATION] = d->sun_rotation;
    data[SKY_SUN_DIAMETER] = d->sun_disc ? d->sun_size : -1.0f;
    data[SKY_SUN_INTENSITY] = d->sun_intensity;
    data[SKY_EARTH_ANGLE] = sky_earth_angle(d->altitude);
    if (!pixels)
        return PHOS_OK;
    bake_job job = {&a, v3(cosf(d->sun_elevation), 0.0f, sinf(d->sun_elevation)), width, height, pixels};
    return parallel_for(height, parallel_thread_count(0), bake_row, &job, NULL) ? PHOS_OK
                                                                                : PHOS_ERROR_OUT_OF_MEMORY;
}

/* ----------------------------------------------------- multiple scattering */

/*
 * García Liñán 2024 ("A spectral sky model with a multiple-scattering
 * approximation", the model of Blender 5's "Multiple Scattering" sky): four
 * wavelengths (630, 560, 490, 430 nm) whose combination against fitted
 * weights gives CIE XYZ; molecules, a log-normal ozone layer and urban
 * aerosols over a 6371 km Earth under 100 km of air; single scattering
 * marched along the view ray with Hillaire's energy-conserving step
 * (2020, "A scalable and production ready sky and atmosphere rendering
 * technique"), plus a fitted term for the light scattered more than once
 * and the ground's (albedo 0.3) reflection of the sun. Lengths in km.
 */
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
    float omega = 2.0f * PHOS_PI * (1.0f - sqrtf(1.0f - sqr(MS_EARTH_RADIUS / r)));
    vec4f ground_to_sun = ms_lookup(a, cos_zenith, 0.0f);
    vec4f from_ground = ms_lookup(a, 1.0f, 0.0f), above = ms_lookup(a, 1.0f, height);
    vec4f ground = v4s(0.0f);
    for (int i = 0; i < 4; i++)
        ground.v[i] = PHOS_INV_4PI * omega * MS_GROUND_ALBEDO * PHOS_INV_PI * ground_to_sun.v[i] *
                      (from_ground.v[i] / above.v[i]) * cos_zenith;
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
    float p_molecular = 3.0f / (16.0f * PHOS_PI) * (1.0f + cos_theta * cos_theta);
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
    uint32_t width, height;
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
    for (uint32_t column = 0; column < job->width; column++) {
        float e;
        vec3 d = texel_direction(column, row, job->width, job->height, &e);
        vec3 rgb = ms_sky(job->a, job->altitude, d, job->sun);
        float *p = job->pixels + ((size_t)row * job->width + column) * 4;
        p[0] = rgb.x, p[1] = rgb.y, p[2] = rgb.z, p[3] = 1.0f;
    }
}

/* The sun's disc seen at `elevation`: its irradiance through the air
 * over the disc's solid angle. */
static vec3 ms_sun(const multiple_atmosphere *a, float elevation, float height, float solid_angle)
{
    vec4f t = ms_transmittance_to_sun(a, sinf(elevation), height);
    return ms_to_rgb(v4_scale(v4_mul(MS_SUN_IRRADIANCE, t), 1.0f / solid_angle));
}

static phos_status bake_multiple_scattering(const phos_sky_desc *d, uint32_t width, uint32_t height,
                                            float *pixels, float *data)
{
    multiple_atmosphere *a = malloc(sizeof(multiple_atmosphere));
    if (!a)
        return PHOS_ERROR_OUT_OF_MEMORY;
    a->air = d->air_density;
    a->aerosol = d->aerosol_density;
    a->ozone = d->ozone_density;
    float altitude = clampf(d->altitude, 1.0f, 99999.0f) * 1e-3f; /* km */
    float half = 0.5f * d->sun_size, solid_angle = 2.0f * PHOS_PI * (1.0f - cosf(half));
    vec3 low = v3s(0.0f), high = v3s(0.0f);
    if (solid_angle > 0.0f) {
        low = ms_sun(a, d->sun_elevation - half, altitude / MS_THICKNESS, solid_angle);
        high = ms_sun(a, d->sun_elevation + half, altitude / MS_THICKNESS, solid_angle);
    }
    memcpy(data + SKY_SUN_BOTTOM, &low, sizeof(float) * 3);
    memcpy(data + SKY_SUN_TOP, &high, sizeof(float) * 3);
    data[SKY_SUN_ELEVATION] = d->sun_elevation;
    data[SKY_SUN_ROTATION] = d->sun_rotation;
    data[SKY_SUN_DIAMETER] = d->sun_disc ? d->sun_size : -1.0f;
    data[SKY_SUN_INTENSITY] = d->sun_intensity;
    data[SKY_EARTH_ANGLE] = -acosf(MS_EARTH_RADIUS / (MS_EARTH_RADIUS + altitude));
    int ok = 1;
    if (pixels) {
        ms_job job = {a, altitude, v3(cosf(d->sun_elevation), 0.0f, sinf(d->sun_elevation)), width, height, pixels};
        uint32_t threads = parallel_thread_count(0);
        ok = parallel_for(MS_LUT_HEIGHT, threads, ms_lut_row, &job, NULL) &&
             parallel_for(height, threads, ms_bake_row, &job, NULL);
    }
    free(a);
    return ok ? PHOS_OK : PHOS_ERROR_OUT_OF_MEMORY;
}

/* -------------------------------------------------------------- Preetham */

/* The Perez function's A..E for Y, x and y, each a·T + b (Preetham et
 * al. 1999, A.2). */
static const float PEREZ[3][5][2] = {
    {{0.1787f, -1.4630f}, {-0.3554f, 0.4275f}, {-0.0227f, 5.3251f}, {0.1206f, -2.5771f}, {-0.0670f, 0.3703f}},
    {{-0.0193f, -0.2592f}, {-0.0665f, 0.0008f}, {-0.0004f, 0.2125f}, {-0.0641f, -0.8989f}, {-0.0033f, 0.0452f}},
    {{-0.0167f, -0.2608f}, {-0.0950f, 0.0092f}, {-0.0079f, 0.2102f}, {-0.0441f, -1.6537f}, {-0.0109f, 0.0529f}},
};

/* The zenith's chromaticity x and y: [T², T, 1] · M · [θ³, θ², θ, 1] (A.3). */
static const float ZENITH_CHROMA[2][3][4] = {
    {{0.00166f, -0.00375f, 0.00209f, 0.0f}, {-0.02903f, 0.06377f, -0.03202f, 0.00394f},
     {0.11693f, -0.21196f, 0.06052f, 0.25886f}},
    {{0.00275f, -0.00610f, 0.00317f, 0.0f}, {-0.04214f, 0.08970f, -0.04153f, 0.00516f},
     {0.15346f, -0.26756f, 0.06670f, 0.26688f}},
};

/* Perez et al.: (1 + A e^{B/cos θ})(1 + C e^{Dγ} + E cos²γ). */
float sky_perez(const float *c, float theta, float gamma)
{
    float cg = cosf(gamma);
    return (1.0f + c[0] * expf(c[1] / cosf(theta))) * (1.0f + c[2] * expf(c[3] * gamma) + c[4] * cg * cg);
}

static phos_status bake_preetham(const phos_sky_desc *d, float *data)
{
    vec3 sun = v3_normalize(v3_load(d->sun_direction));
    float theta = acosf(clampf(sun.z, -1.0f, 1.0f)), t = d->turbidity;
    data[SKY_PREETHAM_THETA] = theta;
    data[SKY_PREETHAM_PHI] = atan2f(sun.x, sun.y);
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < 5; i++)
            data[SKY_PREETHAM_PEREZ + 5 * k + i] = PEREZ[k][i][0] * t + PEREZ[k][i][1];
    /* Zenith luminance in kcd/m² (A.3), scaled by 0.06 as Cycles scales
     * it (measured: Cycles' Preetham sky is 0.06 × the paper's value in
     * kcd/m² on 3.4, 4.5 and 5.3; tests/blender/test_sky.py). */
    float chi = (4.0f / 9.0f - t / 120.0f) * (PHOS_PI - 2.0f * theta);
    float zenith[3];
    zenith[0] = ((4.0453f * t - 4.9710f) * tanf(chi) - 0.2155f * t + 2.4192f) * 0.06f;
    float th[4] = {theta * theta * theta, theta * theta, theta, 1.0f}, tt[3] = {t * t, t, 1.0f};
    for (int k = 0; k < 2; k++) {
        float sum = 0.0f;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 4; j++)
                sum += tt[i] * ZENITH_CHROMA[k][i][j] * th[j];
        zenith[k + 1] = sum;
    }
    /* F(θ, γ) is normalised by its value at the zenith, where γ = θ_sun. */
    for (int k = 0; k < 3; k++)
        data[SKY_PREETHAM_ZENITH + k] = zenith[k] / sky_perez(data + SKY_PREETHAM_PEREZ + 5 * k, 0.0f, theta);
    return PHOS_OK;
}

/* ------------------------------------------------------------------- API */

void phos_sky_desc_init(phos_sky_desc *d)
{
    if (!d)
        return;
    memset(d, 0, sizeof(*d));
    d->model = PHOS_SKY_SINGLE_SCATTERING;
    d->sun_elevation = 15.0f * PHOS_PI / 180.0f;
    d->sun_size = 0.545f * PHOS_PI / 180.0f;
    d->sun_intensity = 1.0f;
    d->sun_disc = 1;
    d->air_density = d->aerosol_density = d->ozone_density = 1.0f;
    d->turbidity = 2.2f;
    d->sun_direction[2] = 1.0f;
}

static int finite_desc(const phos_sky_desc *d)
{
    const float v[] = {d->sun_elevation, d->sun_rotation, d->sun_size, d->sun_intensity, d->altitude,
                       d->air_density, d->aerosol_density, d->ozone_density, d->turbidity,
                       d->sun_direction[0], d->sun_direction[1], d->sun_direction[2]};
    for (size_t i = 0; i < sizeof(v) / sizeof(v[0]); i++)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

phos_status phos_sky_bake(const phos_sky_desc *d, uint32_t width, uint32_t height, float *pixels, float *data)
{
    if (!d || !data || d->model >= PHOS_SKY_MODEL_COUNT || !finite_desc(d) || d->sun_size < 0.0f ||
        d->air_density < 0.0f || d->aerosol_density < 0.0f || d->ozone_density < 0.0f)
        return PHOS_ERROR_INVALID_ARGUMENT;
    if (pixels && (width < 2 || height < 3 || !(height & 1u) || width > 8192 || height > 8193))
        return PHOS_ERROR_INVALID_ARGUMENT;
    memset(data, 0, sizeof(float) * PHOS_SKY_DATA_FLOATS);
    switch (d->model) {
    case PHOS_SKY_PREETHAM:
        if (d->turbidity < 1.0f || v3_length2(v3_load(d->sun_direction)) == 0.0f)
            return PHOS_ERROR_INVALID_ARGUMENT;
        return bake_preetham(d, data);
    case PHOS_SKY_MULTIPLE_SCATTERING:
        return bake_multiple_scattering(d, width, height, pixels, data);
    default:
        return bake_single_scattering(d, width, height, pixels, data);
    }
}
