/*
 * sky.h — the Sky Texture's daylight models (docs/algorithms.md §11.1),
 * one file each in this folder: the physical atmospheres computed once
 * into a texture over elevation and the azimuth from the sun
 * (single_scattering.c, after Nishita et al. 1993; multiple_scattering.c,
 * after García Liñán 2024), and the analytic models evaluated per
 * direction from coefficients computed once (preetham.c, Preetham et al.
 * 1999; hosek_wilkie.c, Hosek and Wilkie 2012). phos_sky_bake (sky.c)
 * computes them; shading/nodes/texture_sky.c looks them up.
 *
 * The texture is Cycles', texel for texel, so that the sky Phos draws is
 * the one Cycles draws, its interpolation included (enum phos_sky_layout):
 * 512 columns over the azimuth from the sun's, the two halves mirrored;
 * rows crowded toward the horizon, where the sky changes fastest, as the
 * square of the elevation's share (sky_texel_direction). Colours are
 * linear Rec. 709, W/(m²·sr).
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
    SKY_LAYOUT = 12,        /* enum phos_sky_layout */
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

/* The texture's size in a layout. */
#define SKY_TEXTURE_WIDTH 512
uint32_t sky_texture_height(uint32_t layout);

/* The texture coordinates (*u, *v) Cycles reads a direction at
 * `elevation` above the horizon (rad) and `azimuth` from the sun's (rad,
 * any sign) at, for image_lookup_rgba; below the horizon the hemisphere
 * layout reads its lowest row. */
void sky_texture_coordinates(uint32_t layout, float elevation, float azimuth, float *u, float *v);

/* The direction a texel of the left half (column < 256) holds, with its
 * elevation, in the frame where the sun's azimuth is 0 (+x): the
 * hemisphere layout's row y at elevation (π/2 + π/512)(y/128)², column x
 * at azimuth 2πx/512 − π; the sphere layout's upper rows y at
 * π/2 (y/128 − 1)² (the lower ones are the single-scattering sky's fade,
 * sky_ground_fade), or with `centred` (the multiple-scattering sky) the
 * texel's centre: elevation ±π/2 l², l = (y + ½)/128 − 1, azimuth
 * 2π(x + ½)/512. */
vec3 sky_texel_direction(uint32_t layout, int centred, uint32_t column, uint32_t row, float *elevation);

/* Stores a left-half texel and its mirror image across the sun's azimuth. */
void sky_store_texel(float *pixels, uint32_t column, uint32_t row, vec3 rgb);

/* The single-scattering sky below the horizon: (1 − 2.5 sin|e|)³ of the
 * horizon's colour, black from sin|e| = 0.4 down (Cycles'; the model has
 * no ground). */
float sky_ground_fade(float elevation);

/* The angle between two unit vectors, accurate near 0 and π. */
static inline float sky_angle_between(vec3 a, vec3 b)
{
    return 2.0f * atan2f(v3_length(v3_sub(a, b)), v3_length(v3_add(a, b)));
}

/* Rayleigh's phase function, 3(1 + μ²)/(16π) per steradian. */
static inline float sky_phase_rayleigh(float mu) { return 3.0f / (16.0f * PHOS_PI) * (1.0f + mu * mu); }

/* The solid angle of a disc of angular diameter `size`, 2π(1 − cos(size/2)). */
static inline float sky_disc_solid_angle(float size) { return 2.0f * PHOS_PI * (1.0f - cosf(0.5f * size)); }

/* The analytic models' angles of a view d: its polar angle θ held above
 * the horizon (π/2 − 0.001, as Cycles), and its angle γ from the sun of
 * the direction (θ, φ) they store. */
void sky_analytic_angles(const float *data, vec3 d, float *theta, float *gamma);

/* Writes the scattering models' sun data: the disc's radiance at its
 * bottom and top, the node's sun settings, and the horizon's dip. */
void sky_write_sun(const phos_sky_desc *d, vec3 bottom, vec3 top, float earth_angle, float *data);

/* --------------------------------------------------------------- models */

phos_status sky_single_scattering_bake(const phos_sky_desc *d, float *pixels, float *data);
phos_status sky_multiple_scattering_bake(const phos_sky_desc *d, float *pixels, float *data);
phos_status sky_preetham_bake(const phos_sky_desc *d, float *data);
phos_status sky_hosek_wilkie_bake(const phos_sky_desc *d, float *data);

/* The analytic models' radiance along the unit d (linear Rec. 709,
 * W/(m²·sr), not yet clamped). */
vec3 sky_preetham_radiance(const float *data, vec3 d);
vec3 sky_hosek_wilkie_radiance(const float *data, vec3 d);

#endif /* PHOS_SKY_H */
