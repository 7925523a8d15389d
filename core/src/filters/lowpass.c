/*
 * lowpass.c — the 3×3 box filter of the course's "3x3 Lowpass Filter"
 * slide (Jensen, "Biased Monte Carlo Ray Tracing"): each pixel becomes the
 * mean of the 3×3 block around it.
 *
 * At the image border the mean runs over the in-image pixels only, so a
 * flat image stays flat. That renormalisation is what makes the filter
 * not energy preserving: inside the image every pixel gives 1/9 of its
 * value to each of 9 pixels (a convolution by a kernel summing to 1 moves
 * energy without changing the total), but a corner pixel gives 1/4 to
 * itself, 1/6 to its two edge neighbours and 1/9 to its diagonal one,
 * ≈ 0.69 of its value in all: a firefly there loses 31 % of its energy.
 * The filter also blurs detail and noise alike.
 */
#include "filters/image_filter.h"

phos_status image_filter_lowpass(const image_filter_input *in, float *out, const atomic_int *cancel)
{
    uint32_t w = in->width, h = in->height;
    for (uint32_t y = 0; y < h; y++) {
        if (image_filter_cancelled(cancel))
            return PHOS_ERROR_CANCELLED;
        uint32_t y0 = y > 0 ? y - 1 : 0, y1 = y + 1 < h ? y + 1 : y;
        for (uint32_t x = 0; x < w; x++) {
            uint32_t x0 = x > 0 ? x - 1 : 0, x1 = x + 1 < w ? x + 1 : x;
            double sum[3] = {0.0, 0.0, 0.0};
            for (uint32_t yy = y0; yy <= y1; yy++)
                for (uint32_t xx = x0; xx <= x1; xx++) {
                    const float *c = in->rgb + 3 * ((size_t)yy * w + xx);
                    sum[0] += c[0];
                    sum[1] += c[1];
                    sum[2] += c[2];
                }
            double inv_count = 1.0 / (double)((x1 - x0 + 1) * (y1 - y0 + 1));
            float *o = out + 3 * ((size_t)y * w + x);
            for (int k = 0; k < 3; k++)
                o[k] = (float)(sum[k] * inv_count);
        }
    }
    return PHOS_OK;
}
