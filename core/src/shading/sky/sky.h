/*
 * sky.h — the Sky Texture's daylight models (docs/algorithms.md §11.4),
 * one file each in this folder: the physical atmospheres computed once
 * into a texture over elevation and the azimuth from the sun
 * (single_scattering.c, after Nishita et al. 1993; multiple_scattering.c,
 * after García Liñán 2024), and the analytic models evaluated per
 * direction from coefficients computed once (preetham.c, Preetham et al.
 * 1999; hosek_wilkie.c, Hosek and Wilkie 2012). phos_sky_bake (sky.c)
 * computes them; shading/nodes/texture_sky.c looks them up.
 *
 * The texture: column k holds the azimuth k/(width − 1)·π away from the
 * sun's (the sky is symmetric about it), row j the elevation
 * sign(s)·s²·π/2 with s = 2j/(height − 1) − 1: rows crowd toward the
 * horizon, where the sky changes fastest, and the horizon is row
 * (height − 1)/2. Colours are linear Rec. 709, W/(m²·sr).
 */
#ifndef PHOS_SKY_H
#define PHOS_SKY_H

#include "phos.h"
#include "util/vec.h"

/* The data floats (PHOS_SKY_DATA_FLOATS) of each model. */
enum sky_data {
    /* SINGLE_ and MULTIPLE_SCATTERING */
    SKY_SUN_BOTTOM = 0,     /* radiance of the disc's lowest point (3 floats), W/(m²·sr) */
    SKY_SUN_TOP = 3,        /* of its highest point (3) */
    SKY_SUN_ELEVATION = 6,  /* rad */
    SKY_SUN_ROTATION = 7,   /* rad */
    SKY_SUN_DIAMETER = 8,   /* rad; < 0 without a disc */
    SKY_SUN_INTENSITY = 9,
    SKY_EARTH_ANGLE = 10,   /* rad: the disc is hidden below this elevation (the horizon's dip) */
    SKY_IMAGE = PHOS_SKY_DATA_IMAGE,
    /* PREETHAM and HOSEK_WILKIE */
    SKY_ANALYTIC_THETA = 0, /* the sun's polar angle from +z, rad */
    SKY_ANALYTIC_PHI = 1,   /* its azimuth, atan2(x, y), rad */
    SKY_ANALYTIC_ZENITH = 2,/* Preetham: Y, x, y at the zenith over the Perez function there (3);
                               Hosek-Wilkie: the radiances of X, Y, Z (3) */
    SKY_ANALYTIC_CONFIG = 5 /* Preetham: A..E of Y, x, y (15); Hosek-Wilkie: A..I of X, Y, Z (27) */
};

/* Whether a model's sky is a texture (the scattering models) rather than
 * analytic. */
static inline int sky_model_textured(uint32_t model)
{
    return model == PHOS_SKY_SINGLE_SCATTERING || model == PHOS_SKY_MULTIPLE_SCATTERING;
}

/* ------------------------------------------------------------- geometry */

/* The sun's direction for the scattering models (elevation and rotation
 * as the node's: rotation 0 puts it toward +y, and it turns toward +x,
 * clockwise seen from above). */
vec3 sky_sun_direction(float elevation, float rotation);

/* The texture coordinates (*u, *v) of a direction at `elevation` above
 * the horizon (rad) and `azimuth` from the sun's (rad, any sign), for
 * image_lookup_rgba with width × height texels. */
void sky_texture_coordinates(float elevation, float azimuth, uint32_t width, uint32_t height, float *u, float *v);

/* The direction of texel (column, row) with its elevation, in the frame
 * where the sun's azimuth is 0 (+x). */
vec3 sky_texel_direction(uint32_t column, uint32_t row, uint32_t width, uint32_t height, float *elevation);

/* The angle between two unit vectors, accurate near 0 and π. */
static inline float sky_angle_between(vec3 a, vec3 b)
{
    return 2.0f * atan2f(v3_length(v3_sub(a, b)), v3_length(v3_add(a, b)));
}

/* The sun of the direction (θ, φ) stored by the analytic models. */
vec3 sky_analytic_sun(const float *data);

/* Writes the scattering models' sun data: the disc's radiance at its
 * bottom and top, the node's sun settings, and the horizon's dip. */
void sky_write_sun(const phos_sky_desc *d, vec3 bottom, vec3 top, float earth_angle, float *data);

/* --------------------------------------------------------------- models */

phos_status sky_single_scattering_bake(const phos_sky_desc *d, uint32_t width, uint32_t height, float *pixels,
                                       float *data);
phos_status sky_multiple_scattering_bake(const phos_sky_desc *d, uint32_t width, uint32_t height, float *pixels,
                                         float *data);
phos_status sky_preetham_bake(const phos_sky_desc *d, float *data);
phos_status sky_hosek_wilkie_bake(const phos_sky_desc *d, float *data);

/* The analytic models' radiance along the unit d (linear Rec. 709,
 * W/(m²·sr), not yet clamped). */
vec3 sky_preetham_radiance(const float *data, vec3 d);
vec3 sky_hosek_wilkie_radiance(const float *data, vec3 d);

#endif /* PHOS_SKY_H */
