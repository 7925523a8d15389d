/*
 * median.c — the 3×3 median filter of the course's "3x3 Median Filter"
 * slide (Jensen, "Biased Monte Carlo Ray Tracing").
 *
 * A per-channel median would assemble colours no pixel had; instead each
 * pixel takes the whole RGB of the pixel of its 3×3 block whose luminance
 * is the median (a vector median), so every output colour is one the
 * renderer produced. An isolated firefly is never the median of its block
 * and disappears, with its energy: the filter is not energy preserving.
 * At the border the median runs over the in-image pixels of the block; of
 * an even count (4 or 6) the lower middle one is taken, so that it is
 * still a pixel of the image.
 */
#include "filters/image_filter.h"

#include <string.h>

typedef struct ranked_pixel {
    float luminance;
    size_t index;  /* pixel index into the image */
} ranked_pixel;

/* Sorts by luminance; equal luminances keep their scan order, so the
 * choice is deterministic. */
static void sort_by_luminance(ranked_pixel *v, uint32_t n)
{
    for (uint32_t i = 1; i < n; i++) {
        ranked_pixel r = v[i];
        uint32_t j = i;
        for (; j > 0 && v[j - 1].luminance > r.luminance; j--)
            v[j] = v[j - 1];
        v[j] = r;
    }
}

phos_status image_filter_median(const image_filter_input *in, float *out, const atomic_int *cancel)
{
    uint32_t w = in->width, h = in->height;
    for (uint32_t y = 0; y < h; y++) {
        if (image_filter_cancelled(cancel))
            return PHOS_ERROR_CANCELLED;
        uint32_t y0 = y > 0 ? y - 1 : 0, y1 = y + 1 < h ? y + 1 : y;
        for (uint32_t x = 0; x < w; x++) {
            uint32_t x0 = x > 0 ? x - 1 : 0, x1 = x + 1 < w ? x + 1 : x;
            ranked_pixel block[9];
            uint32_t n = 0;
            for (uint32_t yy = y0; yy <= y1; yy++)
                for (uint32_t xx = x0; xx <= x1; xx++) {
                    size_t i = (size_t)yy * w + xx;
                    block[n].luminance = image_filter_luminance(in->rgb + 3 * i);
                    block[n].index = i;
                    n++;
                }
            sort_by_luminance(block, n);
            size_t chosen = block[(n - 1) / 2].index;
            memcpy(out + 3 * ((size_t)y * w + x), in->rgb + 3 * chosen, 3 * sizeof(float));
        }
    }
    return PHOS_OK;
}
