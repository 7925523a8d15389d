/*
 * test_nodes_pattern.c — checks of the pattern texture ops
 * (shading/nodes/texture_pattern.c), each run through a hand-built
 * instruction and register file:
 *
 *  1. Checker alternates per unit cell of the scaled point (Cycles'
 *     parity rule), and picks color1/color2 by it;
 *  2. Gradient Linear is x clamped to [0, 1]; the other types stay in it;
 *  3. Voronoi F1 is 0 at a feature point (its own Position output) and
 *     never above F2; Distance to Edge and N-Sphere Radius are >= 0; every
 *     dimension, metric and definition (3.x, 4.x, 5.x) with and without
 *     fractal detail;
 *  4. Brick gives the mortar colour on a mortar line and a brick colour
 *     inside a brick; a negative mortar smoothing is solid mortar with
 *     Blender 3.x's rule and none after;
 *  5. every output of every op and mode is finite over a grid of points;
 *  6. determinism: the same inputs give the same bits.
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "shading/shader_program.h"
#include "test_util.h"

/* The ops under test, with their socket widths and mode counts (as
 * shader_program.c's table has them; this test links only the node files). */
typedef struct op_desc {
    shader_op_fn fn;
    uint8_t in_width[PHOS_SHADER_MAX_INPUTS];
    uint8_t out_width[PHOS_SHADER_MAX_OUTPUTS];
    uint32_t mode_count;
} op_desc;

static const op_desc *op_info(uint32_t op)
{
    static const op_desc voronoi = {shader_op_tex_voronoi, {3, 1, 1, 1, 1, 1, 1, 1, 1}, {1, 3, 3, 1, 1},
                                    PHOS_VORONOI_FEATURE_COUNT};
    static const op_desc wave = {shader_op_tex_wave, {3, 1, 1, 1, 1, 1, 1}, {3, 1}, PHOS_WAVE_TYPE_COUNT};
    static const op_desc brick = {shader_op_tex_brick, {3, 3, 3, 3, 1, 1, 1, 1, 1, 1}, {3, 1}, 0};
    static const op_desc checker = {shader_op_tex_checker, {3, 3, 3, 1}, {3, 1}, 0};
    static const op_desc magic = {shader_op_tex_magic, {3, 1, 1}, {3, 1}, 11};
    static const op_desc gradient = {shader_op_tex_gradient, {3}, {3, 1}, PHOS_GRADIENT_COUNT};
    switch (op) {
    case PHOS_OP_TEX_VORONOI: return &voronoi;
    case PHOS_OP_TEX_WAVE: return &wave;
    case PHOS_OP_TEX_BRICK: return &brick;
    case PHOS_OP_TEX_CHECKER: return &checker;
    case PHOS_OP_TEX_MAGIC: return &magic;
    default: return &gradient;
    }
}

/* Register layout of the test programs: inputs from 0, outputs from 64. */
#define REGS 128
#define OUT0 64

typedef struct rig {
    phos_shader_instruction ins;
    float r[REGS];
    int next_in, next_out;
} rig;

static void rig_init(rig *g, uint32_t op, uint32_t mode, uint32_t flags)
{
    memset(g, 0, sizeof *g);
    g->ins.op = op;
    g->ins.mode = mode;
    g->ins.flags = flags;
    for (int k = 0; k < PHOS_SHADER_MAX_INPUTS; k++)
        g->ins.inputs[k] = 0;
    for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++)
        g->ins.outputs[k] = PHOS_SHADER_NO_REGISTER;
    g->next_in = 0;
    g->next_out = OUT0;
}

static void in1(rig *g, int k, float x)
{
    g->ins.inputs[k] = (uint32_t)g->next_in;
    g->r[g->next_in++] = x;
}

static void in3(rig *g, int k, float x, float y, float z)
{
    g->ins.inputs[k] = (uint32_t)g->next_in;
    g->r[g->next_in++] = x;
    g->r[g->next_in++] = y;
    g->r[g->next_in++] = z;
}

static void out(rig *g, int k, int width)
{
    g->ins.outputs[k] = (uint32_t)g->next_out;
    g->next_out += width;
}

static void run(rig *g)
{
    shader_globals sg;
    memset(&sg, 0, sizeof sg);
    shader_context ctx = {g->r, &sg, NULL, NULL};
    op_info(g->ins.op)->fn(&g->ins, &ctx);
}

static float reg(const rig *g, int k, int c) { return g->r[g->ins.outputs[k] + c]; }

static int all_outputs_finite(const rig *g)
{
    for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++) {
        if (g->ins.outputs[k] == PHOS_SHADER_NO_REGISTER)
            continue;
        int w = op_info(g->ins.op)->out_width[k];
        for (int c = 0; c < w; c++)
            if (!isfinite(reg(g, k, c)))
                return 0;
    }
    return 1;
}

static void out_all(rig *g)
{
    for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++)
        if (op_info(g->ins.op)->out_width[k])
            out(g, k, op_info(g->ins.op)->out_width[k]);
}

/* ------------------------------------------------------------ Checker */

static float checker_fac(float x, float y, float z, float scale, float *rgb)
{
    rig g;
    rig_init(&g, PHOS_OP_TEX_CHECKER, 0, 0);
    in3(&g, 0, x, y, z);
    in3(&g, 1, 0.8f, 0.8f, 0.8f);
    in3(&g, 2, 0.2f, 0.2f, 0.2f);
    in1(&g, 3, scale);
    out_all(&g);
    run(&g);
    if (rgb)
        *rgb = reg(&g, 0, 0);
    return reg(&g, 1, 0);
}

static void test_checker(void)
{
    /* At scale 2 the cells are 0.5 wide; cell (0,0,0) has parity 0. */
    float rgb;
    CHECK(checker_fac(0.1f, 0.1f, 0.1f, 2.0f, &rgb) == 0.0f);
    CHECK(rgb == 0.2f);
    CHECK(checker_fac(0.6f, 0.1f, 0.1f, 2.0f, &rgb) == 1.0f);
    CHECK(rgb == 0.8f);
    CHECK(checker_fac(0.1f, 0.6f, 0.1f, 2.0f, NULL) == 1.0f);
    CHECK(checker_fac(0.1f, 0.1f, 0.6f, 2.0f, NULL) == 1.0f);
    CHECK(checker_fac(0.6f, 0.6f, 0.1f, 2.0f, NULL) == 0.0f);
    CHECK(checker_fac(0.6f, 0.6f, 0.6f, 2.0f, NULL) == 1.0f);
    CHECK(checker_fac(1.1f, 0.1f, 0.1f, 2.0f, NULL) == 0.0f); /* two cells on: same again */
    CHECK(checker_fac(-0.1f, 0.1f, 0.1f, 2.0f, NULL) == 1.0f); /* negative side alternates too */
    CHECK(checker_fac(-0.6f, 0.1f, 0.1f, 2.0f, NULL) == 0.0f);
    /* a unit coordinate is nudged by (p + 1e-6)·0.999999, which puts
     * p = 1 just below 1: into the cell below it */
    CHECK(checker_fac(0.5f, 0.1f, 0.1f, 2.0f, NULL) == 0.0f);
}

/* ----------------------------------------------------------- Gradient */

static float gradient_fac(uint32_t type, float x, float y, float z)
{
    rig g;
    rig_init(&g, PHOS_OP_TEX_GRADIENT, type, 0);
    in3(&g, 0, x, y, z);
    out_all(&g);
    run(&g);
    CHECK(reg(&g, 0, 0) == reg(&g, 1, 0) && reg(&g, 0, 2) == reg(&g, 1, 0));
    return reg(&g, 1, 0);
}

static void test_gradient(void)
{
    CHECK(gradient_fac(PHOS_GRADIENT_LINEAR, -0.5f, 0.3f, 0.0f) == 0.0f);
    CHECK(gradient_fac(PHOS_GRADIENT_LINEAR, 0.3f, 0.9f, 0.0f) == 0.3f);
    CHECK(gradient_fac(PHOS_GRADIENT_LINEAR, 1.7f, 0.0f, 0.0f) == 1.0f);
    CHECK(gradient_fac(PHOS_GRADIENT_QUADRATIC, 0.5f, 0.0f, 0.0f) == 0.25f);
    CHECK(gradient_fac(PHOS_GRADIENT_EASING, 0.5f, 0.0f, 0.0f) == 0.5f);
    CHECK(gradient_fac(PHOS_GRADIENT_DIAGONAL, 0.2f, 0.4f, 0.0f) == (0.2f + 0.4f) * 0.5f);
    CHECK(gradient_fac(PHOS_GRADIENT_RADIAL, -1.0f, -0.0f, 0.0f) == 0.0f); /* atan2 −π */
    CHECK(fabsf(gradient_fac(PHOS_GRADIENT_RADIAL, 0.0f, 1.0f, 0.0f) - 0.75f) < 1e-6f);
    CHECK(gradient_fac(PHOS_GRADIENT_SPHERICAL, 1.0f, 0.0f, 0.0f) == 0.0f);
    CHECK(fabsf(gradient_fac(PHOS_GRADIENT_SPHERICAL, 0.0f, 0.0f, 0.0f) - 0.999999f) < 1e-7f);
    CHECK(fabsf(gradient_fac(PHOS_GRADIENT_QUADRATIC_SPHERE, 0.5f, 0.0f, 0.0f) - 0.499999f * 0.499999f) < 1e-6f);
}

/* ------------------------------------------------------------ Voronoi */

typedef struct vor_in {
    float x, y, z, w, scale, detail, roughness, lacunarity, smoothness, exponent, randomness;
} vor_in;

static const vor_in VOR_DEFAULT = {0, 0, 0, 0, 5.0f, 0.0f, 0.5f, 2.0f, 1.0f, 0.5f, 1.0f};

/* flags: dims | metric << 5 | extra (8 normalize, 16 3.x, 128 5.x) */
static uint32_t vor_flags(int dims, int metric, uint32_t extra) { return (uint32_t)dims | ((uint32_t)metric << 5) | extra; }

static void voronoi_run(rig *g, uint32_t feature, uint32_t flags, const vor_in *a)
{
    rig_init(g, PHOS_OP_TEX_VORONOI, feature, flags);
    in3(g, 0, a->x, a->y, a->z);
    in1(g, 1, a->w);
    in1(g, 2, a->scale);
    in1(g, 3, a->detail);
    in1(g, 4, a->roughness);
    in1(g, 5, a->lacunarity);
    in1(g, 6, a->smoothness);
    in1(g, 7, a->exponent);
    in1(g, 8, a->randomness);
    out_all(g);
    run(g);
}

static const uint32_t VERSIONS[3] = {16u, 0u, 128u}; /* 3.x, 4.x, 5.x */

static void test_voronoi_features(void)
{
    static const float metric_exponent[4] = {0.5f, 0.5f, 0.5f, 1.5f};
    int f1_zero_fail = 0, f1_le_f2_fail = 0, edge_fail = 0, radius_fail = 0, color_fail = 0, checks = 0;
    for (int vi = 0; vi < 3; vi++)
        for (int dims = 1; dims <= 4; dims++)
            for (int metric = 0; metric < 4; metric++)
                for (int i = 0; i < 40; i++) {
                    vor_in a = VOR_DEFAULT;
                    a.x = 0.37f * (float)i - 3.1f;
                    a.y = 0.61f * (float)(i % 7) - 1.3f;
                    a.z = 0.23f * (float)(i % 5) + 0.05f;
                    a.w = 0.71f * (float)(i % 3) - 0.4f;
                    a.exponent = metric_exponent[metric];
                    a.randomness = (float)(i % 4) / 3.0f;
                    uint32_t fl = vor_flags(dims, metric, VERSIONS[vi]);
                    rig f1, f2, edge, rad;
                    voronoi_run(&f1, PHOS_VORONOI_F1, fl, &a);
                    voronoi_run(&f2, PHOS_VORONOI_F2, fl, &a);
                    voronoi_run(&edge, PHOS_VORONOI_DISTANCE_TO_EDGE, fl, &a);
                    voronoi_run(&rad, PHOS_VORONOI_N_SPHERE_RADIUS, fl, &a);
                    float d1 = reg(&f1, 0, 0), d2 = reg(&f2, 0, 0);
                    checks++;
                    f1_le_f2_fail += !(d1 <= d2 && d1 >= 0.0f);
                    edge_fail += !(reg(&edge, 0, 0) >= 0.0f);
                    radius_fail += !(reg(&rad, 4, 0) >= 0.0f);
                    for (int c = 0; c < 3; c++)
                        color_fail += !(reg(&f1, 1, c) >= 0.0f && reg(&f1, 1, c) <= 1.0f);

                    /* Evaluate at the F1 feature point itself (the Position
                     * and W outputs are in input space): distance 0. */
                    vor_in b = a;
                    b.x = reg(&f1, 2, 0), b.y = reg(&f1, 2, 1), b.z = reg(&f1, 2, 2), b.w = reg(&f1, 3, 0);
                    if (dims == 1)
                        b.x = b.y = b.z = 0.0f;
                    rig at;
                    voronoi_run(&at, PHOS_VORONOI_F1, fl, &b);
                    f1_zero_fail += !(reg(&at, 0, 0) < 2e-5f);
                }
    CHECK_MSG(f1_zero_fail == 0, "%d of %d feature points have F1 > 0", f1_zero_fail, checks);
    CHECK_MSG(f1_le_f2_fail == 0, "%d of %d points have F1 > F2 or F1 < 0", f1_le_f2_fail, checks);
    CHECK_MSG(edge_fail == 0, "%d of %d points have a negative distance to edge", edge_fail, checks);
    CHECK_MSG(radius_fail == 0, "%d of %d points have a negative n-sphere radius", radius_fail, checks);
    CHECK_MSG(color_fail == 0, "%d F1 colour components outside [0, 1]", color_fail);
}

static void test_voronoi_details(void)
{
    /* Randomness 0: the feature points sit on the lattice, so in 3D the F1
     * distance at a cell centre (scaled point (k + 0.5)) is √0.75, and at
     * local (0.2, 0.3, 0.1) the nearest edge is the bisector y = 0.5 of
     * the corners (0,0,0) and (0,1,0), 0.2 away. */
    vor_in a = VOR_DEFAULT;
    a.scale = 1.0f, a.randomness = 0.0f;
    a.x = 2.5f, a.y = -1.5f, a.z = 0.5f;
    for (int vi = 0; vi < 3; vi++) {
        rig f1, edge;
        voronoi_run(&f1, PHOS_VORONOI_F1, vor_flags(3, PHOS_VORONOI_EUCLIDEAN, VERSIONS[vi]), &a);
        CHECK(fabsf(reg(&f1, 0, 0) - sqrtf(0.75f)) < 1e-6f);
        vor_in e = a;
        e.x = 2.2f, e.y = -1.7f, e.z = 0.1f;
        voronoi_run(&edge, PHOS_VORONOI_DISTANCE_TO_EDGE, vor_flags(3, 0, VERSIONS[vi]), &e);
        CHECK(fabsf(reg(&edge, 0, 0) - 0.2f) < 1e-5f);
    }
    /* Normalised fractal distance stays in [0, 1]-ish and the Manhattan
     * F1 at a cell centre with randomness 0 is 1.5. */
    rig m;
    voronoi_run(&m, PHOS_VORONOI_F1, vor_flags(3, PHOS_VORONOI_MANHATTAN, 0), &a);
    CHECK(fabsf(reg(&m, 0, 0) - 1.5f) < 1e-6f);
    a.detail = 2.5f, a.randomness = 0.8f;
    int bad = 0;
    for (int i = 0; i < 64; i++) {
        a.x = 0.173f * (float)i, a.y = 0.311f * (float)(i % 9), a.z = -0.07f * (float)i;
        voronoi_run(&m, PHOS_VORONOI_F1, vor_flags(3, 0, 8u), &a);
        bad += !(reg(&m, 0, 0) >= 0.0f && reg(&m, 0, 0) <= 1.0f);
        voronoi_run(&m, PHOS_VORONOI_DISTANCE_TO_EDGE, vor_flags(3, 0, 8u), &a);
        bad += !(reg(&m, 0, 0) >= 0.0f && reg(&m, 0, 0) <= 1.0f);
    }
    CHECK_MSG(bad == 0, "%d normalised fractal distances outside [0, 1]", bad);
    /* 1D: the position output is W; X, Y, Z stay 0. */
    a = VOR_DEFAULT, a.w = 1.37f;
    voronoi_run(&m, PHOS_VORONOI_F1, vor_flags(1, 0, 0), &a);
    CHECK(reg(&m, 2, 0) == 0.0f && reg(&m, 2, 1) == 0.0f && reg(&m, 2, 2) == 0.0f);
    CHECK(fabsf(reg(&m, 3, 0) - 1.37f) < 0.3f);
    /* 4.x and 5.x differ in 3D (hashes), agree in 1D. */
    rig p4, p5;
    a = VOR_DEFAULT, a.x = 0.3f, a.y = 0.7f, a.z = 0.1f, a.w = 0.9f;
    voronoi_run(&p4, PHOS_VORONOI_F1, vor_flags(3, 0, 0), &a);
    voronoi_run(&p5, PHOS_VORONOI_F1, vor_flags(3, 0, 128u), &a);
    CHECK(reg(&p4, 0, 0) != reg(&p5, 0, 0));
    voronoi_run(&p4, PHOS_VORONOI_F1, vor_flags(1, 0, 0), &a);
    voronoi_run(&p5, PHOS_VORONOI_F1, vor_flags(1, 0, 128u), &a);
    CHECK(reg(&p4, 0, 0) == reg(&p5, 0, 0));
}

/* -------------------------------------------------------------- Brick */

static void brick_run_smooth(rig *g, float x, float y, float smooth, uint32_t flags)
{
    rig_init(g, PHOS_OP_TEX_BRICK, 0, flags);
    in3(g, 0, x, y, 0.0f);
    in3(g, 1, 0.8f, 0.8f, 0.8f);  /* color1 */
    in3(g, 2, 0.2f, 0.2f, 0.2f);  /* color2 */
    in3(g, 3, 0.0f, 0.0f, 1.0f);  /* mortar */
    in1(g, 4, 1.0f);              /* scale */
    in1(g, 5, 0.02f);             /* mortar size */
    in1(g, 6, smooth);            /* mortar smooth */
    in1(g, 7, 0.0f);              /* bias */
    in1(g, 8, 0.5f);              /* brick width */
    in1(g, 9, 0.25f);             /* row height */
    g->ins.param[0] = 0.5f;       /* offset */
    g->ins.param[1] = 2.0f;       /* offset frequency */
    g->ins.param[2] = 1.0f;       /* squash */
    g->ins.param[3] = 2.0f;       /* squash frequency */
    out_all(g);
    run(g);
}

static void brick_run(rig *g, float x, float y) { brick_run_smooth(g, x, y, 0.1f, 0); }

static void test_brick(void)
{
    rig g;
    /* Row 1 (y in [0.25, 0.5)) is not offset: a mortar line at x = 0.5. */
    brick_run(&g, 0.5f, 0.375f);
    CHECK(reg(&g, 1, 0) == 1.0f);
    CHECK(reg(&g, 0, 0) == 0.0f && reg(&g, 0, 2) == 1.0f);
    /* the horizontal mortar between rows */
    brick_run(&g, 0.3f, 0.25f);
    CHECK(reg(&g, 1, 0) == 1.0f);
    /* a brick's middle: no mortar, a colour between color1 and color2 */
    brick_run(&g, 0.25f, 0.375f);
    CHECK(reg(&g, 1, 0) == 0.0f);
    CHECK(reg(&g, 0, 0) >= 0.2f - 1e-6f && reg(&g, 0, 0) <= 0.8f + 1e-6f && reg(&g, 0, 0) == reg(&g, 0, 2));
    /* Row 0 is offset by half a brick: x = 0.5 is a brick's middle there. */
    brick_run(&g, 0.5f, 0.125f);
    CHECK(reg(&g, 1, 0) == 0.0f);
    /* the smooth edge of the mortar is between 0 and 1 */
    brick_run(&g, 0.5f + 0.019f, 0.375f);
    CHECK(reg(&g, 1, 0) > 0.0f && reg(&g, 1, 0) < 1.0f);
    /* A negative smoothing inside the mortar band: solid mortar with 3.x's
     * rule (flags 1), none with the clamped smoothstep of 4.0 on; a
     * positive one agrees between the two. */
    brick_run_smooth(&g, 0.5f + 0.01f, 0.375f, -0.4f, 1);
    CHECK(reg(&g, 1, 0) == 1.0f);
    brick_run_smooth(&g, 0.5f + 0.01f, 0.375f, -0.4f, 0);
    CHECK(reg(&g, 1, 0) == 0.0f);
    brick_run_smooth(&g, 0.5f + 0.019f, 0.375f, 0.1f, 1);
    float legacy = reg(&g, 1, 0);
    brick_run_smooth(&g, 0.5f + 0.019f, 0.375f, 0.1f, 0);
    CHECK(legacy == reg(&g, 1, 0));
}

/* --------------------------------------------------- Wave, Magic */

static void wave_run(rig *g, uint32_t type, uint32_t flags, float x, float y, float z, float distortion)
{
    rig_init(g, PHOS_OP_TEX_WAVE, type, flags);
    in3(g, 0, x, y, z);
    in1(g, 1, 5.0f);         /* scale */
    in1(g, 2, distortion);
    in1(g, 3, 2.5f);         /* detail */
    in1(g, 4, 1.0f);         /* detail scale */
    in1(g, 5, 0.5f);         /* detail roughness */
    in1(g, 6, 0.0f);         /* phase */
    out_all(g);
    run(g);
}

static void test_wave(void)
{
    rig g;
    /* Undistorted X bands with the sine profile: 0.5 − 0.5cos(20·5x). */
    wave_run(&g, PHOS_WAVE_BANDS, PHOS_WAVE_X, 0.013f, 0.4f, 0.2f, 0.0f);
    float px = (0.013f * 5.0f + 0.000001f) * 0.999999f;
    CHECK(fabsf(reg(&g, 1, 0) - (0.5f - 0.5f * cosf(px * 20.0f))) < 1e-5f);
    CHECK(reg(&g, 0, 1) == reg(&g, 1, 0));
    /* saw and triangle stay in [0, 1] */
    int bad = 0;
    for (int i = 0; i < 50; i++) {
        for (uint32_t prof = 0; prof < 3; prof++) {
            wave_run(&g, PHOS_WAVE_RINGS, PHOS_WAVE_SPHERICAL << 4 | prof << 8, 0.1f * (float)i, 0.05f, -0.3f, 2.0f);
            bad += !(reg(&g, 1, 0) >= 0.0f && reg(&g, 1, 0) <= 1.0f);
        }
    }
    CHECK_MSG(bad == 0, "%d wave values outside [0, 1]", bad);
    /* The 3.x fBM of unsigned noise and the 4.x normalised fBM of signed
     * noise are the same sum arranged differently: equal up to rounding
     * for a roughness in [0, 1], and distortion moves the bands. */
    rig a, b, c;
    wave_run(&a, PHOS_WAVE_BANDS, PHOS_WAVE_Z, 0.3f, 0.6f, 0.9f, 3.0f);
    wave_run(&b, PHOS_WAVE_BANDS, PHOS_WAVE_Z | (16u << 8), 0.3f, 0.6f, 0.9f, 3.0f);
    wave_run(&c, PHOS_WAVE_BANDS, PHOS_WAVE_Z, 0.3f, 0.6f, 0.9f, 0.0f);
    CHECK(fabsf(reg(&a, 1, 0) - reg(&b, 1, 0)) < 1e-4f);
    CHECK(reg(&a, 1, 0) != reg(&c, 1, 0));
}

static void test_magic(void)
{
    rig g;
    /* depth 0, distortion 1: 0.5 − sin(5s(x + y + z))/2 in the first channel */
    rig_init(&g, PHOS_OP_TEX_MAGIC, 0, 0);
    in3(&g, 0, 0.1f, 0.2f, 0.3f);
    in1(&g, 1, 2.0f);
    in1(&g, 2, 1.0f);
    out_all(&g);
    run(&g);
    float expect = 0.5f - sinf((0.1f + 0.2f + 0.3f) * 5.0f * 2.0f) / 2.0f;
    CHECK(fabsf(reg(&g, 0, 0) - expect) < 1e-6f);
    float avg = (reg(&g, 0, 0) + reg(&g, 0, 1) + reg(&g, 0, 2)) * (1.0f / 3.0f);
    CHECK(reg(&g, 1, 0) == avg);
    /* for points inside [0, 2π) the 5.3 wrap gives the same when scale·p < 2π */
    rig h = g;
    h.ins.flags = 1;
    run(&h);
    CHECK(fabsf(reg(&h, 0, 0) - reg(&g, 0, 0)) < 1e-5f);
}

/* -------------------------------------------- finite, deterministic */

static int eval_op(rig *g, uint32_t op, uint32_t mode, uint32_t flags, float x, float y, float z, float t)
{
    rig_init(g, op, mode, flags);
    for (int k = 0; k < PHOS_SHADER_MAX_INPUTS; k++) {
        int w = op_info(op)->in_width[k];
        if (w == 3)
            in3(g, k, x + 0.1f * (float)k, y, z);
        else if (w == 1)
            in1(g, k, k == 0 ? x : t * (float)(k % 3 + 1));
    }
    if (op == PHOS_OP_TEX_BRICK) {
        g->ins.param[0] = 0.5f, g->ins.param[1] = 2.0f, g->ins.param[2] = 1.0f, g->ins.param[3] = 2.0f;
        g->r[g->ins.inputs[8]] = 0.5f; /* brick width */
        g->r[g->ins.inputs[9]] = 0.25f;
    }
    out_all(g);
    run(g);
    return all_outputs_finite(g);
}

static void test_finite_and_deterministic(void)
{
    static const uint32_t ops[6] = {PHOS_OP_TEX_VORONOI, PHOS_OP_TEX_WAVE, PHOS_OP_TEX_BRICK,
                                    PHOS_OP_TEX_CHECKER, PHOS_OP_TEX_MAGIC, PHOS_OP_TEX_GRADIENT};
    int nonfinite = 0, differ = 0, evals = 0;
    for (int o = 0; o < 6; o++) {
        uint32_t op = ops[o];
        uint32_t modes = op_info(op)->mode_count ? op_info(op)->mode_count : 1;
        for (uint32_t mode = 0; mode < modes; mode++) {
            uint32_t flag_set[24];
            int nf = 0;
            if (op == PHOS_OP_TEX_VORONOI) {
                for (int dims = 1; dims <= 4; dims++)
                    for (int vi = 0; vi < 3; vi++)
                        flag_set[nf++] = vor_flags(dims, (dims + vi) % 4, VERSIONS[vi] | (vi == 1 ? 8u : 0u));
            } else if (op == PHOS_OP_TEX_WAVE) {
                for (uint32_t prof = 0; prof < 3; prof++)
                    for (uint32_t dir = 0; dir < 4; dir++)
                        flag_set[nf++] = dir | dir << 4 | prof << 8 | (dir & 1 ? 16u << 8 : 0u);
            } else if (op == PHOS_OP_TEX_MAGIC) {
                flag_set[nf++] = 0, flag_set[nf++] = 1;
            } else {
                flag_set[nf++] = 0;
            }
            for (int f = 0; f < nf; f++)
                for (int i = 0; i < 6; i++)
                    for (int j = 0; j < 6; j++) {
                        float x = -3.7f + 1.31f * (float)i, y = -2.2f + 0.93f * (float)j, z = 0.37f * (float)(i - j);
                        float t = 0.25f + 0.15f * (float)((i + j) % 5);
                        rig a, b;
                        nonfinite += !eval_op(&a, op, mode, flag_set[f], x, y, z, t);
                        eval_op(&b, op, mode, flag_set[f], x, y, z, t);
                        differ += memcmp(a.r, b.r, sizeof a.r) != 0;
                        evals++;
                    }
        }
    }
    CHECK_MSG(nonfinite == 0, "%d of %d evaluations gave a non-finite output", nonfinite, evals);
    CHECK_MSG(differ == 0, "%d of %d evaluations were not reproducible", differ, evals);
}

int main(void)
{
    test_checker();
    test_gradient();
    test_voronoi_features();
    test_voronoi_details();
    test_brick();
    test_wave();
    test_magic();
    test_finite_and_deterministic();
    return test_summary("test_nodes_pattern");
}
