/*
 * test_nodes_color.c — checks of the Converter and Color nodes of shader
 * programs (shading/nodes/converter.c, color.c): each op run through a
 * hand-built shader_context on a small register file, against values
 * worked out by hand from Cycles' definitions:
 *
 *  1. Math: every operation, with the guarded cases (division by zero,
 *     powers of negative bases, logarithms of non-positive numbers, ...),
 *     the clamp switch and the version flags;
 *  2. Vector Math: every operation, both outputs;
 *  3. Map Range (float and vector, every mode, clamp), Clamp, Combine XYZ;
 *  4. Mix: float, vector (uniform and per-component factor), and every
 *     blend mode on two colours at factor 0.5, with the clamps;
 *  5. colour adjustment: Hue/Saturation/Value (both hue wraps),
 *     Bright/Contrast, Gamma, Invert, RGB to BW;
 *  6. Separate/Combine Color: known values and HSV/HSL round trips;
 *  7. Blackbody (6500 K near white, the clamped ends) and Wavelength;
 *  8. ColorRamp (linear and constant), RGB/Vector Curves and Float Curve
 *     (interpolation, clamping and extrapolation outside the range).
 */
#include <float.h>
#include <string.h>

#include "shading/nodes/node_util.h"
#include "shading/shader_program.h"
#include "test_util.h"

#define TOL 1e-5

/* --------------------------------------------------------------- harness */

/* Registers: inputs from 0 (each socket 3 wide, so socket k at 3k), outputs from 64. */
#define IN_REG(k) (3u * (k))
#define OUT_REG(k) (64u + 3u * (k))

static float regs[128];
static shader_program program;
static shader_context ctx = {.r = regs, .g = NULL, .program = &program, .scene = NULL};

static phos_shader_instruction make_ins(uint32_t mode, uint32_t flags)
{
    phos_shader_instruction ins;
    memset(&ins, 0, sizeof ins);
    ins.mode = mode;
    ins.flags = flags;
    for (int k = 0; k < PHOS_SHADER_MAX_INPUTS; k++)
        ins.inputs[k] = IN_REG(k);
    for (int k = 0; k < PHOS_SHADER_MAX_OUTPUTS; k++)
        ins.outputs[k] = OUT_REG(k);
    memset(regs, 0, sizeof regs);
    return ins;
}

static void set1(int k, float x) { regs[IN_REG(k)] = x; }
static void set3(int k, float x, float y, float z)
{
    regs[IN_REG(k)] = x;
    regs[IN_REG(k) + 1] = y;
    regs[IN_REG(k) + 2] = z;
}
static float out1(int k) { return regs[OUT_REG(k)]; }
static vec3 out3(int k) { return v3_load(regs + OUT_REG(k)); }

static int near(double a, double b) { return fabs(a - b) <= TOL * fmax(1.0, fabs(b)); }

#define CHECK_NEAR(a, b) CHECK_MSG(near((a), (b)), "%.8g vs %.8g", (double)(a), (double)(b))
#define CHECK_V3(v, ex, ey, ez)                                                                   \
    CHECK_MSG(near((v).x, (ex)) && near((v).y, (ey)) && near((v).z, (ez)),                       \
              "(%.8g %.8g %.8g) vs (%.8g %.8g %.8g)", (double)(v).x, (double)(v).y, (double)(v).z, \
              (double)(ex), (double)(ey), (double)(ez))

/* ------------------------------------------------------------------ Math */

static float run_math(uint32_t op, float a, float b, float c, uint32_t flags)
{
    phos_shader_instruction ins = make_ins(op, flags);
    set1(0, a);
    set1(1, b);
    set1(2, c);
    shader_op_math(&ins, &ctx);
    return out1(0);
}

typedef struct math_case {
    uint32_t op;
    float a, b, c, expect;
} math_case;

static void test_math(void)
{
    const float pi = 3.14159265358979f;
    static const math_case cases[] = {
        {PHOS_MATH_ADD, 2, 3, 0, 5},
        {PHOS_MATH_SUBTRACT, 2, 3, 0, -1},
        {PHOS_MATH_MULTIPLY, 2, 3, 0, 6},
        {PHOS_MATH_DIVIDE, 3, 2, 0, 1.5f},
        {PHOS_MATH_DIVIDE, 3, 0, 0, 0},               /* x/0 = 0 */
        {PHOS_MATH_MULTIPLY_ADD, 2, 3, 4, 10},
        {PHOS_MATH_POWER, 2, 3, 0, 8},
        {PHOS_MATH_POWER, -2, 3, 0, -8},              /* integer exponent: defined */
        {PHOS_MATH_POWER, -8, 1.0f / 3.0f, 0, 0},     /* fractional: 0 */
        {PHOS_MATH_POWER, 0, -1, 0, 0},               /* 0^−1 = 0 from Blender 5.0 */
        {PHOS_MATH_POWER, 5, 0, 0, 1},
        {PHOS_MATH_LOGARITHM, 8, 2, 0, 3},
        {PHOS_MATH_LOGARITHM, -1, 2, 0, 0},
        {PHOS_MATH_LOGARITHM, 8, -2, 0, 0},
        {PHOS_MATH_LOGARITHM, 8, 1, 0, 0},            /* log 1 = 0: safe division */
        {PHOS_MATH_SQRT, 4, 0, 0, 2},
        {PHOS_MATH_SQRT, -4, 0, 0, 0},
        {PHOS_MATH_INVERSE_SQRT, 4, 0, 0, 0.5f},
        {PHOS_MATH_INVERSE_SQRT, 0, 0, 0, 0},
        {PHOS_MATH_ABSOLUTE, -3, 0, 0, 3},
        {PHOS_MATH_EXPONENT, 1, 0, 0, 2.7182818f},
        {PHOS_MATH_MINIMUM, 2, 3, 0, 2},
        {PHOS_MATH_MAXIMUM, 2, 3, 0, 3},
        {PHOS_MATH_LESS_THAN, 2, 3, 0, 1},
        {PHOS_MATH_LESS_THAN, 3, 2, 0, 0},
        {PHOS_MATH_GREATER_THAN, 2, 3, 0, 0},
        {PHOS_MATH_GREATER_THAN, 3, 2, 0, 1},
        {PHOS_MATH_SIGN, -2, 0, 0, -1},
        {PHOS_MATH_SIGN, 0, 0, 0, 0},
        {PHOS_MATH_SIGN, 5, 0, 0, 1},
        {PHOS_MATH_COMPARE, 1, 1.05f, 0.1f, 1},
        {PHOS_MATH_COMPARE, 1, 1.2f, 0.1f, 0},
        {PHOS_MATH_COMPARE, 1, 1, 0, 1},
        {PHOS_MATH_SMOOTH_MIN, 1, 2, 0, 1},
        {PHOS_MATH_SMOOTH_MIN, 1, 1, 1, 1.0f - 1.0f / 6.0f},  /* h = 1: min − k/6 */
        {PHOS_MATH_SMOOTH_MIN, 1, 3, 1, 1},           /* farther apart than k */
        {PHOS_MATH_SMOOTH_MAX, 1, 1, 1, 1.0f + 1.0f / 6.0f},
        {PHOS_MATH_ROUND, 2.5f, 0, 0, 3},
        {PHOS_MATH_ROUND, -2.5f, 0, 0, -2},           /* ⌊x + 1/2⌋ */
        {PHOS_MATH_FLOOR, -2.5f, 0, 0, -3},
        {PHOS_MATH_CEIL, -2.5f, 0, 0, -2},
        {PHOS_MATH_TRUNC, -2.5f, 0, 0, -2},
        {PHOS_MATH_TRUNC, 2.5f, 0, 0, 2},
        {PHOS_MATH_FRACT, -2.25f, 0, 0, 0.75f},
        {PHOS_MATH_MODULO, -5, 3, 0, -2},
        {PHOS_MATH_MODULO, 5, 0, 0, 0},
        {PHOS_MATH_FLOORED_MODULO, -5, 3, 0, 1},
        {PHOS_MATH_FLOORED_MODULO, 5, 0, 0, 0},
        {PHOS_MATH_WRAP, 5, 3, 1, 1},                 /* into [1, 3) */
        {PHOS_MATH_WRAP, 0.5f, 3, 1, 2.5f},
        {PHOS_MATH_WRAP, 1.5f, 1, 1, 1},              /* empty range: min */
        {PHOS_MATH_SNAP, 7, 3, 0, 6},
        {PHOS_MATH_SNAP, -7, 3, 0, -9},
        {PHOS_MATH_SNAP, 7, 0, 0, 0},
        {PHOS_MATH_PINGPONG, 5, 3, 0, 1},
        {PHOS_MATH_PINGPONG, 2, 3, 0, 2},
        {PHOS_MATH_PINGPONG, 5, 0, 0, 0},
        {PHOS_MATH_SINE, 1.5707963f, 0, 0, 1},
        {PHOS_MATH_COSINE, 0, 0, 0, 1},
        {PHOS_MATH_TANGENT, 0.78539816f, 0, 0, 1},
        {PHOS_MATH_ARCSINE, 2, 0, 0, 1.5707963f},     /* clamped to 1 */
        {PHOS_MATH_ARCCOSINE, -2, 0, 0, 3.1415927f},  /* clamped to −1 */
        {PHOS_MATH_ARCTANGENT, 1, 0, 0, 0.78539816f},
        {PHOS_MATH_ARCTAN2, 1, 1, 0, 0.78539816f},
        {PHOS_MATH_ARCTAN2, 1, -1, 0, 2.3561945f},
        {PHOS_MATH_SINH, 1, 0, 0, 1.1752012f},
        {PHOS_MATH_COSH, 1, 0, 0, 1.5430806f},
        {PHOS_MATH_TANH, 1, 0, 0, 0.76159416f},
        {PHOS_MATH_RADIANS, 180, 0, 0, 3.1415927f},
        {PHOS_MATH_DEGREES, 3.1415927f, 0, 0, 180},
    };
    int seen[PHOS_MATH_COUNT] = {0};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const math_case *m = &cases[i];
        float r = run_math(m->op, m->a, m->b, m->c, 0);
        CHECK_MSG(near(r, m->expect), "math op %u (%g, %g, %g) = %.8g, expected %.8g", m->op, (double)m->a,
                  (double)m->b, (double)m->c, (double)r, (double)m->expect);
        seen[m->op] = 1;
    }
    for (int op = 0; op < PHOS_MATH_COUNT; op++)
        CHECK_MSG(seen[op], "math op %d untested", op);

    /* Clamp to [0,1]. */
    CHECK_NEAR(run_math(PHOS_MATH_ADD, 0.7f, 0.6f, 0, 1), 1.0f);
    CHECK_NEAR(run_math(PHOS_MATH_SUBTRACT, 0.2f, 0.6f, 0, 1), 0.0f);
    CHECK_NEAR(run_math(PHOS_MATH_MULTIPLY, 0.5f, 0.6f, 0, 1), 0.3f);
    CHECK_NEAR(run_math(PHOS_MATH_SQRT, NAN, 0, 0, 1), 0.0f);      /* NaN clamps to 0, as Cycles */
    /* Before Blender 5.0, 0^−1 is powf's +inf. */
    CHECK(isinf(run_math(PHOS_MATH_POWER, 0, -1, 0, PHOS_NODE_PRE_5_0)));
    /* atan2 of signed zeros: 0 from Blender 4.3, π before. */
    CHECK(run_math(PHOS_MATH_ARCTAN2, 0.0f, -0.0f, 0, 0) == 0.0f);
    CHECK_NEAR(run_math(PHOS_MATH_ARCTAN2, 0.0f, -0.0f, 0, PHOS_NODE_PRE_4_3), pi);
    /* An unknown op gives 0. */
    CHECK(run_math(PHOS_MATH_COUNT, 1, 2, 3, 0) == 0.0f);
}

/* ----------------------------------------------------------- Vector Math */

static void run_vmath(uint32_t op, vec3 a, vec3 b, vec3 c, float s, uint32_t flags, vec3 *vec, float *value)
{
    phos_shader_instruction ins = make_ins(op, flags);
    set3(0, a.x, a.y, a.z);
    set3(1, b.x, b.y, b.z);
    set3(2, c.x, c.y, c.z);
    set1(3, s);
    regs[OUT_REG(0)] = regs[OUT_REG(0) + 1] = regs[OUT_REG(0) + 2] = regs[OUT_REG(1)] = 99.0f;
    shader_op_vector_math(&ins, &ctx);
    *vec = out3(0);
    *value = out1(1);
}

/* Runs a vector-output op and checks both outputs (the value output is 0). */
#define CHECK_VMATH(op, a, b, c, s, ex, ey, ez)                                                    \
    do {                                                                                           \
        vec3 vec_;                                                                                 \
        float val_;                                                                                \
        run_vmath((op), (a), (b), (c), (s), 0, &vec_, &val_);                                      \
        CHECK_V3(vec_, (ex), (ey), (ez));                                                          \
        CHECK(val_ == 0.0f);                                                                       \
        seen[(op)] = 1;                                                                            \
    } while (0)
#define CHECK_VMATH_VALUE(op, a, b, expect)                                                        \
    do {                                                                                           \
        vec3 vec_;                                                                                 \
        float val_;                                                                                \
        run_vmath((op), (a), (b), z3, 0, 0, &vec_, &val_);                                         \
        CHECK_NEAR(val_, (expect));                                                                \
        CHECK(v3_is_zero(vec_));                                                                   \
        seen[(op)] = 1;                                                                            \
    } while (0)

static void test_vector_math(void)
{
    int seen[PHOS_VECTOR_MATH_COUNT] = {0};
    const float pi = 3.14159265358979f;
    vec3 a = v3(1, 2, 3), b = v3(4, -5, 6), c = v3(0.5f, 0.5f, 0.5f), z3 = v3s(0.0f);
    CHECK_VMATH(PHOS_VECTOR_MATH_ADD, a, b, z3, 0, 5, -3, 9);
    CHECK_VMATH(PHOS_VECTOR_MATH_SUBTRACT, a, b, z3, 0, -3, 7, -3);
    CHECK_VMATH(PHOS_VECTOR_MATH_MULTIPLY, a, b, z3, 0, 4, -10, 18);
    CHECK_VMATH(PHOS_VECTOR_MATH_DIVIDE, a, v3(4, 0, 6), z3, 0, 0.25f, 0, 0.5f);   /* x/0 = 0 */
    CHECK_VMATH(PHOS_VECTOR_MATH_MULTIPLY_ADD, a, b, c, 0, 4.5f, -9.5f, 18.5f);
    CHECK_VMATH(PHOS_VECTOR_MATH_CROSS_PRODUCT, a, b, z3, 0, 27, 6, -13);
    /* a·b = 12, |b|² = 77. */
    CHECK_VMATH(PHOS_VECTOR_MATH_PROJECT, a, b, z3, 0, 48.0f / 77, -60.0f / 77, 72.0f / 77);
    CHECK_VMATH(PHOS_VECTOR_MATH_REFLECT, a, v3(0, 0, 2), z3, 0, 1, 2, -3);         /* normal normalised */
    /* η = 1/1.5, i = (0.6, −0.8, 0), n = (0, 1, 0): k = 1 − η²·0.36 = 0.84. */
    CHECK_VMATH(PHOS_VECTOR_MATH_REFRACT, v3(0.6f, -0.8f, 0), v3(0, 2, 0), z3, 1.0f / 1.5f, 0.4f,
                -0.8f / 1.5f - (-0.8f / 1.5f + sqrtf(0.84f)), 0);
    /* η = 1.5 at 53°: total internal reflection gives 0. */
    CHECK_VMATH(PHOS_VECTOR_MATH_REFRACT, v3(0.8f, -0.6f, 0), v3(0, 1, 0), z3, 1.5f, 0, 0, 0);
    CHECK_VMATH(PHOS_VECTOR_MATH_FACEFORWARD, a, b, c, 0, -1, -2, -3);               /* c·b = 2.5 > 0 */
    CHECK_VMATH(PHOS_VECTOR_MATH_FACEFORWARD, a, b, v3(-1, 0, 0), 0, 1, 2, 3);
    CHECK_VMATH_VALUE(PHOS_VECTOR_MATH_DOT_PRODUCT, a, b, 12);
    CHECK_VMATH_VALUE(PHOS_VECTOR_MATH_DISTANCE, a, b, sqrt(67.0));
    CHECK_VMATH_VALUE(PHOS_VECTOR_MATH_LENGTH, a, b, sqrt(14.0));
    CHECK_VMATH(PHOS_VECTOR_MATH_SCALE, a, b, z3, 2, 2, 4, 6);
    CHECK_VMATH(PHOS_VECTOR_MATH_NORMALIZE, a, z3, z3, 0, 1 / sqrt(14.0), 2 / sqrt(14.0), 3 / sqrt(14.0));
    CHECK_VMATH(PHOS_VECTOR_MATH_NORMALIZE, z3, z3, z3, 0, 0, 0, 0);                 /* zero stays zero */
    CHECK_VMATH(PHOS_VECTOR_MATH_ABSOLUTE, b, z3, z3, 0, 4, 5, 6);
    CHECK_VMATH(PHOS_VECTOR_MATH_POWER, v3(-2, 2, -4), v3(3, 0.5f, 0.5f), z3, 0, -8, sqrtf(2.0f), 0);
    CHECK_VMATH(PHOS_VECTOR_MATH_SIGN, v3(4, -5, 0), z3, z3, 0, 1, -1, 0);
    CHECK_VMATH(PHOS_VECTOR_MATH_MINIMUM, a, b, z3, 0, 1, -5, 3);
    CHECK_VMATH(PHOS_VECTOR_MATH_MAXIMUM, a, b, z3, 0, 4, 2, 6);
    CHECK_VMATH(PHOS_VECTOR_MATH_FLOOR, v3(-1.5f, 2.5f, 0), z3, z3, 0, -2, 2, 0);
    CHECK_VMATH(PHOS_VECTOR_MATH_CEIL, v3(-1.5f, 2.5f, 0), z3, z3, 0, -1, 3, 0);
    CHECK_VMATH(PHOS_VECTOR_MATH_FRACTION, v3(-1.25f, 2.5f, 0), z3, z3, 0, 0.75f, 0.5f, 0);
    CHECK_VMATH(PHOS_VECTOR_MATH_MODULO, v3(-5, 5, 5), v3(3, 3, 0), z3, 0, -2, 2, 0);
    CHECK_VMATH(PHOS_VECTOR_MATH_WRAP, v3(5, 5, 5), v3(3, 1, 2), v3(1, 1, 0), 0, 1, 1, 1);
    CHECK_VMATH(PHOS_VECTOR_MATH_SNAP, v3(7, -7, 7), v3(3, 3, 0), z3, 0, 6, -9, 0);
    CHECK_VMATH(PHOS_VECTOR_MATH_SINE, v3(0, pi / 2, -pi / 2), z3, z3, 0, 0, 1, -1);
    CHECK_VMATH(PHOS_VECTOR_MATH_COSINE, v3(0, pi, 2 * pi), z3, z3, 0, 1, -1, 1);
    CHECK_VMATH(PHOS_VECTOR_MATH_TANGENT, v3(pi / 4, 0, -pi / 4), z3, z3, 0, 1, 0, -1);
    for (int op = 0; op < PHOS_VECTOR_MATH_COUNT; op++)
        CHECK_MSG(seen[op], "vector math op %d untested", op);

    /* The wrap of Blender < 5.0 agrees on these. */
    vec3 v;
    float value;
    run_vmath(PHOS_VECTOR_MATH_WRAP, v3(5, 5, 0.5f), v3(3, 1, 3), v3(1, 1, 1), 0, PHOS_NODE_PRE_5_0, &v, &value);
    CHECK_V3(v, 1, 1, 2.5f);
    /* Reflect about a zero normal: a itself from 4.3, NaN before. */
    run_vmath(PHOS_VECTOR_MATH_REFLECT, a, z3, z3, 0, 0, &v, &value);
    CHECK_V3(v, 1, 2, 3);
    run_vmath(PHOS_VECTOR_MATH_REFLECT, a, z3, z3, 0, PHOS_NODE_PRE_4_3, &v, &value);
    CHECK(isnan(v.x));
    /* A missing output is skipped. */
    phos_shader_instruction ins = make_ins(PHOS_VECTOR_MATH_ADD, 0);
    ins.outputs[1] = PHOS_SHADER_NO_REGISTER;
    regs[OUT_REG(1)] = 7.0f;
    shader_op_vector_math(&ins, &ctx);
    CHECK(regs[OUT_REG(1)] == 7.0f);
}

/* ------------------------------------------------------------- Map Range */

static float run_map_range(uint32_t mode, uint32_t flags, float x, float fmin, float fmax, float tmin, float tmax,
                           float steps)
{
    phos_shader_instruction ins = make_ins(mode, flags);
    set1(0, x);
    set1(1, fmin);
    set1(2, fmax);
    set1(3, tmin);
    set1(4, tmax);
    set1(5, steps);
    shader_op_map_range(&ins, &ctx);
    return out1(0);
}

static vec3 run_map_range3(uint32_t mode, uint32_t flags, vec3 x, vec3 fmin, vec3 fmax, vec3 tmin, vec3 tmax,
                           vec3 steps)
{
    phos_shader_instruction ins = make_ins(mode, flags);
    vec3 in[6] = {x, fmin, fmax, tmin, tmax, steps};
    for (int k = 0; k < 6; k++)
        set3(k, in[k].x, in[k].y, in[k].z);
    shader_op_map_range_vector(&ins, &ctx);
    return out3(0);
}

static void test_map_range(void)
{
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_LINEAR, 0, 0.25f, 0, 1, 10, 20, 4), 12.5f);
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_LINEAR, 0, 2, 0, 1, 10, 20, 4), 30);
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_LINEAR, 1, 2, 0, 1, 10, 20, 4), 20);      /* clamped */
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_LINEAR, 1, -2, 0, 1, 20, 10, 4), 20);     /* reversed target */
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_LINEAR, 0, 0.5f, 1, 1, 10, 20, 4), 0);    /* empty source: 0 */
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_LINEAR, 1, 0.5f, 1, 1, 10, 20, 4), 10);   /* ... then clamped */
    /* Stepped, 4 steps: ⌊f·5⌋/4. */
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_STEPPED, 0, 0.3f, 0, 1, 10, 20, 4), 12.5f);
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_STEPPED, 0, 0.85f, 0, 1, 10, 20, 4), 20);
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_STEPPED, 0, 0.85f, 0, 1, 10, 20, 0), 10); /* no steps: factor 0 */
    /* Smoothstep 0.25: 0.25²(3 − 0.5) = 0.15625; smootherstep: 0.103515625. */
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_SMOOTHSTEP, 0, 0.25f, 0, 1, 10, 20, 0), 11.5625f);
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_SMOOTHSTEP, 0, 0.25f, 1, 0, 10, 20, 0), 18.4375f); /* reversed */
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_SMOOTHSTEP, 0, -1, 0, 1, 10, 20, 0), 10);
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_SMOOTHERSTEP, 0, 0.25f, 0, 1, 10, 20, 0), 11.03515625f);
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_SMOOTHERSTEP, 0, 0.25f, 1, 0, 10, 20, 0), 18.96484375f);
    CHECK_NEAR(run_map_range(PHOS_MAP_RANGE_SMOOTHERSTEP, 0, 3, 0, 1, 10, 20, 0), 20);

    vec3 r = run_map_range3(PHOS_MAP_RANGE_LINEAR, 1, v3(0.25f, 2, 0.5f), v3(0, 0, 1), v3(1, 1, 1), v3s(10),
                            v3s(20), v3s(4));
    CHECK_V3(r, 12.5f, 20, 10);   /* clamped; the empty range gives factor 0 */
    r = run_map_range3(PHOS_MAP_RANGE_LINEAR, 0, v3(0.25f, 2, 0.5f), v3(0, 0, 1), v3(1, 1, 1), v3s(10), v3s(20),
                       v3s(4));
    CHECK_V3(r, 12.5f, 30, 10);
    r = run_map_range3(PHOS_MAP_RANGE_STEPPED, 1, v3(0.3f, 0.85f, 2), v3s(0), v3s(1), v3s(10), v3s(20),
                       v3(4, 4, 4));
    CHECK_V3(r, 12.5f, 20, 20);
    r = run_map_range3(PHOS_MAP_RANGE_SMOOTHSTEP, 1, v3(0.25f, 0.25f, 2), v3(0, 1, 0), v3(1, 0, 1), v3s(10),
                       v3s(20), v3s(0));
    CHECK_V3(r, 11.5625f, 18.4375f, 20);
    r = run_map_range3(PHOS_MAP_RANGE_SMOOTHERSTEP, 0, v3(0.25f, 0.25f, -1), v3(0, 1, 0), v3(1, 0, 1), v3s(10),
                       v3s(20), v3s(0));
    CHECK_V3(r, 11.03515625f, 18.96484375f, 10);
}

static void test_clamp_combine(void)
{
    phos_shader_instruction ins = make_ins(PHOS_CLAMP_MINMAX, 0);
    set1(0, 5);
    set1(1, 0);
    set1(2, 1);
    shader_op_clamp(&ins, &ctx);
    CHECK(out1(0) == 1.0f);
    set1(0, 0.5f);
    set1(1, 1);
    set1(2, 0);
    shader_op_clamp(&ins, &ctx);
    CHECK(out1(0) == 0.0f);      /* MINMAX with min > max: max wins */
    ins.mode = PHOS_CLAMP_RANGE;
    shader_op_clamp(&ins, &ctx);
    CHECK(out1(0) == 0.5f);      /* RANGE: either order */
    set1(0, -3);
    shader_op_clamp(&ins, &ctx);
    CHECK(out1(0) == 0.0f);

    ins = make_ins(0, 0);
    set1(0, 1);
    set1(1, 2);
    set1(2, 3);
    shader_op_combine_xyz(&ins, &ctx);
    CHECK_V3(out3(0), 1, 2, 3);
}

/* ------------------------------------------------------------------- Mix */

static vec3 run_mix_color(uint32_t mode, uint32_t flags, float fac, vec3 a, vec3 b)
{
    phos_shader_instruction ins = make_ins(mode, flags);
    set1(0, fac);
    set3(1, a.x, a.y, a.z);
    set3(2, b.x, b.y, b.z);
    shader_op_mix_color(&ins, &ctx);
    return out3(0);
}

static void test_mix(void)
{
    /* a = (0.2, 0.4, 0.8), b = (0.6, 0.2, 0) at t = 1/2, worked out per mode. */
    static const struct {
        uint32_t mode;
        float r, g, b;
    } blends[] = {
        {PHOS_BLEND_MIX, 0.4f, 0.3f, 0.4f},
        {PHOS_BLEND_DARKEN, 0.2f, 0.3f, 0.4f},
        {PHOS_BLEND_MULTIPLY, 0.16f, 0.24f, 0.4f},
        {PHOS_BLEND_BURN, 0.0f, 0.0f, 0.6f},              /* 1 − (1 − a)/(1/2 + b/2), clamped */
        {PHOS_BLEND_LIGHTEN, 0.4f, 0.4f, 0.8f},
        {PHOS_BLEND_SCREEN, 0.44f, 0.46f, 0.8f},
        {PHOS_BLEND_DODGE, 0.2f / 0.7f, 0.4f / 0.9f, 0.8f},
        {PHOS_BLEND_ADD, 0.5f, 0.5f, 0.8f},
        {PHOS_BLEND_OVERLAY, 0.22f, 0.28f, 0.7f},
        {PHOS_BLEND_SOFT_LIGHT, 0.216f, 0.328f, 0.72f},
        {PHOS_BLEND_LINEAR_LIGHT, 0.3f, 0.1f, 0.3f},
        {PHOS_BLEND_DIFFERENCE, 0.3f, 0.3f, 0.8f},
        {PHOS_BLEND_EXCLUSION, 0.38f, 0.42f, 0.8f},
        {PHOS_BLEND_SUBTRACT, -0.1f, 0.3f, 0.8f},
        {PHOS_BLEND_DIVIDE, 0.8f / 3.0f, 1.2f, 0.8f},     /* b = 0 leaves a */
        {PHOS_BLEND_HUE, 0.5f, 0.4f, 0.5f},               /* a's s, v with b's hue: (0.8, 0.4, 0.2) */
        {PHOS_BLEND_SATURATION, 0.1f, 1.0f / 3.0f, 0.8f},
        {PHOS_BLEND_VALUE, 0.175f, 0.35f, 0.7f},
        {PHOS_BLEND_COLOR, 0.5f, 1.0f / 3.0f, 0.4f},      /* b's h, s with a's v: (0.8, 4/15, 0) */
    };
    vec3 a = v3(0.2f, 0.4f, 0.8f), b = v3(0.6f, 0.2f, 0.0f);
    int seen[PHOS_BLEND_COUNT] = {0};
    for (size_t i = 0; i < sizeof blends / sizeof blends[0]; i++) {
        vec3 r = run_mix_color(blends[i].mode, 0, 0.5f, a, b);
        CHECK_MSG(near(r.x, blends[i].r) && near(r.y, blends[i].g) && near(r.z, blends[i].b),
                  "blend %u: (%.7g %.7g %.7g) vs (%.7g %.7g %.7g)", blends[i].mode, (double)r.x, (double)r.y,
                  (double)r.z, (double)blends[i].r, (double)blends[i].g, (double)blends[i].b);
        seen[blends[i].mode] = 1;
    }
    for (int m = 0; m < PHOS_BLEND_COUNT; m++)
        CHECK_MSG(seen[m], "blend mode %d untested", m);

    /* Linear Light at factor 2: a + 2(2b − 1) unclamped; the factor clamped to 1;
     * then the result clamped. */
    CHECK_V3(run_mix_color(PHOS_BLEND_LINEAR_LIGHT, 0, 2, a, b), 0.6f, -0.8f, -1.2f);
    CHECK_V3(run_mix_color(PHOS_BLEND_LINEAR_LIGHT, 2, 2, a, b), 0.4f, -0.2f, -0.2f);
    CHECK_V3(run_mix_color(PHOS_BLEND_LINEAR_LIGHT, 3, 2, a, b), 0.4f, 0.0f, 0.0f);
    /* Hue of a grey b leaves a. */
    CHECK_V3(run_mix_color(PHOS_BLEND_HUE, 0, 1, a, v3s(0.5f)), 0.2f, 0.4f, 0.8f);

    phos_shader_instruction ins = make_ins(0, 0);
    set1(0, 0.25f);
    set1(1, 2);
    set1(2, 6);
    shader_op_mix_float(&ins, &ctx);
    CHECK_NEAR(out1(0), 3);
    set1(0, 2);
    shader_op_mix_float(&ins, &ctx);
    CHECK_NEAR(out1(0), 10);
    ins.flags = 2;
    shader_op_mix_float(&ins, &ctx);
    CHECK_NEAR(out1(0), 6);

    ins = make_ins(0, 0);
    set1(0, 0.5f);
    set3(1, 1, 1, 1);
    set3(2, 3, 5, 7);
    shader_op_mix_vector(&ins, &ctx);
    CHECK_V3(out3(0), 2, 3, 4);
    ins.flags = 4;               /* per-component factor */
    set3(0, 0, 0.5f, 2);
    shader_op_mix_vector(&ins, &ctx);
    CHECK_V3(out3(0), 1, 3, 13);
    ins.flags = 4 | 2;
    shader_op_mix_vector(&ins, &ctx);
    CHECK_V3(out3(0), 1, 3, 7);
}

/* ------------------------------------------------------ colour adjustment */

static vec3 run_color1(void (*op)(const phos_shader_instruction *, shader_context *), uint32_t mode, vec3 c)
{
    phos_shader_instruction ins = make_ins(mode, 0);
    set3(0, c.x, c.y, c.z);
    op(&ins, &ctx);
    return out3(0);
}

static vec3 run_hsv_node(uint32_t flags, float hue, float sat, float val, float fac, vec3 c)
{
    phos_shader_instruction ins = make_ins(0, flags);
    set1(0, hue);
    set1(1, sat);
    set1(2, val);
    set1(3, fac);
    set3(4, c.x, c.y, c.z);
    shader_op_hue_saturation(&ins, &ctx);
    return out3(0);
}

static void test_adjust(void)
{
    vec3 c = v3(0.2f, 0.4f, 0.8f);   /* HSV (0.6111, 0.75, 0.8) */
    CHECK_V3(run_hsv_node(0, 0.5f, 1, 1, 1, c), 0.2f, 0.4f, 0.8f);       /* neutral */
    CHECK_V3(run_hsv_node(0, 0.5f, 0, 1, 1, c), 0.8f, 0.8f, 0.8f);       /* desaturated: v */
    CHECK_V3(run_hsv_node(0, 0.5f, 1, 0.5f, 0.5f, c), 0.15f, 0.3f, 0.6f);
    /* Hue −0.8: h = 0.6111 − 0.8 + 0.5 = 0.3111, sextant 1: (q, v, p). */
    CHECK_V3(run_hsv_node(0, -0.8f, 1, 1, 1, c), 0.28f, 0.8f, 0.2f);
    CHECK_V3(run_hsv_node(PHOS_NODE_PRE_4_3, -0.8f, 1, 1, 1, c), 0.28f, 0.8f, 0.2f);
    /* Hue −1.5: h = −0.3889, wrapped to 0.6111 (the input back); before 4.3
     * fmod keeps it negative, which falls in the last sextant: (v, p, q). */
    CHECK_V3(run_hsv_node(0, -1.5f, 1, 1, 1, c), 0.2f, 0.4f, 0.8f);
    CHECK_V3(run_hsv_node(PHOS_NODE_PRE_4_3, -1.5f, 1, 1, 1, c), 0.8f, 0.2f, 0.4f);
    /* Over-saturation would go negative: clamped at 0. */
    CHECK_V3(run_hsv_node(0, 0.5f, 1, 1, -1, c), 0.2f, 0.4f, 0.8f);

    phos_shader_instruction ins = make_ins(0, 0);
    set3(0, 0.5f, 0.2f, 0.1f);
    set1(1, 0.1f);
    set1(2, 0.5f);
    shader_op_bright_contrast(&ins, &ctx);
    CHECK_V3(out3(0), 0.6f, 0.15f, 0.0f);     /* 1.5c − 0.15, clamped at 0 */

    ins = make_ins(0, 0);
    set3(0, 0.25f, -1, 4);
    set1(1, 0.5f);
    shader_op_gamma(&ins, &ctx);
    CHECK_V3(out3(0), 0.5f, -1, 2);            /* non-positive components unchanged */
    set1(1, 0);
    shader_op_gamma(&ins, &ctx);
    CHECK_V3(out3(0), 1, 1, 1);

    ins = make_ins(0, 0);
    set1(0, 1);
    set3(1, 0.2f, 0.4f, 1.5f);
    shader_op_invert(&ins, &ctx);
    CHECK_V3(out3(0), 0.8f, 0.6f, -0.5f);
    set1(0, 0.5f);
    shader_op_invert(&ins, &ctx);
    CHECK_V3(out3(0), 0.5f, 0.5f, 0.5f);

    ins = make_ins(0, 0);
    set3(0, 1, 1, 1);
    shader_op_rgb_to_bw(&ins, &ctx);
    CHECK_NEAR(out1(0), 1.0f);
    set3(0, 0, 1, 0);
    shader_op_rgb_to_bw(&ins, &ctx);
    CHECK_NEAR(out1(0), 0.7151522f);
}

/* Combine Color reads three 1-wide sockets. */
static vec3 run_combine(uint32_t mode, vec3 c)
{
    phos_shader_instruction ins = make_ins(mode, 0);
    set1(0, c.x);
    set1(1, c.y);
    set1(2, c.z);
    shader_op_combine_color(&ins, &ctx);
    return out3(0);
}

static void test_separate_combine(void)
{
    CHECK_V3(run_color1(shader_op_separate_color, PHOS_COLOR_MODEL_RGB, v3(0.1f, 0.2f, 0.3f)), 0.1f, 0.2f, 0.3f);
    CHECK_V3(run_color1(shader_op_separate_color, PHOS_COLOR_MODEL_HSV, v3(1, 0, 0)), 0, 1, 1);
    CHECK_V3(run_color1(shader_op_separate_color, PHOS_COLOR_MODEL_HSV, v3(0.2f, 0.4f, 0.8f)), 11.0f / 18.0f,
             0.75f, 0.8f);
    CHECK_V3(run_color1(shader_op_separate_color, PHOS_COLOR_MODEL_HSV, v3(1, 0, 0.5f)), 11.0f / 12.0f, 1, 1);
    CHECK_V3(run_color1(shader_op_separate_color, PHOS_COLOR_MODEL_HSV, v3s(0.3f)), 0, 0, 0.3f);
    CHECK_V3(run_color1(shader_op_separate_color, PHOS_COLOR_MODEL_HSL, v3(0.2f, 0.4f, 0.8f)), 11.0f / 18.0f,
             0.6f, 0.5f);
    CHECK_V3(run_color1(shader_op_separate_color, PHOS_COLOR_MODEL_HSL, v3(1, 0.5f, 0.5f)), 0, 1, 0.75f);
    CHECK_V3(run_combine(PHOS_COLOR_MODEL_HSV, v3(1.0f / 3.0f, 1, 0.5f)), 0, 0.5f, 0);
    CHECK_V3(run_combine(PHOS_COLOR_MODEL_HSV, v3(1, 1, 1)), 1, 0, 0);   /* h = 1 is 0 */
    CHECK_V3(run_combine(PHOS_COLOR_MODEL_HSL, v3(2.0f / 3.0f, 1, 0.5f)), 0, 0, 1);

    /* Round trips, on a grid of colours in [0,1]³ (not grey: hue undefined there). */
    int hsv_ok = 1, hsl_ok = 1;
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++)
            for (int k = 0; k < 6; k++) {
                vec3 c = v3(i / 5.0f, j / 5.0f + 0.013f, k / 5.0f + 0.007f);
                vec3 h = run_color1(shader_op_separate_color, PHOS_COLOR_MODEL_HSV, c);
                vec3 back = run_combine(PHOS_COLOR_MODEL_HSV, h);
                hsv_ok &= fabsf(back.x - c.x) < 1e-5f && fabsf(back.y - c.y) < 1e-5f && fabsf(back.z - c.z) < 1e-5f;
                if (c.y <= 1.0f && c.z <= 1.0f) {
                    h = run_color1(shader_op_separate_color, PHOS_COLOR_MODEL_HSL, c);
                    back = run_combine(PHOS_COLOR_MODEL_HSL, h);
                    hsl_ok &= fabsf(back.x - c.x) < 1e-5f && fabsf(back.y - c.y) < 1e-5f &&
                              fabsf(back.z - c.z) < 1e-5f;
                }
            }
    CHECK(hsv_ok);
    CHECK(hsl_ok);
}

/* ---------------------------------------------------- blackbody, wavelength */

static void test_physical(void)
{
    vec3 w = run_color1(shader_op_blackbody, 0, v3s(6500));
    /* The fit at 6500 K (last segment): about (1.043, 0.984, 1.035). */
    CHECK_MSG(fabsf(w.x - 1) < 0.06f && fabsf(w.y - 1) < 0.06f && fabsf(w.z - 1) < 0.06f, "6500 K: %g %g %g",
              (double)w.x, (double)w.y, (double)w.z);
    CHECK_V3(w, 3787.1745f / 6500 + 9.35907826e-06f * 6500 + 0.399075871f,
             -500.799571f / 6500 - 4.59832026e-06f * 6500 + 1.09098763f, 1.0352729f);
    vec3 warm = run_color1(shader_op_blackbody, 0, v3s(2000));
    CHECK(warm.x > warm.y && warm.y > warm.z);
    CHECK_V3(run_color1(shader_op_blackbody, 0, v3s(500)), 5.413294490189271f, 0, 0);     /* held, clamped */
    CHECK_V3(run_color1(shader_op_blackbody, 0, v3s(20000)), 0.8262954810464208f, 0.9945080501520986f,
             1.566307710274283f);
    CHECK_V3(run_color1(shader_op_blackbody, 0, v3s(NAN)), 0, 0, 0);

    /* 555 nm is an entry: XYZ (0.5121, 1, 0.0057) → Rec. 709 / 2.52, clamped. */
    CHECK_V3(run_color1(shader_op_wavelength, 0, v3s(555)), 0.0474033599f, 0.547574028f, 0.0f);
    /* 612.5 nm, halfway between two entries. */
    CHECK_V3(run_color1(shader_op_wavelength, 0, v3s(612.5f)), 0.959941699f, 0.0f, 0.0f);
    /* 377.5 nm: the index truncates to 0 and the first interval extrapolates. */
    CHECK_V3(run_color1(shader_op_wavelength, 0, v3s(377.5f)), 0.000426158661f, 0.0f, 0.00191403099f);
    CHECK_V3(run_color1(shader_op_wavelength, 0, v3s(300)), 0, 0, 0);
    CHECK_V3(run_color1(shader_op_wavelength, 0, v3s(780)), 0, 0, 0);
    CHECK_V3(run_color1(shader_op_wavelength, 0, v3s(900)), 0, 0, 0);
}

/* ------------------------------------------------------ ramps and curves */

static float table[64];

static void test_ramp(void)
{
    static const float ramp[3][4] = {{0, 0, 0, 1}, {1, 0.5f, 0, 0.5f}, {1, 1, 1, 0}};
    memcpy(table + 8, ramp, sizeof ramp);
    program.table = table;
    program.table_size = 64;

    phos_shader_instruction ins = make_ins(3, 0);
    ins.table = 8;
    static const struct {
        float fac, r, g, b, a, cr, cg, cb, ca;  /* linear, then constant */
    } cases[] = {
        {0.25f, 0.5f, 0.25f, 0, 0.75f, 0, 0, 0, 1},
        {0.75f, 1, 0.75f, 0.5f, 0.25f, 1, 0.5f, 0, 0.5f},
        {0.5f, 1, 0.5f, 0, 0.5f, 1, 0.5f, 0, 0.5f},
        {1, 1, 1, 1, 0, 1, 1, 1, 0},
        {-1, 0, 0, 0, 1, 0, 0, 0, 1},          /* clamped, never extrapolated */
        {2, 1, 1, 1, 0, 1, 1, 1, 0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        ins.flags = 0;
        set1(0, cases[i].fac);
        shader_op_ramp(&ins, &ctx);
        CHECK_V3(out3(0), cases[i].r, cases[i].g, cases[i].b);
        CHECK_NEAR(out1(1), cases[i].a);
        ins.flags = 8;
        shader_op_ramp(&ins, &ctx);
        CHECK_V3(out3(0), cases[i].cr, cases[i].cg, cases[i].cb);
        CHECK_NEAR(out1(1), cases[i].ca);
    }
}

static float run_curve_float(uint32_t flags, float fac, float x)
{
    phos_shader_instruction ins = make_ins(3, flags);
    ins.table = 20;
    ins.param[0] = 0;
    ins.param[1] = 2;
    set1(0, fac);
    set1(1, x);
    shader_op_curve_float(&ins, &ctx);
    return out1(0);
}

static void test_curves(void)
{
    /* Float curve through (0, 0), (1, 1), (2, 4), baked at x = 0, 1, 2. */
    static const float fc[3][4] = {{0, 0, 0, 0}, {1, 0, 0, 0}, {4, 0, 0, 0}};
    memcpy(table + 20, fc, sizeof fc);
    program.table = table;
    CHECK_NEAR(run_curve_float(0, 1, 1.5f), 2.5f);
    CHECK_NEAR(run_curve_float(0, 0.5f, 1.5f), 2.0f);     /* mixed with the input */
    CHECK_NEAR(run_curve_float(0, 1, 3), 4);              /* held */
    CHECK_NEAR(run_curve_float(1, 1, 3), 7);              /* extrapolated: 4 + 3·(1/2)·2 */
    CHECK_NEAR(run_curve_float(1, 1, -1), -1);            /* 0 + (0 − 1)·(1/2)·2 */
    CHECK_NEAR(run_curve_float(0, 1, -1), 0);

    /* RGB curves over [0, 1] with 2 entries: R rising, G falling, B flat at 1/2. */
    static const float rc[2][4] = {{0, 1, 0.5f, 0}, {1, 0, 0.5f, 1}};
    memcpy(table + 40, rc, sizeof rc);
    phos_shader_instruction ins = make_ins(2, 0);
    ins.table = 40;
    ins.param[0] = 0;
    ins.param[1] = 1;
    set1(0, 1);
    set3(1, 0.25f, 0.25f, 0.25f);
    shader_op_curves_rgb(&ins, &ctx);
    CHECK_V3(out3(0), 0.25f, 0.75f, 0.5f);
    set1(0, 0.5f);
    set3(1, 0.25f, 1.5f, -1);
    shader_op_curves_rgb(&ins, &ctx);
    CHECK_V3(out3(0), 0.25f, 0.75f, -0.25f);               /* held ends, mixed by 1/2 */
    ins.flags = 1;
    set1(0, 1);
    shader_op_curves_vector(&ins, &ctx);
    CHECK_V3(out3(0), 0.25f, -0.5f, 0.5f);                 /* extrapolated */
    ins.param[0] = -1;                                     /* the range [−1, 1] */
    set3(1, 0, 0, 0);
    shader_op_curves_vector(&ins, &ctx);
    CHECK_V3(out3(0), 0.5f, 0.5f, 0.5f);
}

int main(void)
{
    test_math();
    test_vector_math();
    test_map_range();
    test_clamp_combine();
    test_mix();
    test_adjust();
    test_separate_combine();
    test_physical();
    test_ramp();
    test_curves();
    return test_summary("test_nodes_color");
}
