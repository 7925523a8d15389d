/*
 * texture.h — image lookups: the Image Texture node's interpolations and
 * extension modes.
 */
#ifndef PHOS_TEXTURE_H
#define PHOS_TEXTURE_H

#include "scene/scene.h"

/* Linear RGBA of the image at texture coordinates (u, v), v = 0 at the
 * bottom row: interpolation PHOS_IMAGE_LINEAR, _CLOSEST or _CUBIC, extension
 * PHOS_IMAGE_REPEAT, _EXTEND, _CLIP or _MIRROR (phos.h, enum phos_image_flags,
 * the extension already shifted down to 0-3). With associate, colours are
 * multiplied by their alpha before they are interpolated, as an image
 * stored with associated alpha is (Cycles stores images so). */
void image_lookup_rgba(const image *img, float u, float v, uint32_t interpolation, uint32_t extension,
                       int associate, float out[4]);

#endif /* PHOS_TEXTURE_H */
