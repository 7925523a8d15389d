/*
 * image_filter.h — noise filters run over a finished image, as a
 * post-process: the filters of Jensen's course "Biased Monte Carlo Ray
 * Tracing" (slides "3x3 Lowpass Filter", "3x3 Median Filter" and "Energy
 * Preserving Filters").
 *
 *  - LOWPASS (lowpass.c): the mean of the 3×3 block around each pixel.
 *    Blurs noise and detail alike; its renormalisation at the border
 *    changes the total (a firefly in a corner loses 31 % of its energy).
 *  - MEDIAN (median.c): each pixel takes the colour of the pixel of its 3×3
 *    block whose luminance is the median (a vector median, so colours stay
 *    ones the renderer produced). Removes isolated fireflies entirely, and
 *    with them their energy.
 *  - ADAPTIVE_WIDTH (adaptive_width.c; Rushmeier & Ward 1994, "Energy
 *    preserving non-linear filters", SIGGRAPH): a pixel brighter than a
 *    tolerance from its neighbourhood keeps the tolerance and spreads the
 *    excess over a disc whose area grows with the excess; other pixels are
 *    left alone.
 *  - DIFFUSION (diffusion.c; McCool 1999, "Anisotropic diffusion for Monte
 *    Carlo noise reduction", ACM TOG 18(2)): Perona–Malik diffusion in
 *    conservative flux form, its conductances stopped by statistically
 *    significant colour steps and by normal and albedo edges.
 *  - SPLATTING (splatting.c; Suykens & Willems 2000, "Adaptive filtering
 *    for progressive Monte Carlo image rendering", WSCG): every pixel is
 *    spread with a kernel that narrows as the pixel's sample count grows,
 *    widened for spikes.
 *
 * Energy preserving means that the sum of all pixel values over the image,
 * per channel, is unchanged by the filter: light is moved, never created or
 * lost. The three energy-preserving filters move it with kernels that are
 * renormalised at the image borders (each kernel sums to 1 over the pixels
 * inside the image) and diffusion has no flux out of the image, so their
 * totals match to rounding. The same renormalisation keeps a flat image
 * flat under the lowpass filter.
 *
 * image_filter.c holds the dispatcher and the helpers the filters share
 * (luminance, neighbourhood statistics, the spike tolerance and the
 * normalised-kernel splat).
 */
#ifndef PHOS_IMAGE_FILTER_H
#define PHOS_IMAGE_FILTER_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include "phos.h"

enum image_filter_kind {
    IMAGE_FILTER_NONE,
    IMAGE_FILTER_LOWPASS,
    IMAGE_FILTER_MEDIAN,
    IMAGE_FILTER_ADAPTIVE_WIDTH,
    IMAGE_FILTER_DIFFUSION,
    IMAGE_FILTER_SPLATTING,
    IMAGE_FILTER_KIND_COUNT
};

typedef struct image_filter_input {
    uint32_t width, height;        /* pixels; rows are contiguous, row 0 first */
    const float *rgb;              /* width*height*3, linear radiance (or irradiance) */
    /* Per-pixel statistics from the renderer (any may be NULL: the filter then estimates from the neighbourhood): */
    const float *variance;         /* width*height: variance of the pixel's MEAN luminance (sample variance / n) */
    const uint32_t *samples;       /* width*height: samples the pixel received (adaptive sampling makes them differ) */
    /* Guides for the diffusion filter's edge stopping (either may be NULL): */
    const float *normal;           /* width*height*3, unit-ish normals */
    const float *albedo;           /* width*height*3 */
} image_filter_input;

/* Writes the filtered image to out (width*height*3, must not alias in->rgb).
 * Deterministic (no dependence on thread count; single-threaded is fine), checks *cancel (may be NULL)
 * at least once per image row of work so a cancel is seen within milliseconds; returns PHOS_ERROR_CANCELLED then.
 * PHOS_ERROR_OUT_OF_MEMORY if scratch allocation fails (free everything you allocate on every path).
 * PHOS_ERROR_INVALID_ARGUMENT for an unknown kind or a NULL in, in->rgb or out (when there are pixels).
 * An image with no pixels is PHOS_OK with nothing written. */
phos_status image_filter_apply(uint32_t kind, const image_filter_input *in, float *out, const atomic_int *cancel);

/* 1 for the filters that preserve the image's total energy (adaptive width, diffusion, splatting). */
int image_filter_preserves_energy(uint32_t kind);

/*
 * For the filters' own .c files in this folder, not for callers.
 */

/* Each filter, called by image_filter_apply with a non-empty image. */
phos_status image_filter_lowpass(const image_filter_input *in, float *out, const atomic_int *cancel);
phos_status image_filter_median(const image_filter_input *in, float *out, const atomic_int *cancel);
phos_status image_filter_adaptive_width(const image_filter_input *in, float *out, const atomic_int *cancel);
phos_status image_filter_diffusion(const image_filter_input *in, float *out, const atomic_int *cancel);
phos_status image_filter_splatting(const image_filter_input *in, float *out, const atomic_int *cancel);

/* Kernel radii of the splatting filters stop here (pixels): it bounds the
 * work per pixel (a window of 25×25 pixels) and keeps a firefly's energy
 * near where it was rendered. */
#define IMAGE_FILTER_MAX_SPLAT_RADIUS 12.0

/* Pixels on each side of the centre a kernel of the largest radius reaches. */
#define IMAGE_FILTER_KERNEL_REACH 12

/* The splat kernel of one radius tabulated over its window; image_filter_splat
 * refills it when the radius changes, so consecutive splats of the same
 * radius (most of them, in the splatting filter) share the work. Start
 * with image_filter_kernel_init. */
typedef struct image_filter_kernel {
    double radius;   /* of the table below; negative before the first splat */
    uint32_t reach;  /* pixels on each side of the centre with a weight */
    double weight[(2 * IMAGE_FILTER_KERNEL_REACH + 1) * (2 * IMAGE_FILTER_KERNEL_REACH + 1)];
} image_filter_kernel;

static inline void image_filter_kernel_init(image_filter_kernel *kernel)
{
    kernel->radius = -1.0;
    kernel->reach = 0;
}

static inline int image_filter_cancelled(const atomic_int *cancel)
{
    return cancel && atomic_load_explicit(cancel, memory_order_relaxed);
}

static inline size_t image_filter_pixel_count(const image_filter_input *in)
{
    return (size_t)in->width * in->height;
}

/* Rec. 709 luminance of an RGB triple. */
float image_filter_luminance(const float *rgb);

/* The luminance of every pixel, in a new array the caller frees (NULL when
 * memory is exhausted). */
float *image_filter_luminance_plane(const image_filter_input *in);

/* Mean of a luminance plane, in double. */
double image_filter_mean(const float *luminance, size_t count);

/* Median of v[0..n) (the mean of the middle two for even n); reorders v. */
float image_filter_median_of(float *v, uint32_t n);

/* Median and robust spread σ ≈ 1.4826·MAD (the median absolute deviation
 * from that median, scaled to a Gaussian's σ) of the luminance of the
 * in-image 3×3 neighbours of (x, y), the pixel itself excluded. With no
 * neighbour (a 1×1 image) the median is the pixel's own luminance and the
 * spread 0. */
void image_filter_neighbour_stats(const float *luminance, uint32_t width, uint32_t height, uint32_t x,
                                  uint32_t y, float *median, float *spread);

/* The spike tolerance of every pixel, tol_p = ref_p + c·σ_p (Rushmeier &
 * Ward 1994): ref_p the median luminance of p's 3×3 neighbours, σ_p the
 * standard deviation of a pixel's mean there (the median of the
 * neighbours' in->variance, else the robust spread of their luminance),
 * c = 2.5 (image_filter.c says why); floored at a small fraction of the
 * image's mean luminance so it is positive. A pixel whose luminance
 * exceeds it is a spike. */
phos_status image_filter_tolerance(const image_filter_input *in, const float *luminance, float *tol,
                                   const atomic_int *cancel);

/* Adds rgb·w_q/Σw to accum (width*height*3, double) at the pixels q around
 * (x, y), w_q the integral over pixel q's square of the Epanechnikov kernel
 * k(d) = 1 − (d/r)² (d < r) centred on (x, y). A kernel narrower than the
 * pixel is a delta (r below about 0.64 with the quadrature image_filter.c
 * uses), r = 1 reaches the 3×3 block; r is capped at IMAGE_FILTER_MAX_SPLAT_RADIUS.
 * Σw runs over the in-image pixels only, so the shares sum to 1 and the
 * splat moves rgb without changing its total. kernel: the caller's table,
 * kept between calls. */
void image_filter_splat(double *accum, uint32_t width, uint32_t height, uint32_t x, uint32_t y, double r,
                        const double rgb[3], image_filter_kernel *kernel);

/* out[i] = (float)accum[i] for count values. */
void image_filter_store(const double *accum, size_t count, float *out);

/* How one energy-preserving filter places pixel (x, y), of luminance v and
 * spike tolerance tol, into accum (with image_filter_splat). */
typedef void (*image_filter_place_fn)(double *accum, const image_filter_input *in, uint32_t x, uint32_t y, double v,
                                      double tol, image_filter_kernel *kernel);

/* The spreading filters' shared frame (adaptive width, splatting): the
 * luminance and tolerance planes, every pixel placed row by row (a cancel
 * seen between rows), out written from the sums; frees what it allocates. */
phos_status image_filter_spread_pixels(const image_filter_input *in, float *out, const atomic_int *cancel,
                                       image_filter_place_fn place);

#endif /* PHOS_IMAGE_FILTER_H */
