/*
 * test_api.c — the public API under misuse: every bad input returns the
 * right status with a message that names the problem, nothing crashes, and
 * the render lifecycle (start, stream tiles, cancel, wait, destroy) holds.
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "cache/fingerprint.h"
#include "render/memory.h"
#include "render/stages.h"
#include "scene/scene.h"
#include "test_scenes.h"
#include "test_util.h"

/* Wall-clock bounds are the product's on a Release build; a sanitizer
 * build passes its slowdown (tests/c/CMakeLists.txt). */
#ifndef PHOS_TEST_SLOWDOWN
#define PHOS_TEST_SLOWDOWN 1
#endif

static int contains(const char *haystack, const char *needle) { return strstr(haystack, needle) != NULL; }

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void test_version_and_layout(void)
{
    CHECK(phos_version() == PHOS_VERSION);
    CHECK(phos_struct_size("phos_light_desc") == sizeof(phos_light_desc));
    CHECK(phos_struct_size("phos_render_settings") == sizeof(phos_render_settings));
    CHECK(phos_struct_size("phos_tile") == sizeof(phos_tile));
    CHECK(phos_struct_size("no_such_struct") == 0);
    CHECK(phos_struct_size(NULL) == 0);
    CHECK(phos_struct_size("phos_stage_info") == sizeof(phos_stage_info));
    CHECK(strcmp(phos_status_string(PHOS_ERROR_INVALID_ARGUMENT), "invalid argument") == 0);
    CHECK(phos_pass_channels(PHOS_PASS_COMBINED) == 4);
    CHECK(phos_pass_channels(12345) == 0);
}

static void test_null_handles(void)
{
    phos_scene_destroy(NULL);
    phos_render_destroy(NULL);
    phos_render_cancel(NULL);
    CHECK(phos_scene_error(NULL)[0] != 0);
    CHECK(phos_render_error(NULL)[0] != 0);
    phos_mesh_desc md;
    phos_mesh_desc_init(&md);
    CHECK(phos_scene_add_mesh(NULL, &md, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_scene_commit(NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_render *r = NULL;
    CHECK(phos_render_create(NULL, NULL, &r) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_render_start(NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_render_wait(NULL, 0.0) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_progress p;
    CHECK(phos_render_progress(NULL, &p) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_scene *s = phos_scene_create();
    CHECK(phos_scene_add_mesh(s, NULL, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(contains(phos_scene_error(s), "NULL"));
    phos_scene_destroy(s);
}

/* Mesh attributes: a known type, finite values, ids unique in the mesh,
 * at most PHOS_MAX_MESH_ATTRIBUTES; each refusal names what is wrong. */
static void test_bad_mesh_attributes(void)
{
    phos_scene *s = phos_scene_create();
    float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t idx[3] = {0, 1, 2};
    float values[12] = {1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 0.5f};
    phos_mesh_attribute attrs[2] = {{3, PHOS_ATTRIBUTE_COLOR, values}, {4, PHOS_ATTRIBUTE_FLOAT, values}};
    phos_mesh_desc md;
    phos_mesh_desc_init(&md);
    md.vertex_count = 3, md.positions = pos, md.triangle_count = 1, md.indices = idx;
    md.attribute_count = 2;
    md.attributes = NULL;
    CHECK(phos_scene_add_mesh(s, &md, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "attributes are NULL"), "%s", phos_scene_error(s));
    md.attributes = attrs;
    attrs[1].type = PHOS_ATTRIBUTE_TYPE_COUNT;
    CHECK(phos_scene_add_mesh(s, &md, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "unknown type"), "%s", phos_scene_error(s));
    attrs[1].type = PHOS_ATTRIBUTE_FLOAT;
    attrs[1].id = 3;
    CHECK(phos_scene_add_mesh(s, &md, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "same id 3"), "%s", phos_scene_error(s));
    attrs[1].id = 4;
    attrs[1].values = NULL;
    CHECK(phos_scene_add_mesh(s, &md, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "no values"), "%s", phos_scene_error(s));
    attrs[1].values = values;
    values[7] = INFINITY;
    CHECK(phos_scene_add_mesh(s, &md, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "finite"), "%s", phos_scene_error(s));
    values[7] = 1.0f;
    md.attribute_count = PHOS_MAX_MESH_ATTRIBUTES + 1;
    CHECK(phos_scene_add_mesh(s, &md, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "at most"), "%s", phos_scene_error(s));
    md.attribute_count = 2;
    uint32_t id = 99;
    CHECK(phos_scene_add_mesh(s, &md, &id) == PHOS_OK && id == 0);
    values[0] = 7.0f; /* copied: the caller's array may change after the call */
    CHECK(s->meshes[0].attribute_count == 2 && s->meshes[0].attributes[0].values[0] == 1.0f);

    /* A saved cache's fingerprint sees the attributes: the same mesh with
     * one value changed, or without them, is another scene. */
    uint64_t with = scene_fingerprint_of(s).geometry;
    phos_scene *t = phos_scene_create();
    CHECK(phos_scene_add_mesh(t, &md, NULL) == PHOS_OK); /* values[0] is now 7 */
    CHECK(scene_fingerprint_of(t).geometry != with);
    phos_scene_destroy(t);
    values[0] = 1.0f;
    md.attribute_count = 0;
    t = phos_scene_create();
    CHECK(phos_scene_add_mesh(t, &md, NULL) == PHOS_OK);
    CHECK(scene_fingerprint_of(t).geometry != with);
    phos_scene_destroy(t);
    md.attribute_count = 2;
    t = phos_scene_create();
    CHECK(phos_scene_add_mesh(t, &md, NULL) == PHOS_OK);
    CHECK(scene_fingerprint_of(t).geometry == with);
    phos_scene_destroy(t);
    phos_scene_destroy(s);
}

static void test_bad_meshes(void)
{
    phos_scene *s = phos_scene_create();
    float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t idx[3] = {0, 1, 3};
    phos_mesh_desc md;
    phos_mesh_desc_init(&md);
    md.vertex_count = 3;
    md.positions = pos;
    md.triangle_count = 1;
    md.indices = idx;
    CHECK(phos_scene_add_mesh(s, &md, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "vertex 3"), "%s", phos_scene_error(s));
    idx[2] = 2;
    pos[4] = NAN;
    CHECK(phos_scene_add_mesh(s, &md, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "non-finite"), "%s", phos_scene_error(s));
    pos[4] = 0.0f;
    md.indices = NULL;
    CHECK(phos_scene_add_mesh(s, &md, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    md.indices = idx;
    uint32_t id = 99;
    CHECK(phos_scene_add_mesh(s, &md, &id) == PHOS_OK && id == 0);
    CHECK(phos_scene_error(s)[0] == 0);

    phos_instance_desc inst;
    phos_instance_desc_init(&inst);
    inst.mesh_id = 7;
    CHECK(phos_scene_add_instance(s, &inst, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "mesh 7"), "%s", phos_scene_error(s));
    inst.mesh_id = 0;
    uint32_t mat = 5;
    inst.material_count = 1;
    inst.materials = &mat;
    CHECK(phos_scene_add_instance(s, &inst, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "material 5"), "%s", phos_scene_error(s));
    inst.material_count = 0;
    inst.transform[0] = INFINITY;
    CHECK(phos_scene_add_instance(s, &inst, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_scene_destroy(s);
}

static void test_bad_materials_lights_camera(void)
{
    phos_scene *s = phos_scene_create();
    phos_closure_desc c;
    phos_closure_desc_init(&c);
    phos_material_desc m;
    phos_material_desc_init(&m);
    m.closure_count = 1;
    m.closures = &c;
    c.type = 99;
    CHECK(phos_scene_add_material(s, &m, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "unknown type"), "%s", phos_scene_error(s));
    c.type = PHOS_CLOSURE_GLASS;
    c.roughness = 2.0f;
    CHECK(phos_scene_add_material(s, &m, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "roughness"), "%s", phos_scene_error(s));
    c.roughness = 0.1f;
    c.ior = 0.0f;
    CHECK(phos_scene_add_material(s, &m, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    c.ior = 1.5f;
    c.weight[1] = -1.0f;
    CHECK(phos_scene_add_material(s, &m, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    c.weight[1] = 0.5f;
    /* Anisotropic GGX: roughness across the tangent at most 1 (< 0:
     * isotropic), a finite rotation. */
    c.type = PHOS_CLOSURE_METAL;
    c.roughness_y = 1.5f;
    CHECK(phos_scene_add_material(s, &m, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "across the tangent"), "%s", phos_scene_error(s));
    c.roughness_y = NAN;
    CHECK(phos_scene_add_material(s, &m, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    c.roughness_y = 0.2f;
    c.tangent_rotation = INFINITY;
    CHECK(phos_scene_add_material(s, &m, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "rotation"), "%s", phos_scene_error(s));
    c.tangent_rotation = 0.3f;
    CHECK(phos_scene_add_material(s, &m, NULL) == PHOS_OK);
    c.roughness_y = -1.0f;
    c.tangent_rotation = 0.0f;
    c.type = PHOS_CLOSURE_GLASS;
    m.closure_count = PHOS_MAX_CLOSURES + 1;
    CHECK(phos_scene_add_material(s, &m, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    m.closure_count = 1;
    CHECK(phos_scene_add_material(s, &m, NULL) == PHOS_OK);

    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_SPOT;
    l.spot_angle = 0.0f;
    CHECK(phos_scene_add_light(s, &l, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "spot angle"), "%s", phos_scene_error(s));
    l.type = PHOS_LIGHT_AREA;
    l.axis_v[1] = 0.0f;
    CHECK(phos_scene_add_light(s, &l, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    l.type = PHOS_LIGHT_POINT;
    l.color[0] = NAN;
    CHECK(phos_scene_add_light(s, &l, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    l.color[0] = 1.0f;
    l.radius = -1.0f;
    CHECK(phos_scene_add_light(s, &l, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    l.type = 17;
    CHECK(phos_scene_add_light(s, &l, NULL) == PHOS_ERROR_INVALID_ARGUMENT);

    phos_camera_desc cam;
    phos_camera_desc_init(&cam);
    memset(cam.transform, 0, sizeof(cam.transform));
    CHECK(phos_scene_set_camera(s, &cam) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "singular"), "%s", phos_scene_error(s));
    phos_camera_desc_init(&cam);
    cam.frame_min[0] = 1.0f;
    CHECK(phos_scene_set_camera(s, &cam) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_camera_desc_init(&cam);
    cam.clip_end = 0.0f;
    CHECK(phos_scene_set_camera(s, &cam) == PHOS_ERROR_INVALID_ARGUMENT);

    phos_image_desc img;
    phos_image_desc_init(&img);
    float px[4] = {0, NAN, 0, 1};
    img.width = img.height = 1;
    img.pixels = px;
    CHECK(phos_scene_add_image(s, &img, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    img.width = 0;
    CHECK(phos_scene_add_image(s, &img, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_scene_destroy(s);
}

static phos_scene *small_scene(void)
{
    phos_scene *s = phos_scene_create();
    uint32_t mesh = test_add_sphere_mesh(s, 1.0f, 32, 16, 0);
    uint32_t mat = test_add_diffuse(s, 0.5f, 0.5f, 0.5f);
    test_add_instance(s, mesh, mat, 0, 0, 0);
    phos_world_desc w;
    phos_world_desc_init(&w);
    w.color[0] = w.color[1] = w.color[2] = 1.0f;
    phos_scene_set_world(s, &w);
    test_set_camera(s, 0, 0, 5, 0.4f);
    return s;
}

static void test_lifecycle_errors(void)
{
    phos_scene *s = small_scene();
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    phos_render *r = NULL;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_ERROR_INVALID_STATE && r == NULL);
    CHECK_MSG(contains(phos_scene_error(s), "committed"), "%s", phos_scene_error(s));
    CHECK(phos_scene_commit(s) == PHOS_OK);
    CHECK(phos_scene_commit(s) == PHOS_ERROR_INVALID_STATE);
    /* Changed after commit while a render holds it: refused
     * (test_scene_updates.c has the rest). */
    phos_render *holder = NULL;
    CHECK(phos_render_create(s, &rs, &holder) == PHOS_OK);
    phos_world_desc w;
    phos_world_desc_init(&w);
    CHECK(phos_scene_set_world(s, &w) == PHOS_ERROR_INVALID_STATE);
    CHECK(phos_scene_add_mesh(s, &(phos_mesh_desc){0}, NULL) == PHOS_ERROR_INVALID_STATE);
    phos_render_destroy(holder);

    rs.samples = 0;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "samples"), "%s", phos_scene_error(s));
    rs.samples = 4;
    rs.region_x = 600;
    rs.region_width = 100;
    rs.region_height = 10;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "region"), "%s", phos_scene_error(s));
    rs.region_x = rs.region_width = rs.region_height = 0;
    rs.tile_size = 4;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_ERROR_INVALID_ARGUMENT);
    rs.tile_size = 16;
    rs.filter_width = NAN;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_ERROR_INVALID_ARGUMENT);
    rs.filter_width = 1.5f;
    rs.pass_mask = 0x80000000u;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_ERROR_INVALID_ARGUMENT);
    rs.pass_mask = 1;
    rs.width = rs.height = 32;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_OK && r != NULL);
    CHECK(phos_render_wait(r, 0.0) == PHOS_ERROR_INVALID_STATE);
    float buf[4 * 32 * 32];
    CHECK(phos_render_read(r, PHOS_PASS_COMBINED, 0, 0, 32, 32, buf, 10) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_render_error(r), "buffer"), "%s", phos_render_error(r));
    CHECK(phos_render_read(r, PHOS_PASS_COMBINED, 30, 0, 4, 4, buf, 64) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_render_read(r, 9, 0, 0, 1, 1, buf, 4) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_render_start(r) == PHOS_OK);
    CHECK(phos_render_start(r) == PHOS_ERROR_INVALID_STATE);
    CHECK(phos_render_wait(r, -1.0) == PHOS_OK);
    /* Every tile is handed out once per pass of progressive refinement
     * (1, 2, 4 of the 4 samples: 3 passes) and each pass covers the frame;
     * the 16-pixel tiles of a 32² frame are split to 8 pixels, so that each
     * thread has tiles to choose from (render.c, tile_edge). */
    phos_progress p;
    CHECK(phos_render_progress(r, &p) == PHOS_OK && p.state == PHOS_STATE_DONE && p.fraction == 1.0f);
    CHECK(p.samples == 4 && p.samples_done == 4);
    uint32_t n = 0, count = 1, area = 0;
    phos_tile t;
    while (phos_render_next_tile(r, &t, &count) == PHOS_OK && count) {
        n++;
        area += t.width * t.height;
    }
    CHECK_MSG(n == p.tiles_total && n == 3 * 16 && area == 3 * 32 * 32, "%u tiles (%u reported) of %u pixels", n,
              p.tiles_total, area);
    CHECK(phos_render_read(r, PHOS_PASS_COMBINED, 0, 0, 32, 32, buf, sizeof(buf) / sizeof(float)) == PHOS_OK);
    CHECK(buf[4 * (16 * 32 + 16) + 3] == 1.0f);
    /* The render keeps its scene alive after the caller lets go of it. */
    phos_scene_destroy(s);
    CHECK(phos_render_read(r, PHOS_PASS_COMBINED, 0, 0, 32, 32, buf, sizeof(buf) / sizeof(float)) == PHOS_OK);
    phos_render_destroy(r);
}

/* Every field of the settings table at its offsetof and sizeof; a few of
 * the other structs; unknown names refused. */
static int field_is(const char *s, const char *f, size_t offset, size_t size)
{
    uint32_t o = 12345, n = 12345;
    return phos_struct_field(s, f, &o, &n) == PHOS_OK && o == offset && n == size;
}

static void test_field_layout(void)
{
#define CHECK_SETTING_FIELD(type, name, ...)                                                     \
    CHECK_MSG(field_is("phos_render_settings", #name, offsetof(phos_render_settings, name),    \
                       sizeof(((phos_render_settings *)0)->name)),                               \
              "phos_render_settings.%s", #name);
    PHOS_RENDER_SETTINGS(CHECK_SETTING_FIELD, CHECK_SETTING_FIELD)
#undef CHECK_SETTING_FIELD
    CHECK(field_is("phos_light_desc", "axis_v", offsetof(phos_light_desc, axis_v), 3 * sizeof(float)));
    CHECK(field_is("phos_mesh_desc", "material_slots", offsetof(phos_mesh_desc, material_slots), sizeof(void *)));
    CHECK(field_is("phos_progress", "photons_emitted", offsetof(phos_progress, photons_emitted), 8));
    CHECK(field_is("phos_progress", "stage", offsetof(phos_progress, stage), 64));
    CHECK(field_is("phos_stage_info", "name", offsetof(phos_stage_info, name), 64));
    uint32_t o;
    CHECK(phos_struct_field("phos_light_desc", "no_such_field", &o, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_struct_field("no_such_struct", "type", &o, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_struct_field("phos_tile", "y", NULL, NULL) == PHOS_OK);
    CHECK(phos_struct_field(NULL, "x", &o, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
}

/* Each row of the settings table is checked at create: a value just
 * outside its range is refused with a message naming the field. */
static void test_settings_ranges(void)
{
    phos_scene *s = small_scene();
    CHECK(phos_scene_commit(s) == PHOS_OK);
    phos_render_settings rs;
    phos_render *r = NULL;
#define CHECK_SETTING_RANGE(type, name, def, lo, hi, ...)                                              \
    if ((double)(lo) > 0.0) {                                                                         \
        phos_render_settings_init(&rs);                                                               \
        rs.name = (type)(lo) - (type)1;                                                               \
        CHECK_MSG(phos_render_create(s, &rs, &r) == PHOS_ERROR_INVALID_ARGUMENT &&                     \
                      contains(phos_scene_error(s), #name),                                           \
                  "%s below its min: %s", #name, phos_scene_error(s));                                \
    }                                                                                                 \
    if ((double)(hi) < 4294967295.0) {                                                                \
        phos_render_settings_init(&rs);                                                               \
        rs.name = (type)(hi) + (type)1;                                                               \
        CHECK_MSG(phos_render_create(s, &rs, &r) == PHOS_ERROR_INVALID_ARGUMENT &&                     \
                      contains(phos_scene_error(s), #name),                                           \
                  "%s above its max: %s", #name, phos_scene_error(s));                                \
    }
    PHOS_RENDER_SETTINGS(CHECK_SETTING_RANGE, CHECK_SETTING_RANGE)
#undef CHECK_SETTING_RANGE
    phos_render_settings_init(&rs);
    rs.max_radius = -1.0f;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "max_radius -1 must be finite and >= 0"), "%s", phos_scene_error(s));
    rs.max_radius = INFINITY;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_ERROR_INVALID_ARGUMENT);
    /* The defaults are valid. */
    phos_render_settings_init(&rs);
    rs.width = rs.height = 16;
    CHECK_MSG(phos_render_create(s, &rs, &r) == PHOS_OK, "%s", phos_scene_error(s));
    phos_render_destroy(r);
    phos_scene_destroy(s);
}

/* The plan of a render (phos_render_stages), and progress through it. */
static void check_plan(phos_scene *s, uint32_t integrator, uint32_t view, uint32_t cache, uint32_t pass_mask,
                       const uint32_t *want, uint32_t want_count, const char *render_name)
{
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 16;
    rs.samples = 1;
    rs.integrator = integrator;
    rs.photon_view = view;
    rs.irradiance_cache = cache;
    rs.ic_rays = 16;
    rs.pass_mask = pass_mask;
    rs.global_photons = rs.caustic_photons = 200;
    phos_render *r = NULL;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_OK);
    phos_stage_info plan[PHOS_STAGE_COUNT + 1];
    uint32_t n = 0;
    CHECK(phos_render_stages(r, plan, PHOS_STAGE_COUNT + 1, &n) == PHOS_OK);
    int same = n == want_count;
    for (uint32_t i = 0; same && i < n; i++)
        same = plan[i].id == want[i];
    CHECK_MSG(same, "integrator %u view %u passes 0x%x: %u stages", integrator, view, pass_mask, n);
    /* The plan from the settings alone is the render's. */
    uint32_t ids[PHOS_STAGE_COUNT], id_count = 0;
    CHECK(phos_settings_stages(&rs, ids, PHOS_STAGE_COUNT, &id_count) == PHOS_OK && id_count == n);
    for (uint32_t i = 0; i < n && i < id_count; i++)
        CHECK_MSG(ids[i] == plan[i].id, "settings plan stage %u: %u, the render's %u", i, ids[i], plan[i].id);
    CHECK(phos_settings_stages(&rs, NULL, 0, &id_count) == PHOS_OK && id_count == n);
    CHECK(phos_settings_stages(&rs, NULL, 1, &id_count) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_settings_stages(NULL, ids, PHOS_STAGE_COUNT, &id_count) == PHOS_ERROR_INVALID_ARGUMENT);
    /* Progress through the plan only grows: each stage's share follows
     * the last's, and FINISHED is the whole bar. */
    stage_plan sp;
    stage_plan_make(&rs, &sp);
    float last = -1.0f;
    int grows = stage_plan_fraction(&sp, 0, 0.0f) == 0.0f;
    for (uint32_t i = 0; i < sp.count; i++)
        for (float within = 0.0f; within <= 1.0f; within += 0.25f) {
            float f = stage_plan_fraction(&sp, i, within);
            grows &= f >= last && f <= 1.0f;
            last = f;
        }
    CHECK_MSG(grows && stage_plan_fraction(&sp, sp.count - 1, 0.0f) == 1.0f, "progress through the plan");
    for (uint32_t i = 0; same && i < n; i++)
        if (plan[i].id == PHOS_STAGE_RENDERING)
            CHECK_MSG(strcmp(plan[i].name, render_name) == 0, "%s", plan[i].name);
    phos_progress p;
    CHECK(phos_render_progress(r, &p) == PHOS_OK && p.stage_index == 0 && p.stage_id == PHOS_STAGE_WAITING &&
          strcmp(p.stage, "Waiting") == 0);
    for (uint32_t k = 0; k < PHOS_STAGE_COUNT; k++)
        CHECK_MSG(p.stage_seconds[k] == 0.0, "stage %u: %g s before the start", k, p.stage_seconds[k]);
    CHECK(p.rays_traced == 0);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    CHECK(phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    CHECK(phos_render_progress(r, &p) == PHOS_OK && p.stage_index == n - 1 && p.stage_id == PHOS_STAGE_FINISHED &&
          strcmp(p.stage, plan[n - 1].name) == 0);
    /* Every stage the plan ran took some time, the others none, and
     * together they fit in the wall time from start to wait. */
    double wall = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec), sum = 0.0;
    for (uint32_t k = 0; k < PHOS_STAGE_COUNT; k++) {
        int ran = 0;
        for (uint32_t i = 1; i + 1 < n; i++)
            ran |= plan[i].id == k;
        CHECK_MSG(ran ? p.stage_seconds[k] > 0.0 : p.stage_seconds[k] == 0.0, "stage %u (%s the plan): %g s", k,
                  ran ? "in" : "not in", p.stage_seconds[k]);
        sum += p.stage_seconds[k];
    }
    CHECK_MSG(sum <= wall, "stages %g s in %g s from start to finish", sum, wall);
    /* Every pixel's sample casts its camera ray at least. */
    CHECK_MSG(p.rays_traced >= 16u * 16u, "%llu rays counted for 16 × 16 samples", (unsigned long long)p.rays_traced);
    /* A short buffer gets the first stages and the full count. */
    phos_stage_info first;
    CHECK(phos_render_stages(r, &first, 1, &n) == PHOS_OK && n == want_count && first.id == PHOS_STAGE_WAITING);
    CHECK(phos_render_stages(r, NULL, 0, &n) == PHOS_OK && n == want_count);
    CHECK(phos_render_stages(r, NULL, 1, &n) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_render_destroy(r);
}

static void test_stage_plans(void)
{
    phos_scene *s = small_scene();
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.position[2] = 3.0f;
    CHECK(phos_scene_add_light(s, &l, NULL) == PHOS_OK);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    const uint32_t W = PHOS_STAGE_WAITING, T = PHOS_STAGE_TRACING_PHOTONS, B = PHOS_STAGE_BUILDING_KDTREES,
                   P = PHOS_STAGE_PRECOMPUTING_RADIANCE, C = PHOS_STAGE_FILLING_IRRADIANCE_CACHE,
                   R = PHOS_STAGE_RENDERING, F = PHOS_STAGE_FINISHED;
    const uint32_t OFF = PHOS_IRRADIANCE_CACHE_OFF, PHO = PHOS_IRRADIANCE_CACHE_PHOTON,
                   ALL = PHOS_IRRADIANCE_CACHE_ALWAYS;
    uint32_t combined = 1u << PHOS_PASS_COMBINED;
    check_plan(s, PHOS_INTEGRATOR_PATH, PHOS_PHOTON_VIEW_FINAL_GATHER, PHO, combined, (uint32_t[]){W, R, F}, 3,
               "Path tracing");
    check_plan(s, PHOS_INTEGRATOR_PATH, PHOS_PHOTON_VIEW_FINAL_GATHER, ALL, combined, (uint32_t[]){W, C, R, F}, 4,
               "Path tracing");
    check_plan(s, PHOS_INTEGRATOR_PATH, PHOS_PHOTON_VIEW_FINAL_GATHER, OFF, combined | (1u << PHOS_PASS_PHOTON_MAP),
               (uint32_t[]){W, T, B, R, F}, 5, "Path tracing");
    check_plan(s, PHOS_INTEGRATOR_PATH, PHOS_PHOTON_VIEW_FAST, OFF, combined | (1u << PHOS_PASS_PHOTONS),
               (uint32_t[]){W, T, B, R, F}, 5, "Path tracing");
    check_plan(s, PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_FINAL_GATHER, OFF, combined, (uint32_t[]){W, T, B, P, R, F},
               6, "Rendering with photon maps");
    check_plan(s, PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_FINAL_GATHER, PHO, combined,
               (uint32_t[]){W, T, B, P, C, R, F}, 7, "Rendering with photon maps");
    check_plan(s, PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_PATH_TRACED, ALL, combined, (uint32_t[]){W, T, B, C, R, F},
               6, "Rendering with photon maps");
    /* The fast estimate sends no gather rays: nothing to cache. */
    check_plan(s, PHOS_INTEGRATOR_PHOTON, PHOS_PHOTON_VIEW_FAST, ALL, combined, (uint32_t[]){W, T, B, R, F}, 5,
               "Rendering with photon maps");
    uint32_t n;
    CHECK(phos_render_stages(NULL, NULL, 0, &n) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_scene_destroy(s);
}

typedef struct cancel_args {
    phos_render *r;
    double delay;
} cancel_args;

static void *cancel_later(void *arg)
{
    cancel_args *a = arg;
    struct timespec ts = {0, (long)(a->delay * 1e9)};
    nanosleep(&ts, NULL);
    phos_render_cancel(a->r);
    return NULL;
}

static void test_cancel(void)
{
    phos_scene *s = small_scene();
    CHECK(phos_scene_commit(s) == PHOS_OK);
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 1024;
    rs.samples = 4096; /* minutes of work */
    phos_render *r = NULL;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_OK);
    CHECK(phos_render_start(r) == PHOS_OK);
    CHECK(phos_render_wait(r, 0.05) == PHOS_ERROR_TIMEOUT);
    /* Cancel from another thread, as Blender's UI would. */
    cancel_args a = {r, 0.1};
    pthread_t th;
    pthread_create(&th, NULL, cancel_later, &a);
    pthread_join(th, NULL);
    double t0 = now_seconds();
    phos_status st = phos_render_wait(r, 5.0);
    double dt = now_seconds() - t0;
    CHECK(st == PHOS_ERROR_CANCELLED);
    CHECK_MSG(dt < 0.5 * PHOS_TEST_SLOWDOWN, "cancel took %.3f s", dt);
    phos_progress p;
    phos_render_progress(r, &p);
    CHECK(p.state == PHOS_STATE_CANCELLED && p.tiles_done < p.tiles_total);
    phos_render_destroy(r);
    /* Destroying a running render cancels it too. */
    CHECK(phos_render_create(s, &rs, &r) == PHOS_OK);
    CHECK(phos_render_start(r) == PHOS_OK);
    t0 = now_seconds();
    phos_render_destroy(r);
    CHECK_MSG(now_seconds() - t0 < 0.5 * PHOS_TEST_SLOWDOWN, "destroy of a running render took %.3f s",
              now_seconds() - t0);
    phos_scene_destroy(s);
}

static void test_empty_scene_renders_world(void)
{
    phos_scene *s = phos_scene_create();
    phos_world_desc w;
    phos_world_desc_init(&w);
    w.color[0] = 0.25f;
    phos_scene_set_world(s, &w);
    test_set_camera(s, 0, 0, 0, 1.0f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 8;
    rs.samples = 2;
    float *img = test_render(s, &rs);
    CHECK(img && img[0] == 0.25f && img[1] == 0.0f && img[3] == 1.0f);
    free(img);
    rs.transparent_background = 1;
    img = test_render(s, &rs);
    CHECK(img && img[0] == 0.0f && img[3] == 0.0f);
    free(img);
    phos_scene_destroy(s);
}

/* Angle-weighted vertex normals: a cube's corners point along the
 * diagonals (three right angles of three faces); a vertex on a flat grid
 * of quads and triangles has the plane's normal; bad input is refused. */
static void test_vertex_normals(void)
{
    const float pos[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const uint32_t loops[24] = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
    const float face_n[6][3] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
    const uint32_t starts[6] = {0, 4, 8, 12, 16, 20}, totals[6] = {4, 4, 4, 4, 4, 4};
    float out[8][3];
    CHECK(phos_vertex_normals(8, &pos[0][0], 6, starts, totals, &face_n[0][0], 24, loops, &out[0][0]) == PHOS_OK);
    int diagonal = 1;
    for (int v = 0; v < 8; v++)
        for (int k = 0; k < 3; k++) {
            float expect = (pos[v][k] > 0.5f ? 1.0f : -1.0f) / sqrtf(3.0f);
            diagonal &= fabsf(out[v][k] - expect) < 1e-6f;
        }
    CHECK_MSG(diagonal, "cube corner 0: %g %g %g", (double)out[0][0], (double)out[0][1], (double)out[0][2]);
    /* A triangle and a quad side by side on z = 0, and an unused vertex. */
    const float flat[6][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}, {2, 1, 0}, {5, 5, 5}};
    const uint32_t fl[7] = {0, 1, 2, 1, 3, 4, 2};
    const float fn[2][3] = {{0, 0, 1}, {0, 0, 1}};
    const uint32_t fs[2] = {0, 3}, ft[2] = {3, 4};
    float fo[6][3];
    CHECK(phos_vertex_normals(6, &flat[0][0], 2, fs, ft, &fn[0][0], 7, fl, &fo[0][0]) == PHOS_OK);
    CHECK(fo[1][0] == 0.0f && fo[1][1] == 0.0f && fo[1][2] == 1.0f && fo[2][2] == 1.0f);
    CHECK(fo[5][0] == 0.0f && fo[5][1] == 0.0f && fo[5][2] == 0.0f && !signbit(fo[5][0]));
    /* Refused: a corner beyond the loops, a vertex beyond the vertices, a
     * face of two corners, NULL arrays. */
    const uint32_t far_start[2] = {0, 5};
    CHECK(phos_vertex_normals(6, &flat[0][0], 2, far_start, ft, &fn[0][0], 7, fl, &fo[0][0]) ==
          PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_vertex_normals(4, &flat[0][0], 2, fs, ft, &fn[0][0], 7, fl, &fo[0][0]) == PHOS_ERROR_INVALID_ARGUMENT);
    const uint32_t two[2] = {2, 4};
    CHECK(phos_vertex_normals(6, &flat[0][0], 2, fs, two, &fn[0][0], 7, fl, &fo[0][0]) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_vertex_normals(6, NULL, 2, fs, ft, &fn[0][0], 7, fl, &fo[0][0]) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_vertex_normals(0, NULL, 0, NULL, NULL, NULL, 0, NULL, NULL) == PHOS_OK);
}

/* Instances Embree cannot trace through (an object scaled to zero, a
 * rank-one matrix, a translation of 1e20) render as nothing; an emissive
 * one emits nothing; the rest of the scene renders as without them. */
static void test_singular_instances_render_nothing(void)
{
    float zero_scale[12] = {0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    float rank_one[12] = {-13.875f, -13.875f, -13.875f, -14, -14, -14, -14, -14, -14, -14, -14, -14};
    float far_away[12] = {1, 0, 0, 1e20f, 0, 1, 0, 0, 0, 0, 1, 0};
    const float *bad[3] = {zero_scale, rank_one, far_away};
    float *reference = NULL;
    for (int k = -1; k < 3; k++) {
        phos_scene *s = phos_scene_create();
        uint32_t quad = test_add_quad_mesh(s, 1.0f);
        test_add_instance(s, quad, test_add_diffuse(s, 0.5f, 0.5f, 0.5f), 0, 0, 0);
        if (k >= 0) {
            phos_closure_desc c;
            phos_closure_desc_init(&c);
            c.type = PHOS_CLOSURE_EMISSION;
            c.weight[0] = c.weight[1] = c.weight[2] = 100.0f;
            uint32_t glow = test_add_closure_material(s, &c);
            phos_instance_desc d;
            phos_instance_desc_init(&d);
            d.mesh_id = test_add_sphere_mesh(s, 0.3f, 16, 8, 0);
            memcpy(d.transform, bad[k], sizeof(d.transform));
            d.material_count = 1;
            d.materials = &glow;
            CHECK(phos_scene_add_instance(s, &d, NULL) == PHOS_OK);
        }
        phos_light_desc l;
        phos_light_desc_init(&l);
        l.position[2] = 2.0f;
        l.color[0] = l.color[1] = l.color[2] = 10.0f;
        phos_scene_add_light(s, &l, NULL);
        test_set_camera_pitched(s, 0.0f, -2.5f, 1.2f, 1.1f, 0.5f);
        CHECK_MSG(phos_scene_commit(s) == PHOS_OK, "%s", phos_scene_error(s));
        phos_render_settings rs;
        phos_render_settings_init(&rs);
        rs.integrator = PHOS_INTEGRATOR_PHOTON;
        rs.width = rs.height = 16;
        rs.samples = 2;
        rs.global_photons = rs.caustic_photons = 2000;
        float *img = test_render(s, &rs);
        CHECK_MSG(img != NULL, "singular instance %d: %s", k, phos_scene_error(s));
        if (k < 0)
            reference = img;
        else {
            CHECK_MSG(img && reference && memcmp(img, reference, sizeof(float) * 4 * 16 * 16) == 0,
                      "singular instance %d changes the image", k);
            free(img);
        }
        phos_scene_destroy(s);
    }
    free(reference);
}

/* The memory a render will need, estimated before anything is allocated,
 * and the refusal's message (render/memory.h). Against a fixed amount of
 * available memory, so the test is the same on every machine. */
static void test_memory_estimate(void)
{
    const double GiB = 1024.0 * 1024.0 * 1024.0;
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    memory_estimate e;
    render_memory_estimate(&rs, &e);
    /* PATH at 640×480: the Combined pass only, 4 floats a pixel, its
     * sums between the passes of progressive refinement, 4 doubles, and
     * the pixel's sample count, 4 bytes. */
    CHECK(e.film == 640u * 480u * 52u && e.photon_maps == 0 && e.irradiance_cache == 0 && e.total == e.film);
    rs.progressive = 0;
    render_memory_estimate(&rs, &e);
    CHECK(e.film == 640u * 480u * 20u);
    rs.progressive = 1;
    rs.samples = 1; /* one pass: nothing kept */
    render_memory_estimate(&rs, &e);
    CHECK(e.film == 640u * 480u * 20u);
    rs.adaptive_sampling = 1; /* and each pixel's Σ Y, Σ Y² */
    render_memory_estimate(&rs, &e);
    CHECK(e.film == 640u * 480u * 36u);
    rs.adaptive_sampling = 0;
    rs.samples = 128;
    char msg[512];
    CHECK(render_memory_fits(&e, 1u << 30, msg, sizeof(msg)));

    /* PHOTON's photon maps and cache: the default settings need a few hundred MB. */
    rs.integrator = PHOS_INTEGRATOR_PHOTON;
    render_memory_estimate(&rs, &e);
    CHECK_MSG(e.photon_maps > 0 && e.irradiance_cache > 0 && e.total < 400e6, "default PHOTON needs %.0f MB",
              (double)e.total / 1e6);
    /* The path-traced gather traces no global map, and the estimate
     * counts none; the debug pass that shows the map brings it back. */
    uint64_t both = e.photon_maps;
    rs.photon_view = PHOS_PHOTON_VIEW_PATH_TRACED;
    render_memory_estimate(&rs, &e);
    CHECK_MSG(e.photon_maps > 0 && e.photon_maps < both, "path-traced gather: %.1f MB of maps, with a global map %.1f MB",
              (double)e.photon_maps / 1e6, (double)both / 1e6);
    rs.pass_mask |= 1u << PHOS_PASS_PHOTON_MAP;
    render_memory_estimate(&rs, &e);
    CHECK(e.photon_maps == both);
    rs.pass_mask = 1u << PHOS_PASS_COMBINED;
    rs.photon_view = PHOS_PHOTON_VIEW_FINAL_GATHER;
    /* 2^28 photons in each map: tens of GiB, refused with 16 GiB free. */
    rs.global_photons = rs.caustic_photons = 1u << 28;
    render_memory_estimate(&rs, &e);
    CHECK_MSG(e.photon_maps > 30.0 * GiB, "2^28 photons a map need %.1f GiB", (double)e.photon_maps / GiB);
    CHECK(!render_memory_fits(&e, (uint64_t)(16.0 * GiB), msg, sizeof(msg)));
    CHECK_MSG(contains(msg, "needs about") && contains(msg, "photon maps") && contains(msg, "16.0 GiB is available"),
              "%s", msg);
    /* Every pass of a 65536² frame: half a terabyte of film. */
    phos_render_settings_init(&rs);
    rs.width = rs.height = 65536;
    rs.pass_mask = (1u << PHOS_PASS_COUNT) - 1u;
    rs.progressive = 0;
    render_memory_estimate(&rs, &e);
    /* Combined and Noisy Image 4 channels, Sample Count 1, the others 3;
     * and the sample count, 4 bytes. */
    CHECK(e.film == (uint64_t)65536 * 65536 * (4 * (4 + 4 + 1 + 3 * (PHOS_PASS_COUNT - 3)) + 4));
    /* A border renders only its pixels; the cache's pre-pass covers the
     * whole frame, so a zero minimum spacing on a big frame is refused. */
    rs.region_width = rs.region_height = 64;
    rs.pass_mask = 1u;
    rs.irradiance_cache = PHOS_IRRADIANCE_CACHE_ALWAYS;
    rs.ic_min_spacing = 0.0f;
    render_memory_estimate(&rs, &e);
    CHECK(e.film == 64u * 64u * 20u && e.irradiance_cache > 100.0 * GiB);
    /* Through the API: refused before anything is allocated, with the
     * message on the scene (this machine has less than 500 GiB). */
    phos_scene *s = small_scene();
    CHECK(phos_scene_commit(s) == PHOS_OK);
    phos_render *r = NULL;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_ERROR_OUT_OF_MEMORY && r == NULL);
    CHECK_MSG(contains(phos_scene_error(s), "irradiance cache") && contains(phos_scene_error(s), "GiB"), "%s",
              phos_scene_error(s));
    phos_scene_destroy(s);
    CHECK(memory_available() > 0);
}

/* A grid of small instances of two meshes with two materials, added one
 * by one or (bulk) in one phos_scene_add_instances call. */
enum { GRID = 30 };
static phos_scene *grid_scene(int bulk)
{
    phos_scene *s = phos_scene_create();
    uint32_t meshes[2] = {test_add_sphere_mesh(s, 0.04f, 8, 4, 0), test_add_quad_mesh(s, 0.04f)};
    uint32_t mats[2] = {test_add_diffuse(s, 0.8f, 0.3f, 0.2f), test_add_diffuse(s, 0.2f, 0.5f, 0.8f)};
    static uint32_t mesh_ids[GRID * GRID], offsets[GRID * GRID + 1], materials[GRID * GRID];
    static float transforms[GRID * GRID * 12], randoms[GRID * GRID];
    offsets[0] = 0;
    for (uint32_t k = 0; k < GRID * GRID; k++) {
        float t[12] = {1, 0, 0, -1.0f + 2.0f * (float)(k % GRID) / GRID, 0, 1, 0, -1.0f + 2.0f * (float)(k / GRID) / GRID,
                       0, 0, 1, 0};
        memcpy(transforms + 12 * k, t, sizeof(t));
        mesh_ids[k] = meshes[k % 2];
        materials[k] = mats[(k / 3) % 2];
        offsets[k + 1] = k + 1;
        randoms[k] = (float)k / (GRID * GRID);
    }
    if (bulk) {
        phos_instances_desc d = {GRID * GRID, mesh_ids, transforms, offsets, materials, randoms, NULL};
        uint32_t first = 99;
        CHECK(phos_scene_add_instances(s, &d, &first) == PHOS_OK && first == 0);
    } else {
        for (uint32_t k = 0; k < GRID * GRID; k++) {
            phos_instance_desc d;
            phos_instance_desc_init(&d);
            d.mesh_id = mesh_ids[k];
            memcpy(d.transform, transforms + 12 * k, sizeof(d.transform));
            d.material_count = 1;
            d.materials = &materials[k];
            d.random = randoms[k];
            CHECK(phos_scene_add_instance(s, &d, NULL) == PHOS_OK);
        }
    }
    phos_world_desc w;
    phos_world_desc_init(&w);
    w.color[0] = w.color[1] = w.color[2] = 1.0f;
    phos_scene_set_world(s, &w);
    test_set_camera(s, 0, 0, 3, 0.4f);
    return s;
}

/* Bulk instances render what the same instances added one by one render;
 * a bad one refuses the whole call, names its index and adds nothing. */
static void test_bulk_instances(void)
{
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 32;
    rs.samples = 4;
    float *img[2];
    for (int bulk = 0; bulk < 2; bulk++) {
        phos_scene *s = grid_scene(bulk);
        CHECK(phos_scene_commit(s) == PHOS_OK);
        CHECK(s->instance_count == GRID * GRID);
        img[bulk] = test_render(s, &rs);
        phos_scene_destroy(s);
    }
    CHECK(img[0] && img[1] && memcmp(img[0], img[1], sizeof(float) * 4 * 32 * 32) == 0);
    free(img[0]);
    free(img[1]);

    phos_scene *s = small_scene();
    uint32_t mesh_ids[3] = {0, 0, 7}, offsets[4] = {0, 1, 1, 1}, materials[1] = {0};
    float transforms[36] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0,
                            1, 0, 0, 2, 0, 1, 0, 0, 0, 0, 1, 0};
    phos_instances_desc d = {3, mesh_ids, transforms, offsets, materials, NULL, NULL};
    CHECK(phos_scene_add_instances(s, &d, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "instance 2 of 3") && contains(phos_scene_error(s), "mesh 7"), "%s",
              phos_scene_error(s));
    CHECK(s->instance_count == 1);
    mesh_ids[2] = 0;
    transforms[12 + 5] = NAN;
    CHECK(phos_scene_add_instances(s, &d, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "instance 1 of 3") && contains(phos_scene_error(s), "finite"), "%s",
              phos_scene_error(s));
    transforms[12 + 5] = 0.0f;
    offsets[2] = 0;
    CHECK(phos_scene_add_instances(s, &d, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(contains(phos_scene_error(s), "decrease"), "%s", phos_scene_error(s));
    offsets[2] = 1;
    d.materials = NULL;
    CHECK(phos_scene_add_instances(s, &d, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    d.materials = materials;
    CHECK(phos_scene_add_instances(s, NULL, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    uint32_t first = 0;
    CHECK(phos_scene_add_instances(s, &d, &first) == PHOS_OK && first == 1 && s->instance_count == 4);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    phos_scene_destroy(s);
}

int main(void)
{
    test_memory_estimate();
    test_bulk_instances();
    test_singular_instances_render_nothing();
    test_vertex_normals();
    test_version_and_layout();
    test_null_handles();
    test_bad_meshes();
    test_bad_mesh_attributes();
    test_bad_materials_lights_camera();
    test_lifecycle_errors();
    test_field_layout();
    test_settings_ranges();
    test_stage_plans();
    test_cancel();
    test_empty_scene_renders_world();
    return test_summary("test_api");
}
