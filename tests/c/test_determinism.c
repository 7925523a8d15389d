/*
 * test_determinism.c — the same scene and seed give the same image, bit
 * for bit, whatever the thread count, tile size or render region; another
 * seed gives another image. For PATH (without and with the irradiance
 * cache; with each sampler; with adaptive sampling, whose per-pixel sample
 * counts must not depend on threads or tiles either; with each noise
 * filter) and for PHOTON with each photon view (the photon maps are traced
 * in batches on any number of threads). A frame split into four regions
 * and stitched equals the whole frame (a render farm's split); the photon
 * maps and the irradiance cache, as their files store them, are the same
 * bytes for 1 and 2 threads; and Embree's BVH, built with 1 build thread
 * or with many, returns the same hits (docs/reliability.md).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "scene/embree.h"
#include "scene/scene.h"

#include "test_scenes.h"
#include "test_util.h"

static phos_scene *box_with_spheres(void)
{
    phos_scene *s = phos_scene_create();
    uint32_t quad = test_add_quad_mesh(s, 1.0f);
    uint32_t white = test_add_diffuse(s, 0.7f, 0.7f, 0.7f);
    uint32_t red = test_add_diffuse(s, 0.6f, 0.1f, 0.1f);
    test_add_instance(s, quad, white, 0, 0, 0); /* floor */
    /* A red wall: the quad rotated to face +X at x = −1. */
    phos_instance_desc wall;
    phos_instance_desc_init(&wall);
    float m[12] = {0, 0, 1, -1, 0, 1, 0, 0, -1, 0, 0, 1};
    memcpy(wall.transform, m, sizeof(m));
    wall.mesh_id = quad;
    wall.material_count = 1;
    wall.materials = &red;
    phos_scene_add_instance(s, &wall, NULL);

    uint32_t glass_id = test_add_glass(s, 1.5f);
    uint32_t sphere = test_add_sphere_mesh(s, 0.3f, 32, 16, 0);
    test_add_instance(s, sphere, glass_id, 0.3f, 0.0f, 0.3f);
    test_add_instance(s, sphere, white, -0.4f, 0.2f, 0.3f);

    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_AREA;
    l.position[2] = 1.5f;
    l.axis_u[0] = 0.5f;
    l.axis_v[1] = 0.5f;
    l.color[0] = l.color[1] = l.color[2] = 10.0f;
    phos_scene_add_light(s, &l, NULL);
    test_set_camera_pitched(s, 0.0f, -2.5f, 1.2f, 1.1f, 0.5f);
    return s;
}

/* The integrator, photon view and cache setting of the renders below. */
static uint32_t g_integrator, g_view, g_cache = PHOS_IRRADIANCE_CACHE_PHOTON, g_progressive = 1;
static uint32_t g_sampler = PHOS_SAMPLER_SOBOL, g_adaptive, g_filter, g_progressive_caustics;
static float g_caustic_share = 1.0f;

static float *render_with(phos_scene *s, uint32_t threads, uint32_t tile, uint32_t seed, uint32_t rx, uint32_t ry,
                          uint32_t rw, uint32_t rh)
{
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.integrator = g_integrator;
    rs.photon_view = g_view;
    rs.irradiance_cache = g_cache;
    rs.ic_rays = 64;
    rs.global_photons = 20000;
    rs.caustic_photons = 5000;
    rs.final_gather_rays = 8;
    rs.width = 48;
    rs.height = 40;
    rs.samples = 8;
    rs.threads = threads;
    rs.tile_size = tile;
    rs.seed = seed;
    rs.region_x = rx;
    rs.region_y = ry;
    rs.region_width = rw;
    rs.region_height = rh;
    rs.progressive = g_progressive;
    rs.sampler = g_sampler;
    rs.adaptive_sampling = g_adaptive;
    rs.adaptive_min_samples = 4;
    rs.adaptive_threshold = 0.05f;
    rs.noise_filter = g_filter;
    rs.progressive_caustics = g_progressive_caustics;
    rs.progressive_caustic_photons = 2000;
    rs.caustic_sample_share = g_caustic_share;
    return test_render(s, &rs);
}

/* Same scene and seed, same image: for 1 and 2 threads, any tile size,
 * progressive refinement (8 samples in passes of 1, 1, 2, 4) or one pass,
 * and a border region against the same pixels of the full frame. */
static void check_deterministic(phos_scene *s, const char *name)
{
    const size_t n = 4 * 48 * 40;
    float *a = render_with(s, 1, 16, 7, 0, 0, 0, 0);
    g_progressive = 0;
    float *one_pass = render_with(s, 2, 16, 7, 0, 0, 0, 0);
    g_progressive = 1;
    CHECK_MSG(a && one_pass && memcmp(a, one_pass, n * sizeof(float)) == 0,
              "%s: progressive refinement's image differs from the one-pass render's", name);
    free(one_pass);
    float *b = render_with(s, 2, 8, 7, 0, 0, 0, 0);
    float *c = render_with(s, 2, 64, 7, 0, 0, 0, 0);
    float *d = render_with(s, 2, 16, 8, 0, 0, 0, 0);
    CHECK(a && b && c && d);
    if (a && b && c && d) {
        CHECK_MSG(memcmp(a, b, n * sizeof(float)) == 0, "%s: 1 thread/16px tiles differs from 2 threads/8px tiles",
                  name);
        CHECK_MSG(memcmp(a, c, n * sizeof(float)) == 0, "%s: tile size changes the image", name);
        CHECK_MSG(memcmp(a, d, n * sizeof(float)) != 0, "%s: a different seed gives the same image", name);
        double sum = 0.0;
        for (size_t i = 0; i < n; i++)
            sum += a[i];
        CHECK_MSG(sum > 0.0, "%s: the image is black", name);
    }
    if (g_filter != PHOS_NOISE_FILTER_NONE) {
        /* A filter reads the neighbours a region cuts off: its region's
         * pixels near the edge differ from the full frame's (README). */
        free(a), free(b), free(c), free(d);
        return;
    }
    /* A border region reproduces the same pixels of the full frame. */
    const uint32_t rx = 13, ry = 7, rw = 20, rh = 17;
    float *r = render_with(s, 2, 8, 7, rx, ry, rw, rh);
    CHECK(r != NULL);
    if (a && r) {
        int same = 1;
        for (uint32_t y = 0; y < rh; y++)
            same &= memcmp(r + 4 * (size_t)y * rw, a + 4 * ((size_t)(y + ry) * 48 + rx), 4 * rw * sizeof(float)) == 0;
        CHECK_MSG(same, "%s: region pixels differ from the full frame's", name);
    }
    /* Four regions of uneven size, stitched, give the full frame. */
    const uint32_t sx = 19, sy = 23; /* not multiples of the tile size */
    const uint32_t qx[4] = {0, sx, 0, sx}, qy[4] = {0, 0, sy, sy};
    const uint32_t qw[4] = {sx, 48 - sx, sx, 48 - sx}, qh[4] = {sy, sy, 40 - sy, 40 - sy};
    float *stitched = calloc(n, sizeof(float));
    for (int q = 0; q < 4; q++) {
        float *part = render_with(s, 2, 16, 7, qx[q], qy[q], qw[q], qh[q]);
        CHECK(part != NULL);
        for (uint32_t y = 0; part && y < qh[q]; y++)
            memcpy(stitched + 4 * ((size_t)(y + qy[q]) * 48 + qx[q]), part + 4 * (size_t)y * qw[q],
                   4 * qw[q] * sizeof(float));
        free(part);
    }
    CHECK_MSG(a && memcmp(stitched, a, n * sizeof(float)) == 0, "%s: four stitched regions differ from the frame",
              name);
    free(stitched);
    free(a);
    free(b);
    free(c);
    free(d);
    free(r);
}

/* The settings of the renders whose passes are compared below. */
static void pass_test_settings(phos_render_settings *rs)
{
    phos_render_settings_init(rs);
    rs->integrator = PHOS_INTEGRATOR_PHOTON;
    rs->ic_rays = 64;
    rs->global_photons = 20000;
    rs->caustic_photons = 5000;
    rs->width = 48;
    rs->height = 40;
    rs->threads = 2;
    rs->pass_mask = (1u << PHOS_PASS_COUNT) - 1u;
}

/* Every pass of a finished render, read at full frame (freed by the
 * caller). */
static void read_all_passes(phos_scene *s, const phos_render_settings *rs, float *img[PHOS_PASS_COUNT])
{
    phos_render *r = NULL;
    CHECK(phos_render_create(s, rs, &r) == PHOS_OK);
    CHECK(phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK);
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        size_t count = (size_t)phos_pass_channels(p) * rs->width * rs->height;
        img[p] = malloc(sizeof(float) * count);
        CHECK(phos_render_read(r, p, 0, 0, rs->width, rs->height, img[p], count) == PHOS_OK);
    }
    phos_progress pr;
    CHECK(phos_render_progress(r, &pr) == PHOS_OK);
    CHECK_MSG(pr.samples_done == rs->samples && pr.fraction == 1.0f, "samples done %u of %u, fraction %g",
              pr.samples_done, rs->samples, (double)pr.fraction);
    phos_render_destroy(r);
}

/* Every pass, progressive or in one pass, bit for bit. */
static void check_progressive_passes(phos_scene *s)
{
    phos_render_settings rs;
    pass_test_settings(&rs);
    rs.samples = 6; /* passes end at 1, 2, 4, 6 */
    float *img[2][PHOS_PASS_COUNT];
    for (int k = 0; k < 2; k++) {
        rs.progressive = (uint32_t)k;
        read_all_passes(s, &rs, img[k]);
    }
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        size_t bytes = sizeof(float) * phos_pass_channels(p) * rs.width * rs.height;
        CHECK_MSG(memcmp(img[0][p], img[1][p], bytes) == 0, "pass %u differs between progressive and one pass", p);
        free(img[0][p]);
        free(img[1][p]);
    }
}

/* ------------------------------------------- maps and cache, as files */

static unsigned char *read_file(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    unsigned char *data = malloc(n > 0 ? (size_t)n : 1);
    *size = data ? fread(data, 1, (size_t)n, f) : 0;
    fclose(f);
    return data;
}

/* The photon maps and the irradiance cache a PHOTON render (and a PATH
 * render with the cache on) writes to its files: byte for byte the same
 * whatever the thread count and tile size. */
static void check_caches_identical(phos_scene *s)
{
    static const uint32_t integrators[2] = {PHOS_INTEGRATOR_PHOTON, PHOS_INTEGRATOR_PATH};
    for (int k = 0; k < 2; k++) {
        unsigned char *bytes[2][2] = {{NULL, NULL}, {NULL, NULL}};
        size_t sizes[2][2] = {{0, 0}, {0, 0}};
        for (int t = 0; t < 2; t++) {
            char ic[64], maps[64];
            snprintf(ic, sizeof(ic), "/tmp/phos_test_det_%d_%d.phosirc", (int)getpid(), t);
            snprintf(maps, sizeof(maps), "/tmp/phos_test_det_%d_%d.phospmf", (int)getpid(), t);
            phos_render_settings rs;
            phos_render_settings_init(&rs);
            rs.integrator = integrators[k];
            rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_ALWAYS;
            rs.width = 48;
            rs.height = 40;
            rs.samples = 2;
            rs.ic_rays = 64;
            rs.global_photons = 20000;
            rs.caustic_photons = 5000;
            rs.threads = t ? 2 : 1;
            rs.tile_size = t ? 8 : 32;
            phos_render *r = NULL;
            CHECK(phos_render_create(s, &rs, &r) == PHOS_OK);
            if (!r)
                continue;
            phos_render_set_cache_file(r, PHOS_CACHE_IRRADIANCE, ic, PHOS_CACHE_FILE_SAVE);
            phos_render_set_cache_file(r, PHOS_CACHE_PHOTON_MAPS, maps, PHOS_CACHE_FILE_SAVE);
            CHECK(phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK);
            phos_render_destroy(r);
            bytes[0][t] = read_file(ic, &sizes[0][t]);
            bytes[1][t] = k == 0 ? read_file(maps, &sizes[1][t]) : NULL;
            remove(ic);
            remove(maps);
        }
        for (int f = 0; f < (k == 0 ? 2 : 1); f++) {
            const char *what = f ? "photon maps" : "irradiance cache";
            CHECK_MSG(bytes[f][0] && sizes[f][0] > 64, "%s %s: no file written", k ? "PATH" : "PHOTON", what);
            CHECK_MSG(bytes[f][0] && bytes[f][1] && sizes[f][0] == sizes[f][1] &&
                          memcmp(bytes[f][0], bytes[f][1], sizes[f][0]) == 0,
                      "%s: the %s differ between 1 and 2 threads", k ? "PATH" : "PHOTON", what);
            free(bytes[f][0]);
            free(bytes[f][1]);
        }
    }
}

/* ------------------------------------------------------------ Embree */

/* Embree's high-quality build (spatial splits) runs on its task pool; its
 * documentation promises nothing about the tree being the same from run
 * to run. The hits are what the images depend on: the same rays through
 * BVHs built with one build thread and with the default pool, and built
 * again, must return the same t, primitive and barycentrics. */
static void check_embree_hits(void)
{
    const char *configs[3] = {"threads=1", NULL, NULL};
    ray_hit *hits[3];
    const uint32_t rays = 200000;
    for (int c = 0; c < 3; c++) {
        embree_set_device_config(configs[c]);
        phos_scene *s = box_with_spheres();
        /* Add a dense mesh: a tessellated sphere of many small triangles. */
        uint32_t dense = test_add_sphere_mesh(s, 0.2f, 400, 200, 0);
        test_add_instance(s, dense, 0, 0.0f, 0.4f, 0.6f);
        CHECK(phos_scene_commit(s) == PHOS_OK);
        hits[c] = calloc(rays, sizeof(ray_hit));
        uint64_t state = 12345;
        for (uint32_t i = 0; i < rays; i++) {
            float u[4];
            for (int k = 0; k < 4; k++) {
                state = state * 6364136223846793005ull + 1442695040888963407ull;
                u[k] = (float)(state >> 40) / (float)(1u << 24);
            }
            /* From in front of the box toward a random point inside it. */
            vec3 o = v3(0.0f, -2.0f, 0.6f);
            vec3 d = v3_normalize(v3_sub(v3(2.0f * u[0] - 1.0f, 2.0f * u[1] - 1.0f, u[2]), o));
            if (!embree_intersect(((scene *)s)->bvh, o, d, 0.0f, INFINITY, 0, &hits[c][i]))
                hits[c][i].prim = UINT32_MAX;
        }
        phos_scene_destroy(s);
    }
    embree_set_device_config(NULL);
    uint32_t differ1 = 0, differ2 = 0, hit = 0;
    for (uint32_t i = 0; i < rays; i++) {
        hit += hits[0][i].prim != UINT32_MAX;
        differ1 += memcmp(&hits[0][i], &hits[1][i], sizeof(ray_hit)) != 0;
        differ2 += memcmp(&hits[1][i], &hits[2][i], sizeof(ray_hit)) != 0;
    }
    printf("Embree: %u of %u rays hit; %u differ between 1 build thread and the pool, %u between two pool builds\n",
           hit, rays, differ1, differ2);
    CHECK(hit > rays / 2);
    CHECK_MSG(differ1 == 0 && differ2 == 0, "Embree's BVH changes the hits of %u and %u rays", differ1, differ2);
    for (int c = 0; c < 3; c++)
        free(hits[c]);
}

/* caustic_sample_share (docs/algorithms.md §4.7): with 8 samples and a
 * quarter of them reading the caustic map, each pixel's Caustics are the
 * mean over its first 2 samples, which is what a 2-sample render shows;
 * every other component is the 8 samples' mean, untouched; and Combined
 * is their sum. Rendered in progressive passes (1, 2, 4, 8), so the
 * caustic sums also go through the film between passes. */
static void check_caustic_share(phos_scene *s)
{
    phos_render_settings rs;
    pass_test_settings(&rs);
    rs.caustic_photons = 20000;
    float *quarter[PHOS_PASS_COUNT], *every[PHOS_PASS_COUNT], *two[PHOS_PASS_COUNT];
    rs.samples = 8;
    rs.caustic_sample_share = 0.25f;
    read_all_passes(s, &rs, quarter);
    rs.caustic_sample_share = 1.0f;
    read_all_passes(s, &rs, every);
    rs.samples = 2;
    read_all_passes(s, &rs, two);
    size_t n = 3u * rs.width * rs.height;
    double caustics = 0.0, worst = 0.0;
    for (size_t i = 0; i < n; i++) {
        caustics += quarter[PHOS_PASS_CAUSTICS][i];
        worst = fmax(worst, fabs((double)quarter[PHOS_PASS_CAUSTICS][i] - two[PHOS_PASS_CAUSTICS][i]) /
                                fmax(fabs((double)two[PHOS_PASS_CAUSTICS][i]), 1e-3));
    }
    CHECK_MSG(caustics > 0.0, "the scene's glass sphere casts no caustic: nothing is tested");
    CHECK_MSG(worst < 1e-6, "Caustics of 2 of 8 samples against a 2-sample render: relative difference %g", worst);
    CHECK_MSG(memcmp(quarter[PHOS_PASS_CAUSTICS], every[PHOS_PASS_CAUSTICS], n * sizeof(float)) != 0,
              "the Caustics pass is every sample's");
    static const uint32_t others[] = {PHOS_PASS_EMISSION, PHOS_PASS_DIRECT, PHOS_PASS_SPECULAR, PHOS_PASS_INDIRECT};
    for (size_t k = 0; k < sizeof(others) / sizeof(others[0]); k++)
        CHECK_MSG(memcmp(quarter[others[k]], every[others[k]], n * sizeof(float)) == 0,
                  "pass %u changed with the caustic share", others[k]);
    double combined = 0.0;
    for (size_t px = 0; px < (size_t)rs.width * rs.height; px++)
        for (int c = 0; c < 3; c++) {
            double sum = 0.0;
            for (size_t k = 0; k < sizeof(others) / sizeof(others[0]); k++)
                sum += quarter[others[k]][3 * px + c];
            sum += quarter[PHOS_PASS_CAUSTICS][3 * px + c];
            combined = fmax(combined, fabs(sum - quarter[PHOS_PASS_COMBINED][4 * px + c]) / fmax(fabs(sum), 1e-3));
        }
    CHECK_MSG(combined < 1e-5, "Combined differs from its components' sum by %g", combined);
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        free(quarter[p]);
        free(every[p]);
        free(two[p]);
    }
}

int main(void)
{
    phos_scene *s = box_with_spheres();
    CHECK_MSG(phos_scene_commit(s) == PHOS_OK, "%s", phos_scene_error(s));
    static const struct {
        uint32_t integrator, view, cache;
        const char *name;
    } configs[] = {
        {PHOS_INTEGRATOR_PATH, 0, PHOS_IRRADIANCE_CACHE_OFF, "PATH"},
        {PHOS_INTEGRATOR_PATH, 0, PHOS_IRRADIANCE_CACHE_ALWAYS, "PATH with the irradiance cache"},
        {PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_FINAL_GATHER, PHOS_IRRADIANCE_CACHE_OFF, "PHOTON, final gathering"},
        {PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_FINAL_GATHER, PHOS_IRRADIANCE_CACHE_PHOTON,
         "PHOTON, final gathering with the irradiance cache"},
        {PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_FAST, PHOS_IRRADIANCE_CACHE_PHOTON, "PHOTON, fast estimate"},
        {PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_PATH_TRACED, PHOS_IRRADIANCE_CACHE_PHOTON,
         "PHOTON, path-traced gather with the irradiance cache"},
    };
    for (size_t i = 0; i < sizeof(configs) / sizeof(configs[0]); i++) {
        g_integrator = configs[i].integrator;
        g_view = configs[i].view;
        g_cache = configs[i].cache;
        check_deterministic(s, configs[i].name);
    }
    static const char *sampler_names[] = {"", "PATH, RANDOM", "PATH, STRATIFIED", "PATH, HALTON"};
    g_integrator = PHOS_INTEGRATOR_PATH;
    g_cache = PHOS_IRRADIANCE_CACHE_OFF;
    for (uint32_t k = PHOS_SAMPLER_RANDOM; k <= PHOS_SAMPLER_HALTON; k++) {
        g_sampler = k;
        check_deterministic(s, sampler_names[k]);
    }
    g_sampler = PHOS_SAMPLER_SOBOL;
    g_adaptive = 1;
    check_deterministic(s, "PATH, adaptive sampling");
    g_integrator = PHOS_INTEGRATOR_PHOTON;
    g_cache = PHOS_IRRADIANCE_CACHE_PHOTON;
    check_deterministic(s, "PHOTON, adaptive sampling");
    g_adaptive = 0;
    static const char *filter_names[] = {"", "PHOTON, lowpass", "PHOTON, median", "PHOTON, adaptive width",
                                         "PHOTON, diffusion", "PHOTON, splatting"};
    for (uint32_t f = PHOS_NOISE_FILTER_LOWPASS; f <= PHOS_NOISE_FILTER_SPLATTING; f++) {
        g_filter = f;
        check_deterministic(s, filter_names[f]);
    }
    g_filter = PHOS_NOISE_FILTER_NONE;
    /* Progressive caustics: a caustic map per sample, the same for any
     * thread count, tile order or region; and not the fixed map's image. */
    g_view = PHOS_PHOTON_VIEW_FINAL_GATHER;
    g_progressive_caustics = 1;
    check_deterministic(s, "PHOTON, progressive caustics");
    float *progressive = render_with(s, 2, 16, 7, 0, 0, 0, 0);
    g_progressive_caustics = 0;
    float *fixed = render_with(s, 2, 16, 7, 0, 0, 0, 0);
    CHECK_MSG(progressive && fixed && memcmp(progressive, fixed, 4 * 48 * 40 * sizeof(float)) != 0,
              "progressive caustics render the fixed map's image");
    free(progressive);
    free(fixed);
    /* The caustic map read by a quarter of each pixel's samples (2 of 8),
     * kept apart between the passes of progressive refinement; and not the
     * image of every sample reading it. */
    g_caustic_share = 0.25f;
    check_deterministic(s, "PHOTON, caustics on a quarter of the samples");
    g_adaptive = 1;
    check_deterministic(s, "PHOTON, caustics on a quarter of the samples, adaptive sampling");
    g_adaptive = 0;
    float *shared = render_with(s, 2, 16, 7, 0, 0, 0, 0);
    g_caustic_share = 1.0f;
    fixed = render_with(s, 2, 16, 7, 0, 0, 0, 0);
    CHECK_MSG(shared && fixed && memcmp(shared, fixed, 4 * 48 * 40 * sizeof(float)) != 0,
              "a quarter of the samples reading the caustic map renders every sample's image");
    free(shared);
    free(fixed);
    check_progressive_passes(s);
    check_caustic_share(s);
    check_caches_identical(s);
    phos_scene_destroy(s);
    check_embree_hits();
    return test_summary("test_determinism");
}
