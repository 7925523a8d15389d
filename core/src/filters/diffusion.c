/*
 * diffusion.c — the diffusion-style energy-preserving filter of McCool
 * 1999 ("Anisotropic diffusion for Monte Carlo noise reduction", ACM TOG
 * 18(2)), the course's "diffusion style filters" (Jensen, "Biased Monte
 * Carlo Ray Tracing", "Energy Preserving Filters").
 *
 * The image is treated as heat that flows between 4-neighbours
 * (Perona & Malik 1990) in conservative flux form: each iteration, for each
 * pair of neighbours p, q,
 *
 *   I_p += λ c_pq (I_q − I_p),   I_q −= λ c_pq (I_q − I_p),
 *
 * with the same conductance c_pq = c_qp on both sides, so what leaves one
 * pixel enters the other and Σ I is conserved exactly, up to rounding. No
 * flux crosses the image border. λ = 0.2 <= 1/4 keeps the explicit scheme
 * stable: the weight a pixel keeps on its own value, 1 − λ Σ_q c_pq, stays
 * at least 1 − 4λ = 0.2 (c_pq <= 1).
 *
 * The conductance stops diffusion at edges:
 *
 *   c_pq = g(δc / Kc) · g((1 − n_p·n_q) / Kn) · g(Δa_pq / Ka),  g(x) = exp(−x²),
 *
 * with δc = |Y_p − Y_q| / √(σ²_p + σ²_q + ε) the luminance step in units of
 * its standard deviation (McCool's statistically normalised distance: a
 * step that noise explains conducts, a significant one does not), and the
 * normal and albedo terms (each left out when its guide is absent) stopping
 * it at geometric and texture edges the noise may hide.
 *
 * σ²_p, the variance of pixel p's luminance, is the renderer's when given,
 * else estimated once from the input (robust spread of the neighbours, or
 * the pixel's own squared departure from their median when larger, so that
 * a firefly is known to be uncertain and flows out). It is then tracked
 * through the iterations as for a weighted mean of independent values,
 *
 *   σ²_p ← (1 − λ Σ_q c_pq)² σ²_p + λ² Σ_q c_pq² σ²_q,
 *
 * and a pixel whose σ is below 2 % of its luminance is frozen: it needs no
 * more smoothing. Two frozen neighbours exchange nothing, but a frozen
 * pixel still exchanges with an active neighbour (a pair's activity is the
 * larger of its two sides', which keeps c_pq symmetric): were it closed,
 * a firefly among converged pixels could never flow out. What it receives
 * raises its tracked variance, and it may thaw. Diffusion stops when every
 * pixel is frozen or after a fixed number of iterations. The independence
 * assumption ignores the correlation diffusion builds between neighbours,
 * so the tracked variance falls faster than the true one and pixels freeze
 * early: the filter errs on the side of keeping detail.
 */
#include "filters/image_filter.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* λ, the time step; at most 1/4 for the explicit 4-neighbour scheme. */
#define DIFFUSION_STEP 0.2

/* Iterations at most; 32 steps of 0.2 spread isotropic diffusion to a
 * Gaussian of σ = √(2·λ·32) ≈ 3.6 pixels, which bounds the blur. */
#define DIFFUSION_MAX_ITERATIONS 32

/* Kc: a step of 1 standard deviation conducts at g(0.5) = 0.78, one of 4 or
 * more at g(2) <= 1.8 %. */
#define CONTRAST_SCALE 2.0

/* Kn, on 1 − cos of the angle between normals: 10° conducts at 0.98,
 * 25° at 0.41, a right angle at e^−100. */
#define NORMAL_SCALE 0.1

/* Ka, on the largest per-channel relative albedo difference
 * |a_p − a_q| / (a_p + a_q): 0.5 against 0.6 conducts at 0.81, black
 * against white at e^−25. */
#define ALBEDO_SCALE 0.2

/* A pixel is frozen once its standard deviation is below this fraction of
 * its luminance. */
#define FREEZE_RELATIVE_SIGMA 0.02

/* ε = (this · mean luminance)²: keeps δc finite where both variances are 0. */
#define VARIANCE_FLOOR_OF_MEAN 1e-3

typedef struct diffusion {
    uint32_t width, height;
    double *rgb, *next;          /* 3 per pixel: the current iterate and the one being built */
    float *luminance;            /* of rgb */
    float *variance;             /* σ² of each pixel's luminance */
    float *conductance_sum;      /* Σ_q c_pq over this iteration */
    float *inflow_variance;      /* Σ_q c_pq² σ²_q over this iteration */
    float *guide_right;          /* normal × albedo terms of the pair (p, p + 1), or NULL without guides */
    float *guide_down;           /* the same for (p, p + width), the next row */
    unsigned char *frozen;
    double epsilon;              /* ε of δc */
} diffusion;

static double edge_stop(double x)
{
    return exp(-x * x);
}

/* 1 − cos of the angle between two normals; a missing normal (zero, as
 * where no surface was hit) counts as a right angle to any other. */
static double normal_difference(const float *a, const float *b)
{
    double dot = (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
    double la = (double)a[0] * a[0] + (double)a[1] * a[1] + (double)a[2] * a[2];
    double lb = (double)b[0] * b[0] + (double)b[1] * b[1] + (double)b[2] * b[2];
    if (la == 0.0 && lb == 0.0)
        return 0.0;
    if (!(la * lb > 0.0))
        return 1.0;
    return 1.0 - dot / sqrt(la * lb);
}

/* Largest per-channel |a − b| / (|a| + |b|), in [0, 1]. */
static double albedo_difference(const float *a, const float *b)
{
    double largest = 0.0;
    for (int k = 0; k < 3; k++) {
        double den = fabs((double)a[k]) + fabs((double)b[k]);
        double rel = den > 0.0 ? fabs((double)a[k] - b[k]) / den : 0.0;
        if (rel > largest)
            largest = rel;
    }
    return largest;
}

/* The guide terms of the pair (p, q), which do not change between iterations. */
static float guide_conductance(const image_filter_input *in, size_t p, size_t q)
{
    double c = 1.0;
    if (in->normal)
        c *= edge_stop(normal_difference(in->normal + 3 * p, in->normal + 3 * q) / NORMAL_SCALE);
    if (in->albedo)
        c *= edge_stop(albedo_difference(in->albedo + 3 * p, in->albedo + 3 * q) / ALBEDO_SCALE);
    return (float)c;
}

static phos_status fill_guides(diffusion *d, const image_filter_input *in, const atomic_int *cancel)
{
    uint32_t w = d->width, h = d->height;
    for (uint32_t y = 0; y < h; y++) {
        if (image_filter_cancelled(cancel))
            return PHOS_ERROR_CANCELLED;
        for (uint32_t x = 0; x < w; x++) {
            size_t p = (size_t)y * w + x;
            d->guide_right[p] = x + 1 < w ? guide_conductance(in, p, p + 1) : 0.0f;
            d->guide_down[p] = y + 1 < h ? guide_conductance(in, p, p + w) : 0.0f;
        }
    }
    return PHOS_OK;
}

/* σ²_p of the input: the renderer's, else from the 3×3 neighbourhood. */
static phos_status initial_variance(diffusion *d, const image_filter_input *in, const atomic_int *cancel)
{
    uint32_t w = d->width, h = d->height;
    for (uint32_t y = 0; y < h; y++) {
        if (image_filter_cancelled(cancel))
            return PHOS_ERROR_CANCELLED;
        for (uint32_t x = 0; x < w; x++) {
            size_t p = (size_t)y * w + x;
            if (in->variance) {
                d->variance[p] = fmaxf(in->variance[p], 0.0f);
                continue;
            }
            float ref, spread;
            image_filter_neighbour_stats(d->luminance, w, h, x, y, &ref, &spread);
            float departure = d->luminance[p] - ref;
            d->variance[p] = fmaxf(spread * spread, departure * departure);
        }
    }
    return PHOS_OK;
}

static void free_diffusion(diffusion *d)
{
    free(d->rgb);
    free(d->next);
    free(d->luminance);
    free(d->variance);
    free(d->conductance_sum);
    free(d->inflow_variance);
    free(d->guide_right);
    free(d->guide_down);
    free(d->frozen);
}

/* Allocates the state and fills it from the input. */
static phos_status init_diffusion(diffusion *d, const image_filter_input *in, const atomic_int *cancel)
{
    size_t count = image_filter_pixel_count(in);
    int guided = in->normal || in->albedo;
    memset(d, 0, sizeof(*d));
    d->width = in->width;
    d->height = in->height;
    d->rgb = malloc(count * 3 * sizeof(double));
    d->next = malloc(count * 3 * sizeof(double));
    d->luminance = image_filter_luminance_plane(in);
    d->variance = malloc(count * sizeof(float));
    d->conductance_sum = malloc(count * sizeof(float));
    d->inflow_variance = malloc(count * sizeof(float));
    d->frozen = calloc(count, 1);
    if (guided) {
        d->guide_right = malloc(count * sizeof(float));
        d->guide_down = malloc(count * sizeof(float));
    }
    if (!d->rgb || !d->next || !d->luminance || !d->variance || !d->conductance_sum || !d->inflow_variance ||
        !d->frozen || (guided && (!d->guide_right || !d->guide_down)))
        return PHOS_ERROR_OUT_OF_MEMORY;
    for (size_t i = 0; i < count * 3; i++)
        d->rgb[i] = in->rgb[i];
    double floor_value = VARIANCE_FLOOR_OF_MEAN * image_filter_mean(d->luminance, count);
    d->epsilon = floor_value * floor_value + DBL_MIN;
    phos_status status = initial_variance(d, in, cancel);
    if (status == PHOS_OK && guided)
        status = fill_guides(d, in, cancel);
    return status;
}

/* Updates the luminance of the current iterate and which pixels are
 * frozen (variance at or below the target); returns how many are active. */
static size_t refresh_pixels(diffusion *d)
{
    size_t count = (size_t)d->width * d->height, active = 0;
    for (size_t p = 0; p < count; p++) {
        const double *c = d->rgb + 3 * p;
        float rgb[3] = {(float)c[0], (float)c[1], (float)c[2]};
        float y = image_filter_luminance(rgb);
        float target = (float)FREEZE_RELATIVE_SIGMA * y;
        d->luminance[p] = y;
        d->frozen[p] = d->variance[p] <= target * target;
        active += !d->frozen[p];
    }
    return active;
}

/* Lets the pair (p, q) exchange flux into next, with guide the pair's
 * normal and albedo terms. */
static void exchange(diffusion *d, size_t p, size_t q, double guide)
{
    if ((d->frozen[p] && d->frozen[q]) || guide <= 0.0)
        return;
    double step = fabs((double)d->luminance[p] - d->luminance[q]) /
                  sqrt((double)d->variance[p] + d->variance[q] + d->epsilon);
    double c = guide * edge_stop(step / CONTRAST_SCALE);
    double rate = DIFFUSION_STEP * c;
    const double *ip = d->rgb + 3 * p, *iq = d->rgb + 3 * q;
    double *np = d->next + 3 * p, *nq = d->next + 3 * q;
    for (int k = 0; k < 3; k++) {
        double flux = rate * (iq[k] - ip[k]);
        np[k] += flux;
        nq[k] -= flux;
    }
    d->conductance_sum[p] += (float)c;
    d->conductance_sum[q] += (float)c;
    d->inflow_variance[p] += (float)(c * c * d->variance[q]);
    d->inflow_variance[q] += (float)(c * c * d->variance[p]);
}

/* One explicit step of the whole image into next, then the variances. */
static phos_status diffuse_once(diffusion *d, const atomic_int *cancel)
{
    uint32_t w = d->width, h = d->height;
    size_t count = (size_t)w * h;
    memcpy(d->next, d->rgb, count * 3 * sizeof(double));
    memset(d->conductance_sum, 0, count * sizeof(float));
    memset(d->inflow_variance, 0, count * sizeof(float));
    for (uint32_t y = 0; y < h; y++) {
        if (image_filter_cancelled(cancel))
            return PHOS_ERROR_CANCELLED;
        for (uint32_t x = 0; x < w; x++) {
            size_t p = (size_t)y * w + x;
            if (x + 1 < w)
                exchange(d, p, p + 1, d->guide_right ? d->guide_right[p] : 1.0);
            if (y + 1 < h)
                exchange(d, p, p + w, d->guide_down ? d->guide_down[p] : 1.0);
        }
    }
    for (size_t p = 0; p < count; p++) {
        double keep = 1.0 - DIFFUSION_STEP * d->conductance_sum[p];
        d->variance[p] = (float)(keep * keep * d->variance[p] +
                                 DIFFUSION_STEP * DIFFUSION_STEP * d->inflow_variance[p]);
    }
    double *t = d->rgb;
    d->rgb = d->next;
    d->next = t;
    return PHOS_OK;
}

phos_status image_filter_diffusion(const image_filter_input *in, float *out, const atomic_int *cancel)
{
    diffusion d;
    phos_status status = init_diffusion(&d, in, cancel);
    for (int i = 0; i < DIFFUSION_MAX_ITERATIONS && status == PHOS_OK && refresh_pixels(&d) > 0; i++)
        status = diffuse_once(&d, cancel);
    if (status == PHOS_OK)
        image_filter_store(d.rgb, image_filter_pixel_count(in) * 3, out);
    free_diffusion(&d);
    return status;
}
