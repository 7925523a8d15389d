/*
 * test_image_filters.c — the noise filters of filters/image_filter.h keep
 * their promises:
 *  - the energy-preserving filters (adaptive width, diffusion, splatting)
 *    keep each channel's total over a noisy image with fireflies, border
 *    and corner ones included, while the lowpass filter loses a corner
 *    firefly's energy (so the check can fail);
 *  - the median filter removes an isolated firefly; the adaptive-width and
 *    splatting filters spread one;
 *  - the lowpass filter keeps a flat image flat, borders included;
 *  - diffusion stops at a normal edge and lowers the noise on either side;
 *  - splatting changes the image less when its pixels have more samples;
 *  - every filter is deterministic, honours a cancel, and handles 1×1,
 *    1×N and N×1 images.
 */
#include <stdio.h>
#include <string.h>

#include "filters/image_filter.h"
#include "test_util.h"

#define W 64
#define H 48

static const char *const filter_names[IMAGE_FILTER_KIND_COUNT] = {"none",      "lowpass",   "median",
                                                                  "adaptive",  "diffusion", "splatting"};

/* A small deterministic generator (xorshift64*), uniform in (0, 1). */
static double uniform(uint64_t *state)
{
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    return ((double)((*state * 0x2545F4914F6CDD1DULL) >> 11) + 0.5) * 0x1.0p-53;
}

/* Exponential with mean 1: a long tail, like Monte Carlo pixel noise. */
static double exponential(uint64_t *state)
{
    return -log(uniform(state));
}

/* Approximately standard normal (sum of 12 uniforms). */
static double normal_noise(uint64_t *state)
{
    double s = 0.0;
    for (int i = 0; i < 12; i++)
        s += uniform(state);
    return s - 6.0;
}

static void channel_sums(const float *rgb, size_t count, double sums[3])
{
    sums[0] = sums[1] = sums[2] = 0.0;
    for (size_t i = 0; i < count; i++)
        for (size_t k = 0; k < 3; k++)
            sums[k] += rgb[3 * i + k];
}

/* Largest |Σout − Σin| / Σin over the three channels. */
static double energy_error(const float *in, const float *out, size_t count)
{
    double a[3], b[3], worst = 0.0;
    channel_sums(in, count, a);
    channel_sums(out, count, b);
    for (int k = 0; k < 3; k++) {
        double e = fabs(b[k] - a[k]) / fabs(a[k]);
        if (e > worst)
            worst = e;
    }
    return worst;
}

static float max_value(const float *rgb, size_t n)
{
    float m = rgb[0];
    for (size_t i = 1; i < n; i++)
        if (rgb[i] > m)
            m = rgb[i];
    return m;
}

static void set_pixel(float *rgb, uint32_t width, uint32_t x, uint32_t y, float r, float g, float b)
{
    float *c = rgb + 3 * ((size_t)y * width + x);
    c[0] = r;
    c[1] = g;
    c[2] = b;
}

/* A smooth colour gradient times exponential-tailed noise, with (if asked)
 * fireflies 1000× the mean in the corners, on the edges, inside, and two
 * adjacent. */
static void noisy_image(float *rgb, uint32_t width, uint32_t height, uint64_t seed, int fireflies_too)
{
    uint64_t state = seed;
    for (uint32_t y = 0; y < height; y++)
        for (uint32_t x = 0; x < width; x++) {
            double u = (double)x / width, v = (double)y / height;
            double noise = 1.0 + 0.5 * (exponential(&state) - 1.0);
            set_pixel(rgb, width, x, y, (float)((0.2 + 0.6 * u) * noise), (float)((0.3 + 0.4 * v) * noise),
                      (float)((0.5 + 0.2 * u * v) * noise));
        }
    const uint32_t fireflies[][2] = {
        {0, 0}, {width - 1, 0}, {0, height - 1}, {width - 1, height - 1}, /* corners */
        {width / 2, 0}, {0, height / 2},                                  /* edges */
        {10, 10}, {30, 20}, {31, 20}, {50, 40},                           /* inside, one pair */
    };
    for (size_t i = 0; fireflies_too && i < sizeof(fireflies) / sizeof(fireflies[0]); i++)
        if (fireflies[i][0] < width && fireflies[i][1] < height)
            set_pixel(rgb, width, fireflies[i][0], fireflies[i][1], 500.0f, 600.0f, 700.0f);
}

static void flat_image(float *rgb, size_t count, float r, float g, float b)
{
    for (size_t i = 0; i < count; i++) {
        rgb[3 * i] = r;
        rgb[3 * i + 1] = g;
        rgb[3 * i + 2] = b;
    }
}

static image_filter_input plain_input(uint32_t width, uint32_t height, const float *rgb)
{
    image_filter_input in;
    memset(&in, 0, sizeof(in));
    in.width = width;
    in.height = height;
    in.rgb = rgb;
    return in;
}

/* 1: the energy-preserving filters keep the totals, with and without the
 * optional statistics and guides; the lowpass filter does not. */
static void test_energy_balance(void)
{
    static float rgb[W * H * 3], out[W * H * 3], variance[W * H], normal[W * H * 3], albedo[W * H * 3];
    static uint32_t samples[W * H];
    noisy_image(rgb, W, H, 1, 1);
    for (uint32_t i = 0; i < W * H; i++) {
        float y = image_filter_luminance(rgb + 3 * i);
        samples[i] = 1 + i % 64;
        /* A firefly is one huge sample among n: the variance of its mean is
         * about its value squared. Elsewhere σ/mean of one sample is 0.5. */
        variance[i] = y > 100.0f ? y * y : 0.25f * y * y / (float)samples[i];
        set_pixel(normal, W, i % W, i / W, 0.0f, (i / W) < H / 2 ? 1.0f : 0.0f, (i / W) < H / 2 ? 0.0f : 1.0f);
        set_pixel(albedo, W, i % W, i / W, 0.8f, (i % W) < W / 3 ? 0.2f : 0.8f, 0.5f);
    }
    for (int guided = 0; guided < 2; guided++) {
        image_filter_input in = plain_input(W, H, rgb);
        if (guided) {
            in.variance = variance;
            in.samples = samples;
            in.normal = normal;
            in.albedo = albedo;
        }
        for (uint32_t kind = 0; kind < IMAGE_FILTER_KIND_COUNT; kind++) {
            if (!image_filter_preserves_energy(kind))
                continue;
            CHECK(image_filter_apply(kind, &in, out, NULL) == PHOS_OK);
            double e = energy_error(rgb, out, W * H);
            CHECK_MSG(e < 1e-3, "%s%s: relative energy error %g", filter_names[kind],
                      guided ? " (guided)" : "", e);
            /* Not by leaving the image alone: the fireflies were spread. */
            CHECK_MSG(max_value(out, W * H * 3) < 0.5f * max_value(rgb, W * H * 3), "%s%s: max pixel %g",
                      filter_names[kind], guided ? " (guided)" : "", max_value(out, W * H * 3));
            printf("  energy: %-9s%s relative error %.2e, max pixel %.1f -> %.1f\n", filter_names[kind],
                   guided ? " (with statistics and guides)" : "                             ", e,
                   max_value(rgb, W * H * 3), max_value(out, W * H * 3));
        }
    }
    CHECK(image_filter_preserves_energy(IMAGE_FILTER_ADAPTIVE_WIDTH) &&
          image_filter_preserves_energy(IMAGE_FILTER_DIFFUSION) &&
          image_filter_preserves_energy(IMAGE_FILTER_SPLATTING));
    CHECK(!image_filter_preserves_energy(IMAGE_FILTER_NONE) && !image_filter_preserves_energy(IMAGE_FILTER_LOWPASS) &&
          !image_filter_preserves_energy(IMAGE_FILTER_MEDIAN));

    /* The lowpass filter's border renormalisation loses 1 − (1/4 + 2/6 + 1/9)
     * of a corner firefly: the energy check above can fail. */
    flat_image(rgb, W * H, 0.0f, 0.0f, 0.0f);
    set_pixel(rgb, W, 0, 0, 1000.0f, 1000.0f, 1000.0f);
    image_filter_input in = plain_input(W, H, rgb);
    CHECK(image_filter_apply(IMAGE_FILTER_LOWPASS, &in, out, NULL) == PHOS_OK);
    double e = energy_error(rgb, out, W * H);
    CHECK_MSG(fabs(e - (1.0 - (0.25 + 2.0 / 6.0 + 1.0 / 9.0))) < 1e-5, "lowpass corner firefly error %g", e);
    printf("  energy: lowpass loses %.1f %% of a corner firefly\n", 100.0 * e);
}

/* 2 and 3: a firefly on a flat image is removed by the median filter and
 * spread by the energy-preserving ones. */
static void test_firefly(void)
{
    static float rgb[W * H * 3], out[W * H * 3];
    flat_image(rgb, W * H, 0.5f, 0.5f, 0.5f);
    set_pixel(rgb, W, 20, 17, 1000.0f, 1000.0f, 1000.0f);
    image_filter_input in = plain_input(W, H, rgb);

    CHECK(image_filter_apply(IMAGE_FILTER_MEDIAN, &in, out, NULL) == PHOS_OK);
    const float *c = out + 3 * (17 * W + 20);
    CHECK_MSG(c[0] == 0.5f && c[1] == 0.5f && c[2] == 0.5f, "median left %g %g %g", c[0], c[1], c[2]);
    CHECK_MSG(max_value(out, W * H * 3) <= 0.5f + 1e-6f, "median max %g", max_value(out, W * H * 3));

    const uint32_t spreading[] = {IMAGE_FILTER_ADAPTIVE_WIDTH, IMAGE_FILTER_SPLATTING, IMAGE_FILTER_DIFFUSION};
    for (int i = 0; i < 3; i++) {
        CHECK(image_filter_apply(spreading[i], &in, out, NULL) == PHOS_OK);
        float peak = max_value(out, W * H * 3);
        double e = energy_error(rgb, out, W * H);
        printf("  firefly of 1000 on 0.5: %-9s max pixel %.2f, relative energy error %.2e\n",
               filter_names[spreading[i]], peak, e);
        CHECK_MSG(e < 1e-3, "%s energy error %g", filter_names[spreading[i]], e);
        CHECK_MSG(peak < 100.0f, "%s max pixel %g", filter_names[spreading[i]], peak);
    }
    /* Adaptive width leaves the pixels it does not reach alone. */
    CHECK(image_filter_apply(IMAGE_FILTER_ADAPTIVE_WIDTH, &in, out, NULL) == PHOS_OK);
    CHECK(out[0] == 0.5f && out[3 * (W * H - 1)] == 0.5f);
}

/* 4: a flat image is a fixed point of the lowpass filter, at the borders
 * too (their means run over fewer pixels), and of the adaptive-width
 * filter (no pixel is a spike). */
static void test_flat(void)
{
    static float rgb[W * H * 3], out[W * H * 3];
    flat_image(rgb, W * H, 0.3f, 0.6f, 0.9f);
    image_filter_input in = plain_input(W, H, rgb);
    const uint32_t kinds[] = {IMAGE_FILTER_LOWPASS, IMAGE_FILTER_MEDIAN, IMAGE_FILTER_ADAPTIVE_WIDTH};
    for (int k = 0; k < 3; k++) {
        CHECK(image_filter_apply(kinds[k], &in, out, NULL) == PHOS_OK);
        double worst = 0.0;
        for (size_t i = 0; i < W * H * 3; i++)
            worst = fmax(worst, fabs((double)out[i] - rgb[i]) / rgb[i]);
        CHECK_MSG(worst < 1e-6, "%s changed a flat image by %g", filter_names[kinds[k]], worst);
    }
}

/* Mean and standard deviation of the luminance over columns [x0, x1). */
static void column_stats(const float *rgb, uint32_t x0, uint32_t x1, double *mean, double *sigma)
{
    double s = 0.0, s2 = 0.0;
    uint32_t n = 0;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = x0; x < x1; x++) {
            double v = image_filter_luminance(rgb + 3 * (y * W + x));
            s += v;
            s2 += v * v;
            n++;
        }
    *mean = s / n;
    *sigma = sqrt(fmax(s2 / n - *mean * *mean, 0.0));
}

/* 5: a normal edge stops diffusion; noise drops on both sides. */
static void test_diffusion_edge(void)
{
    static float rgb[W * H * 3], out[W * H * 3], normal[W * H * 3];
    uint64_t state = 7;
    for (uint32_t y = 0; y < H; y++)
        for (uint32_t x = 0; x < W; x++) {
            int left = x < W / 2;
            float v = left ? (float)fmax(1.0 + 0.2 * normal_noise(&state), 0.0) : (float)(0.01 * uniform(&state));
            set_pixel(rgb, W, x, y, v, v, v);
            set_pixel(normal, W, x, y, left ? 0.0f : 1.0f, 0.0f, left ? 1.0f : 0.0f);
        }
    image_filter_input in = plain_input(W, H, rgb);
    in.normal = normal;
    CHECK(image_filter_apply(IMAGE_FILTER_DIFFUSION, &in, out, NULL) == PHOS_OK);
    double mean_in_l, sigma_in_l, mean_in_r, sigma_in_r, mean_l, sigma_l, mean_r, sigma_r;
    column_stats(rgb, 0, W / 2, &mean_in_l, &sigma_in_l);
    column_stats(rgb, W / 2, W, &mean_in_r, &sigma_in_r);
    column_stats(out, 0, W / 2, &mean_l, &sigma_l);
    column_stats(out, W / 2, W, &mean_r, &sigma_r);
    CHECK_MSG(mean_r < 0.02, "right half's mean rose from %g to %g", mean_in_r, mean_r);
    CHECK_MSG(sigma_l <= 0.5 * sigma_in_l, "left σ %g -> %g", sigma_in_l, sigma_l);
    CHECK_MSG(sigma_r <= 0.5 * sigma_in_r, "right σ %g -> %g", sigma_in_r, sigma_r);
    CHECK_REL(mean_l, mean_in_l, 1e-3);
    printf("  diffusion at a normal edge: right mean %.4f -> %.4f; noise σ left %.4f -> %.4f (%.1fx), "
           "right %.5f -> %.5f (%.1fx)\n",
           mean_in_r, mean_r, sigma_in_l, sigma_l, sigma_in_l / sigma_l, sigma_in_r, sigma_r, sigma_in_r / sigma_r);

    /* The column just right of the edge, where a leak would show first. */
    double edge_column, edge_sigma;
    column_stats(out, W / 2, W / 2 + 1, &edge_column, &edge_sigma);
    CHECK_MSG(edge_column < 0.02, "the column right of the edge rose to %g", edge_column);

    /* A renderer that reports σ = 0.5 everywhere makes the step from 1 to 0
     * look like noise: only the normal guide holds the edge then. */
    static float variance[W * H];
    for (uint32_t i = 0; i < W * H; i++)
        variance[i] = 0.25f;
    in.variance = variance;
    for (int guided = 1; guided >= 0; guided--) {
        in.normal = guided ? normal : NULL;
        CHECK(image_filter_apply(IMAGE_FILTER_DIFFUSION, &in, out, NULL) == PHOS_OK);
        column_stats(out, W / 2, W / 2 + 1, &edge_column, &edge_sigma);
        if (guided)
            CHECK_MSG(edge_column < 0.02, "with a reported σ of 0.5 the edge column rose to %g", edge_column);
        else
            CHECK_MSG(edge_column > 0.02, "without the guide the edge column stayed at %g", edge_column);
        printf("  diffusion, reported σ 0.5, %s normal guide: mean of the column right of the edge %.4f\n",
               guided ? "with" : "without", edge_column);
    }
}

/* Σ|out − in| over all values. */
static double total_change(const float *a, const float *b, size_t n)
{
    double s = 0.0;
    for (size_t i = 0; i < n; i++)
        s += fabs((double)a[i] - b[i]);
    return s;
}

/* 6: more samples, narrower kernels, a smaller change (no fireflies: they
 * are widened to the cap at any sample count). */
static void test_splatting_samples(void)
{
    static float rgb[W * H * 3], out[W * H * 3];
    static uint32_t samples[W * H];
    noisy_image(rgb, W, H, 3, 0);
    image_filter_input in = plain_input(W, H, rgb);
    in.samples = samples;
    double change[2];
    const uint32_t counts[2] = {1, 4096};
    for (int i = 0; i < 2; i++) {
        for (uint32_t p = 0; p < W * H; p++)
            samples[p] = counts[i];
        CHECK(image_filter_apply(IMAGE_FILTER_SPLATTING, &in, out, NULL) == PHOS_OK);
        change[i] = total_change(rgb, out, W * H * 3);
    }
    /* At 4096 samples h = 0.5, a delta: what still changes is the noise's
     * exponential tail, widened as spikes. */
    CHECK_MSG(change[1] < 0.2 * change[0], "change with 4096 samples %g, with 1 %g", change[1], change[0]);
    printf("  splatting: Σ|out − in| %.2f with 1 sample per pixel, %.2e with 4096\n", change[0], change[1]);
}

/* 7: the same input gives the same bits. */
static void test_determinism(void)
{
    static float rgb[W * H * 3], a[W * H * 3], b[W * H * 3];
    noisy_image(rgb, W, H, 5, 1);
    image_filter_input in = plain_input(W, H, rgb);
    for (uint32_t kind = 0; kind < IMAGE_FILTER_KIND_COUNT; kind++) {
        CHECK(image_filter_apply(kind, &in, a, NULL) == PHOS_OK);
        CHECK(image_filter_apply(kind, &in, b, NULL) == PHOS_OK);
        CHECK_MSG(memcmp(a, b, sizeof(a)) == 0, "%s differs between two runs", filter_names[kind]);
    }
}

/* 8: a cancel set before the call is honoured, by the dispatcher and by
 * each filter; an unknown kind is refused. */
static void test_cancel(void)
{
    static float rgb[W * H * 3], out[W * H * 3];
    noisy_image(rgb, W, H, 9, 1);
    image_filter_input in = plain_input(W, H, rgb);
    atomic_int cancel = 1, go = 0;
    for (uint32_t kind = 0; kind < IMAGE_FILTER_KIND_COUNT; kind++) {
        CHECK_MSG(image_filter_apply(kind, &in, out, &cancel) == PHOS_ERROR_CANCELLED, "%s", filter_names[kind]);
        CHECK_MSG(image_filter_apply(kind, &in, out, &go) == PHOS_OK, "%s", filter_names[kind]);
    }
    /* The filters' own checks, past the dispatcher's. */
    phos_status (*const filters[])(const image_filter_input *, float *, const atomic_int *) = {
        image_filter_lowpass, image_filter_median, image_filter_adaptive_width, image_filter_diffusion,
        image_filter_splatting};
    for (size_t i = 0; i < sizeof(filters) / sizeof(filters[0]); i++)
        CHECK_MSG(filters[i](&in, out, &cancel) == PHOS_ERROR_CANCELLED, "filter %zu ran on", i);
    CHECK(image_filter_apply(IMAGE_FILTER_KIND_COUNT, &in, out, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
}

/* 9: degenerate shapes, with every optional input given or not. */
static void test_small_images(void)
{
    const uint32_t shapes[][2] = {{1, 1}, {1, 7}, {7, 1}, {2, 2}, {1, 30}};
    for (size_t s = 0; s < sizeof(shapes) / sizeof(shapes[0]); s++) {
        uint32_t w = shapes[s][0], h = shapes[s][1], n = w * h;
        float *rgb = malloc(sizeof(float) * 3 * n), *out = malloc(sizeof(float) * 3 * n);
        float *variance = malloc(sizeof(float) * n), *normal = malloc(sizeof(float) * 3 * n);
        uint32_t *samples = malloc(sizeof(uint32_t) * n);
        if (!rgb || !out || !variance || !normal || !samples) {
            CHECK(!"out of memory");
            free(rgb), free(out), free(variance), free(normal), free(samples);
            return;
        }
        noisy_image(rgb, w, h, 11, 1);
        for (uint32_t i = 0; i < n; i++) {
            variance[i] = 0.01f;
            samples[i] = i;  /* includes a pixel with no sample */
            normal[3 * i] = 0.0f, normal[3 * i + 1] = 0.0f, normal[3 * i + 2] = 1.0f;
        }
        for (int with_stats = 0; with_stats < 2; with_stats++)
            for (uint32_t kind = 0; kind < IMAGE_FILTER_KIND_COUNT; kind++) {
                image_filter_input in = plain_input(w, h, rgb);
                if (with_stats) {
                    in.variance = variance;
                    in.samples = samples;
                    in.normal = normal;
                    in.albedo = normal;
                }
                CHECK_MSG(image_filter_apply(kind, &in, out, NULL) == PHOS_OK, "%s on %ux%u", filter_names[kind],
                          w, h);
                int finite = 1;
                for (uint32_t i = 0; i < 3 * n; i++)
                    finite &= isfinite(out[i]) != 0;
                CHECK_MSG(finite, "%s on %ux%u", filter_names[kind], w, h);
                if (image_filter_preserves_energy(kind))
                    CHECK_MSG(energy_error(rgb, out, n) < 1e-5, "%s on %ux%u: energy error %g",
                              filter_names[kind], w, h, energy_error(rgb, out, n));
            }
        free(rgb);
        free(out);
        free(variance);
        free(normal);
        free(samples);
    }
    /* An empty image is nothing to do. */
    image_filter_input empty = plain_input(0, 5, NULL);
    CHECK(image_filter_apply(IMAGE_FILTER_DIFFUSION, &empty, NULL, NULL) == PHOS_OK);
}

int main(void)
{
    test_energy_balance();
    test_firefly();
    test_flat();
    test_diffusion_edge();
    test_splatting_samples();
    test_determinism();
    test_cancel();
    test_small_images();
    return test_summary("test_image_filters");
}
