/*
 * distribution.h — a discrete distribution with a cumulative table, for
 * picking lights in proportion to their power (pbrt's Distribution1D,
 * discrete form).
 */
#ifndef PHOS_DISTRIBUTION_H
#define PHOS_DISTRIBUTION_H

#include <stdint.h>

typedef struct distribution {
    uint32_t count;
    float *cdf;      /* count+1 entries, cdf[0] = 0, cdf[count] = 1 */
    double total;    /* sum of the weights */
} distribution;

/* Negative or non-finite weights count as zero. If every weight is zero the
 * distribution is uniform. Returns 0 when memory is exhausted. */
int distribution_build(distribution *d, const float *weights, uint32_t count);
void distribution_free(distribution *d);

/* Picks index i with probability p_i; *pdf receives p_i, and *u_remapped
 * (may be NULL) the position of u within the chosen bin, again in [0,1). */
uint32_t distribution_sample(const distribution *d, float u, float *pdf, float *u_remapped);
float distribution_pdf(const distribution *d, uint32_t i);

#endif /* PHOS_DISTRIBUTION_H */
