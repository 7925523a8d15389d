/*
 * sky.h — the Sky Texture's daylight models (docs/algorithms.md §11.4):
 * the physical atmospheres (single scattering after Nishita et al. 1993,
 * multiple scattering after García Liñán 2024) computed once into a
 * texture over elevation and the azimuth from the sun, and Preetham et
 * al.'s analytic model (1999) evaluated per direction from coefficients
 * computed once. phos_sky_bake (phos.h) fills both; shading/nodes/
 * texture_sky.c looks them up.
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
    /* PREETHAM */
    SKY_PREETHAM_THETA = 0, /* the sun's polar angle from +z, rad */
    SKY_PREETHAM_PHI = 1,   /* its azimuth, rad (the op's convention) */
    SKY_PREETHAM_ZENITH = 2,/* Y, x, y at the zenith over the Perez function there (3) */
    SKY_PREETHAM_PEREZ = 5  /* A..E of the Perez function for Y, x, y (15) */
};

/* The texture coordinates (*u, *v) of a direction at `elevation` above
 * the horizon (rad) and `azimuth` from the sun's (rad, any sign), for
 * image_lookup_rgba with width × height texels. */
void sky_texture_coordinates(float elevation, float azimuth, uint32_t width, uint32_t height, float *u, float *v);

/* The sun's direction for the textured models (elevation and rotation
 * as the Sky Texture node's: rotation 0 puts it toward +y, and it turns
 * toward +x, clockwise seen from above). */
vec3 sky_sun_direction(float elevation, float rotation);

/* The elevation of the horizon seen from `altitude` (m) above the
 * model's Earth: −acos(R/(R + altitude)), rad. */
float sky_earth_angle(float altitude);

/* Perez et al.'s sky luminance distribution (1 + A e^{B/cos θ})(1 + C
 * e^{Dγ} + E cos²γ), c = A..E; θ from the zenith, γ from the sun. */
float sky_perez(const float *c, float theta, float gamma);

#endif /* PHOS_SKY_H */
