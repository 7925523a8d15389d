/*
 * test_environment.c — a world lit by an image (lights/environment.h).
 *
 *  - Direction conventions: the equirectangular and mirror-ball lookups
 *    give the pixel Cycles' formulas name for a direction.
 *  - Sampling: directions drawn from the distribution follow the density
 *    environment_pdf reports (chi-square over the sphere), the density
 *    integrates to 1, draws within a bin stay in it, and the power held by
 *    the bins is the radiance's integral.
 *  - Renders: a diffuse plane under a sky whose radiance changes by row,
 *    one row 200 times brighter than the rest, reflects ρE/π with E the
 *    closed-form irradiance Σ L_row · π (z₁² − z₀²) over the rows above it
 *    (both integrators); a white furnace under an image of ones.
 */
#include <stdio.h>
#include <string.h>

#include "cache/fingerprint.h"
#include "chi2.h"
#include "lights/environment.h"
#include "lights/light.h"
#include "sampling/warp.h"
#include "scene/scene.h"
#include "shading/material.h"
#include "test_scenes.h"
#include "test_util.h"

/* A small deterministic generator for the sampling tests (xorshift64*). */
static uint64_t rng_state = 0x9E3779B97F4A7C15ull;
static float rnd(void)
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (float)((rng_state * 0x2545F4914F6CDD1Dull) >> 40) * 0x1p-24f;
}

static const material *world_material(const phos_scene *s) { return &s->materials[s->world.material]; }

/* ------------------------------------------------------------ conventions */

static void test_directions(void)
{
    /* 4 × 2 pixels, each its own colour: red = column, green = row. */
    float px[4 * 2 * 4];
    for (int y = 0; y < 2; y++)
        for (int x = 0; x < 4; x++) {
            float *p = px + 4 * (y * 4 + x);
            p[0] = (float)x, p[1] = (float)y, p[2] = 1.0f, p[3] = 1.0f;
        }
    phos_scene *s = phos_scene_create();
    test_set_environment(s, px, 4, 2, PHOS_PROJECTION_EQUIRECTANGULAR, PHOS_IMAGE_CLOSEST);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    /* u = ½ − atan2(y, x)/2π, v = ½ + atan2(z, √(x²+y²))/π:
     * (1, −1, √2) is u = 0.625 (column 2), v = 0.75 (row 1, the upper);
     * (−1, 1, −√2) is u = 0.125 (column 0), v = 0.25 (row 0). */
    struct { vec3 d; float column, row; } cases[] = {
        {{1.0f, -1.0f, 1.41421356f}, 2, 1}, {{-1.0f, 1.0f, -1.41421356f}, 0, 0},
        {{0.1f, 1.0f, 0.1f}, 1, 1},    /* about +y: u ≈ 0.266 */
        {{-0.1f, -1.0f, -0.1f}, 3, 0}, /* about −y: u ≈ 0.766 */
    };
    for (size_t k = 0; k < sizeof(cases) / sizeof(cases[0]); k++) {
        vec3 L = material_background(s, world_material(s), v3_normalize(cases[k].d), 0);
        CHECK_MSG(L.x == cases[k].column && L.y == cases[k].row, "equirectangular case %zu: (%g, %g) not (%g, %g)",
                  k, L.x, L.y, cases[k].column, cases[k].row);
    }
    phos_scene_destroy(s);

    /* Mirror ball on a 4 × 4 image: d − (0,1,0) normalised gives the
     * sphere's normal; its x and z, in [−1, 1], address the image. Seen
     * from −y the ball shows the direction back toward the camera at its
     * centre; about +x (normal near (½√2, −½√2, 0)) at u ≈ ½ + ¼√2 ≈ 0.85. */
    float ball[4 * 4 * 4];
    for (int y = 0; y < 4; y++)
        for (int x = 0; x < 4; x++) {
            float *p = ball + 4 * (y * 4 + x);
            p[0] = (float)x, p[1] = (float)y, p[2] = 1.0f, p[3] = 1.0f;
        }
    s = phos_scene_create();
    test_set_environment(s, ball, 4, 4, PHOS_PROJECTION_MIRROR_BALL, PHOS_IMAGE_CLOSEST);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    vec3 L = material_background(s, world_material(s), v3_normalize(v3(1.0f, 0.0f, 0.2f)), 0);
    CHECK_MSG(L.x == 3.0f && L.y == 2.0f, "mirror ball about +x: (%g, %g) not (3, 2)", L.x, L.y);
    L = material_background(s, world_material(s), v3_normalize(v3(0.2f, 0.0f, 1.0f)), 0); /* u ≈ 0.57, v ≈ 0.85 */
    CHECK_MSG(L.x == 2.0f && L.y == 3.0f, "mirror ball about +z: (%g, %g) not (2, 3)", L.x, L.y);
    phos_scene_destroy(s);
}

/* ------------------------------------------------------------- sampling */

/* A 64 × 32 sky: a gradient, and a 3 × 2 pixel "sun" of radiance 500. */
static float *sun_sky(void)
{
    float *px = malloc(sizeof(float) * 64 * 32 * 4);
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 64; x++) {
            float *p = px + 4 * (y * 64 + x);
            float g = 0.05f + 0.5f * (float)y / 31.0f;
            int sun = x >= 40 && x < 43 && y >= 24 && y < 26;
            p[0] = sun ? 500.0f : g, p[1] = sun ? 480.0f : g * 1.1f, p[2] = sun ? 450.0f : g * 1.4f, p[3] = 1.0f;
        }
    return px;
}

#define GRID_Z 16
#define GRID_PHI 32
#define DRAWS 400000

/* Bins of θ (from +z) and φ, unions of the map's cells. */
static int grid_bin(vec3 d)
{
    float phi = atan2f(d.y, d.x);
    if (phi < 0.0f)
        phi += 2.0f * PHOS_PI;
    int iz = (int)(acosf(fminf(fmaxf(d.z, -1.0f), 1.0f)) / PHOS_PI * GRID_Z), ip = (int)(phi / (2.0f * PHOS_PI) * GRID_PHI);
    iz = iz < 0 ? 0 : iz >= GRID_Z ? GRID_Z - 1 : iz;
    ip = ip < 0 ? 0 : ip >= GRID_PHI ? GRID_PHI - 1 : ip;
    return iz * GRID_PHI + ip;
}

static void test_sampling(void)
{
    float *px = sun_sky();
    phos_scene *s = phos_scene_create();
    test_set_environment(s, px, 64, 32, PHOS_PROJECTION_EQUIRECTANGULAR, PHOS_IMAGE_LINEAR);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    environment e;
    int zero = 0;
    CHECK(environment_build(&e, s, world_material(s), 0, 2, &zero) == PHOS_OK && !zero);
    CHECK(e.rows % GRID_Z == 0 && e.columns % GRID_PHI == 0);

    /* Expected counts: within a cell the density times sin θ is constant,
     * so its integral over the cell is that at the centre times Δθ Δφ;
     * the grid's bins are unions of cells. */
    static double expected[GRID_Z * GRID_PHI], observed[GRID_Z * GRID_PHI];
    double extent = 2.0 * PHOS_PI * PHOS_PI / ((double)e.rows * e.columns), total = 0.0;
    for (uint32_t r = 0; r < e.rows; r++)
        for (uint32_t c = 0; c < e.columns; c++) {
            double theta = PHOS_PI * (r + 0.5) / e.rows, phi = 2.0 * PHOS_PI * (c + 0.5) / e.columns;
            vec3 d = v3((float)(sin(theta) * cos(phi)), (float)(sin(theta) * sin(phi)), (float)cos(theta));
            double p = environment_pdf(&e, d) * sin(theta) * extent;
            expected[grid_bin(d)] += p * DRAWS;
            total += p;
        }
    CHECK_MSG(fabs(total - 1.0) < 1e-4, "the density integrates to %g, not 1", total);
    int mismatched = 0;
    for (int i = 0; i < DRAWS; i++) {
        float2 u = {rnd(), rnd()};
        float pdf;
        vec3 d = environment_sample(&e, u, &pdf);
        observed[grid_bin(d)] += 1.0;
        float look = environment_pdf(&e, d);
        mismatched += fabsf(pdf - look) > 1e-3f * look;
    }
    int dof;
    double p = chi2_test(observed, expected, GRID_Z * GRID_PHI, &dof);
    CHECK_MSG(p > 1e-3, "chi-square p = %g (dof %d): the draws do not follow environment_pdf", p, dof);
    CHECK_MSG(mismatched < DRAWS / 1000, "%d draws report a density unlike environment_pdf's", mismatched);

    /* The sun: 6 of 2048 pixels, but most of the power, so most draws. */
    double sun_draws = 0.0;
    for (int i = 0; i < 1000; i++) {
        float2 u = {rnd(), rnd()};
        float pdf;
        vec3 d = environment_sample(&e, u, &pdf);
        sun_draws += v3_average(material_background(s, world_material(s), d, 0)) > 100.0f;
    }
    CHECK_MSG(sun_draws > 500, "only %g of 1000 draws find the sun", sun_draws);

    /* Within a bin: every draw stays in it, with the bin's conditional density. */
    uint32_t bins[] = {0, 9, 27, 63};
    for (size_t k = 0; k < sizeof(bins) / sizeof(bins[0]); k++) {
        int outside = 0, wrong = 0;
        float share = 0.0f;
        for (int i = 0; i < 2000; i++) {
            float2 u = {rnd(), rnd()};
            float pdf;
            vec3 d = environment_sample_in_bin(&e, bins[k], u, &pdf);
            outside += environment_bin_of(d) != bins[k];
            share = environment_pdf(&e, d) / pdf; /* the bin's probability, the same for every draw */
            float again = environment_pdf(&e, d) / share;
            wrong += fabsf(again - pdf) > 1e-3f * pdf;
        }
        CHECK_MSG(outside == 0, "bin %u: %d of 2000 draws outside it", bins[k], outside);
        CHECK_MSG(wrong == 0, "bin %u: %d draws with an inconsistent density", bins[k], wrong);
        (void)share;
    }

    /* The bins' integrals add up to ∫ mean(L) dω, here summed over the image's
     * pixels (each of solid angle Δφ·(sin of its latitudes' difference)). */
    double direct = 0.0;
    for (int y = 0; y < 32; y++) {
        double band = 2.0 * PHOS_PI / 64.0 * (sin(PHOS_PI * ((y + 1) / 32.0 - 0.5)) - sin(PHOS_PI * (y / 32.0 - 0.5)));
        for (int x = 0; x < 64; x++) {
            const float *q = px + 4 * (y * 64 + x);
            direct += band * (q[0] + q[1] + q[2]) / 3.0;
        }
    }
    double bins_sum = 0.0;
    for (int b = 0; b < ENVIRONMENT_BINS * ENVIRONMENT_BINS; b++)
        bins_sum += e.bin_integral[b];
    CHECK_MSG(fabs(bins_sum - direct) < 0.05 * direct, "bins hold %g W/m², the image %g", bins_sum, direct);
    CHECK_MSG(fabs(e.integral - bins_sum) < 1e-3 * bins_sum, "integral %g, bins %g", e.integral, bins_sum);
    environment_free(&e);
    phos_scene_destroy(s);
    free(px);
}

/* --------------------------------------------------------------- renders */

/* Rows of an 8 × 16 sky by latitude: 0.3 + 0.1·row above the horizon, one
 * row (the 13th of 16, latitude 56°–67.5°) at 60, none below. */
static float sky_row(int y) { return y < 8 ? 0.0f : y == 12 ? 60.0f : 0.3f + 0.1f * (float)y; }

static void test_plane_under_sky(uint32_t integrator, const char *name)
{
    float px[8 * 16 * 4];
    double E = 0.0;
    for (int y = 0; y < 16; y++) {
        for (int x = 0; x < 8; x++) {
            float *p = px + 4 * (y * 8 + x);
            p[0] = p[1] = p[2] = sky_row(y);
            p[3] = 1.0f;
        }
        /* Row y spans latitudes π(y/16 − ½) .. π((y+1)/16 − ½); above the
         * horizon ∫ cos θ dω over it is π (z₁² − z₀²), z the sine of latitude. */
        double z0 = sin(PHOS_PI * (y / 16.0 - 0.5)), z1 = sin(PHOS_PI * ((y + 1) / 16.0 - 0.5));
        if (y >= 8)
            E += sky_row(y) * PHOS_PI * (z1 * z1 - z0 * z0);
    }
    phos_scene *s = phos_scene_create();
    uint32_t plane = test_add_quad_mesh(s, 50.0f); /* facing +z, at z = 0 */
    uint32_t mat = test_add_diffuse(s, 0.5f, 0.5f, 0.5f);
    test_add_instance(s, plane, mat, 0, 0, 0);
    test_set_environment(s, px, 8, 16, PHOS_PROJECTION_EQUIRECTANGULAR, PHOS_IMAGE_CLOSEST);
    test_set_camera(s, 0.0f, 0.0f, 2.0f, 0.2f); /* looks straight down (−z) */
    CHECK(phos_scene_commit(s) == PHOS_OK);
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 16;
    rs.samples = 64;
    rs.integrator = integrator;
    float *img = test_render(s, &rs);
    CHECK(img != NULL);
    if (img) {
        double mean, se;
        test_image_stats(img, 16 * 16, 0, &mean, &se);
        double want = 0.5 * E / PHOS_PI;
        CHECK_MSG(fabs(mean - want) < 4.0 * se + 2e-3 * want, "%s: plane under the sky %g, closed form %g (se %g)",
                  name, mean, want, se);
        if (getenv("PHOS_TEST_VERBOSE"))
            printf("%s: %g vs %g, se %g (%.2f %%)\n", name, mean, want, se, 100.0 * se / want);
        free(img);
    }
    phos_scene_destroy(s);
}

static void test_furnace(uint32_t integrator, const char *name)
{
    float ones[16 * 8 * 4];
    for (int i = 0; i < 16 * 8 * 4; i++)
        ones[i] = 1.0f;
    phos_scene *s = phos_scene_create();
    uint32_t mesh = test_add_sphere_mesh(s, 1.0f, 96, 48, 0);
    test_add_instance(s, mesh, test_add_diffuse(s, 0.8f, 0.8f, 0.8f), 0, 0, 0);
    test_set_environment(s, ones, 16, 8, PHOS_PROJECTION_EQUIRECTANGULAR, PHOS_IMAGE_LINEAR);
    test_set_camera(s, 0, 0, 4, 0.05f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    CHECK(s->materials[s->world.material].has_program); /* the map path, not the constant world */
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 16;
    rs.samples = 64;
    rs.max_bounces = 16;
    rs.integrator = integrator;
    float *img = test_render(s, &rs);
    CHECK(img != NULL);
    if (img) {
        double mean, se;
        test_image_stats(img, 16 * 16, 0, &mean, &se);
        CHECK_MSG(fabs(mean - 0.8) < 4.0 * se + 4e-3, "%s: white furnace %g, not 0.8 (se %g)", name, mean, se);
        free(img);
    }
    phos_scene_destroy(s);
}

/* A 16K map is sampled on a bounded grid (the memory its distribution
 * takes is environment_bytes of it), a small one at a quarter pixel per
 * cell, a world without an image on the default grid. */
static void test_resolution_bounds(void)
{
    phos_scene *s = phos_scene_create();
    float px[4] = {1, 1, 1, 1};
    test_set_environment(s, px, 1, 1, PHOS_PROJECTION_EQUIRECTANGULAR, PHOS_IMAGE_LINEAR);
    material *m = &s->materials[s->world.material];
    image *img = &s->images[0];
    struct { uint32_t w, h, rows, columns; } cases[] = {
        {16384, 8192, ENVIRONMENT_MAX_ROWS, ENVIRONMENT_MAX_COLUMNS}, {1024, 512, 1024, 2048},
        {100, 50, 104, 200}, {1, 1, 64, 128}};
    for (size_t k = 0; k < sizeof(cases) / sizeof(cases[0]); k++) {
        img->width = cases[k].w, img->height = cases[k].h; /* only the size is read */
        uint32_t rows, columns;
        environment_resolution(s, m, &rows, &columns);
        CHECK_MSG(rows == cases[k].rows && columns == cases[k].columns, "%ux%u map: %ux%u cells, not %ux%u",
                  cases[k].w, cases[k].h, columns, rows, cases[k].columns, cases[k].rows);
    }
    size_t most = environment_bytes(ENVIRONMENT_MAX_ROWS, ENVIRONMENT_MAX_COLUMNS);
    CHECK_MSG(most < (64u << 20), "the largest map's distribution takes %zu bytes", most);
    img->width = img->height = 1;
    phos_scene_destroy(s);
}

/* Cache files are keyed by the scene's fingerprint: one pixel of the
 * environment changed must change it, not only the image's name or size. */
static void test_fingerprint_reads_pixels(void)
{
    float px[8 * 4 * 4];
    for (int i = 0; i < 8 * 4 * 4; i++)
        px[i] = 0.5f;
    scene_fingerprint f[2];
    for (int k = 0; k < 2; k++) {
        phos_scene *s = phos_scene_create();
        px[4 * 13 + 1] = k ? 0.75f : 0.5f;
        test_set_environment(s, px, 8, 4, PHOS_PROJECTION_EQUIRECTANGULAR, PHOS_IMAGE_LINEAR);
        f[k] = scene_fingerprint_of(s);
        phos_scene_destroy(s);
    }
    CHECK_MSG(f[0].materials != f[1].materials || f[0].lights != f[1].lights,
              "one pixel of the environment changed, the fingerprint did not");
}

/* A closed room (2 m cube) lit only through a skylight (0.6 m square in
 * the ceiling) by a world: with a portal over the skylight the floor's
 * light samples go through the opening, so PATH's image is the same (its
 * mean within the noise) and its pixel variance far lower. Under both a
 * uniform world and an HDR-like sky with a bright patch. */
static phos_scene *skylit_room(int portal, int sky)
{
    static const float room[][4][3] = {
        {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}},        /* floor */
        {{-1, -1, 0}, {-1, 1, 0}, {-1, 1, 2}, {-1, -1, 2}},      /* walls */
        {{1, -1, 0}, {1, -1, 2}, {1, 1, 2}, {1, 1, 0}},
        {{-1, -1, 0}, {-1, -1, 2}, {1, -1, 2}, {1, -1, 0}},
        {{-1, 1, 0}, {1, 1, 0}, {1, 1, 2}, {-1, 1, 2}},
        {{-1, -1, 2}, {-1, 1, 2}, {-0.3f, 1, 2}, {-0.3f, -1, 2}}, /* the ceiling around the skylight */
        {{0.3f, -1, 2}, {0.3f, 1, 2}, {1, 1, 2}, {1, -1, 2}},
        {{-0.3f, -1, 2}, {-0.3f, -0.3f, 2}, {0.3f, -0.3f, 2}, {0.3f, -1, 2}},
        {{-0.3f, 0.3f, 2}, {-0.3f, 1, 2}, {0.3f, 1, 2}, {0.3f, 0.3f, 2}},
    };
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_quads(s, room, 9), test_add_diffuse(s, 0.6f, 0.6f, 0.6f), 0, 0, 0);
    if (portal) {
        phos_light_desc l;
        phos_light_desc_init(&l);
        l.type = PHOS_LIGHT_PORTAL;
        l.position[2] = 2.0f;
        l.direction[2] = -1.0f;
        l.axis_u[0] = 0.6f, l.axis_v[1] = 0.6f;
        CHECK(phos_scene_add_light(s, &l, NULL) == PHOS_OK);
    }
    if (sky) {
        test_set_sky_with_patch(s, 0.5f, 40.0f, 13, 14, 18);
    } else {
        phos_world_desc w;
        phos_world_desc_init(&w);
        w.color[0] = w.color[1] = w.color[2] = 1.0f;
        phos_scene_set_world(s, &w);
    }
    test_set_camera(s, 0.0f, 0.0f, 1.9f, 0.9f); /* looks down at the floor */
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

static void test_portal_interior(int sky)
{
    double mean[2], var[2], se[2];
    for (int portal = 0; portal < 2; portal++) {
        phos_scene *s = skylit_room(portal, sky);
        phos_render_settings rs;
        phos_render_settings_init(&rs);
        rs.width = rs.height = 24;
        rs.samples = 32;
        rs.max_bounces = 4;
        rs.integrator = PHOS_INTEGRATOR_PATH;
        rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_OFF;
        float *a = test_render(s, &rs);
        rs.seed = 1;
        float *b = test_render(s, &rs);
        CHECK(a && b);
        if (a && b) {
            double m = 0.0, v = 0.0;
            for (int i = 0; i < 24 * 24; i++) {
                m += 0.5 * (a[4 * i] + b[4 * i]);
                v += 0.5 * (a[4 * i] - b[4 * i]) * (a[4 * i] - b[4 * i]);
            }
            mean[portal] = m / (24 * 24);
            var[portal] = v / (24 * 24);
            se[portal] = sqrt(var[portal] / (2.0 * 24 * 24));
        }
        free(a);
        free(b);
        phos_scene_destroy(s);
    }
    printf("  skylit room%s: mean %.4f ± %.4f without a portal, %.4f ± %.4f with; pixel variance %.3g → %.3g\n",
           sky ? " under a sky" : "", mean[0], se[0], mean[1], se[1], var[0], var[1]);
    CHECK_MSG(fabs(mean[1] - mean[0]) < 4.0 * sqrt(se[0] * se[0] + se[1] * se[1]),
              "the portal changed the image: %.4f vs %.4f", mean[1], mean[0]);
    CHECK_MSG(var[1] < 0.5 * var[0], "the portal did not lower the noise: variance %.3g vs %.3g", var[1], var[0]);
}

/* The environment's photons in the global map (docs/algorithms.md §11):
 * the skylit room under the sky with a bright patch, the global map read
 * straight at the first diffuse hit (PHOTON's fast view), where its bias
 * shows most: the room's corners and the light pool under the opening.
 * Against PATH at 2048 samples, PHOTON's per-pixel RMS error (the
 * reference's own noise taken out in quadrature) must fall as global
 * photons grow, and the mean come within 4 standard errors of both
 * renders' noise at the largest count. */
static void test_global_map_under_sky(void)
{
    enum { W = 24, N = W * W };
    phos_scene *s = skylit_room(1, 1);
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = W;
    rs.max_bounces = 4;
    rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_OFF;
    rs.integrator = PHOS_INTEGRATOR_PATH;
    rs.samples = 2048;
    float *ref = test_render(s, &rs);
    rs.seed = 1;
    float *ref2 = test_render(s, &rs);
    CHECK(ref && ref2);
    if (!ref || !ref2)
        return;
    double ref_mean = 0.5 * (test_mean_rgb(ref, 4, N) + test_mean_rgb(ref2, 4, N));
    double ref_noise = test_rms_difference(ref, ref2, 4, N) / sqrt(2.0);
    double se_ref = ref_noise / sqrt(2.0 * N); /* pixel noise is independent: the mean's */
    printf("  global map under a sky: PATH %.4f (± %.4f), per-pixel noise %.4f\n", ref_mean, se_ref, ref_noise);
    const uint32_t photons[] = {10000, 80000, 640000};
    double rmse[3], mean_err = 0.0, limit = 0.0;
    for (int i = 0; i < 3; i++) {
        rs.integrator = PHOS_INTEGRATOR_PHOTON;
        rs.photon_view = PHOS_PHOTON_VIEW_FAST;
        rs.samples = 64;
        rs.global_photons = photons[i];
        rs.seed = 0;
        float *a = test_render(s, &rs);
        rs.seed = 1;
        float *b = test_render(s, &rs);
        CHECK(a && b);
        if (!a || !b)
            return;
        double m = 0.5 * (test_mean_rgb(a, 4, N) + test_mean_rgb(b, 4, N));
        double se = test_rms_difference(a, b, 4, N) / sqrt(2.0) / sqrt(2.0 * N);
        double d = test_rms_difference(a, ref, 4, N);
        rmse[i] = sqrt(fmax(d * d - ref_noise * ref_noise, 0.0));
        mean_err = m - ref_mean;
        limit = 4.0 * sqrt(se * se + se_ref * se_ref);
        printf("    PHOTON (fast view), %6u global photons: %.4f, mean error %+.2f %% (noise limit %.2f %%), "
               "per-pixel RMS error %.4f\n", photons[i], m, 100.0 * mean_err / ref_mean, 100.0 * limit / ref_mean,
               rmse[i]);
        free(a);
        free(b);
    }
    CHECK_MSG(rmse[2] < 0.7 * rmse[0], "global map under a sky: the per-pixel error did not fall (%.4f → %.4f)",
              rmse[0], rmse[2]);
    CHECK_MSG(fabs(mean_err) < limit, "global map under a sky: mean error %.4f at the most photons (limit %.4f)",
              mean_err, limit);
    free(ref);
    free(ref2);
    phos_scene_destroy(s);
}

/* A world of no power (an image of zeros, through the map path): it stays
 * in the light table for the camera, is never picked and emits no photons,
 * and the photon passes' pilots, which visit every distant light's planes,
 * draw nothing from its empty map (found by the fuzzer). */
static void test_world_of_no_power(void)
{
    float black[8 * 4 * 4] = {0};
    for (int i = 3; i < 8 * 4 * 4; i += 4)
        black[i] = 1.0f;
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_quad_mesh(s, 2.0f), test_add_diffuse(s, 0.5f, 0.5f, 0.5f), 0, 0, 0);
    test_set_environment(s, black, 8, 4, PHOS_PROJECTION_EQUIRECTANGULAR, PHOS_IMAGE_LINEAR);
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.position[2] = 1.0f;
    l.color[0] = l.color[1] = l.color[2] = 1.0f;
    phos_scene_add_light(s, &l, NULL);
    test_set_camera(s, 0.0f, 0.0f, 2.0f, 0.5f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    CHECK(s->lights.env && !s->lights.env->weight && light_power(&s->lights.lights[s->lights.world], 1.0f) == 0.0f);
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 8;
    rs.samples = 4;
    rs.integrator = PHOS_INTEGRATOR_PHOTON;
    rs.global_photons = rs.caustic_photons = 2000;
    float *img = test_render(s, &rs);
    CHECK(img != NULL);
    free(img);
    phos_scene_destroy(s);
}

int main(void)
{
    test_world_of_no_power();
    test_portal_interior(0);
    test_portal_interior(1);
    test_fingerprint_reads_pixels();
    test_resolution_bounds();
    test_directions();
    test_sampling();
    test_plane_under_sky(PHOS_INTEGRATOR_PATH, "PATH");
    test_plane_under_sky(PHOS_INTEGRATOR_PHOTON, "PHOTON");
    test_furnace(PHOS_INTEGRATOR_PATH, "PATH");
    test_furnace(PHOS_INTEGRATOR_PHOTON, "PHOTON");
    test_global_map_under_sky();
    return test_summary("test_environment");
}
