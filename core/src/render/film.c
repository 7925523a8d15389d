/*
 * film.c — pass planes and the Blackman-Harris pixel filter.
 *
 * Cycles' default filter is Blackman-Harris of "width" w = 1.5 px whose
 * window spans 2w (±w around the pixel centre); we sample its 1-D profile
 * by a tabulated inverse CDF and apply it separably in x and y.
 */
#include "render/film.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PASS_CHANNELS_(id, name, channels, ...) channels,
static const uint32_t pass_channels[PHOS_PASS_COUNT] = {PHOS_PASSES(PASS_CHANNELS_)};
#undef PASS_CHANNELS_

uint32_t phos_pass_channels(uint32_t pass)
{
    return pass < PHOS_PASS_COUNT ? pass_channels[pass] : 0;
}

uint64_t film_memory_bytes(uint32_t width, uint32_t height, uint32_t pass_mask, uint32_t extras)
{
    int keep_sums = (extras & FILM_KEEP_SUMS) != 0;
    uint64_t bytes = sizeof(uint32_t) + ((extras & FILM_MOMENTS) ? 2 * sizeof(double) : 0) +
                     ((keep_sums && (extras & FILM_CAUSTIC_READS)) ? 3 * sizeof(double) : 0);
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++)
        if ((pass_mask | (1u << PHOS_PASS_COMBINED)) & (1u << p)) {
            bytes += phos_pass_channels(p) * sizeof(float);
            if (keep_sums && film_pass_is_sample_mean(p))
                bytes += phos_pass_channels(p) * sizeof(double);
        }
    return (uint64_t)width * height * bytes;
}

int film_create(film *f, uint32_t x0, uint32_t y0, uint32_t width, uint32_t height, uint32_t pass_mask,
                uint32_t extras)
{
    int keep_sums = (extras & FILM_KEEP_SUMS) != 0;
    memset(f, 0, sizeof(*f));
    f->x0 = x0;
    f->y0 = y0;
    f->width = width;
    f->height = height;
    f->pass_mask = pass_mask | (1u << PHOS_PASS_COMBINED);
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        if (!(f->pass_mask & (1u << p)))
            continue;
        size_t n = (size_t)width * height * phos_pass_channels(p);
        f->planes[p] = calloc(n, sizeof(float));
        if (keep_sums && film_pass_is_sample_mean(p))
            f->sums[p] = calloc(n, sizeof(double));
        if (!f->planes[p] || (keep_sums && film_pass_is_sample_mean(p) && !f->sums[p])) {
            film_free(f);
            return 0;
        }
    }
    size_t pixels = (size_t)width * height;
    f->sample_counts = calloc(pixels, sizeof(uint32_t));
    if (extras & FILM_MOMENTS)
        f->moments = calloc(2 * pixels, sizeof(double));
    int caustic_reads = keep_sums && (extras & FILM_CAUSTIC_READS);
    if (caustic_reads)
        f->caustic_reads = calloc(3 * pixels, sizeof(double));
    if (!f->sample_counts || ((extras & FILM_MOMENTS) && !f->moments) || (caustic_reads && !f->caustic_reads)) {
        film_free(f);
        return 0;
    }
    return 1;
}

void film_free(film *f)
{
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        free(f->planes[p]);
        free(f->sums[p]);
        f->planes[p] = NULL;
        f->sums[p] = NULL;
    }
    free(f->sample_counts);
    free(f->moments);
    free(f->caustic_reads);
    f->sample_counts = NULL;
    f->moments = NULL;
    f->caustic_reads = NULL;
}

/* Blackman-Harris window over [−w, w] (Harris 1978, 4-term). */
static double blackman_harris(double x, double w)
{
    double v = 2.0 * M_PI * (x / (2.0 * w) + 0.5);
    return 0.35875 - 0.48829 * cos(v) + 0.14128 * cos(2.0 * v) - 0.01168 * cos(3.0 * v);
}

void pixel_filter_init(pixel_filter *pf, float width)
{
    pf->width = width;
    if (!(width > 0.0f)) {
        for (int i = 0; i < PIXEL_FILTER_TABLE_SIZE; i++)
            pf->table[i] = ((float)i + 0.5f) / PIXEL_FILTER_TABLE_SIZE - 0.5f; /* box of one pixel */
        return;
    }
    /* Integrate the profile on a fine grid, then invert the CDF. */
    enum { N = 4096 };
    static const int n = N;
    double cdf[N + 1];
    cdf[0] = 0.0;
    for (int i = 0; i < n; i++) {
        double x = -width + 2.0 * width * (i + 0.5) / n;
        cdf[i + 1] = cdf[i] + fmax(blackman_harris(x, width), 0.0);
    }
    int j = 0;
    for (int i = 0; i < PIXEL_FILTER_TABLE_SIZE; i++) {
        double u = ((double)i + 0.5) / PIXEL_FILTER_TABLE_SIZE * cdf[n];
        while (j < n - 1 && cdf[j + 1] < u)
            j++;
        double seg = cdf[j + 1] - cdf[j];
        double t = seg > 0.0 ? (u - cdf[j]) / seg : 0.5;
        pf->table[i] = (float)(-width + 2.0 * width * (j + t) / n);
    }
}

float pixel_filter_sample(const pixel_filter *pf, float u)
{
    float x = u * (PIXEL_FILTER_TABLE_SIZE - 1);
    int i = (int)x;
    if (i >= PIXEL_FILTER_TABLE_SIZE - 1)
        return pf->table[PIXEL_FILTER_TABLE_SIZE - 1];
    float t = x - (float)i;
    return pf->table[i] * (1.0f - t) + pf->table[i + 1] * t;
}
