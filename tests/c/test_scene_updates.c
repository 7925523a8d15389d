/*
 * test_scene_updates.c — scene updates (phos.h, phos_scene_commit;
 * docs/architecture.md, "Scene updates"): a committed scene changed in
 * place and committed again renders exactly what a scene built with the
 * final data renders, every integrator; a commit rebuilds only what the
 * changes touched; a scene a render holds refuses changes; a refused change
 * leaves the scene committed as it was. Photon maps kept from one render
 * and given to the next (phos_render_keep_photon_maps/use_photon_maps)
 * render exactly what tracing them again renders, and are refused once
 * they no longer fit the scene or the settings.
 */
#include <stdio.h>
#include <string.h>

#include "scene/embree.h"
#include "scene/scene.h"
#include "test_scenes.h"
#include "test_util.h"

/* The scene's variable parts. */
typedef struct variant {
    float box_x, box_half;  /* an instance's place, its mesh's size (m) */
    float floor_grey;       /* a material */
    int box_glows;          /* the box's material emits too: the light table reads materials */
    float lamp_watts;       /* a light */
    float world;            /* the world's colour */
    float camera_z;         /* the camera */
} variant;

static const variant BEFORE = {-0.6f, 0.4f, 0.5f, 0, 800.0f, 0.05f, 4.0f};
static const variant AFTER = {0.5f, 0.6f, 0.7f, 1, 1200.0f, 0.1f, 4.5f};

typedef struct ids {
    uint32_t box_mesh, box_instance, floor_material, box_material, lamp;
} ids;

/* A box of half-size `half` resting on z = 0 (its arrays in pos and idx). */
static phos_mesh_desc box_desc(float half, float pos[24], uint32_t idx[36])
{
    for (int k = 0; k < 8; k++) {
        pos[3 * k] = (k & 1) ? half : -half;
        pos[3 * k + 1] = (k & 2) ? half : -half;
        pos[3 * k + 2] = (k & 4) ? 2.0f * half : 0.0f;
    }
    static const uint32_t faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int f = 0; f < 6; f++) {
        const uint32_t *q = faces[f];
        uint32_t t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
        memcpy(idx + 6 * f, t, sizeof(t));
    }
    phos_mesh_desc md;
    phos_mesh_desc_init(&md);
    md.vertex_count = 8;
    md.positions = pos;
    md.triangle_count = 12;
    md.indices = idx;
    return md;
}

static phos_material_desc diffuse_desc(float grey, int glows, phos_closure_desc c[2])
{
    phos_closure_desc_init(&c[0]);
    c[0].type = PHOS_CLOSURE_DIFFUSE;
    c[0].weight[0] = c[0].weight[1] = c[0].weight[2] = grey;
    phos_closure_desc_init(&c[1]);
    c[1].type = PHOS_CLOSURE_EMISSION;
    c[1].weight[0] = 4.0f, c[1].weight[1] = 2.0f, c[1].weight[2] = 1.0f;
    phos_material_desc md;
    phos_material_desc_init(&md);
    md.closure_count = glows ? 2 : 1;
    md.closures = c;
    return md;
}

static phos_instance_desc box_instance_desc(const variant *v, uint32_t mesh, const uint32_t *material)
{
    phos_instance_desc d;
    phos_instance_desc_init(&d);
    d.mesh_id = mesh;
    d.transform[3] = v->box_x;
    d.material_count = 1;
    d.materials = material;
    return d;
}

static phos_light_desc lamp_desc(const variant *v)
{
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.position[0] = 1.0f, l.position[1] = -1.0f, l.position[2] = 3.0f;
    l.radius = 0.1f;
    l.color[0] = l.color[1] = l.color[2] = v->lamp_watts / (4.0f * (float)M_PI);
    return l;
}

static phos_world_desc world_desc(const variant *v)
{
    phos_world_desc w;
    phos_world_desc_init(&w);
    w.color[0] = w.color[1] = w.color[2] = v->world;
    return w;
}

static void set_camera(phos_scene *s, const variant *v) { test_set_camera_pitched(s, 0.0f, -3.0f, v->camera_z, 0.9f, 0.5f); }

/* The scene of v, not committed; its ids in *out. */
static phos_scene *build(const variant *v, ids *out)
{
    phos_scene *s = phos_scene_create();
    phos_closure_desc c[2];
    phos_material_desc floor = diffuse_desc(v->floor_grey, 0, c);
    CHECK(phos_scene_add_material(s, &floor, &out->floor_material) == PHOS_OK);
    test_add_instance(s, test_add_quad_mesh(s, 3.0f), out->floor_material, 0, 0, 0);
    phos_material_desc box = diffuse_desc(0.6f, v->box_glows, c);
    CHECK(phos_scene_add_material(s, &box, &out->box_material) == PHOS_OK);
    float pos[24];
    uint32_t idx[36];
    phos_mesh_desc md = box_desc(v->box_half, pos, idx);
    CHECK(phos_scene_add_mesh(s, &md, &out->box_mesh) == PHOS_OK);
    phos_instance_desc inst = box_instance_desc(v, out->box_mesh, &out->box_material);
    CHECK(phos_scene_add_instance(s, &inst, &out->box_instance) == PHOS_OK);
    phos_light_desc l = lamp_desc(v);
    CHECK(phos_scene_add_light(s, &l, &out->lamp) == PHOS_OK);
    phos_world_desc w = world_desc(v);
    CHECK(phos_scene_set_world(s, &w) == PHOS_OK);
    set_camera(s, v);
    return s;
}

enum part { PART_INSTANCE = 1, PART_MESH = 2, PART_MATERIAL = 4, PART_LIGHT = 8, PART_WORLD = 16, PART_CAMERA = 32 };

/* Changes the parts of s (built from any variant) to v's. */
static void update(phos_scene *s, const ids *id, const variant *v, uint32_t parts)
{
    phos_closure_desc c[2];
    if (parts & PART_INSTANCE) {
        phos_instance_desc inst = box_instance_desc(v, id->box_mesh, &id->box_material);
        CHECK(phos_scene_update_instance(s, id->box_instance, &inst) == PHOS_OK);
    }
    if (parts & PART_MESH) {
        float pos[24];
        uint32_t idx[36];
        phos_mesh_desc md = box_desc(v->box_half, pos, idx);
        CHECK(phos_scene_update_mesh(s, id->box_mesh, &md) == PHOS_OK);
    }
    if (parts & PART_MATERIAL) {
        phos_material_desc floor = diffuse_desc(v->floor_grey, 0, c);
        CHECK(phos_scene_update_material(s, id->floor_material, &floor) == PHOS_OK);
        phos_material_desc box = diffuse_desc(0.6f, v->box_glows, c);
        CHECK(phos_scene_update_material(s, id->box_material, &box) == PHOS_OK);
    }
    if (parts & PART_LIGHT) {
        phos_light_desc l = lamp_desc(v);
        CHECK(phos_scene_update_light(s, id->lamp, &l) == PHOS_OK);
    }
    if (parts & PART_WORLD) {
        phos_world_desc w = world_desc(v);
        CHECK(phos_scene_set_world(s, &w) == PHOS_OK);
    }
    if (parts & PART_CAMERA)
        set_camera(s, v);
}

static phos_render_settings settings(uint32_t integrator)
{
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 24;
    rs.samples = 4;
    rs.integrator = integrator;
    rs.global_photons = rs.caustic_photons = 5000;
    rs.ic_rays = 64;
    return rs;
}

/* Every part changed at once, under each integrator (PHOTON with its
 * irradiance cache): bit for bit the fresh scene's image. */
static void test_updates_match_fresh_scene(void)
{
    const uint32_t integrators[] = {PHOS_INTEGRATOR_PATH, PHOS_INTEGRATOR_PHOTON};
    for (int k = 0; k < 2; k++) {
        phos_render_settings rs = settings(integrators[k]);
        ids a, b;
        phos_scene *s = build(&BEFORE, &a);
        CHECK(phos_scene_commit(s) == PHOS_OK);
        float *before = test_render(s, &rs);
        update(s, &a, &AFTER, PART_INSTANCE | PART_MESH | PART_MATERIAL | PART_LIGHT | PART_WORLD | PART_CAMERA);
        CHECK(phos_scene_commit(s) == PHOS_OK);
        float *updated = test_render(s, &rs);
        phos_scene *f = build(&AFTER, &b);
        CHECK(phos_scene_commit(f) == PHOS_OK);
        float *fresh = test_render(f, &rs);
        CHECK(before && updated && fresh);
        if (before && updated && fresh) {
            size_t bytes = sizeof(float) * 4 * rs.width * rs.height;
            CHECK_MSG(memcmp(before, fresh, bytes) != 0, "the two variants render alike: the test sees nothing");
            CHECK_MSG(memcmp(updated, fresh, bytes) == 0,
                      "integrator %u: the updated scene renders otherwise than the same scene built afresh",
                      integrators[k]);
        }
        free(before);
        free(updated);
        free(fresh);
        phos_scene_destroy(s);
        phos_scene_destroy(f);
    }
}

typedef struct builds {
    uint32_t meshes, tops, light_tables;
} builds;

static builds count_builds(const phos_scene *s)
{
    builds b;
    embree_bvh_build_counts(s->bvh, &b.meshes, &b.tops);
    b.light_tables = s->light_table_builds;
    return b;
}

/* One part changed, committed: what was rebuilt, and what
 * phos_scene_changes reports. */
static void check_rebuilds(phos_scene *s, const ids *id, uint32_t part, const char *name, builds expect_more,
                           uint32_t expect_changes)
{
    builds before = count_builds(s);
    const struct embree_bvh *bvh = s->bvh;
    update(s, id, &AFTER, part);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    builds after = count_builds(s);
    printf("  %-8s: %u mesh BVH, %u top level, %u light table rebuilt; changes 0x%x\n", name,
           after.meshes - before.meshes, after.tops - before.tops, after.light_tables - before.light_tables,
           phos_scene_changes(s));
    CHECK_MSG(s->bvh == bvh, "%s: the BVH was built anew instead of updated", name);
    CHECK_MSG(after.meshes - before.meshes == expect_more.meshes && after.tops - before.tops == expect_more.tops &&
                  after.light_tables - before.light_tables == expect_more.light_tables,
              "%s: rebuilt %u mesh BVHs, %u top levels, %u light tables; expected %u, %u, %u", name,
              after.meshes - before.meshes, after.tops - before.tops, after.light_tables - before.light_tables,
              expect_more.meshes, expect_more.tops, expect_more.light_tables);
    CHECK_MSG(phos_scene_changes(s) == expect_changes, "%s: changes 0x%x, expected 0x%x", name,
              phos_scene_changes(s), expect_changes);
}

static void test_rebuilds_only_what_changed(void)
{
    ids id;
    phos_scene *s = build(&BEFORE, &id);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    builds first = count_builds(s);
    CHECK(first.meshes == 2 && first.tops == 1 && first.light_tables == 1);
    CHECK(phos_scene_changes(s) == (PHOS_CHANGE_GEOMETRY | PHOS_CHANGE_MATERIALS | PHOS_CHANGE_LIGHTS |
                                    PHOS_CHANGE_CAMERA));
    check_rebuilds(s, &id, PART_CAMERA, "camera", (builds){0, 0, 0}, PHOS_CHANGE_CAMERA);
    check_rebuilds(s, &id, PART_INSTANCE, "instance", (builds){0, 1, 1}, PHOS_CHANGE_GEOMETRY);
    check_rebuilds(s, &id, PART_MESH, "mesh", (builds){1, 1, 1}, PHOS_CHANGE_GEOMETRY);
    check_rebuilds(s, &id, PART_MATERIAL, "material", (builds){0, 0, 1}, PHOS_CHANGE_MATERIALS);
    check_rebuilds(s, &id, PART_LIGHT, "light", (builds){0, 0, 1}, PHOS_CHANGE_LIGHTS);
    check_rebuilds(s, &id, PART_WORLD, "world", (builds){0, 0, 1}, PHOS_CHANGE_LIGHTS);
    /* An added mesh and instance: that mesh's BVH only. */
    builds before = count_builds(s);
    test_add_instance(s, test_add_quad_mesh(s, 0.2f), id.box_material, 0.0f, 1.0f, 1.0f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    builds after = count_builds(s);
    CHECK_MSG(after.meshes - before.meshes == 1 && after.tops - before.tops == 1,
              "an added mesh: rebuilt %u mesh BVHs and %u top levels, expected 1 and 1", after.meshes - before.meshes,
              after.tops - before.tops);
    phos_scene_destroy(s);
}

/* A scene a render holds refuses changes, with a message that says what to
 * do; once the render is gone it changes, and renders refuse it until the
 * next commit. */
static void test_changes_while_a_render_holds_the_scene(void)
{
    ids id;
    phos_scene *s = build(&BEFORE, &id);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    phos_render_settings rs = settings(PHOS_INTEGRATOR_PATH);
    phos_render *r = NULL;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_OK);
    phos_light_desc l = lamp_desc(&AFTER);
    CHECK(phos_scene_update_light(s, id.lamp, &l) == PHOS_ERROR_INVALID_STATE);
    CHECK_MSG(strstr(phos_scene_error(s), "render holds") != NULL, "%s", phos_scene_error(s));
    CHECK(phos_scene_set_camera(s, &(phos_camera_desc){0}) == PHOS_ERROR_INVALID_STATE);
    CHECK(phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK);
    phos_render_destroy(r);
    CHECK(phos_scene_update_light(s, id.lamp, &l) == PHOS_OK);
    r = NULL;
    CHECK(phos_render_create(s, &rs, &r) == PHOS_ERROR_INVALID_STATE && r == NULL);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    CHECK(phos_render_create(s, &rs, &r) == PHOS_OK);
    phos_render_destroy(r);
    phos_scene_destroy(s);
}

/* A refused change (an unknown id, a bad description) leaves the scene
 * committed as it was: it still renders without a commit, the same image. */
static void test_refused_changes_leave_the_scene(void)
{
    ids id;
    phos_scene *s = build(&BEFORE, &id);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    phos_render_settings rs = settings(PHOS_INTEGRATOR_PATH);
    float *before = test_render(s, &rs);
    float pos[24];
    uint32_t idx[36];
    phos_mesh_desc md = box_desc(0.5f, pos, idx);
    CHECK(phos_scene_update_mesh(s, 99, &md) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK_MSG(strstr(phos_scene_error(s), "does not exist") != NULL, "%s", phos_scene_error(s));
    pos[4] = NAN;
    CHECK(phos_scene_update_mesh(s, id.box_mesh, &md) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_light_desc l = lamp_desc(&AFTER);
    l.radius = -1.0f;
    CHECK(phos_scene_update_light(s, id.lamp, &l) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_scene_update_light(s, 7, &l) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_instance_desc inst = box_instance_desc(&AFTER, 42, &id.box_material);
    CHECK(phos_scene_update_instance(s, id.box_instance, &inst) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_closure_desc c[2];
    phos_material_desc m = diffuse_desc(0.5f, 0, c);
    c[0].roughness = 2.0f;
    CHECK(phos_scene_update_material(s, id.floor_material, &m) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(phos_scene_update_material(s, id.floor_material, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    float *after = test_render(s, &rs); /* no commit: still committed */
    CHECK(before && after);
    if (before && after)
        CHECK_MSG(memcmp(before, after, sizeof(float) * 4 * rs.width * rs.height) == 0,
                  "a refused change changed the image");
    free(before);
    free(after);
    phos_scene_destroy(s);
}

/* A render of s given `maps` (if not NULL, from any view if any_view):
 * its image, or NULL with *status the refusal. Its own maps are kept in
 * *keep if asked; *traced says whether its plan traced photons. */
static float *render_with_maps(phos_scene *s, const phos_render_settings *rs, phos_photon_maps *maps,
                               uint32_t any_view, phos_photon_maps **keep, phos_status *status, int *traced)
{
    phos_render *r = NULL;
    CHECK(phos_render_create(s, rs, &r) == PHOS_OK);
    if (!r)
        return NULL;
    *status = maps ? phos_render_use_photon_maps(r, maps, any_view) : PHOS_OK;
    if (*status != PHOS_OK) {
        phos_render_destroy(r);
        return NULL;
    }
    phos_stage_info stages[PHOS_STAGE_COUNT];
    uint32_t n = 0;
    CHECK(phos_render_stages(r, stages, PHOS_STAGE_COUNT, &n) == PHOS_OK);
    *traced = 0;
    for (uint32_t i = 0; i < n; i++)
        *traced |= stages[i].id == PHOS_STAGE_TRACING_PHOTONS;
    CHECK(phos_render_start(r) == PHOS_OK && phos_render_wait(r, -1.0) == PHOS_OK);
    size_t count = (size_t)4 * rs->width * rs->height;
    float *img = malloc(sizeof(float) * count);
    CHECK(phos_render_read(r, PHOS_PASS_COMBINED, 0, 0, rs->width, rs->height, img, count) == PHOS_OK);
    if (keep)
        CHECK(phos_render_keep_photon_maps(r, keep) == PHOS_OK && *keep);
    phos_render_destroy(r);
    return img;
}

static int same_image(const float *a, const float *b, const phos_render_settings *rs)
{
    return a && b && memcmp(a, b, sizeof(float) * 4 * rs->width * rs->height) == 0;
}

/* Kept maps, given back: the same image without tracing, for the same
 * scene and, where no photons were aimed at the view, after a camera move;
 * refused after any other change, with other settings, for another scene
 * or without radiance photons; maps aimed at the view are taken after a
 * camera move only when any view is allowed. */
static void test_kept_photon_maps(void)
{
    phos_render_settings rs = settings(PHOS_INTEGRATOR_PHOTON);
    variant dark = BEFORE, moved = BEFORE;
    /* Nothing aimed at the view: no world light, and the lamp inside the
     * box (a lamp reaching several objects from outside them weighs its
     * cones by what the camera reads). */
    dark.world = 0.0f;
    dark.box_half = 4.0f;
    moved.camera_z = AFTER.camera_z;
    for (int aimed = 0; aimed < 2; aimed++) {
        ids id;
        phos_scene *s = build(aimed ? &BEFORE : &dark, &id);
        CHECK(phos_scene_commit(s) == PHOS_OK);
        phos_photon_maps *maps = NULL;
        phos_status st;
        int traced = 0;
        float *first = render_with_maps(s, &rs, NULL, 0, &maps, &st, &traced);
        CHECK(traced && maps);
        float *again = render_with_maps(s, &rs, maps, 0, NULL, &st, &traced);
        CHECK_MSG(st == PHOS_OK && !traced, "aimed %d: kept maps refused by the same scene: %s", aimed,
                  phos_scene_error(s));
        CHECK_MSG(same_image(first, again, &rs), "aimed %d: kept maps render otherwise than tracing them", aimed);

        /* The camera moves. */
        update(s, &id, &moved, PART_CAMERA);
        CHECK(phos_scene_commit(s) == PHOS_OK);
        float *traced_moved = render_with_maps(s, &rs, NULL, 0, NULL, &st, &traced);
        float *kept_moved = render_with_maps(s, &rs, maps, 0, NULL, &st, &traced);
        if (aimed) {
            CHECK_MSG(!kept_moved && st == PHOS_ERROR_INVALID_ARGUMENT,
                      "maps aimed at another view taken for a final render");
            free(kept_moved);
            kept_moved = render_with_maps(s, &rs, maps, 1, NULL, &st, &traced);
            CHECK_MSG(kept_moved && !traced, "maps aimed at another view refused with any_view");
            CHECK_MSG(kept_moved && !same_image(kept_moved, first, &rs), "the moved view renders as before");
        } else {
            CHECK_MSG(same_image(kept_moved, traced_moved, &rs),
                      "after a camera move, kept maps render otherwise than tracing them");
        }
        free(first);
        free(again);
        free(traced_moved);
        free(kept_moved);

        /* Other settings, other maps, another scene. */
        phos_render_settings more = rs;
        more.global_photons += 1;
        CHECK(!render_with_maps(s, &more, maps, 1, NULL, &st, &traced) && st == PHOS_ERROR_INVALID_ARGUMENT);
        phos_render_settings fast = rs;
        fast.photon_view = PHOS_PHOTON_VIEW_FAST;
        phos_photon_maps *fast_maps = NULL;
        free(render_with_maps(s, &fast, NULL, 0, &fast_maps, &st, &traced));
        CHECK(!render_with_maps(s, &rs, fast_maps, 1, NULL, &st, &traced) && st == PHOS_ERROR_INVALID_ARGUMENT);
        phos_photon_maps_release(fast_maps);
        ids other_ids;
        phos_scene *other = build(aimed ? &BEFORE : &dark, &other_ids);
        CHECK(phos_scene_commit(other) == PHOS_OK);
        CHECK(!render_with_maps(other, &rs, maps, 1, NULL, &st, &traced) && st == PHOS_ERROR_INVALID_ARGUMENT);
        phos_scene_destroy(other);

        /* A light changes: the maps no longer fit. */
        update(s, &id, &AFTER, PART_LIGHT);
        CHECK(phos_scene_commit(s) == PHOS_OK);
        phos_render *r = NULL;
        CHECK(phos_render_create(s, &rs, &r) == PHOS_OK);
        CHECK(phos_render_use_photon_maps(r, maps, 1) == PHOS_ERROR_INVALID_ARGUMENT);
        CHECK_MSG(strstr(phos_render_error(r), "changed") != NULL, "%s", phos_render_error(r));
        /* Not built yet: nothing to keep. */
        phos_photon_maps *none = NULL;
        CHECK(phos_render_keep_photon_maps(r, &none) == PHOS_ERROR_INVALID_STATE && none == NULL);
        phos_render_destroy(r);
        phos_photon_maps_release(maps);
        phos_scene_destroy(s);
    }
    /* A render without photon maps has none to keep or take. */
    ids id;
    phos_scene *s = build(&BEFORE, &id);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    phos_render_settings path = settings(PHOS_INTEGRATOR_PATH);
    phos_render *r = NULL;
    CHECK(phos_render_create(s, &path, &r) == PHOS_OK);
    phos_photon_maps *none = NULL;
    CHECK(phos_render_keep_photon_maps(r, &none) == PHOS_ERROR_INVALID_STATE);
    phos_render_destroy(r);
    phos_scene_destroy(s);
}

int main(void)
{
    test_updates_match_fresh_scene();
    test_rebuilds_only_what_changed();
    test_changes_while_a_render_holds_the_scene();
    test_refused_changes_leave_the_scene();
    test_kept_photon_maps();
    return test_summary("test_scene_updates");
}
