/*
 * splatting.c — the splatting-style energy-preserving filter of Suykens &
 * Willems 2000 ("Adaptive filtering for progressive Monte Carlo image
 * rendering", WSCG), the course's "splatting style filters" (Jensen,
 * "Biased Monte Carlo Ray Tracing", "Energy Preserving Filters").
 *
 * Each pixel's value, the mean of its n_p samples, is spread (splatted)
 * over its neighbourhood with a normalised kernel, and the output is the
 * sum of all splats. The kernel's radius
 *
 *   h_p = h0 · n_p^(−1/6) · max(1, √(v_p / tol_p)),  at most 12 pixels,
 *
 * follows kernel density estimation: in d dimensions the bandwidth that
 * balances bias against variance shrinks as n^(−1/(d+4)), n^(−1/6) on the
 * 2-D image, so a pixel with more samples is trusted more, its kernel
 * shrinks towards a delta, and the filtered image converges to the true
 * one (the filter is consistent). A spike (luminance v_p above the
 * tolerance tol_p of the adaptive-width filter, image_filter_tolerance) is
 * widened in proportion to √(v_p / tol_p), the factor by which its disc
 * must grow for its value to average down to the tolerance.
 *
 * Every kernel sums to 1 over the in-image pixels, so the image's total is
 * unchanged. Without sample counts every pixel counts as one sample; a
 * pixel that received none also counts as one (its value, usually 0, is
 * spread like the others).
 */
#include "filters/image_filter.h"

#include <math.h>

/* h0, the kernel radius of a one-sample pixel (pixels): 21 pixels of the
 * 5×5 block (image_filter_splat), narrowing to the 3×3 block at 64 samples
 * and to the pixel alone at 4096 (h = 0.5). */
#define SPLAT_RADIUS_ONE_SAMPLE 2.0

/* h_p, from the input image alone so the result does not depend on the
 * order of the splats. */
static double splat_radius(uint32_t samples, double v, double tol)
{
    double n = samples > 0 ? (double)samples : 1.0;
    double h = SPLAT_RADIUS_ONE_SAMPLE * pow(n, -1.0 / 6.0);
    if (v > tol)
        h *= sqrt(v / tol);
    return h < IMAGE_FILTER_MAX_SPLAT_RADIUS ? h : IMAGE_FILTER_MAX_SPLAT_RADIUS;
}

/* Splats pixel (x, y) whole with its radius h_p. */
static void splat_pixel(double *accum, const image_filter_input *in, uint32_t x, uint32_t y, double v, double tol,
                        image_filter_kernel *kernel)
{
    size_t p = (size_t)y * in->width + x;
    const float *c = in->rgb + 3 * p;
    double rgb[3] = {c[0], c[1], c[2]};
    double h = splat_radius(in->samples ? in->samples[p] : 1, v, tol);
    image_filter_splat(accum, in->width, in->height, x, y, h, rgb, kernel);
}

phos_status image_filter_splatting(const image_filter_input *in, float *out, const atomic_int *cancel)
{
    return image_filter_spread_pixels(in, out, cancel, splat_pixel);
}
