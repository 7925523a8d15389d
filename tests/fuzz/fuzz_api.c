/*
 * fuzz_api.c — libFuzzer target on the public C API (phos.h): a scene and
 * a render are built from the fuzzer's bytes, with every call's status
 * taken as it comes, and the render is run with a short time budget and
 * then cancelled. What must hold, whatever the bytes (docs/reliability.md):
 *   - nothing crashes, reads out of bounds or leaks (ASan, UBSan, LSan);
 *   - every failing call leaves a message on its handle;
 *   - a cancel returns within CANCEL_LIMIT_S (else abort: a hang);
 *   - every pixel a render delivers is finite.
 *
 * The input is read as a stream (reader below): counts are bytes taken
 * modulo a small limit, numbers come from tables of ordinary and absurd
 * values (NaN, ±∞, ±FLT_MAX, 1e±30, denormals, −0) or from raw bits, so
 * that the seeds in tests/fuzz/corpus (written by make_seeds.py) stay
 * readable and mutations stay meaningful. An exhausted input reads zeros.
 */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "phos.h"

#define CANCEL_LIMIT_S 2.0   /* the product's bound is 0.5 s (tests/c/test_cancel.c); this catches hangs */
#define RENDER_BUDGET_S 0.25/* how long a render runs before it is cancelled */

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* FUZZ_API_VERBOSE=1 prints what each input did (to check the seeds). */
static int verbose = -1;
#define SAY(...)                                                                                   \
    do {                                                                                           \
        if (verbose < 0)                                                                           \
            verbose = getenv("FUZZ_API_VERBOSE") != NULL;                                          \
        if (verbose) {                                                                             \
            fprintf(stderr, "[%7.3f] ", now_seconds());                                            \
            fprintf(stderr, __VA_ARGS__);                                                          \
        }                                                                                          \
    } while (0)

/* ------------------------------------------------------------- reader */

typedef struct reader {
    const uint8_t *p;
    size_t n;
} reader;

static uint8_t take_u8(reader *r)
{
    if (!r->n)
        return 0;
    r->n--;
    return *r->p++;
}

static uint32_t take_raw_u32(reader *r)
{
    uint32_t v = 0;
    for (int i = 0; i < 4; i++)
        v |= (uint32_t)take_u8(r) << (8 * i);
    return v;
}

/* A float: selector bytes below 0xE0 are (b − 112)/8, i.e. −14 … +13.875
 * in steps of 1/8; the rest pick an absurd value or raw bits. */
static float take_float(reader *r)
{
    static const float special[] = {NAN, INFINITY, -INFINITY, FLT_MAX, -FLT_MAX, 1e30f, -1e30f, 1e-30f,
                                    1.4e-45f, -0.0f, 1e6f, -1e6f, 1e-6f, 65536.0f, 3.14159265f, 0.999999f,
                                    1.000001f, 1e12f, 4096.0f, 0.01f, 100.0f, 1e-3f, 2.0f, 0.5f,
                                    1e38f, -1e-38f, 8192.0f, 0.25f, 1.5f, 10.0f, 1000.0f};
    uint8_t b = take_u8(r);
    if (b < 0xE0)
        return ((float)b - 112.0f) / 8.0f;
    uint32_t k = b - 0xE0u;
    if (k < sizeof(special) / sizeof(special[0]))
        return special[k];
    uint32_t bits = take_raw_u32(r);
    float f;
    memcpy(&f, &bits, sizeof(f));
    return f;
}

static void take_floats(reader *r, float *out, size_t n)
{
    for (size_t i = 0; i < n; i++)
        out[i] = take_float(r);
}

/* An unsigned value: selector bytes below 0xC0 are themselves minus 0x40
 * when ≥ 0x40 (0 … 127) or an index; the rest pick a boundary. */
static uint32_t take_u32(reader *r)
{
    static const uint32_t special[] = {0u, 1u, 2u, 3u, 7u, 8u, 9u, 15u, 16u, 17u, 31u, 32u, 33u, 63u, 64u, 65u,
                                       255u, 256u, 1000u, 1023u, 1024u, 1025u, 4096u, 8192u, 8193u, 10000u,
                                       10001u, 20000u, 65535u, 65536u, 65537u, 1u << 20, 1u << 24,
                                       (1u << 24) + 1, 1u << 26, 1u << 28, (1u << 28) + 1, 1u << 31,
                                       UINT32_MAX - 1, UINT32_MAX};
    uint8_t b = take_u8(r);
    if (b < 0x40)
        return b;
    if (b < 0xC0) {
        uint32_t k = b - 0x40u;
        if (k < sizeof(special) / sizeof(special[0]))
            return special[k];
        return b;
    }
    return take_raw_u32(r);
}

/* ------------------------------------------------------------ scene */

static void fuzz_images(reader *r, phos_scene *s)
{
    uint32_t n = take_u8(r) % 3;
    for (uint32_t i = 0; i < n; i++) {
        phos_image_desc d;
        phos_image_desc_init(&d);
        d.width = take_u8(r) % 5;
        d.height = take_u8(r) % 5;
        float px[4 * 4 * 4 * 4];
        uint32_t count = d.width * d.height * 4;
        for (uint32_t k = 0; k < count; k++)
            px[k] = take_float(r);
        d.pixels = take_u8(r) == 0xFF ? NULL : px;
        uint32_t id;
        if (phos_scene_add_image(s, &d, &id) != PHOS_OK && !phos_scene_error(s)[0])
            abort(); /* a failure without a message */
    }
}

/* A shader program from the stream: registers, constants, instructions
 * (any op, mode, flags and registers, 0xFF meaning none), a table and
 * bindings; the core must refuse what is inconsistent and evaluate the
 * rest, whatever the values. */
typedef struct fuzz_program {
    phos_shader_program_desc d;
    float constants[64], table[48];
    phos_shader_instruction ins[8];
    phos_shader_binding bind[4];
} fuzz_program;

static uint32_t take_register(reader *r, uint32_t registers)
{
    uint8_t b = take_u8(r);
    return b == 0xFF ? PHOS_SHADER_NO_REGISTER : b % (registers + 2);
}

static const phos_shader_program_desc *take_program(reader *r, fuzz_program *p)
{
    memset(p, 0, sizeof(*p));
    uint32_t registers = take_u8(r) % 64 + 1;
    p->d.register_count = registers;
    p->d.constant_count = take_u8(r) % (registers + 1);
    take_floats(r, p->constants, p->d.constant_count);
    p->d.constants = p->constants;
    p->d.instruction_count = take_u8(r) % 9;
    for (uint32_t i = 0; i < p->d.instruction_count; i++) {
        phos_shader_instruction *in = &p->ins[i];
        in->op = take_u8(r) % (PHOS_OP_COUNT + 1);
        in->mode = take_u32(r);
        in->flags = take_u32(r);
        in->table = take_u32(r);
        take_floats(r, in->param, 4);
        for (int k = 0; k < PHOS_SHADER_MAX_INPUTS; k++)
            in->inputs[k] = take_register(r, registers);
        for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++)
            in->outputs[k] = take_register(r, registers);
    }
    p->d.instructions = take_u8(r) == 0xFF ? NULL : p->ins;
    p->d.table_size = take_u8(r) % 49;
    take_floats(r, p->table, p->d.table_size);
    p->d.table = p->table;
    p->d.binding_count = take_u8(r) % 5;
    for (uint32_t b = 0; b < p->d.binding_count; b++) {
        p->bind[b].closure = take_u8(r) % 3;
        p->bind[b].field = take_u8(r) % (PHOS_FIELD_COUNT + 1);
        p->bind[b].reg = take_register(r, registers);
    }
    p->d.bindings = p->bind;
    return &p->d;
}

static void fuzz_materials(reader *r, phos_scene *s)
{
    uint32_t n = take_u8(r) % 4;
    for (uint32_t i = 0; i < n; i++) {
        phos_closure_desc c[PHOS_MAX_CLOSURES + 1];
        uint32_t count = take_u8(r) % (PHOS_MAX_CLOSURES + 2);
        for (uint32_t k = 0; k < count && k <= PHOS_MAX_CLOSURES; k++) {
            phos_closure_desc_init(&c[k]);
            c[k].type = take_u8(r) % (PHOS_CLOSURE_TYPE_COUNT + 1);
            take_floats(r, c[k].weight, 3);
            c[k].roughness = take_float(r);
            c[k].ior = take_float(r);
            if (take_u8(r) & 1)
                take_floats(r, c[k].specular_color, 3);
            c[k].glass_fresnel = take_u8(r) % 3;
            if (take_u8(r) & 1)
                take_floats(r, c[k].transmission_tint, 3);
            c[k].transmission_roughness = take_float(r);
            c[k].microfacet = take_u8(r) % 4;
            if (take_u8(r) & 1)
                take_floats(r, c[k].multiscatter_fresnel, 3);
            if (take_u8(r) & 1)
                take_floats(r, c[k].specular_tint, 3);
            c[k].thin_film_thickness = take_float(r);
            c[k].thin_film_ior = take_float(r);
            c[k].layer_span = take_u8(r) % (PHOS_MAX_CLOSURES + 2);
            if (take_u8(r) & 1)
                take_floats(r, c[k].layer_weight, 3);
            if (take_u8(r) & 1)
                take_floats(r, c[k].layer_tint, 3);
            c[k].layer_tint_weight = take_float(r);
            if (take_u8(r) & 1) { /* anisotropic GGX */
                c[k].roughness_y = take_float(r);
                c[k].tangent_rotation = take_float(r);
            }
            c[k].normal_correction = take_u8(r) % 4; /* 3 is refused */
        }
        phos_material_desc m;
        phos_material_desc_init(&m);
        m.closure_count = count;
        m.closures = take_u8(r) == 0xFF ? NULL : c;
        fuzz_program p;
        if (take_u8(r))
            m.program = take_program(r, &p);
        uint32_t id;
        phos_status st = phos_scene_add_material(s, &m, &id);
        if (st != PHOS_OK && !phos_scene_error(s)[0])
            abort();
        SAY("  material%s: %s %s\n", m.program ? " with a program" : "", phos_status_string(st),
            st == PHOS_OK ? "" : phos_scene_error(s));
    }
}

#define MAX_VERTICES 24
#define MAX_TRIANGLES 24
#define MAX_ATTRIBUTES 3

/* Extras bit 32: up to MAX_ATTRIBUTES attributes, each an id among a few
 * (so duplicates occur), a type one past the known ones at times, values
 * or NULL; a count byte with its top bit set claims more attributes than
 * the core allows (the core must refuse before reading the array). */
static uint32_t take_attributes(reader *r, uint32_t triangle_count, phos_mesh_attribute *attrs,
                                float values[MAX_ATTRIBUTES][12 * MAX_TRIANGLES])
{
    uint8_t count_byte = take_u8(r);
    uint32_t n = count_byte % (MAX_ATTRIBUTES + 1);
    for (uint32_t k = 0; k < n; k++) {
        attrs[k].id = take_u8(r) % 4;
        uint8_t type = take_u8(r);
        attrs[k].type = type % (PHOS_ATTRIBUTE_TYPE_COUNT + 1);
        take_floats(r, values[k], 12 * triangle_count);
        attrs[k].values = (type & 0x80) ? NULL : values[k];
    }
    return (count_byte & 0x80) ? PHOS_MAX_MESH_ATTRIBUTES + 1 : n;
}

static void fuzz_meshes(reader *r, phos_scene *s)
{
    uint32_t n = take_u8(r) % 4;
    for (uint32_t i = 0; i < n; i++) {
        float pos[3 * MAX_VERTICES], nrm[9 * MAX_TRIANGLES], uv[6 * MAX_TRIANGLES];
        float attr_values[MAX_ATTRIBUTES][12 * MAX_TRIANGLES];
        phos_mesh_attribute attrs[MAX_ATTRIBUTES];
        uint32_t idx[3 * MAX_TRIANGLES], slots[MAX_TRIANGLES];
        phos_mesh_desc d;
        phos_mesh_desc_init(&d);
        d.vertex_count = take_u8(r) % (MAX_VERTICES + 1);
        d.triangle_count = take_u8(r) % (MAX_TRIANGLES + 1);
        take_floats(r, pos, 3 * d.vertex_count);
        for (uint32_t k = 0; k < 3 * d.triangle_count; k++)
            idx[k] = take_u8(r) % (d.vertex_count + 2); /* one index in a few out of range */
        uint8_t extras = take_u8(r);
        if (extras & 1)
            take_floats(r, nrm, 9 * d.triangle_count);
        if (extras & 2)
            take_floats(r, uv, 6 * d.triangle_count);
        if (extras & 4)
            for (uint32_t k = 0; k < d.triangle_count; k++)
                slots[k] = take_u8(r) % 6;
        d.positions = (extras & 8) ? NULL : pos;
        d.indices = (extras & 16) ? NULL : idx;
        d.normals = (extras & 1) ? nrm : NULL;
        d.uvs = (extras & 2) ? uv : NULL;
        d.material_slots = (extras & 4) ? slots : NULL;
        if (extras & 32) {
            d.attribute_count = take_attributes(r, d.triangle_count, attrs, attr_values);
            d.attributes = attrs;
        }
        uint32_t id;
        phos_status st = phos_scene_add_mesh(s, &d, &id);
        SAY("mesh %u×%u: %s %s\n", d.vertex_count, d.triangle_count, phos_status_string(st), phos_scene_error(s));
        if (st != PHOS_OK && !phos_scene_error(s)[0])
            abort();
    }
    uint32_t instances = take_u8(r) % 5;
    for (uint32_t i = 0; i < instances; i++) {
        phos_instance_desc d;
        phos_instance_desc_init(&d);
        d.mesh_id = take_u8(r) % 5;
        if (take_u8(r) & 1)
            take_floats(r, d.transform, 12);
        uint32_t mats[4];
        d.material_count = take_u8(r) % 5;
        for (uint32_t k = 0; k < d.material_count; k++)
            mats[k] = take_u8(r) % 5;
        d.materials = d.material_count ? mats : NULL;
        uint32_t id;
        phos_status st = phos_scene_add_instance(s, &d, &id);
        SAY("instance of mesh %u [%g %g %g %g | %g %g %g %g | %g %g %g %g]: %s %s\n", d.mesh_id, d.transform[0],
            d.transform[1], d.transform[2], d.transform[3], d.transform[4], d.transform[5], d.transform[6],
            d.transform[7], d.transform[8], d.transform[9], d.transform[10], d.transform[11],
            phos_status_string(st), phos_scene_error(s));
        if (st != PHOS_OK && !phos_scene_error(s)[0])
            abort();
    }
}

/* phos_scene_add_instances: a few instances in one call, with fuzzed mesh
 * ids, transforms, material offsets (possibly decreasing) and ids, and
 * NULL arrays. */
static void fuzz_bulk_instances(reader *r, phos_scene *s)
{
    enum { MAX_BULK = 4 };
    uint32_t count = take_u8(r) % (MAX_BULK + 1), ids[MAX_BULK], offsets[MAX_BULK + 1], materials[2 * MAX_BULK];
    float transforms[12 * MAX_BULK], randoms[MAX_BULK];
    offsets[0] = take_u8(r) % 2; /* 1 is refused */
    for (uint32_t k = 0; k < count; k++) {
        ids[k] = take_u8(r) % 5;
        take_floats(r, transforms + 12 * k, 12);
        offsets[k + 1] = take_u8(r) % (2 * MAX_BULK + 1);
        randoms[k] = take_float(r);
    }
    for (uint32_t k = 0; k < 2 * MAX_BULK; k++)
        materials[k] = take_u8(r) % 5;
    uint8_t nulls = take_u8(r);
    phos_instances_desc d = {count, (nulls & 1) ? NULL : ids, (nulls & 2) ? NULL : transforms,
                             (nulls & 4) ? NULL : offsets, (nulls & 8) ? NULL : materials,
                             (nulls & 16) ? NULL : randoms, NULL};
    phos_status st = phos_scene_add_instances(s, &d, NULL);
    SAY("%u instances in one call: %s %s\n", count, phos_status_string(st), phos_scene_error(s));
    if (st != PHOS_OK && !phos_scene_error(s)[0])
        abort();
}

/* phos_vertex_normals on a fuzzed polygon soup (a few polygons of up to
 * 6 corners, starts and totals anywhere). */
static void fuzz_vertex_normals(reader *r)
{
    uint32_t v = take_u8(r) % 9, p = take_u8(r) % 5, l = take_u8(r) % 25;
    float pos[3 * 8], fn[3 * 4], out[3 * 8];
    uint32_t starts[4], totals[4], loops[24];
    take_floats(r, pos, 3 * v);
    for (uint32_t i = 0; i < p; i++) {
        starts[i] = take_u8(r) % 26;
        totals[i] = take_u8(r) % 7;
        take_floats(r, fn + 3 * i, 3);
    }
    for (uint32_t i = 0; i < l; i++)
        loops[i] = take_u8(r) % 10;
    phos_status st = phos_vertex_normals(v, pos, p, starts, totals, fn, l, loops, out);
    SAY("vertex normals of %u polygons: %s\n", p, phos_status_string(st));
}

static void take_light_desc(reader *r, phos_light_desc *out)
{
    phos_light_desc d;
    phos_light_desc_init(&d);
    d.type = take_u8(r) % 5;
    take_floats(r, d.color, 3);
    take_floats(r, d.position, 3);
    take_floats(r, d.direction, 3);
    take_floats(r, d.axis_u, 3);
    take_floats(r, d.axis_v, 3);
    d.area_shape = take_u8(r) % 3;
    d.radius = take_float(r);
    d.point_shape = take_u8(r) % 3;
    d.spot_angle = take_float(r);
    d.spot_blend = take_float(r);
    d.spot_cosine = take_u8(r) % 3;
    d.sun_angle = take_float(r);
    d.camera_visible = take_u8(r) % 3;
    *out = d;
}

/* A camera from the input: Phos's defaults with any of its parts taken
 * (the scene's camera and a render's further views alike). */
static void take_camera(reader *r, phos_camera_desc *c)
{
    phos_camera_desc_init(c);
    c->type = take_u8(r) % 3;
    if (take_u8(r) & 1)
        take_floats(r, c->transform, 12);
    if (take_u8(r) & 1) {
        take_floats(r, c->frame_min, 2);
        take_floats(r, c->frame_max, 2);
    }
    if (take_u8(r) & 1) {
        c->aperture_radius = take_float(r);
        c->focus_distance = take_float(r);
    }
    if (take_u8(r) & 1) {
        c->clip_start = take_float(r);
        c->clip_end = take_float(r);
    }
}

static void fuzz_lights(reader *r, phos_scene *s)
{
    uint32_t n = take_u8(r) % 4;
    for (uint32_t i = 0; i < n; i++) {
        phos_light_desc d;
        take_light_desc(r, &d);
        uint32_t id;
        if (phos_scene_add_light(s, &d, &id) != PHOS_OK && !phos_scene_error(s)[0])
            abort();
    }
    if (take_u8(r) & 1) {
        phos_world_desc w;
        phos_world_desc_init(&w);
        take_floats(r, w.color, 3);
        uint8_t m = take_u8(r); /* a material as the world (any id, valid or not), or 0xFF: none */
        w.material = m == 0xFF ? PHOS_WORLD_NO_MATERIAL : m;
        phos_scene_set_world(s, &w);
    }
    if (take_u8(r) != 0xFF) { /* almost always a camera */
        phos_camera_desc c;
        take_camera(r, &c);
        phos_scene_set_camera(s, &c);
    }
}

/* ----------------------------------------------------------- render */

/* The settings' fields by the table in phos.h: offset and whether float. */
#define FIELD_(type, name, ...) {offsetof(phos_render_settings, name), _Generic(((phos_render_settings *)0)->name, float: 1, default: 0)},
static const struct {
    size_t offset;
    int is_float;
} setting_fields[] = {PHOS_RENDER_SETTINGS(FIELD_, FIELD_)};
#undef FIELD_
#define SETTING_COUNT (sizeof(setting_fields) / sizeof(setting_fields[0]))

static void fuzz_settings(reader *r, phos_render_settings *rs)
{
    phos_render_settings_init(rs);
    /* Small and quick unless the bytes say otherwise. */
    rs->width = 8;
    rs->height = 8;
    rs->samples = 2;
    rs->global_photons = 500;
    rs->caustic_photons = 500;
    rs->ic_rays = 16;
    rs->threads = 2;
    rs->tile_size = 8;
    uint32_t n = take_u8(r) % 12;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t f = take_u8(r) % SETTING_COUNT;
        char *field = (char *)rs + setting_fields[f].offset;
        if (setting_fields[f].is_float) {
            float v = take_float(r);
            memcpy(field, &v, sizeof(v));
        } else {
            uint32_t v = take_u32(r);
            memcpy(field, &v, sizeof(v));
        }
    }
}

/* Every delivered tile's pixels, and a read of a fuzzed rectangle. */
static void read_tiles(reader *r, phos_render *render)
{
    phos_tile t;
    uint32_t count;
    float *buf = NULL;
    size_t cap = 0;
    while (phos_render_next_tile(render, &t, &count) == PHOS_OK && count == 1) {
        for (uint32_t pass = 0; pass < PHOS_PASS_COUNT; pass++) {
            uint32_t ch = phos_pass_channels(pass);
            size_t need = (size_t)t.width * t.height * ch;
            if (need > cap) {
                free(buf);
                cap = need;
                buf = malloc(sizeof(float) * cap);
                if (!buf)
                    return;
            }
            if (phos_render_read(render, pass, t.x, t.y, t.width, t.height, buf, need) != PHOS_OK)
                continue; /* a pass not enabled */
            for (size_t k = 0; k < need; k++)
                if (!isfinite(buf[k])) {
                    fprintf(stderr, "fuzz_api: pass %u pixel value %g is not finite\n", pass, (double)buf[k]);
                    abort();
                }
        }
    }
    free(buf);
    float small[64];
    uint32_t x = take_u32(r), y = take_u32(r), w = take_u8(r) % 5, h = take_u8(r) % 5;
    phos_render_read(render, take_u8(r) % (PHOS_PASS_COUNT + 1), x, y, w, h, small, take_u8(r) % 65);
}

/* One render; *kept holds the photon maps an earlier render of the scene
 * built (phos_render_keep_photon_maps), which this one may be given: taken
 * or refused with a message, never a crash, whatever changed in between. */
static void fuzz_render(reader *r, phos_scene *s, phos_photon_maps **kept)
{
    phos_render_settings rs;
    fuzz_settings(r, &rs);
    phos_render *render = NULL;
    phos_status st = phos_render_create(s, &rs, &render);
    SAY("  render %ux%u integrator %u: %s %s\n", rs.width, rs.height, rs.integrator, phos_status_string(st),
        phos_scene_error(s));
    if (st != PHOS_OK) {
        if (!phos_scene_error(s)[0] || render)
            abort();
        return;
    }
    phos_stage_info stages[PHOS_STAGE_COUNT];
    uint32_t stage_count;
    phos_render_stages(render, stages, take_u8(r) % (PHOS_STAGE_COUNT + 1), &stage_count);
    uint8_t file = take_u8(r);
    char path[64] = "";
    if (file & 1) {
        /* A cache file: the rest of the input written as one, then loaded
         * (a loader must refuse garbage), or a file to save. */
        snprintf(path, sizeof(path), "/tmp/phos_fuzz_%d.cache", (int)getpid());
        uint32_t mode = (file >> 1) % 3, kind = (file >> 3) % 3;
        if (mode == PHOS_CACHE_FILE_LOAD) {
            FILE *f = fopen(path, "wb");
            if (f) {
                fwrite(r->p, 1, r->n, f);
                fclose(f);
            }
        }
        phos_render_set_cache_file(render, kind, path, mode);
    }
    for (uint8_t views = take_u8(r) % 3; views > 0; views--) {
        phos_camera_desc c;
        take_camera(r, &c);
        phos_status added = phos_render_add_view(render, &c);
        SAY("  add view: %s %s\n", phos_status_string(added), phos_render_error(render));
        if (added != PHOS_OK && !phos_render_error(render)[0])
            abort();
    }
    if (*kept) {
        uint8_t use = take_u8(r);
        if (use & 1) {
            phos_status used = phos_render_use_photon_maps(render, *kept, use >> 1 & 1);
            SAY("  use kept maps: %s %s\n", phos_status_string(used), phos_render_error(render));
            if (used != PHOS_OK && !phos_render_error(render)[0])
                abort();
        }
    }
    if (phos_render_start(render) == PHOS_OK) {
        st = phos_render_wait(render, RENDER_BUDGET_S);
        if (st == PHOS_ERROR_TIMEOUT) {
            phos_progress p;
            phos_render_progress(render, &p);
            phos_render_cancel(render);
            st = phos_render_wait(render, CANCEL_LIMIT_S);
            if (st == PHOS_ERROR_TIMEOUT) {
                fprintf(stderr, "fuzz_api: a cancel in stage %u took more than %.1f s\n", p.stage_id,
                        CANCEL_LIMIT_S);
                abort();
            }
        }
        SAY("  ended: %s %s\n", phos_status_string(st), phos_render_error(render));
        if (st != PHOS_OK && st != PHOS_ERROR_CANCELLED && !phos_render_error(render)[0])
            abort();
        read_tiles(r, render);
    }
    phos_photon_maps *maps = NULL;
    if (phos_render_keep_photon_maps(render, &maps) == PHOS_OK) {
        phos_photon_maps_release(*kept);
        *kept = maps;
    }
    phos_progress p;
    phos_render_progress(render, &p);
    SAY("  stages (s):");
    for (uint32_t i = 0; i < PHOS_STAGE_COUNT; i++)
        SAY(" %.3f", p.stage_seconds[i]);
    SAY("; photons %u stored of %llu emitted\n", p.photons_stored, (unsigned long long)p.photons_emitted);
    phos_render_destroy(render);
    if (path[0])
        remove(path);
}

/* Scene updates after a commit (phos.h): a few replacements by id (any id,
 * valid or not) of a light, an instance and a mesh, then more of
 * everything added; each refused with a message or taken. */
static void fuzz_updates(reader *r, phos_scene *s)
{
    uint32_t n = take_u8(r) % 4;
    for (uint32_t i = 0; i < n; i++) {
        uint8_t kind = take_u8(r) % 3, id = take_u8(r) % 6;
        phos_status st;
        if (kind == 0) {
            phos_light_desc d;
            take_light_desc(r, &d);
            st = phos_scene_update_light(s, id, &d);
        } else if (kind == 1) {
            phos_instance_desc d;
            phos_instance_desc_init(&d);
            d.mesh_id = take_u8(r) % 5;
            take_floats(r, d.transform, 12);
            st = phos_scene_update_instance(s, id, &d);
        } else {
            float pos[3 * MAX_VERTICES];
            uint32_t idx[3 * MAX_TRIANGLES];
            phos_mesh_desc d;
            phos_mesh_desc_init(&d);
            d.vertex_count = take_u8(r) % (MAX_VERTICES + 1);
            d.triangle_count = take_u8(r) % (MAX_TRIANGLES + 1);
            take_floats(r, pos, 3 * d.vertex_count);
            for (uint32_t k = 0; k < 3 * d.triangle_count; k++)
                idx[k] = take_u8(r) % (d.vertex_count + 2);
            d.positions = pos;
            d.indices = idx;
            st = phos_scene_update_mesh(s, id, &d);
        }
        SAY("update %u of id %u: %s %s\n", kind, id, phos_status_string(st), phos_scene_error(s));
        if (st != PHOS_OK && !phos_scene_error(s)[0])
            abort();
    }
    fuzz_meshes(r, s);
    fuzz_lights(r, s);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    reader r = {data, size};
    SAY("input of %zu bytes\n", size);
    phos_scene *s = phos_scene_create();
    if (!s)
        return 0;
    fuzz_images(&r, s);
    fuzz_materials(&r, s);
    fuzz_meshes(&r, s);
    uint8_t extra = take_u8(&r);
    if (extra == 0x5A)
        fuzz_vertex_normals(&r);
    else if (extra == 0x5C)
        fuzz_bulk_instances(&r, s);
    fuzz_lights(&r, s);
    uint8_t commit = take_u8(&r);
    if (commit == 0xFE)
        phos_scene_cancel(s);
    phos_status committed = commit == 0xFF ? PHOS_ERROR_INVALID_STATE : phos_scene_commit(s);
    SAY("scene: commit %s %s\n", phos_status_string(committed), phos_scene_error(s));
    phos_photon_maps *kept = NULL;
    if (committed == PHOS_OK) {
        uint32_t renders = 1 + take_u8(&r) % 2; /* two renders may share a scene */
        for (uint32_t i = 0; i < renders; i++)
            fuzz_render(&r, s, &kept);
        if (take_u8(&r) == 0x5B) { /* changed and committed again */
            fuzz_updates(&r, s);
            phos_status again = phos_scene_commit(s);
            SAY("scene: commit again %s %s\n", phos_status_string(again), phos_scene_error(s));
            if (again == PHOS_OK)
                fuzz_render(&r, s, &kept);
            else if (!phos_scene_error(s)[0])
                abort();
        }
    } else if (commit != 0xFF && !phos_scene_error(s)[0]) {
        abort();
    }
    phos_scene_destroy(s);
    phos_photon_maps_release(kept); /* may outlive its scene */
    SAY("done\n");
    return 0;
}
