/*
 * texture.c — bilinear and nearest image lookups with Blender's extension
 * modes (Repeat, Extend, Clip). Pixel centres sit at (i + ½)/width.
 */
#include "shading/texture.h"

/* Maps integer texel coordinate i to a valid index, or −1 for Clip outside. */
static int wrap_index(int i, int n, uint32_t extension)
{
    switch (extension) {
    case PHOS_EXTEND_EXTEND:
        return i < 0 ? 0 : (i >= n ? n - 1 : i);
    case PHOS_EXTEND_CLIP:
        return (i < 0 || i >= n) ? -1 : i;
    default: {
        int r = i % n;
        return r < 0 ? r + n : r;
    }
    }
}

static vec3 texel(const image *img, int x, int y)
{
    int ix = wrap_index(x, (int)img->width, img->extension);
    int iy = wrap_index(y, (int)img->height, img->extension);
    if (ix < 0 || iy < 0)
        return v3s(0.0f);
    const float *p = img->pixels + 4 * ((size_t)iy * img->width + (size_t)ix);
    return v3(p[0], p[1], p[2]);
}

vec3 image_lookup(const image *img, float u, float v)
{
    if (!isfinite(u) || !isfinite(v))
        return v3s(0.0f);
    float x = u * (float)img->width - 0.5f;
    float y = v * (float)img->height - 0.5f;
    /* Keep the float → int conversion in range for absurd coordinates. */
    if (fabsf(x) > 1e8f || fabsf(y) > 1e8f)
        return v3s(0.0f);
    if (img->interpolation == PHOS_INTERP_CLOSEST)
        return texel(img, (int)floorf(x + 0.5f), (int)floorf(y + 0.5f));
    float fx = floorf(x), fy = floorf(y);
    float tx = x - fx, ty = y - fy;
    int x0 = (int)fx, y0 = (int)fy;
    vec3 a = v3_add(v3_scale(texel(img, x0, y0), 1.0f - tx), v3_scale(texel(img, x0 + 1, y0), tx));
    vec3 b = v3_add(v3_scale(texel(img, x0, y0 + 1), 1.0f - tx), v3_scale(texel(img, x0 + 1, y0 + 1), tx));
    return v3_add(v3_scale(a, 1.0f - ty), v3_scale(b, ty));
}

vec3 image_average(const image *img)
{
    double sum[3] = {0.0, 0.0, 0.0};
    size_t n = (size_t)img->width * img->height;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            sum[c] += img->pixels[4 * i + c];
    double inv = n ? 1.0 / (double)n : 0.0;
    return v3((float)(sum[0] * inv), (float)(sum[1] * inv), (float)(sum[2] * inv));
}
