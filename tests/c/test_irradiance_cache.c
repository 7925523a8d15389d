/*
 * test_irradiance_cache.c — the irradiance cache (Ward et al. 1988;
 * docs/algorithms.md §10): against the analytic irradiance inside a closed
 * emitting sphere, its gradients against finite differences, PATH with
 * the cache against PATH without, PHOTON with the cache against final
 * gathering at every sample, and determinism across threads and borders.
 */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "indirect/irradiance_record.h"
#include "integrators/integrator.h"
#include "scene/embree.h"
#include "shading/material.h"
#include "test_scenes.h"
#include "test_util.h"

#define ALL_LIGHT_PASSES ((1u << (PHOS_PASS_INDIRECT + 1)) - 1u)

typedef struct render_out {
    float *pass[PHOS_PASS_COUNT];
    phos_progress progress;
    uint32_t w, h;
} render_out;

/* Renders every pass of rs->pass_mask of the region (or frame). */
static int render_all(phos_scene *s, const phos_render_settings *rs, render_out *out)
{
    memset(out, 0, sizeof(*out));
    out->w = rs->region_width ? rs->region_width : rs->width;
    out->h = rs->region_height ? rs->region_height : rs->height;
    phos_render *r = NULL;
    if (phos_render_create(s, rs, &r) != PHOS_OK) {
        fprintf(stderr, "render: %s\n", phos_scene_error(s));
        return 0;
    }
    int ok = phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK &&
             phos_render_progress(r, &out->progress) == PHOS_OK;
    for (uint32_t p = 0; p < PHOS_PASS_COUNT && ok; p++) {
        if (!(rs->pass_mask & (1u << p)) && p != PHOS_PASS_COMBINED)
            continue;
        size_t n = (size_t)phos_pass_channels(p) * out->w * out->h;
        out->pass[p] = calloc(n, sizeof(float));
        ok = out->pass[p] && phos_render_read(r, p, rs->region_x, rs->region_y, out->w, out->h, out->pass[p], n) ==
                                 PHOS_OK;
    }
    phos_render_destroy(r);
    return ok;
}

static void render_out_free(render_out *o)
{
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++)
        free(o->pass[p]);
    memset(o, 0, sizeof(*o));
}

/* Mean over pixels and RGB of a pass. */
static double pass_mean(const render_out *o, uint32_t pass)
{
    uint32_t ch = phos_pass_channels(pass);
    size_t n = (size_t)o->w * o->h;
    double m = 0.0;
    for (size_t i = 0; i < n; i++)
        m += o->pass[pass][i * ch] + o->pass[pass][i * ch + 1] + o->pass[pass][i * ch + 2];
    return m / (3.0 * (double)n);
}

static phos_render_settings cache_settings(uint32_t integrator, uint32_t w, uint32_t samples, uint32_t seed)
{
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.integrator = integrator;
    rs.width = rs.height = w;
    rs.samples = samples;
    rs.seed = seed;
    rs.max_bounces = 8;
    rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_ALWAYS;
    rs.pass_mask = ALL_LIGHT_PASSES | (1u << PHOS_PASS_IRRADIANCE_CACHE);
    return rs;
}

/* ------------------------------------------------------------ analytic */

/* Inside a closed sphere whose inner surface emits L_e and reflects with
 * albedo ρ, the radiance is L_e/(1 − ρ) everywhere; light that scattered
 * at least once arrives with L_e ρ/(1 − ρ), so the cached irradiance is
 * E = π L_e ρ/(1 − ρ), and the Indirect pass f_d E = L_e ρ²/(1 − ρ). */
static void test_closed_sphere_analytic(void)
{
    const float Le = 1.0f, rho = 0.5f;
    phos_scene *s = phos_scene_create();
    phos_closure_desc c[2];
    phos_closure_desc_init(&c[0]);
    phos_closure_desc_init(&c[1]);
    c[0].type = PHOS_CLOSURE_DIFFUSE;
    c[0].weight[0] = c[0].weight[1] = c[0].weight[2] = rho;
    c[1].type = PHOS_CLOSURE_EMISSION;
    c[1].weight[0] = c[1].weight[1] = c[1].weight[2] = Le;
    uint32_t mat = test_add_mix_material(s, c, 2);
    test_add_instance(s, test_add_sphere_mesh(s, 1.0f, 64, 32, 1), mat, 0, 0, 0);
    test_set_camera(s, 0, 0, 0.5f, 0.6f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    phos_render_settings rs = cache_settings(PHOS_INTEGRATOR_PATH, 32, 4, 1);
    rs.max_bounces = 64;
    rs.ic_rays = 1024;
    render_out o;
    CHECK(render_all(s, &rs, &o));
    if (o.pass[0]) {
        double indirect = pass_mean(&o, PHOS_PASS_INDIRECT), combined = pass_mean(&o, PHOS_PASS_COMBINED);
        double expect_indirect = Le * rho * rho / (1.0 - rho), expect_combined = Le / (1.0 - rho);
        printf("  closed sphere: indirect %.5f (analytic %.5f), combined %.5f (analytic %.5f); %u records, "
               "%.1f %% of lookups interpolated\n",
               indirect, expect_indirect, combined, expect_combined, o.progress.cache_records,
               100.0 * (double)o.progress.cache_interpolated / (double)(o.progress.cache_lookups ? o.progress.cache_lookups : 1));
        CHECK_REL(indirect, expect_indirect, 0.01);
        CHECK_REL(combined, expect_combined, 0.01);
        CHECK(o.progress.cache_records > 0);
    }
    render_out_free(&o);
    phos_scene_destroy(s);
}

/* ------------------------------------------------------------ gradients */

/* A PATH record at the floor point (x, y) of the Cornell box s. */
static int floor_record(phos_scene *s, float x, float y, uint32_t seed, uint32_t rays, irradiance_record *out)
{
    integrator_settings is;
    memset(&is, 0, sizeof(is));
    is.max_bounces = 8;
    is.cache_inner = &indirect_path_hemisphere;
    is.gathers_find_caustics = 1;
    integrator_scratch scratch;
    memset(&scratch, 0, sizeof(scratch));
    ray_hit h;
    vec3 o = v3(x, y, 1.0f), d = v3(0.0f, 0.0f, -1.0f);
    if (!embree_intersect(s->bvh, o, d, 0.0f, INFINITY, 0, &h))
        return 0;
    surface sf;
    surface_from_hit(s, h.instance, h.prim, h.b1, h.b2, d, &sf);
    bsdf b;
    material_bsdf(s, &sf, &b);
    light_context light = light_context_at(&sf);
    sampler smp = sampler_for_pixel(SAMPLER_SOBOL, seed, 0, 0, 0, 1);
    indirect_query q = {s, &is, &sf, &light, &b, sf.wo, &smp, 0, 0, &scratch};
    return irradiance_record_compute(&q, is.cache_inner->incoming, rays, 0.0f, INFINITY, out);
}

/* Ward & Heckbert's gradients on the floor near the red wall (x = −1).
 * Translational: against the finite difference of two records δ apart
 * toward the wall, each pair drawn with the same seed, so that the strata's
 * jitter is shared and the difference has little noise. Over several
 * seeds, the mean of (difference − gradient) must be zero within 4
 * standard errors, while the gradient itself is many standard errors from
 * zero, of the sign the wall gives: red light falls away from it.
 * Rotational: a normal tilted toward the wall, n = (−sin ε, 0, cos ε),
 * turns by n_i × n = (0, −sin ε, 0) and sees more red, so ∇_r E (red)
 * must point along −y (docs/algorithms.md §10.5). */
static void test_translational_gradient_matches_finite_differences(void)
{
    phos_scene *s = test_cornell_box(0);
    CHECK(s != NULL);
    if (!s)
        return;
    const float x0 = -0.6f, y0 = 0.0f, delta = 0.02f;
    const int seeds = 8;
    double diff_sum = 0, diff_sum2 = 0, grad_sum = 0, grad_sum2 = 0, rot_sum = 0, rot_sum2 = 0;
    for (int k = 0; k < seeds; k++) {
        irradiance_record lo, mid, hi;
        CHECK(floor_record(s, x0 - delta, y0, 100 + k, 4096, &lo));
        CHECK(floor_record(s, x0, y0, 100 + k, 4096, &mid));
        CHECK(floor_record(s, x0 + delta, y0, 100 + k, 4096, &hi));
        double fd = (hi.E.x - lo.E.x) / (2.0 * delta); /* red: the wall at x = −1 is red */
        double g = mid.grad_t[0].x;
        diff_sum += fd - g;
        diff_sum2 += (fd - g) * (fd - g);
        grad_sum += g;
        grad_sum2 += g * g;
        rot_sum += mid.grad_r[0].y;
        rot_sum2 += (double)mid.grad_r[0].y * mid.grad_r[0].y;
    }
    double n = seeds;
    double diff_mean = diff_sum / n, diff_se = sqrt(fmax(diff_sum2 / n - diff_mean * diff_mean, 0.0) / (n - 1));
    double grad_mean = grad_sum / n, grad_se = sqrt(fmax(grad_sum2 / n - grad_mean * grad_mean, 0.0) / (n - 1));
    printf("  translational gradient (red, toward the red wall): %.4f ± %.4f W/m³; finite difference − gradient "
           "%.4f ± %.4f\n",
           grad_mean, grad_se, diff_mean, diff_se);
    CHECK_MSG(fabs(diff_mean) <= 4.0 * diff_se, "the gradient differs from the finite difference by %.4f ± %.4f",
              diff_mean, diff_se);
    CHECK_MSG(grad_mean < -8.0 * grad_se, "the red irradiance must fall away from the red wall: %.4f ± %.4f",
              grad_mean, grad_se);
    double rot_mean = rot_sum / n, rot_se = sqrt(fmax(rot_sum2 / n - rot_mean * rot_mean, 0.0) / (n - 1));
    printf("  rotational gradient (red), y: %.4f ± %.4f W/m² per radian\n", rot_mean, rot_se);
    CHECK_MSG(rot_mean < -8.0 * rot_se, "turning toward the red wall must add red: %.4f ± %.4f", rot_mean, rot_se);
    phos_scene_destroy(s);
}

/* ------------------------------------------------------------ Cornell box */

/* Relative MSE of a against the reference: Σ (a − r)² / Σ r² over pixels and RGB. */
static double relative_mse_ch(const float *a, const float *ref, size_t pixels, uint32_t ch)
{
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < pixels; i++)
        for (uint32_t c = 0; c < 3; c++) {
            double d = a[ch * i + c] - ref[ch * i + c];
            num += d * d;
            den += (double)ref[ch * i + c] * ref[ch * i + c];
        }
    return num / den;
}

static double relative_mse(const float *a, const float *ref, size_t pixels)
{
    return relative_mse_ch(a, ref, pixels, 4);
}

static uint64_t total_rays(const render_out *o) { return o->progress.rays_traced + o->progress.cache_rays_traced; }

/* PATH with the cache (Ward's method) on the Cornell box with its glass
 * and mirror spheres, against a converged PATH render. The bound: at the
 * same samples per pixel, the cached render's relative MSE is below
 * PATH's. Both have the same noise of direct light and of the specular
 * paths; the cache replaces the indirect light's noise with its own
 * error (interpolation and its records' noise), and that error must be
 * the smaller one, or the cache is not worth its records at any time
 * budget (which make bench measures). Both errors include the reference's
 * own noise (2048 samples: 1/32 of the 64-sample render's), which only
 * makes the comparison harder for the cache. */
static void test_path_with_cache_against_path(void)
{
    if (test_left_to_plain_build(__func__))
        return;
    phos_scene *s = test_cornell_box(1);
    CHECK(s != NULL);
    if (!s)
        return;
    const uint32_t w = 64, n = w * w;
    render_out ref, path, cached;
    phos_render_settings rs = cache_settings(PHOS_INTEGRATOR_PATH, w, 2048, 7);
    rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_OFF;
    CHECK(render_all(s, &rs, &ref));
    rs.samples = 64;
    rs.seed = 1;
    CHECK(render_all(s, &rs, &path));
    rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_ALWAYS;
    CHECK(render_all(s, &rs, &cached));
    if (ref.pass[0] && path.pass[0] && cached.pass[0]) {
        double e_path = relative_mse(path.pass[0], ref.pass[0], n), e_cached = relative_mse(cached.pass[0], ref.pass[0], n);
        printf("  Cornell box, %u², 64 spp: PATH relMSE %.5f (%.2f M rays); PATH + cache relMSE %.5f "
               "(%.2f M rays, %u records, %.1f %% interpolated)\n",
               w, e_path, total_rays(&path) * 1e-6, e_cached, total_rays(&cached) * 1e-6, cached.progress.cache_records,
               100.0 * cached.progress.cache_interpolated / (double)(cached.progress.cache_lookups + 1));
        CHECK_MSG(e_cached < e_path, "PATH + cache %.5f vs PATH %.5f", e_cached, e_path);
        /* Consistent: the error of the Indirect pass, all that the cache
         * makes, falls as the records grow denser and gather more rays
         * (here, where the bias lives: the box's corners and edges, the
         * floor under the spheres). The reference's own noise in that
         * pass is the same in each. */
        const float q[3] = {2.0f, 5.0f, 12.0f};
        const uint32_t rays[3] = {128, 1024, 4096};
        double e_prev = INFINITY;
        for (int k = 0; k < 3; k++) {
            render_out o;
            phos_render_settings cs = rs;
            cs.ic_accuracy = q[k];
            cs.ic_rays = rays[k];
            cs.ic_min_spacing = 1.0f;
            CHECK(render_all(s, &cs, &o));
            if (o.pass[0]) {
                double e = relative_mse_ch(o.pass[PHOS_PASS_INDIRECT], ref.pass[PHOS_PASS_INDIRECT], n, 3);
                printf("  q = %g, %u rays: %u records, Indirect relMSE %.5f\n", (double)q[k], rays[k], o.progress.cache_records, e);
                CHECK_MSG(e < e_prev, "q = %g, %u rays: relMSE %.5f, not below %.5f", (double)q[k], rays[k], e, e_prev);
                e_prev = e;
            }
            render_out_free(&o);
        }
        /* The Caustics pass keeps its meaning: the caustic under the glass
         * sphere, now from the records' rays. */
        double c_ref = pass_mean(&ref, PHOS_PASS_CAUSTICS), c_cached = pass_mean(&cached, PHOS_PASS_CAUSTICS);
        printf("  caustics pass: PATH %.5f, PATH + cache %.5f\n", c_ref, c_cached);
        CHECK_REL(c_cached, c_ref, 0.25);
    }
    render_out_free(&ref);
    render_out_free(&path);
    render_out_free(&cached);
    phos_scene_destroy(s);
}

/* Records stay few at the defaults (fewer than 5 % of the pixels at 256²,
 * where the spacing clamps do not decide), and a stricter accuracy adds
 * records: the course's q = 10 against q = 20. */
static void test_record_counts(void)
{
    if (test_left_to_plain_build(__func__))
        return;
    phos_scene *s = test_cornell_box(1);
    CHECK(s != NULL);
    if (!s)
        return;
    const uint32_t w = 256;
    uint32_t records[2] = {0, 0};
    float q[2] = {10.0f, 20.0f};
    phos_render_settings rs = cache_settings(PHOS_INTEGRATOR_PATH, w, 1, 1);
    rs.pass_mask = 1u << PHOS_PASS_COMBINED;
    render_out o;
    CHECK(render_all(s, &rs, &o));
    printf("  defaults at %u²: %u records, %.2f %% of the pixels\n", w, o.progress.cache_records,
           100.0 * o.progress.cache_records / (w * w));
    CHECK(o.progress.cache_records > 0 && o.progress.cache_records < 0.05 * w * w);
    render_out_free(&o);
    for (int k = 0; k < 2; k++) {
        rs.ic_accuracy = q[k];
        CHECK(render_all(s, &rs, &o));
        records[k] = o.progress.cache_records;
        render_out_free(&o);
    }
    printf("  q = 10: %u records; q = 20: %u records\n", records[0], records[1]);
    CHECK(records[1] > records[0]);
    phos_scene_destroy(s);
}

/* PHOTON with the cache against final gathering at every sample, on the
 * Cornell box at the default 128 samples: the same mean within 1 % (the
 * cache's interpolation adds no bias the image shows), from at least 10×
 * fewer gather rays (the records' rays counted with the tiles'). The
 * records' count grows more slowly than the pixels', so the ratio grows
 * with the image: 8.6× at 128², 12× at 192². */
static void test_photon_with_cache_against_final_gather(void)
{
    if (test_left_to_plain_build(__func__))
        return;
    phos_scene *s = test_cornell_box(1);
    CHECK(s != NULL);
    if (!s)
        return;
    const uint32_t w = 192;
    render_out gathered, cached;
    phos_render_settings rs = cache_settings(PHOS_INTEGRATOR_PHOTON, w, 128, 3);
    rs.global_photons = rs.caustic_photons = 200000;
    rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_OFF;
    CHECK(render_all(s, &rs, &gathered));
    rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_ALWAYS;
    CHECK(render_all(s, &rs, &cached));
    if (gathered.pass[0] && cached.pass[0]) {
        double a = pass_mean(&gathered, PHOS_PASS_COMBINED), b = pass_mean(&cached, PHOS_PASS_COMBINED);
        double ia = pass_mean(&gathered, PHOS_PASS_INDIRECT), ib = pass_mean(&cached, PHOS_PASS_INDIRECT);
        uint64_t ga = gathered.progress.gather_rays, gb = cached.progress.gather_rays;
        printf("  PHOTON, %u², 128 spp: mean %.5f gathering, %.5f cached (indirect %.5f, %.5f); gather rays "
               "%.2f M against %.2f M (%.1f×); %u records\n",
               w, a, b, ia, ib, ga * 1e-6, gb * 1e-6, (double)ga / (double)(gb ? gb : 1), cached.progress.cache_records);
        CHECK_REL(b, a, 0.01);
        CHECK_MSG(gb * 10 <= ga, "gather rays: %llu cached against %llu", (unsigned long long)gb,
                  (unsigned long long)ga);
    }
    render_out_free(&gathered);
    render_out_free(&cached);
    phos_scene_destroy(s);
}

static int same_pass(const render_out *a, const render_out *b, uint32_t pass, uint32_t ax, uint32_t ay)
{
    uint32_t ch = phos_pass_channels(pass);
    for (uint32_t y = 0; y < b->h; y++)
        if (memcmp(&a->pass[pass][((size_t)(y + ay) * a->w + ax) * ch], &b->pass[pass][(size_t)y * b->w * ch],
                   sizeof(float) * ch * b->w) != 0)
            return 0;
    return 1;
}

/* The same image, bit for bit, on 1 and 2 threads, with other tiles, and
 * for a border against the same pixels of the full frame, for PATH and
 * PHOTON with the cache (its pre-pass inserts in a fixed order and covers
 * the full frame). */
static void test_cache_is_deterministic(void)
{
    phos_scene *s = test_cornell_box(1);
    CHECK(s != NULL);
    if (!s)
        return;
    for (uint32_t integrator = 0; integrator < 2; integrator++) {
        render_out full, other, border;
        phos_render_settings rs = cache_settings(integrator, 48, 4, 5);
        rs.global_photons = rs.caustic_photons = 50000;
        rs.threads = 1;
        CHECK(render_all(s, &rs, &full));
        rs.threads = 2;
        rs.tile_size = 16;
        CHECK(render_all(s, &rs, &other));
        rs.region_x = 13;
        rs.region_y = 7;
        rs.region_width = 20;
        rs.region_height = 30;
        CHECK(render_all(s, &rs, &border));
        if (full.pass[0] && other.pass[0] && border.pass[0]) {
            for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
                if (!full.pass[p])
                    continue;
                CHECK_MSG(same_pass(&full, &other, p, 0, 0), "%s: pass %u differs between 1 and 2 threads",
                          integrator ? "PHOTON" : "PATH", p);
                CHECK_MSG(same_pass(&full, &border, p, 13, 7), "%s: pass %u of a border differs from the full frame",
                          integrator ? "PHOTON" : "PATH", p);
            }
            CHECK(full.progress.cache_records > 0 && full.progress.cache_records == border.progress.cache_records);
        }
        render_out_free(&full);
        render_out_free(&other);
        render_out_free(&border);
    }
    phos_scene_destroy(s);
}

/* Renders with a cache file (phos_render_set_cache_file); 0 if the render
 * failed, its message in msg. */
static int render_with_file(phos_scene *s, const phos_render_settings *rs, const char *path, uint32_t mode,
                            render_out *out, char *msg, size_t msg_size)
{
    memset(out, 0, sizeof(*out));
    out->w = rs->width;
    out->h = rs->height;
    msg[0] = 0;
    phos_render *r = NULL;
    if (phos_render_create(s, rs, &r) != PHOS_OK)
        return 0;
    CHECK(phos_render_set_cache_file(r, PHOS_CACHE_IRRADIANCE, path, mode) == PHOS_OK);
    int ok = phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK &&
             phos_render_progress(r, &out->progress) == PHOS_OK;
    snprintf(msg, msg_size, "%s", phos_render_error(r));
    if (ok) {
        size_t n = (size_t)4 * out->w * out->h;
        out->pass[0] = calloc(n, sizeof(float));
        ok = phos_render_read(r, PHOS_PASS_COMBINED, 0, 0, out->w, out->h, out->pass[0], n) == PHOS_OK;
    }
    phos_render_destroy(r);
    return ok;
}

/* A cache saved, then read back by another render of the same scene,
 * renders the identical image, also with another camera resolution of
 * the same view; a file made for another scene, or with another setting
 * that shapes its records, is refused with a message saying what differs;
 * a missing or cut file is an error, not a crash. */
static void test_cache_file_round_trip(void)
{
    const char *path = "/tmp/phos_test_cache.phosirc";
    char msg[512];
    phos_scene *s = test_cornell_box(1);
    CHECK(s != NULL);
    if (!s)
        return;
    for (uint32_t integrator = 0; integrator < 2; integrator++) {
        render_out saved, loaded, plain;
        phos_render_settings rs = cache_settings(integrator, 40, 4, 9);
        rs.global_photons = rs.caustic_photons = 30000;
        rs.pass_mask = 1u << PHOS_PASS_COMBINED;
        remove(path);
        CHECK(render_with_file(s, &rs, path, PHOS_CACHE_FILE_SAVE, &saved, msg, sizeof(msg)));
        CHECK(render_with_file(s, &rs, path, PHOS_CACHE_FILE_LOAD, &loaded, msg, sizeof(msg)));
        CHECK(render_with_file(s, &rs, path, PHOS_CACHE_FILE_NONE, &plain, msg, sizeof(msg)));
        if (saved.pass[0] && loaded.pass[0] && plain.pass[0]) {
            CHECK_MSG(memcmp(saved.pass[0], loaded.pass[0], sizeof(float) * 4 * 40 * 40) == 0,
                      "%s: the image from the loaded cache differs", integrator ? "PHOTON" : "PATH");
            CHECK(memcmp(saved.pass[0], plain.pass[0], sizeof(float) * 4 * 40 * 40) == 0);
            CHECK(loaded.progress.cache_records == saved.progress.cache_records && saved.progress.cache_records > 0);
            CHECK_MSG(loaded.progress.cache_rays_traced == 0, "loading cast %llu rays",
                      (unsigned long long)loaded.progress.cache_rays_traced);
        }
        render_out_free(&saved);
        render_out_free(&loaded);
        render_out_free(&plain);
        /* Another image size of the same view reads the same records. */
        render_out bigger;
        phos_render_settings rb = rs;
        rb.width = rb.height = 48;
        CHECK(render_with_file(s, &rb, path, PHOS_CACHE_FILE_LOAD, &bigger, msg, sizeof(msg)));
        render_out_free(&bigger);
        /* Settings that shape the records are refused, by name. */
        phos_render_settings rr = rs;
        rr.ic_rays = rs.ic_rays / 2;
        CHECK(!render_with_file(s, &rr, path, PHOS_CACHE_FILE_LOAD, &bigger, msg, sizeof(msg)));
        CHECK_MSG(strstr(msg, "ic_rays") != NULL, "%s", msg);
        render_out_free(&bigger);
        rr = rs;
        rr.seed = rs.seed + 1;
        CHECK(!render_with_file(s, &rr, path, PHOS_CACHE_FILE_LOAD, &bigger, msg, sizeof(msg)));
        CHECK_MSG(strstr(msg, "seed") != NULL, "%s", msg);
        render_out_free(&bigger);
    }
    /* Another scene: the light moved, or the geometry. */
    phos_scene *t = test_cornell_box(0);
    render_out o;
    phos_render_settings rs = cache_settings(PHOS_INTEGRATOR_PHOTON, 40, 4, 9);
    rs.global_photons = rs.caustic_photons = 30000;
    CHECK(!render_with_file(t, &rs, path, PHOS_CACHE_FILE_LOAD, &o, msg, sizeof(msg)));
    printf("  another scene: %s\n", msg);
    CHECK_MSG(strstr(msg, "geometry") != NULL, "%s", msg);
    render_out_free(&o);
    phos_scene_destroy(t);
    /* Missing and cut files. */
    CHECK(!render_with_file(s, &rs, "/tmp/phos_no_such_cache.phosirc", PHOS_CACHE_FILE_LOAD, &o, msg, sizeof(msg)));
    CHECK_MSG(strstr(msg, "cannot read") != NULL, "%s", msg);
    render_out_free(&o);
    FILE *f = fopen(path, "r+b");
    if (f) {
        fseek(f, 0, SEEK_END);
        long size = ftell(f);
        fclose(f);
        CHECK(truncate(path, size / 2) == 0);
    }
    CHECK(!render_with_file(s, &rs, path, PHOS_CACHE_FILE_LOAD, &o, msg, sizeof(msg)));
    CHECK_MSG(strstr(msg, "ends before") != NULL || strstr(msg, "ends in") != NULL, "%s", msg);
    render_out_free(&o);
    remove(path);
    phos_scene_destroy(s);
}

/* A render farm's cache job (docs/farm.md): one render that renders no
 * pixel (caches_only) fills the cache from the scene's camera A and from
 * a further view B (phos_render_add_view), and saves it. A render from B
 * that loads it finds its lookups covered as well as B's own pre-pass
 * covers them, where A's cache alone leaves gaps; the file is the same
 * for 1 and 2 threads; a view is checked as the camera is. */
static int save_cache_for_views(phos_scene *s, const phos_render_settings *rs, const phos_camera_desc *views,
                                uint32_t view_count, const char *path, uint32_t *records)
{
    phos_render *r = NULL;
    if (phos_render_create(s, rs, &r) != PHOS_OK)
        return 0;
    int ok = phos_render_set_cache_file(r, PHOS_CACHE_IRRADIANCE, path, PHOS_CACHE_FILE_SAVE) == PHOS_OK;
    for (uint32_t v = 0; v < view_count && ok; v++)
        ok = phos_render_add_view(r, &views[v]) == PHOS_OK;
    phos_stage_info plan[PHOS_STAGE_COUNT];
    uint32_t stages = 0;
    ok = ok && phos_render_stages(r, plan, PHOS_STAGE_COUNT, &stages) == PHOS_OK;
    for (uint32_t i = 0; i < stages; i++)
        CHECK_MSG(plan[i].id != PHOS_STAGE_RENDERING, "a caches_only render plans its rendering stage");
    phos_progress p;
    ok = ok && phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK &&
         phos_render_progress(r, &p) == PHOS_OK;
    if (ok)
        *records = p.cache_records;
    else
        printf("  cache job failed: %s\n", phos_render_error(r));
    phos_render_destroy(r);
    return ok;
}

static int same_file(const char *a, const char *b)
{
    FILE *fa = fopen(a, "rb"), *fb = fopen(b, "rb");
    int same = fa && fb;
    while (same) {
        int ca = fgetc(fa), cb = fgetc(fb);
        same = ca == cb;
        if (ca == EOF || cb == EOF)
            break;
    }
    if (fa)
        fclose(fa);
    if (fb)
        fclose(fb);
    return same;
}

static void test_views_fill_the_cache(void)
{
    const char *path_a = "/tmp/phos_test_views_a.phosirc", *path_ab = "/tmp/phos_test_views_ab.phosirc",
               *path_ab1 = "/tmp/phos_test_views_ab1.phosirc";
    char msg[512];
    phos_scene *s = test_cornell_box(0);
    CHECK(s != NULL);
    if (!s)
        return;
    phos_camera_desc b = test_camera_pitched(0.3f, 3.5f, 1.2f, -1.5708f, 0.45f);
    phos_render_settings rs = cache_settings(PHOS_INTEGRATOR_PATH, 40, 4, 9);
    rs.pass_mask = 1u << PHOS_PASS_COMBINED;
    rs.caches_only = 1;
    uint32_t records_a = 0, records_ab = 0, records_ab1 = 0;
    CHECK(save_cache_for_views(s, &rs, NULL, 0, path_a, &records_a));
    CHECK(save_cache_for_views(s, &rs, &b, 1, path_ab, &records_ab));
    rs.threads = 1;
    CHECK(save_cache_for_views(s, &rs, &b, 1, path_ab1, &records_ab1));
    CHECK_MSG(same_file(path_ab, path_ab1), "the cache of views A and B differs between 1 and 2 threads");
    CHECK_MSG(records_ab > records_a, "view B added no record (%u, A alone %u)", records_ab, records_a);

    /* Bad views are refused as a bad camera is, and not after start. */
    phos_render *r = NULL;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_OK);
    phos_camera_desc bad = b;
    bad.frame_max[0] = bad.frame_min[0];
    CHECK(phos_render_add_view(r, &bad) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(strstr(phos_render_error(r), "frame") != NULL, "%s", phos_render_error(r));
    CHECK(phos_render_add_view(r, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_render_add_view(NULL, &b) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK);
    CHECK(phos_render_add_view(r, &b) == PHOS_ERROR_INVALID_STATE);
    phos_render_destroy(r);

    /* Rendered from B: its own pre-pass, A's cache, A and B's cache. */
    CHECK(phos_scene_set_camera(s, &b) == PHOS_OK && phos_scene_commit(s) == PHOS_OK);
    rs.caches_only = 0;
    rs.threads = 0;
    render_out own, from_a, from_ab;
    CHECK(render_with_file(s, &rs, path_a, PHOS_CACHE_FILE_NONE, &own, msg, sizeof(msg)));
    CHECK(render_with_file(s, &rs, path_a, PHOS_CACHE_FILE_LOAD, &from_a, msg, sizeof(msg)));
    CHECK(render_with_file(s, &rs, path_ab, PHOS_CACHE_FILE_LOAD, &from_ab, msg, sizeof(msg)));
    double f_own = (double)own.progress.cache_interpolated / (double)own.progress.cache_lookups,
           f_a = (double)from_a.progress.cache_interpolated / (double)from_a.progress.cache_lookups,
           f_ab = (double)from_ab.progress.cache_interpolated / (double)from_ab.progress.cache_lookups;
    printf("  view B's lookups covered: own pre-pass %.4f, A's cache %.4f, A and B's %.4f (%u, %u records)\n",
           f_own, f_a, f_ab, records_a, records_ab);
    CHECK_MSG(f_ab >= f_own - 0.002, "A and B's cache covers %.4f of B's lookups, B's own %.4f", f_ab, f_own);
    CHECK_MSG(f_a < f_ab - 0.01, "A's cache alone already covers B (%.4f): the test shows nothing", f_a);
    CHECK(from_ab.progress.cache_rays_traced == 0);
    render_out_free(&own);
    render_out_free(&from_a);
    render_out_free(&from_ab);
    remove(path_a);
    remove(path_ab);
    remove(path_ab1);
    phos_scene_destroy(s);
}

/* The photon maps kept in a file: PHOTON with the maps read back renders
 * the image of the render that traced them, bit for bit, and (with the
 * irradiance cache read too) without tracing a photon or casting a
 * pre-pass ray; maps traced with other settings are refused by name. */
static void test_photon_map_file_round_trip(void)
{
    const char *maps_path = "/tmp/phos_test_maps.phospmf", *cache_path = "/tmp/phos_test_maps_cache.phosirc";
    char msg[512];
    phos_scene *s = test_cornell_box(1);
    CHECK(s != NULL);
    if (!s)
        return;
    phos_render_settings rs = cache_settings(PHOS_INTEGRATOR_PHOTON, 40, 4, 3);
    rs.global_photons = rs.caustic_photons = 30000;
    rs.pass_mask = 1u << PHOS_PASS_COMBINED;
    float *img[2] = {NULL, NULL};
    phos_progress pg[2];
    for (int k = 0; k < 2; k++) {
        uint32_t mode = k ? PHOS_CACHE_FILE_LOAD : PHOS_CACHE_FILE_SAVE;
        phos_render *r = NULL;
        CHECK(phos_render_create(s, &rs, &r) == PHOS_OK);
        if (!r)
            break;
        CHECK(phos_render_set_cache_file(r, PHOS_CACHE_PHOTON_MAPS, maps_path, mode) == PHOS_OK);
        CHECK(phos_render_set_cache_file(r, PHOS_CACHE_IRRADIANCE, cache_path, mode) == PHOS_OK);
        CHECK_MSG(phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK, "%s", phos_render_error(r));
        CHECK(phos_render_progress(r, &pg[k]) == PHOS_OK);
        img[k] = calloc((size_t)4 * 40 * 40, sizeof(float));
        CHECK(phos_render_read(r, PHOS_PASS_COMBINED, 0, 0, 40, 40, img[k], (size_t)4 * 40 * 40) == PHOS_OK);
        phos_render_destroy(r);
    }
    if (img[0] && img[1]) {
        CHECK_MSG(memcmp(img[0], img[1], sizeof(float) * 4 * 40 * 40) == 0, "the image from the loaded maps differs");
        CHECK(pg[1].global_photons == pg[0].global_photons && pg[1].caustic_photons == pg[0].caustic_photons);
        CHECK(pg[1].cache_rays_traced == 0 && pg[1].cache_records == pg[0].cache_records);
        printf("  photon maps read back: %u global, %u caustic photons, %u records\n", pg[1].global_photons,
               pg[1].caustic_photons, pg[1].cache_records);
    }
    free(img[0]);
    free(img[1]);
    phos_render_settings rr = rs;
    rr.global_photons = 20000;
    phos_render *r = NULL;
    CHECK(phos_render_create(s, &rr, &r) == PHOS_OK);
    if (r) {
        CHECK(phos_render_set_cache_file(r, PHOS_CACHE_PHOTON_MAPS, maps_path, PHOS_CACHE_FILE_LOAD) == PHOS_OK);
        CHECK(phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) != PHOS_OK);
        CHECK_MSG(strstr(phos_render_error(r), "global_photons") != NULL, "%s", phos_render_error(r));
        phos_render_destroy(r);
    }
    remove(maps_path);
    remove(cache_path);
    phos_scene_destroy(s);
}

int main(void)
{
    test_closed_sphere_analytic();
    test_translational_gradient_matches_finite_differences();
    test_path_with_cache_against_path();
    test_record_counts();
    test_photon_with_cache_against_final_gather();
    test_cache_is_deterministic();
    test_cache_file_round_trip();
    test_photon_map_file_round_trip();
    test_views_fill_the_cache();
    return test_summary("test_irradiance_cache");
}
