/*
 * distribution.c — discrete distribution sampled by binary search on its
 * cumulative table.
 */
#include "sampling/distribution.h"

#include <math.h>
#include <stdlib.h>

int distribution_build(distribution *d, const float *weights, uint32_t count)
{
    d->count = count;
    d->total = 0.0;
    d->cdf = malloc(sizeof(float) * ((size_t)count + 1));
    if (!d->cdf)
        return 0;
    double *sum = malloc(sizeof(double) * ((size_t)count + 1));
    if (!sum) {
        free(d->cdf);
        d->cdf = NULL;
        return 0;
    }
    sum[0] = 0.0;
    for (uint32_t i = 0; i < count; i++) {
        float w = weights[i];
        sum[i + 1] = sum[i] + ((isfinite(w) && w > 0.0f) ? (double)w : 0.0);
    }
    d->total = sum[count];
    for (uint32_t i = 0; i <= count; i++)
        d->cdf[i] = d->total > 0.0 ? (float)(sum[i] / d->total) : (float)i / (float)(count ? count : 1);
    if (count)
        d->cdf[count] = 1.0f;
    free(sum);
    return 1;
}

void distribution_free(distribution *d)
{
    free(d->cdf);
    d->cdf = NULL;
    d->count = 0;
}

float distribution_pdf(const distribution *d, uint32_t i)
{
    if (i >= d->count)
        return 0.0f;
    return d->cdf[i + 1] - d->cdf[i];
}

uint32_t distribution_sample(const distribution *d, float u, float *pdf, float *u_remapped)
{
    /* Find the last i with cdf[i] <= u, skipping empty bins. */
    uint32_t lo = 0, hi = d->count;
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (d->cdf[mid] <= u)
            lo = mid;
        else
            hi = mid;
    }
    while (lo + 1 < d->count && d->cdf[lo + 1] - d->cdf[lo] <= 0.0f)
        lo++;
    float p = d->cdf[lo + 1] - d->cdf[lo];
    if (pdf)
        *pdf = p;
    if (u_remapped) {
        float r = p > 0.0f ? (u - d->cdf[lo]) / p : 0.0f;
        *u_remapped = fminf(fmaxf(r, 0.0f), 0x1.fffffep-1f);
    }
    return lo;
}
