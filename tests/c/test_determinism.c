/*
 * test_determinism.c — the same scene and seed give the same image, bit
 * for bit, whatever the thread count, tile size or render region; another
 * seed gives another image. For PATH and for PHOTON with each photon view
 * (the photon maps are traced in batches on any number of threads).
 */
#include <stdio.h>
#include <string.h>

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

/* The integrator and photon view of the renders below. */
static uint32_t g_integrator, g_view;

static float *render_with(phos_scene *s, uint32_t threads, uint32_t tile, uint32_t seed, uint32_t rx, uint32_t ry,
                          uint32_t rw, uint32_t rh)
{
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.integrator = g_integrator;
    rs.photon_view = g_view;
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
    return test_render(s, &rs);
}

/* Same scene and seed, same image: for 1 and 2 threads, any tile size, and
 * a border region against the same pixels of the full frame. */
static void check_deterministic(phos_scene *s, const char *name)
{
    const size_t n = 4 * 48 * 40;
    float *a = render_with(s, 1, 16, 7, 0, 0, 0, 0);
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
    free(a);
    free(b);
    free(c);
    free(d);
    free(r);
}

int main(void)
{
    phos_scene *s = box_with_spheres();
    CHECK_MSG(phos_scene_commit(s) == PHOS_OK, "%s", phos_scene_error(s));
    static const struct {
        uint32_t integrator, view;
        const char *name;
    } configs[] = {
        {PHOS_INTEGRATOR_PATH, 0, "PATH"},
        {PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_FINAL_GATHER, "PHOTON, final gathering"},
        {PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_FAST, "PHOTON, fast estimate"},
        {PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_PATH_TRACED, "PHOTON, path-traced gather"},
    };
    for (size_t i = 0; i < sizeof(configs) / sizeof(configs[0]); i++) {
        g_integrator = configs[i].integrator;
        g_view = configs[i].view;
        check_deterministic(s, configs[i].name);
    }
    phos_scene_destroy(s);
    return test_summary("test_determinism");
}
