/*
 * sky.c — phos_sky_bake: the Sky Texture's model computed once per node
 * (sky.h), and the geometry its models and its lookup share.
 */
#include "shading/sky/sky.h"

#include <string.h>

/* ------------------------------------------------------------- geometry */

vec3 sky_sun_direction(float elevation, float rotation)
{
    float ce = cosf(elevation);
    return v3(ce * sinf(rotation), ce * cosf(rotation), sinf(elevation));
}

void sky_texture_coordinates(float elevation, float azimuth, uint32_t width, uint32_t height, float *u, float *v)
{
    float a = fabsf(remainderf(azimuth, 2.0f * PHOS_PI)) * PHOS_INV_PI; /* [0, 1] */
    float s = copysignf(sqrtf(fminf(fabsf(elevation) * (2.0f * PHOS_INV_PI), 1.0f)), elevation);
    *u = (a * (float)(width - 1) + 0.5f) / (float)width;
    *v = ((s + 1.0f) * 0.5f * (float)(height - 1) + 0.5f) / (float)height;
}

vec3 sky_texel_direction(uint32_t column, uint32_t row, uint32_t width, uint32_t height, float *elevation)
{
    float s = 2.0f * (float)row / (float)(height - 1) - 1.0f;
    float e = copysignf(s * s, s) * (0.5f * PHOS_PI);
    float a = PHOS_PI * (float)column / (float)(width - 1);
    *elevation = e;
    return v3(cosf(e) * cosf(a), cosf(e) * sinf(a), sinf(e));
}

vec3 sky_analytic_sun(const float *data)
{
    float st = sinf(data[SKY_ANALYTIC_THETA]);
    return v3(st * sinf(data[SKY_ANALYTIC_PHI]), st * cosf(data[SKY_ANALYTIC_PHI]), cosf(data[SKY_ANALYTIC_THETA]));
}

void sky_write_sun(const phos_sky_desc *d, vec3 bottom, vec3 top, float earth_angle, float *data)
{
    memcpy(data + SKY_SUN_BOTTOM, &bottom, sizeof(float) * 3);
    memcpy(data + SKY_SUN_TOP, &top, sizeof(float) * 3);
    data[SKY_SUN_ELEVATION] = d->sun_elevation;
    data[SKY_SUN_ROTATION] = d->sun_rotation;
    data[SKY_SUN_DIAMETER] = d->sun_disc ? d->sun_size : -1.0f;
    data[SKY_SUN_INTENSITY] = d->sun_intensity;
    data[SKY_EARTH_ANGLE] = earth_angle;
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
    d->ground_albedo = 0.3f;
    d->sun_direction[2] = 1.0f;
}

static int finite_desc(const phos_sky_desc *d)
{
    const float v[] = {d->sun_elevation, d->sun_rotation, d->sun_size, d->sun_intensity, d->altitude,
                       d->air_density, d->aerosol_density, d->ozone_density, d->turbidity, d->ground_albedo,
                       d->sun_direction[0], d->sun_direction[1], d->sun_direction[2]};
    for (size_t i = 0; i < sizeof(v) / sizeof(v[0]); i++)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

/* Settings no model can use (Blender's own ranges are narrower). */
static int valid_desc(const phos_sky_desc *d)
{
    if (d->model >= PHOS_SKY_MODEL_COUNT || !finite_desc(d))
        return 0;
    if (d->model == PHOS_SKY_PREETHAM || d->model == PHOS_SKY_HOSEK_WILKIE)
        return d->turbidity >= 1.0f && d->turbidity <= 64.0f && d->ground_albedo >= 0.0f &&
               d->ground_albedo <= 1.0f && v3_length2(v3_load(d->sun_direction)) > 0.0f;
    return d->sun_size >= 0.0f && d->sun_size <= PHOS_PI && d->air_density >= 0.0f && d->aerosol_density >= 0.0f &&
           d->ozone_density >= 0.0f;
}

phos_status phos_sky_bake(const phos_sky_desc *d, uint32_t width, uint32_t height, float *pixels, float *data)
{
    if (!d || !data || !valid_desc(d))
        return PHOS_ERROR_INVALID_ARGUMENT;
    if (pixels && (width < 2 || height < 3 || !(height & 1u) || width > 8192 || height > 8193))
        return PHOS_ERROR_INVALID_ARGUMENT;
    memset(data, 0, sizeof(float) * PHOS_SKY_DATA_FLOATS);
    switch (d->model) {
    case PHOS_SKY_PREETHAM:
        return sky_preetham_bake(d, data);
    case PHOS_SKY_HOSEK_WILKIE:
        return sky_hosek_wilkie_bake(d, data);
    case PHOS_SKY_MULTIPLE_SCATTERING:
        return sky_multiple_scattering_bake(d, width, height, pixels, data);
    default:
        return sky_single_scattering_bake(d, width, height, pixels, data);
    }
}
