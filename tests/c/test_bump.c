/*
 * test_bump.c — checks of the pixel footprint Bump steps over
 * (scene/camera.c, shading/nodes/vector.c; docs/architecture.md, "Shader
 * programs"):
 *
 *  1. an orthographic camera ray's footprint is one pixel's width and does
 *     not grow; a perspective one starts as a point and grows by the angle
 *     between neighbouring pixels (1/width of the frame's tangent span at
 *     the centre);
 *  2. a height linear along the surface gives the same normal whatever
 *     the filter width (a forward difference is exact there), and the
 *     analytic one;
 *  3. a height that bends within the footprint gives the slope half a step
 *     away: the filter width changes the normal as a forward difference
 *     predicts;
 *  4. BUMP_OFFSET moves the position by filter width × the differentials;
 *  5. flags 2 (Blender before 4.0) tilts a normal whose mirror reflection
 *     of the viewer would go below the surface back until it leaves at
 *     the threshold 0.01, and leaves other normals alone;
 *  6. a negative filter width is refused when the program is created;
 *  7. both of Cycles' rules for keeping a closure's normal from reflecting
 *     the viewer into the surface (shading/valid_reflection.c) put the
 *     reflection at its threshold, in the plane of Ng and N.
 */
#include <math.h>
#include <string.h>

#include "scene/camera.h"
#include "shading/shader_program.h"
#include "shading/valid_reflection.h"
#include "test_util.h"

/* ------------------------------------------------------------- footprint */

static void test_camera_footprint(void)
{
    phos_camera_desc c;
    phos_camera_desc_init(&c);
    c.type = PHOS_CAMERA_ORTHOGRAPHIC;
    c.frame_min[0] = c.frame_min[1] = -2.0f;
    c.frame_max[0] = c.frame_max[1] = 2.0f;
    float2 lens = {0.5f, 0.5f};
    camera_ray r = camera_generate_ray(&c, 0.3f, 0.6f, lens);
    CHECK(r.spread_origin == 0.0f && r.spread_per_distance == 0.0f);
    camera_ray_set_footprint(&c, 0.3f, 0.6f, 128, 128, &r);
    CHECK_REL(r.spread_origin, 4.0f / 128.0f, 1e-5);
    CHECK(r.spread_per_distance == 0.0f);

    phos_camera_desc_init(&c); /* perspective, tan of the half angle 0.36 */
    r = camera_generate_ray(&c, 0.5f, 0.5f, lens);
    camera_ray_set_footprint(&c, 0.5f, 0.5f, 200, 200, &r);
    CHECK(r.spread_origin == 0.0f);
    /* At the centre a pixel step of 0.72/200 on the plane z = −1 turns the
     * direction by about that many radians. */
    CHECK_REL(r.spread_per_distance, 0.72f / 200.0f, 1e-3);
    /* Off centre the plane is farther and slanted: the angle is smaller. */
    camera_ray corner = camera_generate_ray(&c, 0.02f, 0.02f, lens);
    camera_ray_set_footprint(&c, 0.02f, 0.02f, 200, 200, &corner);
    CHECK(corner.spread_per_distance < r.spread_per_distance);

    /* A render measures the footprint once per pixel, at its centre
     * (render.c): within a pixel, even a wide camera's corner pixel (tan of
     * the half angle 1.5, 64 pixels), it changes by about one part in the
     * image's width, 1.5 % here. */
    c.frame_min[0] = c.frame_min[1] = -1.5f;
    c.frame_max[0] = c.frame_max[1] = 1.5f;
    camera_ray centre, edge;
    camera_ray_set_footprint(&c, 0.5f / 64.0f, 0.5f / 64.0f, 64, 64, &centre);
    camera_ray_set_footprint(&c, 0.0f, 0.0f, 64, 64, &edge);
    float change = fabsf(edge.spread_per_distance / centre.spread_per_distance - 1.0f);
    CHECK_MSG(change > 0.0f && change < 2.0f / 64.0f, "footprint change across a corner pixel %g", change);
}

/* ------------------------------------------------------------------ Bump */

/* A flat surface z = 0 seen from above, with differentials of length s
 * along x and y. */
static shader_globals flat_globals(float s)
{
    shader_globals g;
    memset(&g, 0, sizeof g);
    g.N = g.Ng = g.I = v3(0.0f, 0.0f, 1.0f);
    g.dPdx = v3(s, 0.0f, 0.0f);
    g.dPdy = v3(0.0f, s, 0.0f);
    g.dPdu = v3(1.0f, 0.0f, 0.0f);
    g.dPdv = v3(0.0f, 1.0f, 0.0f);
    return g;
}

/* Registers: 0 strength, 1 distance, 2-4 heights, 5-7 normal, 8-10 out. */
static vec3 bump(const shader_globals *g, float width, uint32_t flags, float h, float hx, float hy, float distance)
{
    phos_shader_instruction ins;
    memset(&ins, 0, sizeof ins);
    ins.op = PHOS_OP_BUMP;
    ins.flags = flags;
    ins.param[0] = width;
    for (int k = 0; k < PHOS_SHADER_MAX_INPUTS; k++)
        ins.inputs[k] = 0;
    for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++)
        ins.outputs[k] = PHOS_SHADER_NO_REGISTER;
    for (int k = 0; k < 6; k++)
        ins.inputs[k] = (uint32_t)k;
    ins.outputs[0] = 8;
    float r[16] = {1.0f, distance, h, hx, hy, g->N.x, g->N.y, g->N.z};
    shader_context ctx = {r, g, NULL, NULL};
    shader_op_bump(&ins, &ctx);
    return v3(r[8], r[9], r[10]);
}

static int near3(vec3 a, vec3 b, float tol)
{
    return fabsf(a.x - b.x) <= tol && fabsf(a.y - b.y) <= tol && fabsf(a.z - b.z) <= tol;
}

static void test_linear_height(void)
{
    /* h = 0.5 x + 0.25 y: the surface (x, y, h) has normal ∝ (−0.5, −0.25, 1). */
    shader_globals g = flat_globals(0.01f);
    vec3 expect = v3_normalize(v3(-0.5f, -0.25f, 1.0f));
    for (int i = 0; i < 3; i++) {
        float width = i == 0 ? 1.0f : i == 1 ? 0.1f : 0.0f; /* 0 reads as 1 */
        float step = 0.01f * (width > 0.0f ? width : 1.0f);
        vec3 n = bump(&g, width, 0, 0.0f, 0.5f * step, 0.25f * step, 1.0f);
        CHECK_MSG(near3(n, expect, 1e-4f), "width %g: (%g %g %g)", (double)width, (double)n.x, (double)n.y,
                  (double)n.z);
    }
}

static void test_bending_height(void)
{
    /* h = x²: a forward difference over step d gives slope 2(x + d/2). At
     * x = 0 with d = 0.1 the slope is 0.1; with d = 0.01 it is 0.01. */
    shader_globals g = flat_globals(0.1f);
    for (int i = 0; i < 2; i++) {
        float width = i == 0 ? 1.0f : 0.1f, d = 0.1f * width;
        vec3 n = bump(&g, width, 0, 0.0f, d * d, 0.0f, 1.0f);
        vec3 expect = v3_normalize(v3(-d, 0.0f, 1.0f));
        CHECK_MSG(near3(n, expect, 1e-5f), "width %g: (%g %g %g)", (double)width, (double)n.x, (double)n.y,
                  (double)n.z);
    }
}

static void test_offsets(void)
{
    shader_globals g = flat_globals(0.2f);
    g.P = v3(1.0f, 2.0f, 0.0f);
    phos_shader_instruction ins;
    memset(&ins, 0, sizeof ins);
    ins.op = PHOS_OP_BUMP_OFFSET;
    ins.param[0] = 0.1f;
    for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++)
        ins.outputs[k] = PHOS_SHADER_NO_REGISTER;
    ins.outputs[0] = 0;
    ins.outputs[2] = 3;
    float r[8];
    shader_context ctx = {r, &g, NULL, NULL};
    ins.mode = 1;
    shader_op_bump_offset(&ins, &ctx);
    CHECK(near3(v3(r[0], r[1], r[2]), v3(1.02f, 2.0f, 0.0f), 1e-6f));
    CHECK(near3(v3(r[3], r[4], r[5]), v3(0.02f, 0.0f, 0.0f), 1e-6f)); /* uv moves with dPdu = x */
    ins.mode = 2;
    shader_op_bump_offset(&ins, &ctx);
    CHECK(near3(v3(r[0], r[1], r[2]), v3(1.0f, 2.02f, 0.0f), 1e-6f));
}

static void test_valid_reflection(void)
{
    shader_globals g = flat_globals(0.01f);
    /* A slope of 2 tilts the normal 63° from Ng: seen from straight above
     * its mirror reflection points below the surface. */
    vec3 tilted = bump(&g, 1.0f, 0, 0.0f, 0.02f, 0.0f, 1.0f);
    vec3 r = v3_sub(v3_scale(tilted, 2.0f * v3_dot(tilted, g.I)), g.I);
    CHECK(v3_dot(r, g.Ng) < 0.0f);
    vec3 fixed = bump(&g, 1.0f, 2, 0.0f, 0.02f, 0.0f, 1.0f);
    r = v3_sub(v3_scale(fixed, 2.0f * v3_dot(fixed, g.I)), g.I);
    CHECK_MSG(fabsf(v3_dot(r, g.Ng) - 0.01f) < 1e-4f, "reflection height %g", (double)v3_dot(r, g.Ng));
    CHECK(fabsf(v3_length(fixed) - 1.0f) < 1e-5f);
    CHECK(fixed.x < 0.0f && fabsf(fixed.y) < 1e-6f); /* tilted back in the same plane */
    /* A slope of 0.5 (27°) keeps its reflection above: unchanged. */
    vec3 mild = bump(&g, 1.0f, 0, 0.0f, 0.005f, 0.0f, 1.0f);
    CHECK(near3(bump(&g, 1.0f, 2, 0.0f, 0.005f, 0.0f, 1.0f), mild, 0.0f));
}

/* Both rules over random bent normals and views (valid_reflection.h): a
 * normal whose reflection of the viewer is already t = min(0.9 Ng·I, 0.01)
 * above the surface is kept bit for bit; any other comes back unit, in
 * the plane of Ng and N on N's side, with its reflection exactly at t for
 * ONE_ROOT, and above the surface (or Ng itself) for BOTH_ROOTS, which
 * takes the lower of two roots that both reflect above it: near Ix = 0,
 * where the true and the spurious root nearly meet, that is the spurious
 * one, as in Cycles 3.x. The two rules solve the same quadratic, so where
 * BOTH_ROOTS lands on t the normals agree. */
static void test_valid_reflection_rules(void)
{
    vec3 ng = v3(0.0f, 0.0f, 1.0f);
    uint32_t state = 12345u;
    int fixed = 0, agree = 0, both_at_t = 0;
    for (int k = 0; k < 20000; k++) {
        float u[5];
        for (int j = 0; j < 5; j++) {
            state = state * 1664525u + 1013904223u;
            u[j] = (float)(state >> 8) * (1.0f / 16777216.0f);
        }
        /* A view anywhere above the surface, down to 0.5° from grazing,
         * and a normal up to 89° from Ng. */
        float ci = 0.01f + 0.99f * u[0], si = sqrtf(1.0f - ci * ci), pi_ = 6.2831853f * u[1];
        vec3 i = v3(si * cosf(pi_), si * sinf(pi_), ci);
        float cn = 0.02f + 0.98f * u[2], sn = sqrtf(1.0f - cn * cn), pn = 6.2831853f * u[3];
        vec3 n = v3(sn * cosf(pn), sn * sinf(pn), cn);
        float t = fminf(0.9f * ci, 0.01f);
        vec3 r = v3_sub(v3_scale(n, 2.0f * v3_dot(n, i)), i);
        int valid = v3_dot(r, ng) >= t;
        vec3 a = valid_reflection_normal(ng, i, n, PHOS_NORMAL_CORRECTION_ONE_ROOT);
        vec3 b = valid_reflection_normal(ng, i, n, PHOS_NORMAL_CORRECTION_BOTH_ROOTS);
        vec3 none = valid_reflection_normal(ng, i, n, PHOS_NORMAL_CORRECTION_NONE);
        CHECK(memcmp(&none, &n, sizeof n) == 0);
        if (valid) {
            CHECK(memcmp(&a, &n, sizeof n) == 0 && memcmp(&b, &n, sizeof n) == 0);
            continue;
        }
        fixed++;
        vec3 ra = v3_sub(v3_scale(a, 2.0f * v3_dot(a, i)), i);
        CHECK_MSG(fabsf(v3_dot(ra, ng) - t) < 2e-4f, "ONE_ROOT reflection height %g, t %g",
                  (double)v3_dot(ra, ng), (double)t);
        CHECK(fabsf(v3_length(a) - 1.0f) < 1e-4f);
        CHECK(fabsf(v3_dot(v3_cross(ng, n), a)) < 1e-4f); /* in the plane of Ng and N */
        CHECK(a.x * n.x + a.y * n.y >= 0.0f);              /* on N's side of Ng */
        vec3 rb = v3_sub(v3_scale(b, 2.0f * v3_dot(b, i)), i);
        int b_is_ng = near3(b, ng, 0.0f);
        CHECK(b_is_ng || v3_dot(rb, ng) >= 1e-5f - 2e-4f);
        if (!b_is_ng && fabsf(v3_dot(rb, ng) - t) < 2e-4f) {
            both_at_t++;
            agree += near3(a, b, 1e-3f);
        }
    }
    CHECK_MSG(fixed > 1000, "only %d of the normals needed tilting", fixed);
    CHECK_MSG(agree == both_at_t, "the rules disagree on %d of %d normals both put at t", both_at_t - agree,
              both_at_t);
}

/* --------------------------------------------------------------- program */

static void test_negative_width_refused(void)
{
    phos_shader_instruction ins;
    memset(&ins, 0, sizeof ins);
    ins.op = PHOS_OP_BUMP_OFFSET;
    ins.mode = 1;
    for (int k = 0; k < PHOS_SHADER_MAX_INPUTS; k++)
        ins.inputs[k] = PHOS_SHADER_NO_REGISTER;
    for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++)
        ins.outputs[k] = (uint32_t)(3 * k);
    phos_shader_program_desc d;
    memset(&d, 0, sizeof d);
    d.register_count = 15;
    d.instruction_count = 1;
    d.instructions = &ins;
    shader_program p;
    char msg[256];
    ins.param[0] = 0.1f;
    const char *err = shader_program_create(&d, 1, 0, &p, msg, sizeof msg);
    CHECK_MSG(err == NULL, "%s", err ? err : "");
    if (!err)
        shader_program_free(&p);
    ins.param[0] = -0.1f;
    err = shader_program_create(&d, 1, 0, &p, msg, sizeof msg);
    CHECK(err != NULL && strstr(err, "filter width") != NULL);
    if (!err)
        shader_program_free(&p);
}

int main(void)
{
    test_camera_footprint();
    test_linear_height();
    test_bending_height();
    test_offsets();
    test_valid_reflection();
    test_valid_reflection_rules();
    test_negative_width_refused();
    return test_summary("test_bump");
}
