/*
 * adaptive_width.c — the energy-preserving adaptive-width filter of
 * Rushmeier & Ward 1994 ("Energy preserving non-linear filters",
 * SIGGRAPH), the course's "adaptive filter width" (Jensen, "Biased Monte
 * Carlo Ray Tracing", "Energy Preserving Filters").
 *
 * A Monte Carlo firefly is a correct sample of a rare, bright path: its
 * energy belongs in the image, just not all in one pixel. So instead of
 * removing it (the median filter) the filter spreads it. Each pixel p with
 * luminance v is compared with its tolerance tol_p = ref_p + c·σ_p (the
 * median of its neighbours plus 2.5 standard deviations of a pixel's mean
 * there; image_filter_tolerance):
 *  - v <= tol_p: the pixel stays where it is (a delta kernel: "minimal
 *    disruption" of everything that is not a spike);
 *  - v > tol_p: the pixel keeps the share tol_p/v of its RGB and spreads
 *    the excess, (v − tol_p)/v of it, with a normalised kernel of radius
 *    r = √(v/(π·tol_p)), the disc over which v would average to tol_p.
 * Radii and tolerances come from the input image alone, so the result does
 * not depend on the order pixels are processed in, and every kernel sums
 * to 1 over the in-image pixels, so the image's total is unchanged.
 */
#include "filters/image_filter.h"

#include <math.h>

/* A spread spike reaches at least the 3×3 block around it: a kernel
 * narrower than about 0.64 pixels would keep its excess in the pixel. */
#define MIN_SPREAD_RADIUS 1.0

/* The radius over which a spike of luminance v averages to tol:
 * v = tol·π·r², clamped to [MIN_SPREAD_RADIUS, IMAGE_FILTER_MAX_SPLAT_RADIUS]. */
static double spread_radius(double v, double tol)
{
    double r = sqrt(v / (M_PI * tol));
    if (!(r > MIN_SPREAD_RADIUS))
        return MIN_SPREAD_RADIUS;
    return r < IMAGE_FILTER_MAX_SPLAT_RADIUS ? r : IMAGE_FILTER_MAX_SPLAT_RADIUS;
}

/* Adds pixel p's contribution to accum: all of it in place, or tol's share
 * in place and the excess spread. */
static void place_pixel(double *accum, const image_filter_input *in, uint32_t x, uint32_t y, double v,
                        double tol, image_filter_kernel *kernel)
{
    size_t p = (size_t)y * in->width + x;
    const float *c = in->rgb + 3 * p;
    double *a = accum + 3 * p;
    if (!(v > tol)) {
        a[0] += c[0];
        a[1] += c[1];
        a[2] += c[2];
        return;
    }
    /* 0 < tol/v < 1; written so that an infinite v spreads everything. */
    double kept = tol / v, excess = 1.0 - kept;
    a[0] += c[0] * kept;
    a[1] += c[1] * kept;
    a[2] += c[2] * kept;
    double spread[3] = {c[0] * excess, c[1] * excess, c[2] * excess};
    image_filter_splat(accum, in->width, in->height, x, y, spread_radius(v, tol), spread, kernel);
}

phos_status image_filter_adaptive_width(const image_filter_input *in, float *out, const atomic_int *cancel)
{
    return image_filter_spread_pixels(in, out, cancel, place_pixel);
}
