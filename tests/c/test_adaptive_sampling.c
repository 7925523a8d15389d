/*
 * test_adaptive_sampling.c — adaptive sampling, the time limit and the
 * noise-filter stage, through the public API on the Cornell box:
 *  - adaptive sampling: every pixel takes at least the minimum and at most
 *    the Samples setting; counts differ across the image; the pixels it
 *    stopped are within their threshold of a converged render (the error
 *    it promises, measured, not assumed); the Sample Count pass is the
 *    same for 1 and 2 threads; without adaptive sampling it is 1;
 *  - the time limit: a render of a million samples a pixel ends by
 *    itself, DONE, every pixel with at least one sample and fewer than
 *    asked;
 *  - the FILTERING stage: over the whole image each energy-preserving
 *    filter keeps the Combined pass's total within 0.1 % of the Noisy
 *    Image's, which the filter changed; filtering only the indirect light
 *    moves each pixel by what the filter moved its Indirect component,
 *    and by nothing else.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "test_scenes.h"
#include "test_util.h"

#define W 48
#define H 40

typedef struct rendered {
    float *combined, *count, *noisy, *indirect;
    phos_progress progress;
} rendered;

static void rendered_free(rendered *r)
{
    free(r->combined), free(r->count), free(r->noisy), free(r->indirect);
    memset(r, 0, sizeof(*r));
}

static float *read_pass(phos_render *r, uint32_t pass)
{
    size_t n = (size_t)phos_pass_channels(pass) * W * H;
    float *img = malloc(sizeof(float) * n);
    if (img && phos_render_read(r, pass, 0, 0, W, H, img, n) != PHOS_OK) {
        free(img);
        img = NULL;
    }
    return img;
}

static int render_passes(phos_scene *s, const phos_render_settings *rs, rendered *out)
{
    memset(out, 0, sizeof(*out));
    phos_render *r = NULL;
    if (phos_render_create(s, rs, &r) != PHOS_OK)
        return 0;
    int ok = phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK;
    if (ok) {
        out->combined = read_pass(r, PHOS_PASS_COMBINED);
        out->count = read_pass(r, PHOS_PASS_SAMPLE_COUNT);
        out->noisy = (rs->pass_mask & (1u << PHOS_PASS_NOISY_IMAGE)) ? read_pass(r, PHOS_PASS_NOISY_IMAGE) : NULL;
        out->indirect = (rs->pass_mask & (1u << PHOS_PASS_INDIRECT)) ? read_pass(r, PHOS_PASS_INDIRECT) : NULL;
        phos_render_progress(r, &out->progress);
        ok = out->combined && out->count;
    }
    phos_render_destroy(r);
    return ok;
}

static void base_settings(phos_render_settings *rs)
{
    phos_render_settings_init(rs);
    rs->width = W;
    rs->height = H;
    rs->threads = 2;
    rs->max_bounces = 4;
    rs->pass_mask = (1u << PHOS_PASS_SAMPLE_COUNT) | (1u << PHOS_PASS_NOISY_IMAGE) | (1u << PHOS_PASS_INDIRECT);
}

static double luminance(const float *px) { return 0.2126 * px[0] + 0.7152 * px[1] + 0.0722 * px[2]; }

static void check_adaptive(phos_scene *s)
{
    phos_render_settings rs;
    base_settings(&rs);
    rs.samples = 512;
    rendered full;
    CHECK(render_passes(s, &rs, &full));
    for (size_t i = 0; full.count && i < (size_t)W * H; i++)
        if (full.count[i] != 1.0f) {
            CHECK_MSG(0, "without adaptive sampling pixel %zu has %g of the samples", i, (double)full.count[i]);
            break;
        }
    rendered ref;
    rs.samples = 8192;
    CHECK(render_passes(s, &rs, &ref));

    rs.samples = 512;
    rs.adaptive_sampling = 1;
    rs.adaptive_min_samples = 16;
    rs.adaptive_threshold = 0.02f;
    rendered ad, ad1;
    CHECK(render_passes(s, &rs, &ad));
    rs.threads = 1;
    rs.tile_size = 16;
    CHECK(render_passes(s, &rs, &ad1));
    if (!(full.combined && ref.combined && ad.combined && ad1.combined))
        return;
    CHECK_MSG(memcmp(ad.count, ad1.count, sizeof(float) * W * H) == 0,
              "adaptive sample counts differ between 2 threads and 1 thread with other tiles");
    double lo = 1.0, hi = 0.0, total = 0.0;
    double se_stopped = 0.0;
    uint32_t stopped = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        double c = ad.count[i];
        lo = fmin(lo, c), hi = fmax(hi, c), total += c;
        uint32_t n = (uint32_t)lround(c * 512.0);
        CHECK_MSG(n >= 16 && n <= 512 && fabs(c * 512.0 - n) < 1e-3, "pixel %zu: %g samples", i, c * 512.0);
        if (n < 512) {
            /* The error the threshold promises: |mean − truth| / √μ. The
             * reference has its own noise, 1/4 of a 512-sample pixel's. */
            double mu = luminance(ref.combined + 4 * i);
            double scale = mu < 1.0 ? sqrt(fmax(mu, 0.0)) : mu;
            double e = (luminance(ad.combined + 4 * i) - mu) / fmax(scale, 1e-3);
            se_stopped += e * e;
            stopped++;
        }
    }
    double rms = stopped ? sqrt(se_stopped / stopped) : 0.0;
    printf("adaptive: samples per pixel %.0f..%.0f, mean %.0f; %u pixels stopped early, their relative "
           "error %.4f (threshold 0.02)\n",
           lo * 512, hi * 512, total / (W * H) * 512, stopped, rms);
    CHECK_MSG(lo < hi && total < 0.8 * W * H, "adaptive sampling saved nothing: %g..%g", lo, hi);
    CHECK_MSG(stopped > W * H / 10, "only %u pixels stopped early", stopped);
    /* The standard error is a 1-σ estimate from the pixel's own samples:
     * the RMS over the stopped pixels lands near the threshold, and a
     * broken estimate (a wrong variance, or checks that stop pixels at
     * their first lucky run) lands far above it. */
    CHECK_MSG(rms < 2.0 * 0.02, "pixels stopped with relative error %.4f, over twice the threshold", rms);
    rendered_free(&full), rendered_free(&ref), rendered_free(&ad), rendered_free(&ad1);
}

static void check_time_limit(phos_scene *s)
{
    phos_render_settings rs;
    base_settings(&rs);
    rs.samples = 1u << 20;
    rs.time_limit = 0.3f;
    rs.progressive = 0; /* a time limit renders in passes all the same */
    rendered t;
    CHECK_MSG(render_passes(s, &rs, &t), "a time-limited render did not end DONE");
    if (!t.count)
        return;
    double lo = 1.0, hi = 0.0;
    for (size_t i = 0; i < (size_t)W * H; i++)
        lo = fmin(lo, t.count[i]), hi = fmax(hi, t.count[i]);
    printf("time limit 0.3 s: samples per pixel %.0f..%.0f\n", lo * rs.samples, hi * rs.samples);
    CHECK_MSG(lo * rs.samples >= 0.999 && hi < 1.0, "sample counts %g..%g of %u", lo * rs.samples,
              hi * rs.samples, rs.samples);
    CHECK(t.progress.state == PHOS_STATE_DONE);
    rendered_free(&t);
}

static double sum_rgb(const float *img)
{
    double sum = 0.0;
    for (size_t i = 0; i < (size_t)W * H; i++)
        sum += img[4 * i] + img[4 * i + 1] + img[4 * i + 2];
    return sum;
}

static void check_filters(phos_scene *s)
{
    phos_render_settings rs;
    base_settings(&rs);
    rs.samples = 4;
    rs.integrator = PHOS_INTEGRATOR_PATH;
    rs.filter_target = PHOS_FILTER_TARGET_ALL;
    for (uint32_t f = PHOS_NOISE_FILTER_ADAPTIVE_WIDTH; f <= PHOS_NOISE_FILTER_SPLATTING; f++) {
        rs.noise_filter = f;
        rendered r;
        CHECK(render_passes(s, &rs, &r));
        if (!r.noisy)
            continue;
        double before = sum_rgb(r.noisy), after = sum_rgb(r.combined);
        CHECK_MSG(fabs(after - before) <= 1e-3 * before, "filter %u: total %.6g → %.6g", f, before, after);
        CHECK_MSG(memcmp(r.noisy, r.combined, sizeof(float) * 4 * W * H) != 0, "filter %u changed nothing", f);
        rendered_free(&r);
    }
    /* Only the indirect light filtered: each pixel of Combined moved by
     * exactly what the 3×3 lowpass moved its Indirect component, so the
     * rest of the light (direct, the lamp seen, the walls' colours) is
     * as it was. */
    rs.filter_target = PHOS_FILTER_TARGET_INDIRECT;
    rs.noise_filter = PHOS_NOISE_FILTER_LOWPASS;
    rendered r;
    CHECK(render_passes(s, &rs, &r));
    if (!(r.noisy && r.indirect))
        return;
    double worst = 0.0, moved = 0.0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++) {
                double sum = 0.0;
                int n = 0;
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++)
                        if (x + dx >= 0 && y + dy >= 0 && x + dx < W && y + dy < H) {
                            sum += r.indirect[3 * ((size_t)(y + dy) * W + x + dx) + c];
                            n++;
                        }
                size_t i = (size_t)y * W + x;
                double expect = sum / n - r.indirect[3 * i + c];
                double got = (double)r.combined[4 * i + c] - r.noisy[4 * i + c];
                worst = fmax(worst, fabs(got - expect) / (1e-3 + fabs(r.noisy[4 * i + c])));
                moved += fabs(got);
            }
    printf("indirect-only lowpass: Combined moved by the Indirect pass's lowpass to %.1e (relative), %.3g in all\n",
           worst, moved);
    CHECK_MSG(worst < 1e-5 && moved > 0.0, "Combined moved otherwise than its Indirect component: %.2e", worst);
    rendered_free(&r);
}

int main(void)
{
    phos_scene *s = test_cornell_box(0);
    CHECK(s != NULL);
    if (!s)
        return test_summary("test_adaptive_sampling");
    check_adaptive(s);
    check_time_limit(s);
    check_filters(s);
    phos_scene_destroy(s);
    return test_summary("test_adaptive_sampling");
}
