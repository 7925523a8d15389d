/*
 * test_sampler.c — the properties the sampler promises:
 *  - 1-D sets: the first 2^m samples of a pixel put one point in each of
 *    the 2^m strata of [0, 1) (Sobol dimension 0 under Owen scrambling);
 *  - 2-D sets: the first 2^m samples form a (0, m, 2)-net: one point in
 *    every elementary interval of area 2^−m (Sobol dimensions 0 and 1);
 *  - different dimension sets and pixels are decorrelated, and the mean
 *    over pixels is unbiased;
 *  - everything is a pure function of (seed, pixel, sample, dimension);
 *  - the other samplers: STRATIFIED's 1-D sets one point per stratum of N
 *    and its 2-D sets multi-jittered (one per cell of the m×n grid and one
 *    per fine row and column) for any N; HALTON's first 2^m samples one
 *    per stratum of 2^m (1-D) and evenly over the boxes 2^−a × 3^−b (2-D),
 *    its sets uncorrelated; RANDOM uniform and uncorrelated; all four unbiased, and the three stratified ones
 *    integrating a smooth 2-D function with less error than RANDOM.
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
        sampler s = sampler_for_pixel(SAMPLER_SOBOL, seed, px, 7, i, 256);
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
        sampler s = sampler_for_pixel(SAMPLER_SOBOL, seed, px, 3, i, n);
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

/* STRATIFIED, N samples of one pixel: 1-D one per stratum of N; 2-D one
 * per cell of the m×n grid and one per fine column and row of N. */
static int stratified_is_multi_jittered(uint32_t n, uint32_t px, uint32_t dim)
{
    static int col[4096], row[4096], strata[4096], cell[4096];
    memset(col, 0, sizeof(int) * n), memset(row, 0, sizeof(int) * n);
    memset(strata, 0, sizeof(int) * n), memset(cell, 0, sizeof(int) * n);
    uint32_t m = 1;
    for (uint32_t d = 1; d * d <= n; d++)
        if (n % d == 0)
            m = d;
    for (uint32_t i = 0; i < n; i++) {
        sampler s = sampler_for_pixel(SAMPLER_STRATIFIED, 4, px, 9, i, n);
        float2 u = sampler_2d(&s, dim);
        float v = sampler_1d(&s, dim + 2);
        if (!(u.x >= 0.0f && u.x < 1.0f && u.y >= 0.0f && u.y < 1.0f && v >= 0.0f && v < 1.0f))
            return 0;
        col[(uint32_t)(u.x * (float)n)]++;
        row[(uint32_t)(u.y * (float)n)]++;
        strata[(uint32_t)(v * (float)n)]++;
        cell[(uint32_t)(u.y * (float)(n / m)) * m + (uint32_t)(u.x * (float)m)]++;
    }
    for (uint32_t k = 0; k < n; k++)
        if (col[k] != 1 || row[k] != 1 || strata[k] != 1 || cell[k] != 1)
            return 0;
    return 1;
}

/* HALTON, the first 2^m samples of one pixel: (Φ₂, Φ₃) of a run of 2^m
 * consecutive indices (the per-set shuffle maps the first 2^m onto
 * themselves), so every box 2^−a × 3^−b with 2^a·3^b ≤ 2^m holds
 * ⌊2^m/(2^a·3^b)⌋ or ⌈…⌉ points, and the 1-D sets one per stratum of 2^m. */
static int halton_is_stratified(uint32_t m, uint32_t px, uint32_t dim)
{
    uint32_t n = 1u << m;
    static float x[4096], y[4096];
    static int box[4096], strata[4096];
    memset(strata, 0, sizeof(int) * n);
    for (uint32_t i = 0; i < n; i++) {
        sampler s = sampler_for_pixel(SAMPLER_HALTON, 6, px, 2, i, n);
        float2 u = sampler_2d(&s, dim);
        float v = sampler_1d(&s, dim + 2);
        if (!(u.x >= 0.0f && u.x < 1.0f && u.y >= 0.0f && u.y < 1.0f && v >= 0.0f && v < 1.0f))
            return 0;
        x[i] = u.x, y[i] = u.y;
        strata[(uint32_t)(v * (float)n)]++;
    }
    for (uint32_t k = 0; k < n; k++)
        if (strata[k] != 1)
            return 0;
    for (uint32_t nx = 1; nx <= n; nx *= 2)
        for (uint32_t ny = 1; nx * ny <= n; ny *= 3) {
            uint32_t cells = nx * ny, lo = n / cells, hi = (n + cells - 1) / cells;
            memset(box, 0, sizeof(int) * cells);
            for (uint32_t i = 0; i < n; i++)
                box[(uint32_t)(y[i] * (float)ny) * nx + (uint32_t)(x[i] * (float)nx)]++;
            for (uint32_t k = 0; k < cells; k++)
                if (box[k] < (int)lo || box[k] > (int)hi)
                    return 0;
        }
    return 1;
}

/* HALTON's sets are decorrelated: within a pixel, the x of one 2-D set
 * against the x of another is as uncorrelated as independent numbers
 * (they were not when the sets differed by an index offset alone). */
static double halton_set_correlation(void)
{
    double sa = 0.0, sb = 0.0, sab = 0.0, sa2 = 0.0, sb2 = 0.0;
    const int N = 256, P = 400;
    double worst = 0.0;
    for (int p = 0; p < P; p++) {
        sa = sb = sab = sa2 = sb2 = 0.0;
        for (int i = 0; i < N; i++) {
            sampler s = sampler_for_pixel(SAMPLER_HALTON, 1, (uint32_t)p, 0, (uint32_t)i, (uint32_t)N);
            double a = sampler_2d(&s, 5).x, b = sampler_2d(&s, 13).x;
            sa += a, sb += b, sab += a * b, sa2 += a * a, sb2 += b * b;
        }
        double ma = sa / N, mb = sb / N;
        double corr = (sab / N - ma * mb) / sqrt((sa2 / N - ma * ma) * (sb2 / N - mb * mb));
        worst += corr * corr;
    }
    return sqrt(worst / P); /* RMS over pixels: 1/√N ≈ 0.0625 for independent sets */
}

/* ∫∫ f over the unit square with N samples per pixel, the RMS error over
 * many pixels; also the mean estimate (bias). f is smooth: the integrand
 * of a soft light seen over a pixel. */
static double smooth_f(float x, float y) { return exp(-(x - 0.3) * (x - 0.3) * 4.0) * (1.0 + 0.5 * sin(6.0 * y)); }

static void integration_error(uint32_t kind, uint32_t n, double *rms, double *mean)
{
    double se = 0.0, sum = 0.0;
    const uint32_t pixels = 4000;
    double exact = 0.0; /* f is separable: the midpoint rule on 4000 points per axis */
    for (uint32_t k = 0; k < 4000; k++)
        exact += exp(-((k + 0.5) / 4000.0 - 0.3) * ((k + 0.5) / 4000.0 - 0.3) * 4.0) / 4000.0;
    double ey = 0.0;
    for (uint32_t k = 0; k < 4000; k++)
        ey += (1.0 + 0.5 * sin(6.0 * (k + 0.5) / 4000.0)) / 4000.0;
    exact *= ey;
    for (uint32_t p = 0; p < pixels; p++) {
        double est = 0.0;
        for (uint32_t i = 0; i < n; i++) {
            sampler s = sampler_for_pixel(kind, 3, p % 64u, p / 64u, i, n);
            float2 u = sampler_2d(&s, 12);
            est += smooth_f(u.x, u.y);
        }
        est /= n;
        se += (est - exact) * (est - exact);
        sum += est - exact;
    }
    *rms = sqrt(se / pixels);
    *mean = sum / pixels;
}

static void check_other_samplers(void)
{
    static const uint32_t counts[] = {1, 2, 7, 10, 16, 37, 64, 100, 256};
    for (uint32_t c = 0; c < sizeof(counts) / sizeof(counts[0]); c++)
        for (uint32_t px = 0; px < 8; px++)
            CHECK_MSG(stratified_is_multi_jittered(counts[c], px, 4 + 8 * px), "STRATIFIED N=%u pixel %u",
                      counts[c], px);
    for (uint32_t px = 0; px < 8; px++) {
        CHECK_MSG(halton_is_stratified(6, px, 4 + 8 * px), "HALTON 64 samples, pixel %u", px);
        CHECK_MSG(halton_is_stratified(10, px, 20 + px), "HALTON 1024 samples, pixel %u", px);
    }
    double rms_corr = halton_set_correlation();
    printf("HALTON: RMS correlation between two sets of a pixel %.4f (independent: %.4f)\n", rms_corr, 1.0 / 16.0);
    CHECK_MSG(rms_corr < 0.1, "HALTON's sets are correlated: RMS %.3f", rms_corr);
    /* Samples past N start fresh strata: still in [0, 1). */
    sampler late = sampler_for_pixel(SAMPLER_STRATIFIED, 1, 0, 0, 1000, 16);
    float2 lu = sampler_2d(&late, 0);
    CHECK(lu.x >= 0.0f && lu.x < 1.0f && lu.y >= 0.0f && lu.y < 1.0f);
    /* A photon stream (stratified in blocks) stays in [0, 1) and uniform. */
    int bins[16] = {0};
    for (uint64_t i = 0; i < 16 * 4096; i++) {
        sampler s = sampler_for_index(SAMPLER_STRATIFIED, 2, 1, i);
        bins[(int)(sampler_1d(&s, 3) * 16.0f)]++;
    }
    for (int b = 0; b < 16; b++)
        CHECK_MSG(bins[b] == 4096, "stratified photon stream bin %d holds %d", b, bins[b]);

    /* Unbiased, and the stratified kinds beat RANDOM at 64 samples. The
     * mean over 4000 pixels has σ = rms/√4000; 4σ bounds it. */
    static const char *names[] = {"RANDOM", "STRATIFIED", "HALTON", "SOBOL"};
    static const uint32_t kinds[] = {SAMPLER_RANDOM, SAMPLER_STRATIFIED, SAMPLER_HALTON, SAMPLER_SOBOL};
    double rms[4], mean[4];
    for (uint32_t k = 0; k < 4; k++) {
        integration_error(kinds[k], 64, &rms[k], &mean[k]);
        printf("%-10s 64 spp: RMS error %.2e, bias %.1e\n", names[k], rms[k], mean[k]);
        CHECK_MSG(fabs(mean[k]) < 4.0 * rms[k] / sqrt(4000.0) + 1e-7, "%s bias %.2e (rms %.2e)", names[k],
                  mean[k], rms[k]);
    }
    for (uint32_t k = 1; k < 4; k++)
        CHECK_MSG(rms[k] < 0.5 * rms[0], "%s RMS %.2e not below half RANDOM's %.2e", names[k], rms[k], rms[0]);

    /* RANDOM: pixels' sample sets uncorrelated between dimensions. */
    double sa = 0.0, sb = 0.0, sab = 0.0, sa2 = 0.0, sb2 = 0.0;
    const int N = 100000;
    for (int k = 0; k < N; k++) {
        sampler s = sampler_for_pixel(SAMPLER_RANDOM, 8, (uint32_t)k % 100u, (uint32_t)k / 100u, (uint32_t)k % 8u, 8);
        double a = sampler_1d(&s, 4), b = sampler_1d(&s, 5);
        sa += a, sb += b, sab += a * b, sa2 += a * a, sb2 += b * b;
    }
    double ma = sa / N, mb = sb / N;
    double corr = (sab / N - ma * mb) / sqrt((sa2 / N - ma * ma) * (sb2 / N - mb * mb));
    CHECK_MSG(fabs(corr) < 0.015 && fabs(ma - 0.5) < 0.005, "RANDOM corr %.4f mean %.4f", corr, ma);
}

int main(void)
{
    check_other_samplers();
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
        sampler s = sampler_for_pixel(SAMPLER_SOBOL, 5, (uint32_t)k % 500u, (uint32_t)k / 500u, (uint32_t)k % 16u, 16);
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
    sampler s = sampler_for_pixel(SAMPLER_SOBOL, 1, 10, 10, 3, 16), t = sampler_for_pixel(SAMPLER_SOBOL, 1, 11, 10, 3, 16);
    float2 p = sampler_2d(&s, 4), q = sampler_2d(&s, 8), r = sampler_2d(&t, 4);
    CHECK(p.x != q.x && p.x != r.x && p.y != r.y);
    /* Pure function: the same inputs give the same numbers. */
    sampler s2 = sampler_for_pixel(SAMPLER_SOBOL, 1, 10, 10, 3, 16);
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
