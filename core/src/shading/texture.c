/*
 * texture.c — image lookups with Blender's interpolations (Closest, Linear,
 * Cubic: the uniform cubic B-spline, as Cycles) and extension modes
 * (Repeat, Extend, Clip, Mirror). Pixel centres sit at (i + ½)/width.
 */
#include "shading/texture.h"

enum { EXT_REPEAT = 0, EXT_EXTEND = 1, EXT_CLIP = 2, EXT_MIRROR = 3 };

/* Maps integer texel coordinate i to a valid index, or −1 for Clip outside. */
static int wrap_index(int i, int n, uint32_t extension)
{
    switch (extension) {
    case EXT_EXTEND:
        return i < 0 ? 0 : (i >= n ? n - 1 : i);
    case EXT_CLIP:
        return (i < 0 || i >= n) ? -1 : i;
    case EXT_MIRROR: {
        /* … 2 1 0 | 0 1 2 … n−1 | n−1 n−2 … */
        int period = 2 * n, r = i % period;
        if (r < 0)
            r += period;
        return r < n ? r : period - 1 - r;
    }
    default: {
        int r = i % n;
        return r < 0 ? r + n : r;
    }
    }
}

static void texel(const image *img, int x, int y, uint32_t extension, int associate, float out[4])
{
    int ix = wrap_index(x, (int)img->width, extension);
    int iy = wrap_index(y, (int)img->height, extension);
    if (ix < 0 || iy < 0) {
        out[0] = out[1] = out[2] = out[3] = 0.0f;
        return;
    }
    const float *p = img->pixels + 4 * ((size_t)iy * img->width + (size_t)ix);
    float k = associate ? p[3] : 1.0f;
    for (int c = 0; c < 3; c++)
        out[c] = p[c] * k;
    out[3] = p[3];
}

/* Weights of the uniform cubic B-spline at offset t ∈ [0,1) for the texels
 * at −1, 0, 1, 2 (they sum to 1). */
static void bspline_weights(float t, float w[4])
{
    float t2 = t * t, t3 = t2 * t;
    w[0] = (1.0f / 6.0f) * (-t3 + 3.0f * t2 - 3.0f * t + 1.0f);
    w[1] = (1.0f / 6.0f) * (3.0f * t3 - 6.0f * t2 + 4.0f);
    w[2] = (1.0f / 6.0f) * (-3.0f * t3 + 3.0f * t2 + 3.0f * t + 1.0f);
    w[3] = (1.0f / 6.0f) * t3;
}

void image_lookup_rgba(const image *img, float u, float v, uint32_t interpolation, uint32_t extension,
                       int associate, float out[4])
{
    out[0] = out[1] = out[2] = out[3] = 0.0f;
    if (!isfinite(u) || !isfinite(v))
        return;
    float x = u * (float)img->width, y = v * (float)img->height;
    /* Keep the float → int conversion in range for absurd coordinates. */
    if (fabsf(x) > 1e8f || fabsf(y) > 1e8f)
        return;
    if (interpolation == PHOS_IMAGE_CLOSEST) {
        texel(img, (int)floorf(x), (int)floorf(y), extension, associate, out);
        return;
    }
    x -= 0.5f;
    y -= 0.5f;
    float fx = floorf(x), fy = floorf(y);
    float tx = x - fx, ty = y - fy;
    int x0 = (int)fx, y0 = (int)fy;
    float wx[4], wy[4], t[4];
    int first, taps;
    if (interpolation == PHOS_IMAGE_CUBIC) {
        bspline_weights(tx, wx);
        bspline_weights(ty, wy);
        first = -1, taps = 4;
    } else {
        wx[0] = 1.0f - tx, wx[1] = tx, wy[0] = 1.0f - ty, wy[1] = ty;
        first = 0, taps = 2;
    }
    for (int j = 0; j < taps; j++)
        for (int i = 0; i < taps; i++) {
            float w = wx[i] * wy[j];
            texel(img, x0 + first + i, y0 + first + j, extension, associate, t);
            for (int c = 0; c < 4; c++)
                out[c] += w * t[c];
        }
}
