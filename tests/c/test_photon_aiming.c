/*
 * test_photon_aiming.c — global photons from lamps aimed at what they can
 * land on (projection_map_build_global; docs/algorithms.md §3.1), shown
 * unbiased and worth it:
 *  - on an open scene (a cube on nothing) lit by a point lamp, a spot, an
 *    area lamp and an emissive plane in turn, and with the cube on a floor, the power the
 *    global map stores equals the unaimed map's within 4 standard errors,
 *    direct and all bounces, while far more of the emitted paths store a
 *    photon (the yield);
 *  - in a closed scene (a lamp inside a sphere), and under a spot whose
 *    cone lies inside the ceiling's (aiming would spread its photons over
 *    more directions than the spot does: 5 times the paths), nothing is
 *    aimed, and the map is the unaimed one bit for bit;
 *  - a spot that lights nothing ends its map early, short, and says so
 *    (photon_maps.short_maps);
 *  - with a camera, a lamp's cones are weighed by pilot photons toward
 *    what the camera reads: between a cube in view and one out of it, the
 *    cube in view gets a larger share of the photons than without a
 *    camera, each cube's power is unchanged within noise, and the maps
 *    are the same for 1 and 2 threads;
 *  - a global map that no gather from what the camera sees would read (a
 *    cube on nothing) is not traced, while a cube on a floor gets its map;
 *    a render without one is PATH's image within noise, and so is a view
 *    whose gathers do find surfaces rendered with the empty map of
 *    another view loaded from its file (its gathers path-trace: read from
 *    the empty map, the inside of a closed box is 35 % too dark).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "photons/photon_trace.h"
#include "scene/scene.h"
#include "test_scenes.h"
#include "test_util.h"

static photon_trace_settings trace_settings(uint32_t global, uint32_t unaimed)
{
    photon_trace_settings ps;
    memset(&ps, 0, sizeof(ps));
    ps.global_photons = global;
    ps.max_emitted = 50000000;
    ps.max_bounces = 8;
    ps.seed = 5;
    ps.threads = 2;
    ps.radiance_k = 50;
    ps.max_radius = 1.0f;
    ps.unaimed = unaimed;
    return ps;
}

/* A unit cube centred at (0, 0, 0.5), faces outward. */
static uint32_t add_cube(phos_scene *s)
{
    const float a = 0.5f;
    float q[6][4][3] = {
        {{-a, -a, 0}, {-a, a, 0}, {a, a, 0}, {a, -a, 0}},             /* bottom, −z */
        {{-a, -a, 1}, {a, -a, 1}, {a, a, 1}, {-a, a, 1}},             /* top, +z */
        {{-a, -a, 0}, {a, -a, 0}, {a, -a, 1}, {-a, -a, 1}},           /* front, −y */
        {{-a, a, 0}, {-a, a, 1}, {a, a, 1}, {a, a, 0}},               /* back, +y */
        {{-a, -a, 0}, {-a, -a, 1}, {-a, a, 1}, {-a, a, 0}},           /* left, −x */
        {{a, -a, 0}, {a, a, 0}, {a, a, 1}, {a, -a, 1}},               /* right, +x */
    };
    return test_add_quads(s, (const float(*)[4][3])q, 6);
}

enum lamp { LAMP_POINT, LAMP_SPOT, LAMP_AREA, LAMP_SPOT_AWAY, LAMP_MESH };

/* A 0.4 m square emissive mesh (both faces) at height 3, tilted toward the cube. */
static void add_mesh_lamp(phos_scene *s)
{
    phos_closure_desc c;
    phos_closure_desc_init(&c);
    c.type = PHOS_CLOSURE_EMISSION;
    c.weight[0] = c.weight[1] = c.weight[2] = 50.0f;
    uint32_t glow = test_add_closure_material(s, &c);
    float q[1][4][3] = {{{1.8f, -1.2f, 3.0f}, {2.2f, -1.2f, 3.1f}, {2.2f, -0.8f, 3.1f}, {1.8f, -0.8f, 3.0f}}};
    test_add_instance(s, test_add_quads(s, (const float(*)[4][3])q, 1), glow, 0, 0, 0);
}

static void add_lamp(phos_scene *s, enum lamp kind)
{
    if (kind == LAMP_MESH) {
        add_mesh_lamp(s);
        return;
    }
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.color[0] = l.color[1] = l.color[2] = 50.0f;
    l.position[0] = 2.0f, l.position[1] = -1.0f, l.position[2] = 3.0f;
    float to_cube[3] = {-2.0f, 1.0f, -2.5f};
    float len = sqrtf(to_cube[0] * to_cube[0] + to_cube[1] * to_cube[1] + to_cube[2] * to_cube[2]);
    for (int k = 0; k < 3; k++)
        l.direction[k] = (kind == LAMP_SPOT_AWAY ? -1.0f : 1.0f) * to_cube[k] / len;
    switch (kind) {
    case LAMP_POINT: l.type = PHOS_LIGHT_POINT, l.radius = 0.1f; break;
    case LAMP_SPOT:
    case LAMP_SPOT_AWAY: l.type = PHOS_LIGHT_SPOT, l.radius = 0.1f, l.spot_angle = 1.2f, l.spot_blend = 0.2f; break;
    case LAMP_MESH: break;
    case LAMP_AREA:
        l.type = PHOS_LIGHT_AREA;
        l.position[0] = 0.0f, l.position[1] = 0.0f, l.position[2] = 3.0f;
        l.direction[0] = 0.0f, l.direction[1] = 0.0f, l.direction[2] = -1.0f;
        l.axis_u[0] = 0.5f, l.axis_v[1] = 0.5f;
        break;
    }
    phos_scene_add_light(s, &l, NULL);
}

static phos_scene *cube_scene(enum lamp kind, int floor)
{
    phos_scene *s = phos_scene_create();
    uint32_t grey = test_add_diffuse(s, 0.6f, 0.6f, 0.6f);
    test_add_instance(s, add_cube(s), grey, 0, 0, 0);
    if (floor)
        test_add_instance(s, test_add_quad_mesh(s, 5.0f), grey, 0, 0, -0.001f);
    add_lamp(s, kind);
    test_set_camera_pitched(s, 0.0f, -6.0f, 3.0f, 0.45f, 0.5f);
    if (phos_scene_commit(s) != PHOS_OK) {
        phos_scene_destroy(s);
        return NULL;
    }
    return s;
}

/* Σ of the stored photons' power (RGB mean), direct (0) and all (1), with
 * standard errors (photons as independent draws). */
static void map_power(const photon_map *m, double sum[2], double se[2])
{
    double sum2[2] = {0.0, 0.0};
    sum[0] = sum[1] = 0.0;
    for (uint32_t k = 0; k < m->count; k++) {
        double w = v3_average(photon_power(&m->photons[k]));
        int direct = photon_is_direct(&m->photons[k]);
        sum[1] += w, sum2[1] += w * w;
        if (direct)
            sum[0] += w, sum2[0] += w * w;
    }
    se[0] = sqrt(sum2[0]), se[1] = sqrt(sum2[1]);
}

static uint32_t g_threads = 2;

static int trace(phos_scene *ps_scene, uint32_t photons, uint32_t unaimed, photon_maps *m)
{
    photon_trace_settings ps = trace_settings(photons, unaimed);
    ps.threads = g_threads;
    photon_maps_init(m);
    atomic_int cancel = 0;
    return photon_maps_trace((const scene *)ps_scene, &ps, m, &cancel, NULL) == PHOS_OK;
}

static void check_unbiased_and_worth_it(enum lamp kind, int floor, const char *name, double min_gain)
{
    phos_scene *s = cube_scene(kind, floor);
    CHECK(s != NULL);
    if (!s)
        return;
    photon_maps m[2];
    double sum[2][2], se[2][2], yield[2];
    for (int unaimed = 0; unaimed < 2; unaimed++) {
        CHECK(trace(s, 200000, (uint32_t)unaimed, &m[unaimed]));
        map_power(&m[unaimed].global, sum[unaimed], se[unaimed]);
        yield[unaimed] = (double)m[unaimed].global.count / (double)m[unaimed].global_emitted;
    }
    printf("%s: stored power aimed %.4f W (± %.4f), unaimed %.4f W (± %.4f); yield %.1f %% aimed, %.1f %% unaimed\n",
           name, sum[0][1], se[0][1], sum[1][1], se[1][1], 100.0 * yield[0], 100.0 * yield[1]);
    for (int d = 0; d < 2; d++) {
        double tol = 4.0 * sqrt(se[0][d] * se[0][d] + se[1][d] * se[1][d]);
        CHECK_MSG(fabs(sum[0][d] - sum[1][d]) < tol, "%s: %s power aimed %.4f, unaimed %.4f (± %.4f)", name,
                  d ? "all" : "direct", sum[0][d], sum[1][d], tol);
    }
    CHECK_MSG(yield[0] > min_gain * yield[1], "%s: yield %.2f %% aimed, %.2f %% unaimed", name, 100.0 * yield[0],
              100.0 * yield[1]);
    photon_maps_free(&m[0]);
    photon_maps_free(&m[1]);
    phos_scene_destroy(s);
}

/* Nothing to aim, and the map is the unaimed one bit for bit: a lamp
 * inside a closed sphere (every direction lands), and a spot under a
 * ceiling and over a floor (its cone inside the ceiling's). */
static void check_unaimed_where_nothing_gains(int spot)
{
    phos_scene *s = phos_scene_create();
    uint32_t grey = test_add_diffuse(s, 0.5f, 0.5f, 0.5f);
    if (spot) {
        test_add_instance(s, test_add_quad_mesh(s, 3.0f), grey, 0, 0, 0);
        test_add_ceiling(s, 3.0f, 2.0f, grey);
    } else {
        test_add_instance(s, test_add_sphere_mesh(s, 2.0f, 32, 16, 1), grey, 0, 0, 0);
    }
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.color[0] = l.color[1] = l.color[2] = 10.0f;
    if (spot) {
        l.type = PHOS_LIGHT_SPOT;
        l.position[2] = 1.0f;
        l.direction[2] = 1.0f;
        l.spot_angle = 1.6f;
    }
    phos_scene_add_light(s, &l, NULL);
    test_set_camera(s, 0.0f, 0.0f, 1.0f, 0.5f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    photon_maps a, b;
    CHECK(trace(s, 20000, 0, &a) && trace(s, 20000, 1, &b));
    CHECK_MSG(a.global.count == b.global.count && a.global_emitted == b.global_emitted &&
                  memcmp(a.global.photons, b.global.photons, sizeof(photon) * a.global.count) == 0,
              "%s: the aimed map differs from the unaimed one", spot ? "spot under a ceiling" : "closed sphere");
    photon_maps_free(&a);
    photon_maps_free(&b);
    phos_scene_destroy(s);
}

/* A spot turned away from the cube lights nothing: the pass stops at its
 * probe, short, rather than emitting the 50 M paths the cap allows. */
static void check_hopeless_map_stops(void)
{
    phos_scene *s = cube_scene(LAMP_SPOT_AWAY, 0);
    CHECK(s != NULL);
    if (!s)
        return;
    photon_maps m;
    CHECK(trace(s, 200000, 0, &m));
    printf("spot turned away: %u photons from %llu paths, short maps 0x%x\n", m.global.count,
           (unsigned long long)m.global_emitted, m.short_maps);
    CHECK(m.global_emitted < 10000000u);
    CHECK(m.short_maps == (1u << PHOS_MAP_GLOBAL));
    photon_maps_free(&m);
    phos_scene_destroy(s);
}

/* Power (RGB mean) and count of the global map's photons with x below
 * (side 0) or above (side 1) a plane x = split. */
static void side_power(const photon_map *m, float split, double sum[2], double se[2], uint32_t n[2])
{
    double sum2[2] = {0.0, 0.0};
    sum[0] = sum[1] = 0.0;
    n[0] = n[1] = 0;
    for (uint32_t k = 0; k < m->count; k++) {
        int side = photon_position(&m->photons[k]).x > split;
        double w = v3_average(photon_power(&m->photons[k]));
        sum[side] += w, sum2[side] += w * w, n[side]++;
    }
    se[0] = sqrt(sum2[0]), se[1] = sqrt(sum2[1]);
}

static void check_cones_weighed_by_the_camera(void)
{
    double sum[2][2], se[2][2];
    uint32_t n[2][2];
    for (int camera = 0; camera < 3; camera++) { /* 2: with the camera again, on 1 thread */
        phos_scene *s = phos_scene_create();
        uint32_t grey = test_add_diffuse(s, 0.6f, 0.6f, 0.6f), cube = add_cube(s);
        test_add_instance(s, cube, grey, 0.0f, 0.0f, 0.0f); /* in view */
        test_add_instance(s, cube, grey, 5.0f, 0.0f, 0.0f); /* out of view, behind a wall */
        float wall[1][4][3] = {{{2.5f, -2.0f, 0.0f}, {2.5f, 2.0f, 0.0f}, {2.5f, 2.0f, 1.5f}, {2.5f, -2.0f, 1.5f}}};
        test_add_instance(s, test_add_quads(s, (const float(*)[4][3])wall, 1), grey, 0, 0, 0);
        phos_light_desc l;
        phos_light_desc_init(&l);
        l.color[0] = l.color[1] = l.color[2] = 50.0f;
        l.position[0] = 2.5f;
        l.position[2] = 3.0f;
        phos_scene_add_light(s, &l, NULL);
        if (camera) /* looking at the first cube; the wall hides the second from it and from its gathers */
            test_set_camera_pitched(s, 0.0f, -4.0f, 1.5f, 1.33f, 0.3f);
        CHECK(phos_scene_commit(s) == PHOS_OK);
        photon_maps m;
        static photon_maps two_threads;
        g_threads = camera == 2 ? 1u : 2u;
        CHECK(trace(s, 100000, 0, &m));
        g_threads = 2;
        if (camera < 2)
            side_power(&m.global, 2.5f, sum[camera], se[camera], n[camera]);
        if (camera == 1) {
            two_threads = m;
        } else if (camera == 2) {
            /* Pilots and paths are per item: the same maps on any thread count. */
            CHECK_MSG(m.global.count == two_threads.global.count && m.global_emitted == two_threads.global_emitted &&
                          memcmp(m.global.photons, two_threads.global.photons, sizeof(photon) * m.global.count) == 0,
                      "camera-weighed maps differ between 1 and 2 threads");
            photon_maps_free(&two_threads);
        }
        if (camera != 1)
            photon_maps_free(&m);
        phos_scene_destroy(s);
    }
    double share[2] = {(double)n[0][0] / (n[0][0] + n[0][1]), (double)n[1][0] / (n[1][0] + n[1][1])};
    printf("two cubes: the one in view holds %.1f %% of the photons without a camera, %.1f %% with; its power "
           "%.4f W (± %.4f) and %.4f W (± %.4f)\n", 100.0 * share[0], 100.0 * share[1], sum[0][0], se[0][0], sum[1][0],
           se[1][0]);
    CHECK_MSG(share[1] > 1.3 * share[0], "the camera's cube holds %.1f %% of the photons with a camera, %.1f %% without",
              100.0 * share[1], 100.0 * share[0]);
    for (int side = 0; side < 2; side++) {
        double tol = 4.0 * sqrt(se[0][side] * se[0][side] + se[1][side] * se[1][side]);
        CHECK_MSG(fabs(sum[1][side] - sum[0][side]) < tol, "cube %d: %.4f W with a camera, %.4f W without (± %.4f)",
                  side, sum[1][side], sum[0][side], tol);
    }
}

/* ------------------------------------------------ a map nothing reads */

/* A closed 2 m box of albedo 0.5 with a lamp inside and a lamp outside.
 * View A, from outside, sees only its outer faces, whose gathers all leave
 * for the empty world: nothing would read a global photon. View B, from
 * inside, sees walls lit by many bounces, which the gathers bring: what a
 * global map would hold. */
static phos_scene *closed_box(int view_b)
{
    phos_scene *s = phos_scene_create();
    uint32_t grey = test_add_diffuse(s, 0.5f, 0.5f, 0.5f);
    const float a = 1.0f;
    float q[6][4][3] = {
        {{-a, -a, -a}, {-a, a, -a}, {a, a, -a}, {a, -a, -a}}, {{-a, -a, a}, {a, -a, a}, {a, a, a}, {-a, a, a}},
        {{-a, -a, -a}, {a, -a, -a}, {a, -a, a}, {-a, -a, a}}, {{-a, a, -a}, {-a, a, a}, {a, a, a}, {a, a, -a}},
        {{-a, -a, -a}, {-a, -a, a}, {-a, a, a}, {-a, a, -a}}, {{a, -a, -a}, {a, a, -a}, {a, a, a}, {a, -a, a}},
    };
    test_add_instance(s, test_add_quads(s, (const float(*)[4][3])q, 6), grey, 0, 0, 0);
    for (int inside = 0; inside < 2; inside++) {
        phos_light_desc l;
        phos_light_desc_init(&l);
        l.type = PHOS_LIGHT_POINT;
        l.radius = 0.05f;
        l.color[0] = l.color[1] = l.color[2] = inside ? 5.0f : 50.0f;
        l.position[0] = inside ? 0.0f : 3.0f, l.position[1] = inside ? -0.5f : -2.0f, l.position[2] = inside ? 0.8f : 4.0f;
        phos_scene_add_light(s, &l, NULL);
    }
    if (view_b)
        test_set_camera_pitched(s, 0.0f, -0.9f, 0.0f, 1.5708f, 0.8f);
    else
        test_set_camera_pitched(s, 0.0f, -6.0f, 3.0f, 1.2f, 0.3f);
    if (phos_scene_commit(s) != PHOS_OK) {
        phos_scene_destroy(s);
        return NULL;
    }
    return s;
}

static phos_render_settings unread_settings(uint32_t integrator)
{
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.integrator = integrator;
    rs.width = rs.height = 24;
    rs.samples = 16;
    rs.seed = 3;
    rs.max_bounces = 8;
    rs.global_photons = 20000;
    rs.caustic_photons = 1000;
    rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_OFF; /* final gathering: unbiased against PATH */
    rs.pass_mask = 1u << PHOS_PASS_COMBINED;
    return rs;
}

/* The closed box seen from outside (a) and from inside (b), with the
 * settings of PHOTON and of PATH's reference renders of them; 0 (and
 * nothing to free) if a scene could not be made. */
typedef struct box_views {
    phos_scene *a, *b;
    phos_render_settings photon, path;
} box_views;

static void box_views_free(box_views *v)
{
    phos_scene_destroy(v->a);
    phos_scene_destroy(v->b);
}

static int box_views_make(box_views *v)
{
    v->a = closed_box(0);
    v->b = closed_box(1);
    v->photon = unread_settings(PHOS_INTEGRATOR_PHOTON);
    v->path = unread_settings(PHOS_INTEGRATOR_PATH);
    v->path.samples = 64;
    CHECK(v->a && v->b);
    if (v->a && v->b)
        return 1;
    box_views_free(v);
    return 0;
}

/* Renders with the photon maps' file in `mode` (path NULL: none); the
 * Combined image (RGBA, to free) and the photons stored. */
static float *render_with_maps_file(phos_scene *s, const phos_render_settings *rs, const char *path, uint32_t mode,
                                    uint32_t *stored)
{
    phos_render *r = NULL;
    float *img = NULL;
    *stored = UINT32_MAX;
    if (phos_render_create(s, rs, &r) != PHOS_OK)
        return NULL;
    if ((!path || phos_render_set_cache_file(r, PHOS_CACHE_PHOTON_MAPS, path, mode) == PHOS_OK) &&
        phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK) {
        phos_progress p;
        if (phos_render_progress(r, &p) == PHOS_OK)
            *stored = p.photons_stored;
        size_t n = (size_t)4 * rs->width * rs->height;
        img = malloc(sizeof(float) * n);
        if (img && phos_render_read(r, PHOS_PASS_COMBINED, 0, 0, rs->width, rs->height, img, n) != PHOS_OK) {
            free(img);
            img = NULL;
        }
    } else {
        printf("  render failed: %s\n", phos_render_error(r));
    }
    phos_render_destroy(r);
    return img;
}

/* The mean of a − b over pixels and RGB, and its standard error from the
 * pixels' spread (independent per pixel). */
static void mean_difference(const float *a, const float *b, uint32_t pixels, double *mean, double *se)
{
    double sum = 0.0, sum2 = 0.0;
    for (uint32_t i = 0; i < pixels; i++) {
        double d = 0.0;
        for (int c = 0; c < 3; c++)
            d += (a[4 * i + c] - b[4 * i + c]) / 3.0;
        sum += d;
        sum2 += d * d;
    }
    *mean = sum / pixels;
    *se = sqrt(fmax(sum2 / pixels - *mean * *mean, 0.0) / (pixels - 1));
}

static void check_same_as_path(const char *what, const float *photon_img, const float *path_img, uint32_t pixels)
{
    double mean, se, path_mean = test_mean_rgb(path_img, 4, pixels);
    mean_difference(photon_img, path_img, pixels, &mean, &se);
    printf("  %s: PHOTON - PATH %.5f (± %.5f) on a PATH mean of %.5f\n", what, mean, se, path_mean);
    CHECK_MSG(path_mean > 10.0 * se, "%s: PATH's mean %.5f is lost in its noise %.5f", what, path_mean, se);
    CHECK_MSG(fabs(mean) < 4.0 * se, "%s: PHOTON differs from PATH by %.5f (± %.5f)", what, mean, se);
}

/* The pilot (photon_importance.h) sees that no gather from what the
 * camera sees finds a surface: the global map is not traced, and it is
 * not short either. With a floor the gathers reach, or in a render that
 * does not read the map through gathers only, it is traced. A render of
 * the view that traced none is PATH's image; maps saved from it and loaded
 * for a view whose gathers do find the floor leave those gathers to path
 * tracing, not to the empty map, and that render is PATH's image too. */
static void check_unread_map_not_traced(void)
{
    photon_maps m;
    photon_trace_settings ps = trace_settings(20000, 0);
    for (int floor = 0; floor < 2; floor++)
        for (int gathers_only = 0; gathers_only < 2; gathers_only++) {
            phos_scene *s = cube_scene(LAMP_POINT, floor);
            ps.gathers_only = (uint32_t)gathers_only;
            photon_maps_init(&m);
            atomic_int cancel = 0;
            CHECK(photon_maps_trace((const scene *)s, &ps, &m, &cancel, NULL) == PHOS_OK);
            int skipped = gathers_only && !floor;
            printf("cube %s, gathers only %d: %u global photons from %llu paths\n", floor ? "on a floor" : "on nothing",
                   gathers_only, m.global.count, (unsigned long long)m.global_emitted);
            CHECK_MSG(skipped ? m.global.count == 0 && m.global_emitted == 0 : m.global.count == 20000,
                      "%u global photons", m.global.count);
            CHECK(m.short_maps == 0);
            /* Left out for this view: a final render after a camera move traces it again. */
            CHECK(!skipped || m.aimed_at_view);
            photon_maps_free(&m);
            phos_scene_destroy(s);
        }

    const char *path = "/tmp/phos_test_unread_global.phosmap";
    remove(path);
    box_views v;
    if (!box_views_make(&v))
        return;
    phos_scene *a = v.a, *b = v.b;
    const phos_render_settings photon = v.photon, path_rs = v.path;
    uint32_t pixels = photon.width * photon.height, stored_a, stored_b, stored_loaded, unused;
    float *img_a = render_with_maps_file(a, &photon, path, PHOS_CACHE_FILE_SAVE, &stored_a);
    float *ref_a = render_with_maps_file(a, &path_rs, NULL, 0, &unused);
    float *img_b = render_with_maps_file(b, &photon, NULL, 0, &stored_b);
    float *loaded_b = render_with_maps_file(b, &photon, path, PHOS_CACHE_FILE_LOAD, &stored_loaded);
    float *ref_b = render_with_maps_file(b, &path_rs, NULL, 0, &unused);
    CHECK(img_a && ref_a && img_b && loaded_b && ref_b);
    printf("closed box: %u photons stored for view A, %u for view B, %u loaded from A's file\n", stored_a,
           stored_b, stored_loaded);
    CHECK_MSG(stored_a == 0, "view A stored %u photons that nothing reads", stored_a);
    CHECK_MSG(stored_b >= 20000, "view B stored %u photons", stored_b);
    CHECK(stored_loaded == 0);
    if (img_a && ref_a && img_b && loaded_b && ref_b) {
        check_same_as_path("view A, no global map", img_a, ref_a, pixels);
        check_same_as_path("view B, its own map", img_b, ref_b, pixels);
        check_same_as_path("view B, view A's maps loaded", loaded_b, ref_b, pixels);
    }
    free(img_a), free(ref_a), free(img_b), free(loaded_b), free(ref_b);
    remove(path);
    box_views_free(&v);
}

/* A render farm's cache job aims one map at a whole camera path
 * (phos_render_add_view, docs/farm.md): the closed box's outside view A
 * with view B inside added traces the global map that A alone would leave
 * out, in a render that renders no pixel; B's render that loads it stores
 * its photons and renders PATH's image. */
static void check_views_aim_the_map(void)
{
    const char *path = "/tmp/phos_test_views.phosmap";
    remove(path);
    box_views v;
    if (!box_views_make(&v))
        return;
    phos_scene *a = v.a, *b = v.b;
    const phos_render_settings photon = v.photon, path_rs = v.path;
    phos_render_settings job = photon;
    job.caches_only = 1;
    phos_camera_desc inside = test_camera_pitched(0.0f, -0.9f, 0.0f, 1.5708f, 0.8f);
    phos_render *r = NULL;
    phos_progress p = {0};
    CHECK(phos_render_create(a, &job, &r) == PHOS_OK);
    CHECK(phos_render_set_cache_file(r, PHOS_CACHE_PHOTON_MAPS, path, PHOS_CACHE_FILE_SAVE) == PHOS_OK);
    CHECK(phos_render_add_view(r, &inside) == PHOS_OK);
    CHECK(phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK);
    CHECK(phos_render_progress(r, &p) == PHOS_OK);
    phos_render_destroy(r);
    printf("closed box, view A with view B added: %u photons stored\n", p.photons_stored);
    CHECK_MSG(p.photons_stored >= 20000, "%u photons stored for the views A and B", p.photons_stored);
    uint32_t pixels = photon.width * photon.height, loaded, unused;
    float *img = render_with_maps_file(b, &photon, path, PHOS_CACHE_FILE_LOAD, &loaded);
    float *ref = render_with_maps_file(b, &path_rs, NULL, 0, &unused);
    CHECK(img && ref && loaded >= 20000);
    if (img && ref)
        check_same_as_path("view B, the map of views A and B loaded", img, ref, pixels);
    free(img), free(ref);
    remove(path);
    box_views_free(&v);
}

int main(void)
{
    check_unbiased_and_worth_it(LAMP_POINT, 0, "point lamp, cube on nothing", 5.0);
    check_unbiased_and_worth_it(LAMP_SPOT, 0, "spot, cube on nothing", 1.5);
    check_unbiased_and_worth_it(LAMP_AREA, 0, "area lamp, cube on nothing", 1.5);
    check_unbiased_and_worth_it(LAMP_POINT, 1, "point lamp, cube on a floor", 1.5);
    check_unbiased_and_worth_it(LAMP_MESH, 0, "emissive plane, cube on nothing", 3.0);
    check_unaimed_where_nothing_gains(0);
    check_unaimed_where_nothing_gains(1);
    check_hopeless_map_stops();
    check_cones_weighed_by_the_camera();
    check_unread_map_not_traced();
    check_views_aim_the_map();
    return test_summary("test_photon_aiming");
}
