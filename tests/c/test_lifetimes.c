/*
 * test_lifetimes.c — small renders through the public API that walk every
 * allocation's life: a PATH and a PHOTON render (with the irradiance
 * cache, debug passes and both cache files saved and loaded), a render
 * cancelled mid-way, a render destroyed while running, refused settings,
 * a failed and a cancelled commit, scenes shared by two renders. Fast
 * enough for valgrind: `make valgrind` runs this program under memcheck
 * and requires zero errors and zero definitely lost bytes
 * (docs/reliability.md); ctest runs it as a plain test too.
 */
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "test_scenes.h"
#include "test_util.h"

static phos_render_settings small(uint32_t integrator)
{
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.integrator = integrator;
    rs.width = 24;
    rs.height = 16;
    rs.samples = 2;
    rs.global_photons = 2000;
    rs.caustic_photons = 2000;
    rs.ic_rays = 32;
    rs.threads = 2;
    rs.tile_size = 8;
    return rs;
}

static double image_sum(const float *img, size_t n)
{
    double sum = 0.0;
    for (size_t i = 0; i < n; i++)
        sum += img[i];
    return sum;
}

/* A render run to the end, every tile read as it comes, every pass read. */
static void render_whole(phos_scene *s, const phos_render_settings *rs, const char *what, const char *ic_file,
                         const char *maps_file, uint32_t mode)
{
    phos_render *r = NULL;
    CHECK_MSG(phos_render_create(s, rs, &r) == PHOS_OK, "%s: %s", what, phos_scene_error(s));
    if (!r)
        return;
    if (ic_file)
        CHECK(phos_render_set_cache_file(r, PHOS_CACHE_IRRADIANCE, ic_file, mode) == PHOS_OK);
    if (maps_file)
        CHECK(phos_render_set_cache_file(r, PHOS_CACHE_PHOTON_MAPS, maps_file, mode) == PHOS_OK);
    CHECK(phos_render_start(r) == PHOS_OK);
    float tile[4 * 8 * 8];
    uint32_t tiles = 0;
    for (;;) {
        phos_tile t;
        uint32_t count = 0;
        CHECK(phos_render_next_tile(r, &t, &count) == PHOS_OK);
        if (count) {
            CHECK(phos_render_read(r, PHOS_PASS_COMBINED, t.x, t.y, t.width, t.height, tile,
                                   sizeof(tile) / sizeof(float)) == PHOS_OK);
            tiles++;
            continue;
        }
        if (phos_render_wait(r, 0.001) != PHOS_ERROR_TIMEOUT)
            break;
    }
    phos_tile t;
    uint32_t count = 1;
    while (count)
        CHECK(phos_render_next_tile(r, &t, &count) == PHOS_OK && (tiles += count, 1));
    CHECK_MSG(phos_render_wait(r, -1.0) == PHOS_OK, "%s: %s", what, phos_render_error(r));
    CHECK(tiles == 6 * 2); /* 6 tiles, each in both passes of 2 samples (1, then 2) */
    size_t n = 4u * rs->width * rs->height;
    float *img = malloc(sizeof(float) * n);
    for (uint32_t pass = 0; pass < PHOS_PASS_COUNT; pass++) {
        if (!(rs->pass_mask & (1u << pass)))
            continue;
        size_t m = (size_t)phos_pass_channels(pass) * rs->width * rs->height;
        CHECK(phos_render_read(r, pass, 0, 0, rs->width, rs->height, img, m) == PHOS_OK);
        if (pass == PHOS_PASS_COMBINED)
            CHECK_MSG(image_sum(img, m) > 0.0, "%s: black image", what);
    }
    free(img);
    phos_progress p;
    CHECK(phos_render_progress(r, &p) == PHOS_OK && p.state == PHOS_STATE_DONE);
    phos_render_destroy(r);
}

static void test_renders(void)
{
    phos_scene *s = test_cornell_box(1);
    CHECK(s != NULL);
    if (!s)
        return;
    phos_render_settings rs = small(PHOS_INTEGRATOR_PATH);
    render_whole(s, &rs, "PATH", NULL, NULL, PHOS_CACHE_FILE_NONE);
    rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_ALWAYS;
    render_whole(s, &rs, "PATH with the cache", NULL, NULL, PHOS_CACHE_FILE_NONE);

    rs = small(PHOS_INTEGRATOR_PHOTON);
    rs.pass_mask = (1u << PHOS_PASS_COUNT) - 1u; /* every pass, the debug passes too */
    char ic[64], maps[64];
    snprintf(ic, sizeof(ic), "/tmp/phos_test_lifetimes_%d.phosirc", (int)getpid());
    snprintf(maps, sizeof(maps), "/tmp/phos_test_lifetimes_%d.phospmf", (int)getpid());
    render_whole(s, &rs, "PHOTON, saving", ic, maps, PHOS_CACHE_FILE_SAVE);
    render_whole(s, &rs, "PHOTON, loading", ic, maps, PHOS_CACHE_FILE_LOAD);
    remove(ic);
    remove(maps);
    rs.photon_view = PHOS_PHOTON_VIEW_PATH_TRACED;
    render_whole(s, &rs, "PHOTON, path-traced gather", NULL, NULL, PHOS_CACHE_FILE_NONE);
    rs.photon_view = PHOS_PHOTON_VIEW_FAST;
    render_whole(s, &rs, "PHOTON, fast", NULL, NULL, PHOS_CACHE_FILE_NONE);

    /* Two renders of one scene at once, the scene released first. */
    phos_render *a = NULL, *b = NULL;
    rs = small(PHOS_INTEGRATOR_PHOTON);
    CHECK(phos_render_create(s, &rs, &a) == PHOS_OK && phos_render_create(s, &rs, &b) == PHOS_OK);
    phos_scene_destroy(s);
    CHECK(phos_render_start(a) == PHOS_OK && phos_render_start(b) == PHOS_OK);
    CHECK(phos_render_wait(a, -1.0) == PHOS_OK && phos_render_wait(b, -1.0) == PHOS_OK);
    phos_render_destroy(a);
    phos_render_destroy(b);
}

static void test_failures(void)
{
    phos_scene *s = test_cornell_box(1);
    CHECK(s != NULL);
    if (!s)
        return;
    /* Refused settings, and a render that would not fit in memory. */
    phos_render_settings rs = small(PHOS_INTEGRATOR_PHOTON);
    rs.global_estimate_photons = 0;
    phos_render *r = NULL;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_ERROR_INVALID_ARGUMENT && r == NULL);
    rs = small(PHOS_INTEGRATOR_PATH);
    rs.width = rs.height = 65536;
    rs.pass_mask = (1u << PHOS_PASS_COUNT) - 1u;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_ERROR_OUT_OF_MEMORY && r == NULL);
    /* A missing cache file: the render fails with a message. */
    rs = small(PHOS_INTEGRATOR_PHOTON);
    CHECK(phos_render_create(s, &rs, &r) == PHOS_OK);
    CHECK(phos_render_set_cache_file(r, PHOS_CACHE_PHOTON_MAPS, "/nonexistent/maps.phospmf", PHOS_CACHE_FILE_LOAD) ==
          PHOS_OK);
    CHECK(phos_render_start(r) == PHOS_OK);
    CHECK(phos_render_wait(r, -1.0) != PHOS_OK && phos_render_error(r)[0]);
    phos_render_destroy(r);
    /* Cancelled while running, and destroyed while running. */
    rs = small(PHOS_INTEGRATOR_PHOTON);
    rs.samples = 1u << 20;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_OK);
    CHECK(phos_render_start(r) == PHOS_OK);
    CHECK(phos_render_wait(r, 0.05) == PHOS_ERROR_TIMEOUT);
    phos_render_cancel(r);
    CHECK(phos_render_wait(r, -1.0) == PHOS_ERROR_CANCELLED);
    phos_render_destroy(r);
    CHECK(phos_render_create(s, &rs, &r) == PHOS_OK);
    CHECK(phos_render_start(r) == PHOS_OK);
    phos_render_destroy(r);
    phos_scene_destroy(s);

    /* A commit refused, one cancelled, then one that succeeds. */
    s = phos_scene_create();
    float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t idx[3] = {0, 1, 2};
    phos_mesh_desc md;
    phos_mesh_desc_init(&md);
    md.vertex_count = 3;
    md.positions = pos;
    md.triangle_count = 1;
    md.indices = idx;
    uint32_t mesh;
    CHECK(phos_scene_add_mesh(s, &md, &mesh) == PHOS_OK);
    test_add_instance(s, mesh, test_add_diffuse(s, 0.5f, 0.5f, 0.5f), 0, 0, 0);
    phos_scene_cancel(s);
    CHECK(phos_scene_commit(s) == PHOS_ERROR_CANCELLED);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    CHECK(phos_scene_commit(s) == PHOS_ERROR_INVALID_STATE);
    phos_scene_destroy(s);
}

int main(void)
{
    test_renders();
    test_failures();
    return test_summary("test_lifetimes");
}
