/*
 * test_shader_program.c — shader programs through the public API
 * (docs/architecture.md, "Shader programs"): what phos_scene_add_material
 * refuses, that constant programs fold away, and that a program's values
 * reach the closures a render shades with: an emissive quad whose colour
 * is a program of its UV coordinates renders that colour in every pixel.
 */
#include <string.h>

#include "phos.h"
#include "scene/scene.h"
#include "shading/material.h"
#include "test_scenes.h"
#include "test_util.h"

#define NO PHOS_SHADER_NO_REGISTER

static phos_shader_instruction instruction(uint32_t op, uint32_t mode)
{
    phos_shader_instruction i;
    memset(&i, 0, sizeof(i));
    i.op = op;
    i.mode = mode;
    for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++)
        i.outputs[k] = NO;
    return i;
}

static phos_status add(phos_scene *s, const phos_closure_desc *c, const phos_shader_program_desc *p, uint32_t *id)
{
    phos_material_desc m;
    phos_material_desc_init(&m);
    m.closure_count = 1;
    m.closures = c;
    m.program = p;
    return phos_scene_add_material(s, &m, id);
}

static phos_closure_desc emission(void)
{
    phos_closure_desc c;
    phos_closure_desc_init(&c);
    c.type = PHOS_CLOSURE_EMISSION;
    c.weight[0] = c.weight[1] = c.weight[2] = 1.0f;
    return c;
}

/* Registers: 0-2 constants (0.25, 2, 0.5); the program's own from 3. */
static const float constants[3] = {0.25f, 2.0f, 0.5f};

static void test_refusals(void)
{
    phos_scene *s = phos_scene_create();
    phos_closure_desc c = emission();
    phos_shader_instruction ins[2];
    phos_shader_binding bind = {0, PHOS_FIELD_WEIGHT, 3};
    phos_shader_program_desc p;
    memset(&p, 0, sizeof(p));
    p.register_count = 6;
    p.constant_count = 3;
    p.constants = constants;
    p.instructions = ins;
    p.instruction_count = 1;
    p.bindings = &bind;
    p.binding_count = 1;

    /* A valid program: COMBINE_XYZ of three constants into 3..5. */
    ins[0] = instruction(PHOS_OP_COMBINE_XYZ, 0);
    ins[0].inputs[0] = 0, ins[0].inputs[1] = 1, ins[0].inputs[2] = 2, ins[0].outputs[0] = 3;
    CHECK(add(s, &c, &p, NULL) == PHOS_OK);

    ins[0].op = PHOS_OP_COUNT; /* unknown op */
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(phos_scene_error(s), "unknown op") != NULL);
    ins[0].op = PHOS_OP_COMBINE_XYZ;

    ins[0].inputs[1] = 4; /* read before anything writes it */
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(phos_scene_error(s), "before any instruction writes it") != NULL);
    ins[0].inputs[1] = 99; /* beyond the register file */
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    ins[0].inputs[1] = 1;

    ins[0].outputs[0] = 1; /* over a constant */
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    ins[0].outputs[0] = 4; /* 4..6: past the end */
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    ins[0].outputs[0] = 3;

    ins[0].op = PHOS_OP_MATH, ins[0].mode = PHOS_MATH_COUNT; /* unknown mode */
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    ins[0].op = PHOS_OP_COMBINE_XYZ, ins[0].mode = 0;

    ins[0].op = PHOS_OP_TEX_IMAGE; /* the scene has no image 0 */
    ins[0].inputs[0] = 0;
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    CHECK(strstr(phos_scene_error(s), "image") != NULL);
    ins[0] = instruction(PHOS_OP_COMBINE_XYZ, 0);
    ins[0].inputs[0] = 0, ins[0].inputs[1] = 1, ins[0].inputs[2] = 2, ins[0].outputs[0] = 3;

    ins[0].op = PHOS_OP_RAMP; /* a ramp reading past the table */
    ins[0].mode = 256;
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    ins[0] = instruction(PHOS_OP_COMBINE_XYZ, 0);
    ins[0].inputs[0] = 0, ins[0].inputs[1] = 1, ins[0].inputs[2] = 2, ins[0].outputs[0] = 3;

    bind.closure = 1; /* the material has one closure */
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    bind.closure = 0, bind.field = PHOS_FIELD_COUNT;
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    bind.field = PHOS_FIELD_WEIGHT, bind.reg = 5; /* 5..7: past the end */
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    bind.reg = 3;

    float bad[3] = {0.0f, NAN, 0.0f};
    p.constants = bad;
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    p.constants = constants;
    p.register_count = PHOS_SHADER_MAX_REGISTERS + 1;
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    p.register_count = 6;
    p.instructions = NULL;
    CHECK(add(s, &c, &p, NULL) == PHOS_ERROR_INVALID_ARGUMENT);
    phos_scene_destroy(s);
}

/* A program of constants only folds into the closures: nothing is kept. */
static void test_folding(void)
{
    phos_scene *s = phos_scene_create();
    phos_closure_desc c = emission();
    phos_shader_instruction ins[2];
    /* 3..5 = (0.25, 2, 0.5); 6..8 = 3..5 · 2 (Vector Math SCALE); 9 = value out */
    ins[0] = instruction(PHOS_OP_COMBINE_XYZ, 0);
    ins[0].inputs[0] = 0, ins[0].inputs[1] = 1, ins[0].inputs[2] = 2, ins[0].outputs[0] = 3;
    ins[1] = instruction(PHOS_OP_VECTOR_MATH, PHOS_VECTOR_MATH_SCALE);
    ins[1].inputs[0] = 3, ins[1].inputs[1] = 3, ins[1].inputs[2] = 3, ins[1].inputs[3] = 1;
    ins[1].outputs[0] = 6, ins[1].outputs[1] = 9;
    phos_shader_binding bind = {0, PHOS_FIELD_WEIGHT, 6};
    phos_shader_program_desc p;
    memset(&p, 0, sizeof(p));
    p.register_count = 10;
    p.constant_count = 3;
    p.constants = constants;
    p.instructions = ins;
    p.instruction_count = 2;
    p.bindings = &bind;
    p.binding_count = 1;
    uint32_t id = 0;
    CHECK(add(s, &c, &p, &id) == PHOS_OK);
    const material *m = &s->materials[id];
    CHECK(!m->has_program);
    CHECK_MSG(m->closures[0].weight[0] == 0.5f && m->closures[0].weight[1] == 4.0f && m->closures[0].weight[2] == 1.0f,
              "folded weight (%g, %g, %g), expected (0.5, 4, 1)", (double)m->closures[0].weight[0],
              (double)m->closures[0].weight[1], (double)m->closures[0].weight[2]);
    phos_scene_destroy(s);
}

/* Emission colour (u, v, 0.25) from Texture Coordinate's UV: a quad that
 * fills the frame renders its UV coordinates, pixel by pixel. */
static void test_uv_emission_render(void)
{
    phos_scene *s = phos_scene_create();
    float pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    float uvs[12] = {0, 0, 1, 0, 1, 1, 0, 0, 1, 1, 0, 1};
    phos_mesh_desc md;
    phos_mesh_desc_init(&md);
    md.vertex_count = 4, md.positions = pos, md.triangle_count = 2, md.indices = idx, md.uvs = uvs;
    uint32_t mesh = 0;
    CHECK(phos_scene_add_mesh(s, &md, &mesh) == PHOS_OK);

    phos_closure_desc c = emission();
    phos_shader_instruction ins[2];
    /* 3..17: Texture Coordinate (generated, normal, uv at 9..11, object, camera);
     * 18..20 = Combine XYZ(u, v, 0.25). */
    ins[0] = instruction(PHOS_OP_TEXTURE_COORDINATE, 0);
    for (int k = 0; k < 5; k++)
        ins[0].outputs[k] = 3 + 3 * (uint32_t)k;
    ins[1] = instruction(PHOS_OP_COMBINE_XYZ, 0);
    ins[1].inputs[0] = 9, ins[1].inputs[1] = 10, ins[1].inputs[2] = 0, ins[1].outputs[0] = 18;
    phos_shader_binding bind = {0, PHOS_FIELD_WEIGHT, 18};
    phos_shader_program_desc p;
    memset(&p, 0, sizeof(p));
    p.register_count = 21;
    p.constant_count = 3;
    p.constants = constants;
    p.instructions = ins;
    p.instruction_count = 2;
    p.bindings = &bind;
    p.binding_count = 1;
    uint32_t mat = 0;
    CHECK(add(s, &c, &p, &mat) == PHOS_OK);
    CHECK(s->materials[mat].has_program);
    test_add_instance(s, mesh, mat, 0.0f, 0.0f, 0.0f);
    test_set_camera(s, 0.0f, 0.0f, 2.0f, 0.5f); /* sees [−1, 1]² at z = 0 */
    CHECK(phos_scene_commit(s) == PHOS_OK);

    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 16;
    rs.samples = 4;
    rs.filter_width = 0.01f;
    rs.integrator = PHOS_INTEGRATOR_PATH;
    float *img = test_render(s, &rs);
    CHECK(img != NULL);
    if (img) {
        double worst = 0.0;
        for (int y = 0; y < 16; y++)
            for (int x = 0; x < 16; x++) {
                const float *px = img + 4 * (y * 16 + x);
                double u = (x + 0.5) / 16.0, v = (y + 0.5) / 16.0;
                worst = fmax(worst, fabs(px[0] - u));
                worst = fmax(worst, fabs(px[1] - v));
                worst = fmax(worst, fabs(px[2] - 0.25));
            }
        CHECK_MSG(worst < 2e-3, "a pixel differs from its UV coordinates by %g", worst);
        free(img);
    }
    phos_scene_destroy(s);
}

/* The ATTRIBUTE op at a point of a triangle whose corners hold
 * (1,0,0,0), (0,1,0,1), (0,0,1,0.5): barycentric interpolation, and each
 * type's outputs (Cycles' Attribute node: Fac the mean of three numbers,
 * a 2D attribute's first; Alpha a colour's fourth, else 1); a mesh
 * without the id reads 0 with alpha 1. */
static void test_attribute_op(void)
{
    float corners[12] = {1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1, 0.5f};
    mesh_attribute attr = {5, PHOS_ATTRIBUTE_COLOR, corners};
    mesh m;
    memset(&m, 0, sizeof(m));
    m.triangle_count = 1;
    m.attribute_count = 1;
    m.attributes = &attr;
    shader_globals g;
    memset(&g, 0, sizeof(g));
    g.mesh = &m;
    g.b1 = 0.2f, g.b2 = 0.3f; /* b0 = 0.5 */
    phos_shader_instruction ins = instruction(PHOS_OP_ATTRIBUTE, 0);
    ins.table = 5;
    ins.outputs[0] = 0, ins.outputs[1] = 3, ins.outputs[2] = 6, ins.outputs[3] = 7;
    shader_program p;
    memset(&p, 0, sizeof(p));
    p.register_count = 8;
    p.instruction_count = 1;
    p.instructions = &ins;
    float r[8];
    const float expect[4][4] = {/* color/vector x, y, z, fac, alpha by type FLOAT, FLOAT2, VECTOR, COLOR */
                                {0.5f, 0.5f, 0.5f, 0.5f}, {0.5f, 0.2f, 0.0f, 0.5f},
                                {0.5f, 0.2f, 0.3f, 1.0f / 3.0f}, {0.5f, 0.2f, 0.3f, 1.0f / 3.0f}};
    const float alpha[4] = {1.0f, 1.0f, 1.0f, 0.2f + 0.15f};
    for (uint32_t type = 0; type < PHOS_ATTRIBUTE_TYPE_COUNT; type++) {
        attr.type = type;
        shader_program_eval(&p, NULL, &g, r);
        for (int k = 0; k < 3; k++) {
            CHECK_MSG(fabsf(r[k] - expect[type][k]) < 1e-6f && r[3 + k] == r[k], "type %u component %d: %g",
                      type, k, (double)r[k]);
        }
        CHECK_MSG(fabsf(r[6] - expect[type][3]) < 1e-6f, "type %u fac %g", type, (double)r[6]);
        CHECK_MSG(fabsf(r[7] - alpha[type]) < 1e-6f, "type %u alpha %g", type, (double)r[7]);
    }
    ins.table = 6; /* another name: not on this mesh */
    shader_program_eval(&p, NULL, &g, r);
    CHECK(r[0] == 0.0f && r[1] == 0.0f && r[2] == 0.0f && r[6] == 0.0f && r[7] == 1.0f);
    ins.flags = 1; /* the Color Attribute node's missing alpha */
    shader_program_eval(&p, NULL, &g, r);
    CHECK(r[0] == 0.0f && r[7] == 0.0f);
    ins.flags = 0;
    g.mesh = NULL; /* the globals of a program that does not read attributes */
    ins.table = 5;
    shader_program_eval(&p, NULL, &g, r);
    CHECK(r[0] == 0.0f && r[7] == 1.0f);

    /* At a Bump's moved points (modes 1, 2): the triangle (0,0,0), (1,0,0),
     * (0,1,0) with steps of 0.1 along x and y moves b1, then b2, by
     * 0.1; a FLOAT attribute of corners (0, 1, 0) reads b1. */
    float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    uint32_t indices[3] = {0, 1, 2};
    float b1_corners[12] = {0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0};
    mesh_attribute b1_attr = {5, PHOS_ATTRIBUTE_FLOAT, b1_corners};
    m.positions = positions, m.indices = indices, m.vertex_count = 3;
    m.attributes = &b1_attr;
    g.mesh = &m;
    g.Ng = g.N = v3(0.0f, 0.0f, 1.0f);
    g.dPdx = v3(0.1f, 0.0f, 0.0f); /* the footprint's steps, taken whole (filter width 1) */
    g.dPdy = v3(0.0f, 0.1f, 0.0f);
    ins.param[0] = 1.0f;
    const float moved[3] = {0.2f, 0.3f, 0.2f}; /* b1 at the point, after dx, after dy */
    for (uint32_t mode = 0; mode < 3; mode++) {
        ins.mode = mode;
        shader_program_eval(&p, NULL, &g, r);
        CHECK_MSG(fabsf(r[6] - moved[mode]) < 1e-6f, "mode %u: %g", mode, (double)r[6]);
    }
}

/* A quad whose corners carry a colour attribute equal to their UVs (and
 * blue 0.25) renders, through ATTRIBUTE → emission, the same picture as
 * test_uv_emission_render: the attribute reaches the render, interpolated
 * per pixel, only for the program that reads it (its needs mask). */
static void test_attribute_emission_render(void)
{
    phos_scene *s = phos_scene_create();
    float pos[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    uint32_t idx[6] = {0, 1, 2, 0, 2, 3};
    float colors[24] = {0, 0, 0.25f, 1, 1, 0, 0.25f, 1, 1, 1, 0.25f, 1,
                        0, 0, 0.25f, 1, 1, 1, 0.25f, 1, 0, 1, 0.25f, 1};
    phos_mesh_attribute attr = {2, PHOS_ATTRIBUTE_COLOR, colors};
    phos_mesh_desc md;
    phos_mesh_desc_init(&md);
    md.vertex_count = 4, md.positions = pos, md.triangle_count = 2, md.indices = idx;
    md.attribute_count = 1, md.attributes = &attr;
    uint32_t mesh = 0;
    CHECK(phos_scene_add_mesh(s, &md, &mesh) == PHOS_OK);

    phos_closure_desc c = emission();
    phos_shader_instruction ins = instruction(PHOS_OP_ATTRIBUTE, 0);
    ins.table = 2;
    ins.outputs[0] = 3;
    phos_shader_binding bind = {0, PHOS_FIELD_WEIGHT, 3};
    phos_shader_program_desc p;
    memset(&p, 0, sizeof(p));
    p.register_count = 6;
    p.instructions = &ins;
    p.instruction_count = 1;
    p.bindings = &bind;
    p.binding_count = 1;
    uint32_t mat = 0;
    CHECK(add(s, &c, &p, &mat) == PHOS_OK);
    CHECK(s->materials[mat].has_program && (s->materials[mat].program.needs & SHADER_NEEDS_ATTRIBUTES));
    test_add_instance(s, mesh, mat, 0.0f, 0.0f, 0.0f);
    test_set_camera(s, 0.0f, 0.0f, 2.0f, 0.5f);
    CHECK(phos_scene_commit(s) == PHOS_OK);

    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.width = rs.height = 16;
    rs.samples = 4;
    rs.filter_width = 0.01f;
    float *img = test_render(s, &rs);
    CHECK(img != NULL);
    if (img) {
        double worst = 0.0;
        for (int y = 0; y < 16; y++)
            for (int x = 0; x < 16; x++) {
                const float *px = img + 4 * (y * 16 + x);
                worst = fmax(worst, fabs(px[0] - (x + 0.5) / 16.0));
                worst = fmax(worst, fabs(px[1] - (y + 0.5) / 16.0));
                worst = fmax(worst, fabs(px[2] - 0.25));
            }
        CHECK_MSG(worst < 2e-3, "a pixel differs from its corner colours' interpolation by %g", worst);
        free(img);
    }
    phos_scene_destroy(s);
}

int main(void)
{
    test_attribute_op();
    test_attribute_emission_render();
    test_refusals();
    test_folding();
    test_uv_emission_render();
    return test_summary("test_shader_program");
}
