/*
 * test_sampler.c — the properties the sampler promises:
 *  - 1-D sets: the first 2^m samples of a pixel put one point in each of
 *    the 2^m strata of [0, 1) (Sobol dimension 0 under Owen scrambling);
 *  - 2-D sets: the first 2^m samples form a (0, m, 2)-net: one point in
 *    every elementary interval of area 2^−m (Sobol dimensions 0 and 1);
 *  - different dimension sets and pixels are decorrelated, and the mean
 *    over pixels is unbiased;
 *  - everything is a pure function of (seed, pixel, sample, dimension).
 */
#include <stdio.h>
#include <string.h>

#include "sampling/sampler.h"
#include "test_util.h"

static int one_per_stratum_1d(uint32_t seed, uint32_t px, uint32_t dim, uint32_t n)
{
    static int hits[4096];
    memset(hits, 0, sizeof(int) * n);
    for (uint32_t i = 0; i < n; i++) {
        sampler s = sampler_for_pixel(seed, px, 7, i);
        float u = sampler_1d(&s, dim);
        if (!(u >= 0.0f && u < 1.0f))
            return 0;
        hits[(uint32_t)(u * (float)n)]++;
    }
    for (uint32_t k = 0; k < n; k++)
        if (hits[k] != 1)
            return 0;
    return 1;
}

/* Every elementary interval 2^a × 2^b with a + b = m holds one point. */
static int is_02_net(uint32_t seed, uint32_t px, uint32_t dim, uint32_t m)
{
    uint32_t n = 1u << m;
    static float x[4096], y[4096];
    for (uint32_t i = 0; i < n; i++) {
        sampler s = sampler_for_pixel(seed, px, 3, i);
        float2 u = sampler_2d(&s, dim);
        x[i] = u.x;
        y[i] = u.y;
    }
    static int hits[4096];
    for (uint32_t a = 0; a <= m; a++) {
        uint32_t nx = 1u << a, ny = 1u << (m - a);
        memset(hits, 0, sizeof(int) * n);
        for (uint32_t i = 0; i < n; i++)
            hits[(uint32_t)(x[i] * nx) * ny + (uint32_t)(y[i] * ny)]++;
        for (uint32_t k = 0; k < n; k++)
            if (hits[k] != 1)
                return 0;
    }
    return 1;
}

int main(void)
{
    for (uint32_t px = 0; px < 20; px++)
        for (uint32_t dim = 0; dim < 12; dim += 3) {
            CHECK_MSG(one_per_stratum_1d(1, px, dim, 256), "1-D strata, pixel %u dim %u", px, dim);
            CHECK_MSG(is_02_net(1, px, dim, 8), "(0,8,2)-net, pixel %u dim %u", px, dim);
        }
    CHECK(is_02_net(9, 3, 40, 12));

    /* Mean and correlation over many pixels and samples. */
    double sum_a = 0.0, sum_b = 0.0, sum_ab = 0.0, sum_a2 = 0.0, sum_b2 = 0.0;
    const int N = 200000;
    for (int k = 0; k < N; k++) {
        sampler s = sampler_for_pixel(5, (uint32_t)k % 500u, (uint32_t)k / 500u, (uint32_t)k % 16u);
        double a = sampler_1d(&s, 4), b = sampler_1d(&s, 7);
        sum_a += a, sum_b += b, sum_ab += a * b, sum_a2 += a * a, sum_b2 += b * b;
    }
    double ma = sum_a / N, mb = sum_b / N;
    double cov = sum_ab / N - ma * mb;
    double corr = cov / sqrt((sum_a2 / N - ma * ma) * (sum_b2 / N - mb * mb));
    /* Independent uniforms: σ(mean) = 0.29/√N ≈ 6.5e-4, σ(corr) ≈ 1/√N ≈ 2.2e-3. */
    CHECK_MSG(fabs(ma - 0.5) < 0.003 && fabs(mb - 0.5) < 0.003, "means %.4f %.4f", ma, mb);
    CHECK_MSG(fabs(corr) < 0.01, "correlation between dimensions %.4f", corr);

    /* The same pixel in two 2-D sets, and two pixels in the same set, differ. */
    sampler s = sampler_for_pixel(1, 10, 10, 3), t = sampler_for_pixel(1, 11, 10, 3);
    float2 p = sampler_2d(&s, 4), q = sampler_2d(&s, 8), r = sampler_2d(&t, 4);
    CHECK(p.x != q.x && p.x != r.x && p.y != r.y);
    /* Pure function: the same inputs give the same numbers. */
    sampler s2 = sampler_for_pixel(1, 10, 10, 3);
    CHECK(sampler_1d(&s, 17) == sampler_1d(&s2, 17));

    /* Independent mode: uniform by a coarse histogram (10 bins, 100k draws). */
    int bins[10] = {0};
    for (uint32_t i = 0; i < 100000; i++) {
        sampler u = sampler_independent(3, 1, i);
        bins[(int)(sampler_1d(&u, 2) * 10.0f)]++;
    }
    for (int b = 0; b < 10; b++)
        CHECK_MSG(abs(bins[b] - 10000) < 500, "bin %d holds %d", b, bins[b]);
    return test_summary("test_sampler");
}
