/*
 * texture.h — image lookups for material colour inputs.
 */
#ifndef PHOS_TEXTURE_H
#define PHOS_TEXTURE_H

#include "scene/scene.h"

/* Linear RGB of the image at texture coordinates (u, v), v = 0 at the
 * bottom row, with the image's interpolation and extension modes. */
vec3 image_lookup(const image *img, float u, float v);

/* Mean RGB over all pixels. */
vec3 image_average(const image *img);

#endif /* PHOS_TEXTURE_H */
