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

uint32_t sky_texture_height(uint32_t layout) { return layout == PHOS_SKY_LAYOUT_SPHERE ? 256u : 128u; }

void sky_texture_coordinates(uint32_t layout, float elevation, float azimuth, float *u, float *v)
{
    float a = remainderf(azimuth, 2.0f * PHOS_PI); /* (−π, π] */
    *u = 0.5f + a * (0.5f * PHOS_INV_PI);
    *u -= floorf(*u);
    float s = sqrtf(fminf(fabsf(elevation) * (2.0f * PHOS_INV_PI), 1.0f));
    if (layout == PHOS_SKY_LAYOUT_SPHERE)
        *v = copysignf(s, elevation) * 0.5f + 0.5f;
    else
        *v = elevation >= 0.0f ? s : -0.5f;
}

vec3 sky_texel_direction(uint32_t layout, int centred, uint32_t column, uint32_t row, float *elevation)
{
    const float w = SKY_TEXTURE_WIDTH, h = (float)sky_texture_height(layout);
    float e, a;
    if (centred) {
        float l = ((float)row + 0.5f) / (0.5f * h) - 1.0f;
        e = copysignf(l * l, l) * (0.5f * PHOS_PI);
        a = 2.0f * PHOS_PI * ((float)column + 0.5f) / w;
    } else {
        float f = layout == PHOS_SKY_LAYOUT_SPHERE ? (float)row / (0.5f * h) - 1.0f : (float)row / h;
        float top = layout == PHOS_SKY_LAYOUT_SPHERE ? 0.5f * PHOS_PI : 0.5f * PHOS_PI + 0.25f * PHOS_PI / h;
        e = top * f * f;
        a = 2.0f * PHOS_PI * (float)column / w - PHOS_PI;
    }
    *elevation = e;
    return v3(cosf(e) * cosf(a), cosf(e) * sinf(a), sinf(e));
}

void sky_store_texel(float *pixels, uint32_t column, uint32_t row, vec3 rgb)
{
    uint32_t columns[2] = {column, SKY_TEXTURE_WIDTH - 1 - column};
    for (int k = 0; k < 2; k++) {
        float *p = pixels + ((size_t)row * SKY_TEXTURE_WIDTH + columns[k]) * 4;
        p[0] = rgb.x, p[1] = rgb.y, p[2] = rgb.z, p[3] = 1.0f;
    }
}

float sky_ground_fade(float elevation)
{
    float z = sinf(fabsf(elevation));
    return z >= 0.4f ? 0.0f : powf(1.0f - 2.5f * z, 3.0f);
}

void sky_analytic_angles(const float *data, vec3 d, float *theta, float *gamma)
{
    float st = sinf(data[SKY_ANALYTIC_THETA]);
    vec3 sun = v3(st * sinf(data[SKY_ANALYTIC_PHI]), st * cosf(data[SKY_ANALYTIC_PHI]), cosf(data[SKY_ANALYTIC_THETA]));
    *gamma = sky_angle_between(d, sun);
    *theta = minf(acosf(clampf(d.z, -1.0f, 1.0f)), 0.5f * PHOS_PI - 0.001f);
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
    if (d->model >= PHOS_SKY_MODEL_COUNT || d->layout >= PHOS_SKY_LAYOUT_COUNT || !finite_desc(d))
        return 0;
    if (d->model == PHOS_SKY_MULTIPLE_SCATTERING && d->layout != PHOS_SKY_LAYOUT_SPHERE)
        return 0;
    if (d->model == PHOS_SKY_PREETHAM || d->model == PHOS_SKY_HOSEK_WILKIE)
        return d->turbidity >= 1.0f && d->turbidity <= 10.0f && d->ground_albedo >= 0.0f &&
               d->ground_albedo <= 1.0f && v3_length2(v3_load(d->sun_direction)) > 0.0f;
    /* Blender's densities reach 10; far denser air only underflows. */
    const float most = 1000.0f;
    return d->sun_size >= 0.0f && d->sun_size <= PHOS_PI && d->air_density >= 0.0f && d->air_density <= most &&
           d->aerosol_density >= 0.0f && d->aerosol_density <= most && d->ozone_density >= 0.0f &&
           d->ozone_density <= most;
}

phos_status phos_sky_texture_size(const phos_sky_desc *d, uint32_t *width, uint32_t *height)
{
    if (!d || !width || !height || !valid_desc(d))
        return PHOS_ERROR_INVALID_ARGUMENT;
    int textured = sky_model_textured(d->model);
    *width = textured ? SKY_TEXTURE_WIDTH : 0;
    *height = textured ? sky_texture_height(d->layout) : 0;
    return PHOS_OK;
}

phos_status phos_sky_bake(const phos_sky_desc *d, float *pixels, float *data)
{
    if (!d || !data || !valid_desc(d))
        return PHOS_ERROR_INVALID_ARGUMENT;
    memset(data, 0, sizeof(float) * PHOS_SKY_DATA_FLOATS);
    data[SKY_LAYOUT] = (float)d->layout;
    switch (d->model) {
    case PHOS_SKY_PREETHAM:
        return sky_preetham_bake(d, data);
    case PHOS_SKY_HOSEK_WILKIE:
        return sky_hosek_wilkie_bake(d, data);
    case PHOS_SKY_MULTIPLE_SCATTERING:
        return sky_multiple_scattering_bake(d, pixels, data);
    default:
        return sky_single_scattering_bake(d, pixels, data);
    }
}
