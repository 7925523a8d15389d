/*
 * test_scenes.h — small scenes built through the public API for the C
 * tests, and a helper that renders them synchronously.
 */
#ifndef PHOS_TEST_SCENES_H
#define PHOS_TEST_SCENES_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phos.h"

/* A UV sphere of `radius` at the origin, normals pointing outward (or
 * inward if `inward`), with smooth per-corner normals if `smooth`, else the
 * faces' own. Returns the mesh id. */
static uint32_t test_add_sphere_mesh_shaded(phos_scene *s, float radius, int segments, int rings, int inward,
                                            int smooth)
{
    uint32_t nv = (uint32_t)((rings + 1) * (segments + 1));
    uint32_t nt = (uint32_t)(2 * rings * segments);
    float *pos = malloc(sizeof(float) * 3 * nv);
    uint32_t *idx = malloc(sizeof(uint32_t) * 3 * nt);
    float *nrm = malloc(sizeof(float) * 9 * nt);
    uint32_t t = 0;
    for (int r = 0; r <= rings; r++) {
        double th = M_PI * r / rings;
        for (int sg = 0; sg <= segments; sg++) {
            double ph = 2.0 * M_PI * sg / segments;
            float *p = pos + 3 * (r * (segments + 1) + sg);
            p[0] = (float)(radius * sin(th) * cos(ph));
            p[1] = (float)(radius * sin(th) * sin(ph));
            p[2] = (float)(radius * cos(th));
        }
    }
    for (int r = 0; r < rings; r++) {
        for (int sg = 0; sg < segments; sg++) {
            uint32_t a = (uint32_t)(r * (segments + 1) + sg), b = a + 1;
            uint32_t c = a + (uint32_t)(segments + 1), d = c + 1;
            uint32_t tri[2][3] = {{a, c, b}, {b, c, d}};
            for (int k = 0; k < 2; k++) {
                if (inward) {
                    uint32_t tmp = tri[k][1];
                    tri[k][1] = tri[k][2];
                    tri[k][2] = tmp;
                }
                for (int j = 0; j < 3; j++) {
                    idx[3 * t + j] = tri[k][j];
                    const float *p = pos + 3 * tri[k][j];
                    float sgn = inward ? -1.0f : 1.0f;
                    for (int c2 = 0; c2 < 3; c2++)
                        nrm[9 * t + 3 * j + c2] = sgn * p[c2] / radius;
                }
                t++;
            }
        }
    }
    phos_mesh_desc md;
    phos_mesh_desc_init(&md);
    md.vertex_count = nv;
    md.positions = pos;
    md.triangle_count = t;
    md.indices = idx;
    md.normals = smooth ? nrm : NULL;
    uint32_t id = 0;
    phos_scene_add_mesh(s, &md, &id);
    free(pos);
    free(idx);
    free(nrm);
    return id;
}

static uint32_t test_add_sphere_mesh(phos_scene *s, float radius, int segments, int rings, int inward)
{
    return test_add_sphere_mesh_shaded(s, radius, segments, rings, inward, 1);
}

/* A square of side 2·half in the z = 0 plane, normal +Z. */
static uint32_t test_add_quad_mesh(phos_scene *s, float half)
{
    float pos[12] = {-half, -half, 0, half, -half, 0, half, half, 0, -half, half, 0};
    uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    phos_mesh_desc md;
    phos_mesh_desc_init(&md);
    md.vertex_count = 4;
    md.positions = pos;
    md.triangle_count = 2;
    md.indices = idx;
    uint32_t id = 0;
    phos_scene_add_mesh(s, &md, &id);
    return id;
}

/* A mesh of `count` flat quads, each given by its four corners in order
 * (the normal follows the right-hand rule). Returns the mesh id. */
static uint32_t test_add_quads(phos_scene *s, const float (*quads)[4][3], uint32_t count)
{
    float *pos = malloc(sizeof(float) * 12 * count);
    uint32_t *idx = malloc(sizeof(uint32_t) * 6 * count);
    for (uint32_t q = 0; q < count; q++) {
        memcpy(pos + 12 * q, quads[q], sizeof(float) * 12);
        uint32_t tri[6] = {0, 1, 2, 0, 2, 3};
        for (int j = 0; j < 6; j++)
            idx[6 * q + j] = 4 * q + tri[j];
    }
    phos_mesh_desc md;
    phos_mesh_desc_init(&md);
    md.vertex_count = 4 * count;
    md.positions = pos;
    md.triangle_count = 2 * count;
    md.indices = idx;
    uint32_t id = 0;
    phos_scene_add_mesh(s, &md, &id);
    free(pos);
    free(idx);
    return id;
}

/* A material of `count` closures (a mix, their weights already split);
 * returns its id. */
static uint32_t test_add_mix_material(phos_scene *s, const phos_closure_desc *c, uint32_t count)
{
    phos_material_desc m;
    phos_material_desc_init(&m);
    m.closure_count = count;
    m.closures = c;
    uint32_t id = 0;
    phos_scene_add_material(s, &m, &id);
    return id;
}

/* A material of one closure; returns its id. */
static uint32_t test_add_closure_material(phos_scene *s, const phos_closure_desc *c)
{
    return test_add_mix_material(s, c, 1);
}

/* Clear sharp glass of index ior. */
static uint32_t test_add_glass(phos_scene *s, float ior)
{
    phos_closure_desc c;
    phos_closure_desc_init(&c);
    c.type = PHOS_CLOSURE_GLASS;
    c.weight[0] = c.weight[1] = c.weight[2] = 1.0f;
    c.roughness = 0.0f;
    c.ior = ior;
    return test_add_closure_material(s, &c);
}

/* A sharp mirror (Glossy of roughness 0, white). */
static uint32_t test_add_mirror(phos_scene *s)
{
    phos_closure_desc c;
    phos_closure_desc_init(&c);
    c.type = PHOS_CLOSURE_REFLECTION;
    c.roughness = 0.0f;
    return test_add_closure_material(s, &c);
}

static uint32_t test_add_diffuse(phos_scene *s, float r, float g, float b)
{
    phos_closure_desc c;
    phos_closure_desc_init(&c);
    c.type = PHOS_CLOSURE_DIFFUSE;
    c.weight[0] = r;
    c.weight[1] = g;
    c.weight[2] = b;
    return test_add_closure_material(s, &c);
}

static uint32_t test_add_instance(phos_scene *s, uint32_t mesh, uint32_t material, float tx, float ty, float tz)
{
    phos_instance_desc d;
    phos_instance_desc_init(&d);
    d.mesh_id = mesh;
    d.transform[3] = tx;
    d.transform[7] = ty;
    d.transform[11] = tz;
    d.material_count = 1;
    d.materials = &material;
    uint32_t id = 0;
    phos_scene_add_instance(s, &d, &id);
    return id;
}

/* A square of side 2·half at height z, facing down (normal −Z). */
static uint32_t test_add_ceiling(phos_scene *s, float half, float z, uint32_t material)
{
    phos_instance_desc d;
    phos_instance_desc_init(&d);
    d.mesh_id = test_add_quad_mesh(s, half);
    float t[12] = {1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1, z}; /* a half turn about X */
    memcpy(d.transform, t, sizeof(t));
    d.material_count = 1;
    d.materials = &material;
    uint32_t id = 0;
    phos_scene_add_instance(s, &d, &id);
    return id;
}

/* Camera at `pos` looking down −Z (identity rotation), field of view given
 * by tan of the half angle. */
static void test_set_camera(phos_scene *s, float x, float y, float z, float tan_half)
{
    phos_camera_desc c;
    phos_camera_desc_init(&c);
    c.transform[3] = x;
    c.transform[7] = y;
    c.transform[11] = z;
    c.frame_min[0] = c.frame_min[1] = -tan_half;
    c.frame_max[0] = c.frame_max[1] = tan_half;
    c.clip_start = 1e-3f;
    c.clip_end = 1e4f;
    phos_scene_set_camera(s, &c);
}

/* Camera at (x, y, z) pitched down by `pitch` radians from looking along
 * −Z (a rotation about X: −Z maps to (0, sin p, −cos p)), of square frame
 * ±tan_half. */
static phos_camera_desc test_camera_pitched(float x, float y, float z, float pitch, float tan_half)
{
    phos_camera_desc c;
    phos_camera_desc_init(&c);
    float cp = cosf(pitch), sp = sinf(pitch);
    float m[12] = {1, 0, 0, x, 0, cp, -sp, y, 0, sp, cp, z};
    memcpy(c.transform, m, sizeof(m));
    c.frame_min[0] = c.frame_min[1] = -tan_half;
    c.frame_max[0] = c.frame_max[1] = tan_half;
    c.clip_start = 1e-3f;
    c.clip_end = 1e4f;
    return c;
}

/* The scene's camera, as test_camera_pitched. */
static void test_set_camera_pitched(phos_scene *s, float x, float y, float z, float pitch, float tan_half)
{
    phos_camera_desc c = test_camera_pitched(x, y, z, pitch, tan_half);
    phos_scene_set_camera(s, &c);
}

/* The Cornell box of scenes/cornell_box.py in spirit: a 2 m box open
 * toward the camera, red and green side walls, a square area light under
 * the ceiling, a glass and a mirror sphere (if `spheres`). Committed;
 * NULL if the commit fails. */
static phos_scene *test_cornell_box(int spheres)
{
    const float a = 1.0f, h = 2.0f;
    float white[3][4][3] = {
        {{-a, -a, 0}, {a, -a, 0}, {a, a, 0}, {-a, a, 0}}, /* floor, +z */
        {{-a, -a, h}, {-a, a, h}, {a, a, h}, {a, -a, h}}, /* ceiling, −z */
        {{-a, a, 0}, {a, a, 0}, {a, a, h}, {-a, a, h}},   /* back wall y = a, −y */
    };
    float red[1][4][3] = {{{-a, -a, 0}, {-a, a, 0}, {-a, a, h}, {-a, -a, h}}}; /* x = −a, +x */
    float green[1][4][3] = {{{a, -a, 0}, {a, -a, h}, {a, a, h}, {a, a, 0}}};   /* x = +a, −x */
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_quads(s, (const float(*)[4][3])white, 3), test_add_diffuse(s, 0.73f, 0.73f, 0.73f),
                      0, 0, 0);
    test_add_instance(s, test_add_quads(s, (const float(*)[4][3])red, 1), test_add_diffuse(s, 0.63f, 0.06f, 0.05f),
                      0, 0, 0);
    test_add_instance(s, test_add_quads(s, (const float(*)[4][3])green, 1), test_add_diffuse(s, 0.14f, 0.45f, 0.09f),
                      0, 0, 0);
    if (spheres) {
        test_add_instance(s, test_add_sphere_mesh(s, 0.35f, 64, 32, 0), test_add_glass(s, 1.5f), -0.4f, 0.2f, 0.35f);
        test_add_instance(s, test_add_sphere_mesh(s, 0.35f, 64, 32, 0), test_add_mirror(s), 0.45f, 0.45f, 0.35f);
    }
    phos_light_desc l;
    phos_light_desc_init(&l);
    l.type = PHOS_LIGHT_AREA;
    l.position[2] = h - 0.01f;
    l.direction[2] = -1.0f;
    l.axis_u[0] = 0.5f;
    l.axis_v[1] = 0.5f;
    l.color[0] = l.color[1] = l.color[2] = 15.0f; /* W/(m²·sr) */
    phos_scene_add_light(s, &l, NULL);
    test_set_camera_pitched(s, 0.0f, -3.6f, 1.0f, 1.5707963f, 0.32f);
    if (phos_scene_commit(s) != PHOS_OK) {
        phos_scene_destroy(s);
        return NULL;
    }
    return s;
}

/* The world as the add-on writes a textured one: Texture Coordinate's
 * Generated (the direction, registers 0-2) into `texture` (its op, mode,
 * flags and table set by the caller; its input and output are filled in
 * here), whose Color (registers 3-5) is the weight of the world's one
 * EMISSION closure; `table` the program's floats. Returns the status of
 * adding the material. */
static phos_status test_set_world_texture(phos_scene *s, phos_shader_instruction texture, const float *table,
                                          uint32_t table_size)
{
    phos_shader_instruction ins[2];
    memset(ins, 0, sizeof(ins));
    ins[1] = texture;
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++)
            ins[i].outputs[k] = PHOS_SHADER_NO_REGISTER;
    ins[0].op = PHOS_OP_TEXTURE_COORDINATE;
    ins[0].outputs[0] = 0;
    ins[1].inputs[0] = 0;
    ins[1].outputs[0] = 3;
    phos_shader_binding bind = {0, PHOS_FIELD_WEIGHT, 3};
    phos_shader_program_desc p;
    memset(&p, 0, sizeof(p));
    p.register_count = 6;
    p.instructions = ins;
    p.instruction_count = 2;
    p.table = table;
    p.table_size = table_size;
    p.bindings = &bind;
    p.binding_count = 1;
    phos_closure_desc c;
    phos_closure_desc_init(&c);
    c.type = PHOS_CLOSURE_EMISSION;
    c.weight[0] = c.weight[1] = c.weight[2] = 1.0f;
    phos_material_desc m;
    phos_material_desc_init(&m);
    m.closure_count = 1;
    m.closures = &c;
    m.program = &p;
    phos_world_desc wd;
    phos_world_desc_init(&wd);
    phos_status st = phos_scene_add_material(s, &m, &wd.material);
    return st == PHOS_OK ? phos_scene_set_world(s, &wd) : st;
}

/* A world lit by an image of w × h linear RGBA pixels (rows bottom-up),
 * through an Environment Texture of the given projection (enum
 * phos_image_projection) fed by Texture Coordinate's Generated: the
 * world's program, as the add-on writes it for an HDR. */
static void test_set_environment(phos_scene *s, const float *pixels, uint32_t w, uint32_t h, uint32_t projection,
                                 uint32_t interpolation)
{
    phos_image_desc im;
    phos_image_desc_init(&im);
    im.width = w, im.height = h, im.pixels = pixels;
    uint32_t image = 0;
    phos_scene_add_image(s, &im, &image);
    phos_shader_instruction tex;
    memset(&tex, 0, sizeof(tex));
    tex.op = PHOS_OP_TEX_IMAGE;
    tex.mode = projection;
    tex.flags = interpolation;
    tex.table = image;
    test_set_world_texture(s, tex, NULL, 0);
}

/* A 32 × 16 sky of radiance `background` with a patch of radiance `patch`
 * over rows [row0, 16) and columns [col0, col1) (rows bottom-up: high
 * rows are near the zenith), as the world. */
static void test_set_sky_with_patch(phos_scene *s, float background, float patch, int row0, int col0, int col1)
{
    float *px = malloc(sizeof(float) * 32 * 16 * 4);
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 32; x++) {
            float *q = px + 4 * (y * 32 + x);
            q[0] = q[1] = q[2] = y >= row0 && x >= col0 && x < col1 ? patch : background;
            q[3] = 1.0f;
        }
    test_set_environment(s, px, 32, 16, PHOS_PROJECTION_EQUIRECTANGULAR, PHOS_IMAGE_LINEAR);
    free(px);
}

/* Renders synchronously; returns a malloc'd RGBA image or NULL. */
static float *test_render(phos_scene *s, const phos_render_settings *rs)
{
    phos_render *r = NULL;
    if (phos_render_create(s, rs, &r) != PHOS_OK)
        return NULL;
    if (phos_render_start(r) != PHOS_OK || phos_render_wait(r, -1.0) != PHOS_OK) {
        phos_render_destroy(r);
        return NULL;
    }
    uint32_t w = rs->region_width ? rs->region_width : rs->width;
    uint32_t h = rs->region_height ? rs->region_height : rs->height;
    float *img = malloc(sizeof(float) * 4 * w * h);
    if (phos_render_read(r, PHOS_PASS_COMBINED, rs->region_x, rs->region_y, w, h, img, (size_t)4 * w * h) != PHOS_OK) {
        free(img);
        img = NULL;
    }
    phos_render_destroy(r);
    return img;
}

/* Mean over n pixels and their RGB channels of an image of `channels`
 * floats a pixel. */
static double test_mean_rgb(const float *img, uint32_t channels, uint32_t n)
{
    double m = 0.0;
    for (uint32_t i = 0; i < n; i++)
        m += img[i * channels] + img[i * channels + 1] + img[i * channels + 2];
    return m / (3.0 * n);
}

/* Root mean square over n pixels and their RGB channels of a − b, images
 * of `channels` floats a pixel. */
static double test_rms_difference(const float *a, const float *b, uint32_t channels, uint32_t n)
{
    double sum = 0.0;
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t c = 0; c < 3; c++) {
            double d = (double)a[i * channels + c] - b[i * channels + c];
            sum += d * d;
        }
    return sqrt(sum / (3.0 * n));
}

/* Mean and standard error of the mean of one channel over all pixels. */
static void test_image_stats(const float *img, size_t pixels, int channel, double *mean, double *stderr_mean)
{
    double s = 0.0, s2 = 0.0;
    for (size_t i = 0; i < pixels; i++) {
        double v = img[4 * i + channel];
        s += v;
        s2 += v * v;
    }
    *mean = s / (double)pixels;
    double var = s2 / (double)pixels - (*mean) * (*mean);
    *stderr_mean = sqrt(fmax(var, 0.0) / (double)pixels);
}

#endif /* PHOS_TEST_SCENES_H */
