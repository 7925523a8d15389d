/*
 * image_filter.c — the dispatcher of the image noise filters and the
 * helpers they share: luminance, neighbourhood statistics, the spike
 * tolerance of Rushmeier & Ward (1994) and the normalised-kernel splat used
 * by the adaptive-width and splatting filters.
 */
#include "filters/image_filter.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/vec.h"

/* A pixel is a spike when it lies this many standard deviations (of a
 * pixel's mean, in its neighbourhood) above its neighbours' median. Under
 * Gaussian noise 2.5σ is exceeded by 0.6 % of pixels, so ordinary noise is
 * left where it is ("minimal disruption", Rushmeier & Ward 1994) while
 * fireflies, tens or thousands of σ out, are caught. */
#define TOLERANCE_SIGMAS 2.5

/* The median absolute deviation of Gaussian samples is 0.6745σ. */
#define MAD_TO_SIGMA 1.4826

/* The tolerance is at least this fraction of the image's mean luminance:
 * a black neighbourhood (median and spread 0) would otherwise make any
 * positive pixel an infinitely strong spike. */
#define TOLERANCE_FLOOR_OF_MEAN 1e-3

phos_status image_filter_apply(uint32_t kind, const image_filter_input *in, float *out, const atomic_int *cancel)
{
    if (kind >= IMAGE_FILTER_KIND_COUNT || !in)
        return PHOS_ERROR_INVALID_ARGUMENT;
    size_t count = image_filter_pixel_count(in);
    if (count == 0)
        return PHOS_OK;
    if (!in->rgb || !out)
        return PHOS_ERROR_INVALID_ARGUMENT;
    if (image_filter_cancelled(cancel))
        return PHOS_ERROR_CANCELLED;
    switch ((enum image_filter_kind)kind) {
    case IMAGE_FILTER_LOWPASS:
        return image_filter_lowpass(in, out, cancel);
    case IMAGE_FILTER_MEDIAN:
        return image_filter_median(in, out, cancel);
    case IMAGE_FILTER_ADAPTIVE_WIDTH:
        return image_filter_adaptive_width(in, out, cancel);
    case IMAGE_FILTER_DIFFUSION:
        return image_filter_diffusion(in, out, cancel);
    case IMAGE_FILTER_SPLATTING:
        return image_filter_splatting(in, out, cancel);
    case IMAGE_FILTER_NONE:
    default:
        memcpy(out, in->rgb, count * 3 * sizeof(float));
        return PHOS_OK;
    }
}

int image_filter_preserves_energy(uint32_t kind)
{
    return kind == IMAGE_FILTER_ADAPTIVE_WIDTH || kind == IMAGE_FILTER_DIFFUSION ||
           kind == IMAGE_FILTER_SPLATTING;
}

float image_filter_luminance(const float *rgb)
{
    return rgb_luminance(v3_load(rgb));
}

float *image_filter_luminance_plane(const image_filter_input *in)
{
    size_t count = image_filter_pixel_count(in);
    float *luminance = malloc(count * sizeof(float));
    if (!luminance)
        return NULL;
    for (size_t i = 0; i < count; i++)
        luminance[i] = image_filter_luminance(in->rgb + 3 * i);
    return luminance;
}

double image_filter_mean(const float *luminance, size_t count)
{
    double sum = 0.0;
    for (size_t i = 0; i < count; i++)
        sum += luminance[i];
    return count ? sum / (double)count : 0.0;
}

/* Sorts a handful of values (at most 9 here) in place. */
static void insertion_sort(float *v, uint32_t n)
{
    for (uint32_t i = 1; i < n; i++) {
        float x = v[i];
        uint32_t j = i;
        for (; j > 0 && v[j - 1] > x; j--)
            v[j] = v[j - 1];
        v[j] = x;
    }
}

float image_filter_median_of(float *v, uint32_t n)
{
    insertion_sort(v, n);
    return (n & 1) ? v[n / 2] : 0.5f * (v[n / 2 - 1] + v[n / 2]);
}

/* Copies the values of plane at the in-image 3×3 neighbours of (x, y), the
 * pixel itself excluded, into v; returns how many (0 to 8). */
static uint32_t gather_neighbours(const float *plane, uint32_t width, uint32_t height, uint32_t x, uint32_t y,
                                  float v[8])
{
    uint32_t n = 0;
    uint32_t x0 = x > 0 ? x - 1 : 0, x1 = x + 1 < width ? x + 1 : x;
    uint32_t y0 = y > 0 ? y - 1 : 0, y1 = y + 1 < height ? y + 1 : y;
    for (uint32_t yy = y0; yy <= y1; yy++)
        for (uint32_t xx = x0; xx <= x1; xx++)
            if (xx != x || yy != y)
                v[n++] = plane[(size_t)yy * width + xx];
    return n;
}

void image_filter_neighbour_stats(const float *luminance, uint32_t width, uint32_t height, uint32_t x,
                                  uint32_t y, float *median, float *spread)
{
    float v[8];
    uint32_t n = gather_neighbours(luminance, width, height, x, y, v);
    if (n == 0) {
        *median = luminance[(size_t)y * width + x];
        *spread = 0.0f;
        return;
    }
    float m = image_filter_median_of(v, n);
    for (uint32_t i = 0; i < n; i++)
        v[i] = fabsf(v[i] - m);
    *median = m;
    *spread = (float)(MAD_TO_SIGMA * image_filter_median_of(v, n));
}

/* σ of pixel p's mean from the renderer's variances: the median over its
 * neighbours, not p's own. A firefly is one huge sample among n, so its
 * own variance of the mean is about its excess squared, and ref + 2.5·σ_p
 * would always exceed it: it would never count as a spike. */
static float neighbours_sigma(const float *variance, uint32_t width, uint32_t height, uint32_t x, uint32_t y)
{
    float v[8];
    uint32_t n = gather_neighbours(variance, width, height, x, y, v);
    float var = n ? image_filter_median_of(v, n) : variance[(size_t)y * width + x];
    /* fmaxf drops a NaN variance as it drops a negative one. */
    return sqrtf(fmaxf(var, 0.0f));
}

phos_status image_filter_tolerance(const image_filter_input *in, const float *luminance, float *tol,
                                   const atomic_int *cancel)
{
    uint32_t w = in->width, h = in->height;
    double floor_value = TOLERANCE_FLOOR_OF_MEAN * image_filter_mean(luminance, image_filter_pixel_count(in));
    float tol_floor = floor_value > FLT_MIN ? (float)floor_value : FLT_MIN;
    for (uint32_t y = 0; y < h; y++) {
        if (image_filter_cancelled(cancel))
            return PHOS_ERROR_CANCELLED;
        for (uint32_t x = 0; x < w; x++) {
            size_t p = (size_t)y * w + x;
            float ref, sigma;
            image_filter_neighbour_stats(luminance, w, h, x, y, &ref, &sigma);
            if (in->variance)
                sigma = neighbours_sigma(in->variance, w, h, x, y);
            float t = ref + (float)TOLERANCE_SIGMAS * sigma;
            tol[p] = t > tol_floor ? t : tol_floor;
        }
    }
    return PHOS_OK;
}

/* w_q: the Epanechnikov kernel of radius r integrated over the square of
 * the pixel at offset (i, j) by the midpoint rule on a 4×4 grid. Integrated
 * rather than sampled at the pixel centre, a pixel's share grows smoothly
 * from 0 as the kernel's edge enters it, instead of jumping when the edge
 * passes its centre. */
#define KERNEL_SUBSAMPLES 4

static double pixel_weight(int i, int j, double r)
{
    double inv_r2 = 1.0 / (r * r), w = 0.0;
    for (int a = 0; a < KERNEL_SUBSAMPLES; a++)
        for (int b = 0; b < KERNEL_SUBSAMPLES; b++) {
            double dx = i + (a + 0.5) / KERNEL_SUBSAMPLES - 0.5;
            double dy = j + (b + 0.5) / KERNEL_SUBSAMPLES - 0.5;
            double k = 1.0 - (dx * dx + dy * dy) * inv_r2;
            if (k > 0.0)
                w += k;
        }
    return w;
}

static void tabulate_kernel(image_filter_kernel *kernel, double r)
{
    /* The nearest subsample of the pixel at offset i lies |i| − 3/8 away. */
    double nearest = 0.5 - 0.5 / KERNEL_SUBSAMPLES;
    double reach = r > 0.0 ? ceil(r + nearest) - 1.0 : 0.0;
    kernel->radius = r;
    kernel->reach = reach < IMAGE_FILTER_KERNEL_REACH ? (uint32_t)reach : IMAGE_FILTER_KERNEL_REACH;
    int n = (int)kernel->reach, side = 2 * n + 1;
    for (int j = -n; j <= n; j++)
        for (int i = -n; i <= n; i++)
            kernel->weight[(j + n) * side + (i + n)] = r > 0.0 ? pixel_weight(i, j, r) : 0.0;
    /* A kernel that misses every subsample of its own pixel is a delta. */
    if (kernel->weight[n * side + n] <= 0.0)
        kernel->weight[n * side + n] = 1.0;
}

void image_filter_splat(double *accum, uint32_t width, uint32_t height, uint32_t x, uint32_t y, double r,
                        const double rgb[3], image_filter_kernel *kernel)
{
    /* A NaN or negative radius is a delta; the radius never exceeds the cap. */
    r = r > 0.0 ? fmin(r, IMAGE_FILTER_MAX_SPLAT_RADIUS) : 0.0;
    if (r != kernel->radius)
        tabulate_kernel(kernel, r);
    uint32_t reach = kernel->reach, side = 2 * reach + 1;
    uint32_t x0 = x > reach ? x - reach : 0, x1 = width - 1 - x > reach ? x + reach : width - 1;
    uint32_t y0 = y > reach ? y - reach : 0, y1 = height - 1 - y > reach ? y + reach : height - 1;
    /* (xx, yy) → weight[(yy − y + reach)·side + (xx − x + reach)] */
    const double *row0 = kernel->weight + (size_t)(y0 + reach - y) * side + (x0 + reach - x);

    /* Σw over the in-image pixels; the centre's weight makes it positive. */
    double sum = 0.0;
    for (uint32_t yy = y0; yy <= y1; yy++) {
        const double *w = row0 + (size_t)(yy - y0) * side;
        for (uint32_t xx = x0; xx <= x1; xx++)
            sum += w[xx - x0];
    }
    double scale = 1.0 / sum;
    for (uint32_t yy = y0; yy <= y1; yy++) {
        const double *w = row0 + (size_t)(yy - y0) * side;
        double *a = accum + 3 * ((size_t)yy * width + x0);
        for (uint32_t xx = x0; xx <= x1; xx++, a += 3) {
            double share = w[xx - x0] * scale;
            a[0] += rgb[0] * share;
            a[1] += rgb[1] * share;
            a[2] += rgb[2] * share;
        }
    }
}

void image_filter_store(const double *accum, size_t count, float *out)
{
    for (size_t i = 0; i < count; i++)
        out[i] = (float)accum[i];
}

phos_status image_filter_spread_pixels(const image_filter_input *in, float *out, const atomic_int *cancel,
                                       image_filter_place_fn place)
{
    size_t count = image_filter_pixel_count(in);
    float *luminance = image_filter_luminance_plane(in);
    float *tol = malloc(count * sizeof(float));
    double *accum = calloc(count * 3, sizeof(double));
    phos_status status = PHOS_ERROR_OUT_OF_MEMORY;
    if (luminance && tol && accum)
        status = image_filter_tolerance(in, luminance, tol, cancel);
    image_filter_kernel kernel;
    image_filter_kernel_init(&kernel);
    for (uint32_t y = 0; y < in->height && status == PHOS_OK; y++) {
        if (image_filter_cancelled(cancel)) {
            status = PHOS_ERROR_CANCELLED;
            break;
        }
        for (uint32_t x = 0; x < in->width; x++) {
            size_t p = (size_t)y * in->width + x;
            place(accum, in, x, y, luminance[p], tol[p], &kernel);
        }
    }
    if (status == PHOS_OK)
        image_filter_store(accum, count * 3, out);
    free(luminance);
    free(tol);
    free(accum);
    return status;
}
