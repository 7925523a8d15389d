/*
 * converter.c — the Converter nodes of a shader program: Math, Vector Math,
 * Map Range (float and vector), Clamp and Combine XYZ, evaluated as Cycles
 * evaluates them (the Blender manual, "Shader Nodes > Converter"), guards
 * included: a division by zero gives 0, a power of a negative base with a
 * fractional exponent gives 0, a logarithm of a non-positive number gives 0,
 * arcsine and arccosine clamp their argument to [−1, 1], and so on.
 *
 * Blender changed a few definitions over the versions the add-on supports;
 * the add-on sets these flag bits for the older ones:
 *   PHOS_NODE_PRE_4_3 (16)  Blender < 4.3: Arctangent2 is plain atan2 (signed
 *                           zeros give ±π), Reflect and Refract normalise
 *                           the normal without a guard (a zero normal gives
 *                           NaN), by division rather than by a reciprocal.
 *   PHOS_NODE_PRE_5_0 (32)  Blender < 5.0: 0 to a negative power is +inf
 *                           (pow), not 0; vector Wrap is computed as
 *                           v − r·⌊(v − min)/r⌋ rather than as a floored
 *                           modulo of v − min plus min (equal up to rounding).
 */
#include <float.h>

#include "shading/nodes/node_util.h"
#include "shading/shader_program.h"

#define MATH_CLAMP 1u
#define MAP_RANGE_CLAMP 1u

/* ---------------------------------------------------------- scalar guards */

/* x/y, 0 when y is 0. */
static inline float safe_div(float x, float y) { return y != 0.0f ? x / y : 0.0f; }

/* pow with Cycles' conventions: x⁰ = 1 (also 0⁰); from Blender 5.0, 0 to any
 * power is 0 (before, 0 to a negative power is +inf as powf gives). */
static float compat_pow(float x, float y, uint32_t flags)
{
    if (!(flags & PHOS_NODE_PRE_5_0)) {
        if (y == 0.0f)
            return 1.0f;
        if (x == 0.0f)
            return 0.0f;
    }
    return powf(x, y);
}

/* A negative base with an exponent that is not an integer has no real
 * power: 0. The integer test is the truncating float → int conversion. */
static float safe_pow(float x, float y, uint32_t flags)
{
    if (x < 0.0f && y != (float)node_float_to_int(y))
        return 0.0f;
    return compat_pow(x, y, flags);
}

/* log_b(x), 0 unless both are positive (and 0 for b = 1). */
static float safe_log(float x, float b)
{
    if (x <= 0.0f || b <= 0.0f)
        return 0.0f;
    return safe_div(logf(x), logf(b));
}

/* Truncated modulo (the sign of x), 0 for y = 0. */
static inline float safe_mod(float x, float y) { return y != 0.0f ? fmodf(x, y) : 0.0f; }

/* Floored modulo (the sign of y): x − y·⌊x/y⌋, 0 for y = 0. */
static inline float safe_floored_mod(float x, float y) { return y != 0.0f ? x - floorf(x / y) * y : 0.0f; }

static inline float inverse_sqrt(float x) { return x > 0.0f ? 1.0f / sqrtf(x) : 0.0f; }
static inline float fract(float x) { return x - floorf(x); }

/* Wraps v into [min, max): v − r·⌊(v − min)/r⌋ with r = max − min; min when r = 0. */
static inline float wrap(float v, float max, float min)
{
    float r = max - min;
    return r != 0.0f ? v - r * floorf((v - min) / r) : min;
}

/* A triangle wave of period 2s between 0 and s: |fract((x − s)/2s)·2s − s|; 0 for s = 0. */
static inline float pingpong(float x, float s)
{
    return s != 0.0f ? fabsf(fract((x - s) / (s * 2.0f)) * s * 2.0f - s) : 0.0f;
}

/* Polynomial smooth minimum of distance k (Quilez, "smooth minimum", cubic):
 * h = max(k − |a − b|, 0)/k, min(a, b) − h³·k/6. */
static float smooth_min(float a, float b, float k)
{
    if (k == 0.0f)
        return fminf(a, b);
    float h = fmaxf(k - fabsf(a - b), 0.0f) / k;
    return fminf(a, b) - h * h * h * k * (1.0f / 6.0f);
}

/* sign with sign(0) = 0. */
static inline float sign0(float x) { return x == 0.0f ? 0.0f : (x < 0.0f ? -1.0f : 1.0f); }

/* atan2(y, x) that is 0 at the origin whatever the signs of the zeros (4.3+). */
static inline float compat_atan2(float y, float x, uint32_t flags)
{
    if (!(flags & PHOS_NODE_PRE_4_3) && x == 0.0f && y == 0.0f)
        return 0.0f;
    return atan2f(y, x);
}

/* ------------------------------------------------------------------ Math */

static float math_eval(uint32_t op, float a, float b, float c, uint32_t flags)
{
    switch (op) {
    case PHOS_MATH_ADD: return a + b;
    case PHOS_MATH_SUBTRACT: return a - b;
    case PHOS_MATH_MULTIPLY: return a * b;
    case PHOS_MATH_DIVIDE: return safe_div(a, b);
    case PHOS_MATH_MULTIPLY_ADD: return a * b + c;
    case PHOS_MATH_POWER: return safe_pow(a, b, flags);
    case PHOS_MATH_LOGARITHM: return safe_log(a, b);
    case PHOS_MATH_SQRT: return safe_sqrtf(a);
    case PHOS_MATH_INVERSE_SQRT: return inverse_sqrt(a);
    case PHOS_MATH_ABSOLUTE: return fabsf(a);
    case PHOS_MATH_EXPONENT: return expf(a);
    case PHOS_MATH_MINIMUM: return fminf(a, b);
    case PHOS_MATH_MAXIMUM: return fmaxf(a, b);
    case PHOS_MATH_LESS_THAN: return a < b ? 1.0f : 0.0f;
    case PHOS_MATH_GREATER_THAN: return a > b ? 1.0f : 0.0f;
    case PHOS_MATH_SIGN: return sign0(a);
    /* 1 when |a − b| <= max(c, FLT_EPSILON) (or a = b, for infinities). */
    case PHOS_MATH_COMPARE: return (a == b || fabsf(a - b) <= fmaxf(c, FLT_EPSILON)) ? 1.0f : 0.0f;
    case PHOS_MATH_SMOOTH_MIN: return smooth_min(a, b, c);
    case PHOS_MATH_SMOOTH_MAX: return -smooth_min(-a, -b, c);
    case PHOS_MATH_ROUND: return floorf(a + 0.5f);
    case PHOS_MATH_FLOOR: return floorf(a);
    case PHOS_MATH_CEIL: return ceilf(a);
    case PHOS_MATH_TRUNC: return a >= 0.0f ? floorf(a) : ceilf(a);
    case PHOS_MATH_FRACT: return a - floorf(a);
    case PHOS_MATH_MODULO: return safe_mod(a, b);
    case PHOS_MATH_FLOORED_MODULO: return safe_floored_mod(a, b);
    case PHOS_MATH_WRAP: return wrap(a, b, c);
    case PHOS_MATH_SNAP: return floorf(safe_div(a, b)) * b;
    case PHOS_MATH_PINGPONG: return pingpong(a, b);
    case PHOS_MATH_SINE: return sinf(a);
    case PHOS_MATH_COSINE: return cosf(a);
    case PHOS_MATH_TANGENT: return tanf(a);
    case PHOS_MATH_ARCSINE: return asinf(node_clamp(a, -1.0f, 1.0f));
    case PHOS_MATH_ARCCOSINE: return acosf(node_clamp(a, -1.0f, 1.0f));
    case PHOS_MATH_ARCTANGENT: return atanf(a);
    case PHOS_MATH_ARCTAN2: return compat_atan2(a, b, flags);
    case PHOS_MATH_SINH: return sinhf(a);
    case PHOS_MATH_COSH: return coshf(a);
    case PHOS_MATH_TANH: return tanhf(a);
    case PHOS_MATH_RADIANS: return a * (PHOS_PI / 180.0f);
    case PHOS_MATH_DEGREES: return a * (180.0f / PHOS_PI);
    default: return 0.0f;
    }
}

/* in a, b, c; out value. Clamp (flags 1) is Cycles' Clamp node after it,
 * [0, 1] with a NaN going to 0. */
void shader_op_math(const phos_shader_instruction *ins, shader_context *ctx)
{
    float r = math_eval(ins->mode, SHADER_IN(0), SHADER_IN(1), SHADER_IN(2), ins->flags);
    if (ins->flags & MATH_CLAMP)
        r = node_clamp(r, 0.0f, 1.0f);
    SHADER_OUT(0, r);
}

/* ----------------------------------------------------------- Vector Math */

static inline vec3 v3_floor(vec3 a) { return v3(floorf(a.x), floorf(a.y), floorf(a.z)); }

/* a/|a|, a itself when |a| = 0 (Cycles' safe_normalize: times 1/|a|). */
static inline vec3 safe_normalize(vec3 a)
{
    float l = v3_length(a);
    return l != 0.0f ? v3_scale(a, 1.0f / l) : a;
}

/* The normal of Reflect and Refract: before 4.3 a/|a| by division, NaN for
 * a zero vector; from 4.3 safe_normalize. */
static inline vec3 node_normal(vec3 n, uint32_t flags)
{
    if (flags & PHOS_NODE_PRE_4_3) {
        float l = v3_length(n);
        return v3(n.x / l, n.y / l, n.z / l);
    }
    return safe_normalize(n);
}

/* The projection of a on b, 0 for b = 0. */
static vec3 project(vec3 a, vec3 b)
{
    float l2 = v3_dot(b, b);
    return l2 != 0.0f ? v3_scale(b, v3_dot(a, b) / l2) : v3s(0.0f);
}

/* Mirror of i about the unit normal n: i − 2n(i·n). */
static inline vec3 reflect(vec3 i, vec3 n) { return v3_sub(i, v3_scale(n, 2.0f * v3_dot(i, n))); }

/* GLSL's refract with eta the ratio of indices: k = 1 − η²(1 − (n·i)²),
 * 0 under total internal reflection, else η·i − (η(n·i) + √k)·n. */
static vec3 refract(vec3 i, vec3 n, float eta)
{
    float ni = v3_dot(n, i);
    float k = 1.0f - eta * eta * (1.0f - ni * ni);
    if (k < 0.0f)
        return v3s(0.0f);
    return v3_sub(v3_scale(i, eta), v3_scale(n, eta * ni + sqrtf(k)));
}

/* Vector Wrap: per component; from Blender 5.0 as a floored modulo of v − min. */
static float wrap_component(float v, float max, float min, uint32_t flags)
{
    if (flags & PHOS_NODE_PRE_5_0)
        return wrap(v, max, min);
    float r = max - min;
    float d = v - min;
    return (r != 0.0f ? d - floorf(d / r) * r : 0.0f) + min;
}

/* Evaluates one vector operation; *value and *vec keep 0 where the
 * operation has no such output (Cycles from 4.5; before, they were left
 * unset, and the UI hides that socket). */
static void vector_math_eval(uint32_t op, vec3 a, vec3 b, vec3 c, float s, uint32_t flags, vec3 *vec,
                             float *value)
{
    switch (op) {
    case PHOS_VECTOR_MATH_ADD: *vec = v3_add(a, b); break;
    case PHOS_VECTOR_MATH_SUBTRACT: *vec = v3_sub(a, b); break;
    case PHOS_VECTOR_MATH_MULTIPLY: *vec = v3_mul(a, b); break;
    case PHOS_VECTOR_MATH_DIVIDE: *vec = v3(safe_div(a.x, b.x), safe_div(a.y, b.y), safe_div(a.z, b.z)); break;
    case PHOS_VECTOR_MATH_MULTIPLY_ADD: *vec = v3_add(v3_mul(a, b), c); break;
    case PHOS_VECTOR_MATH_CROSS_PRODUCT: *vec = v3_cross(a, b); break;
    case PHOS_VECTOR_MATH_PROJECT: *vec = project(a, b); break;
    case PHOS_VECTOR_MATH_REFLECT: *vec = reflect(a, node_normal(b, flags)); break;
    /* The Scale socket is the ratio of indices η. */
    case PHOS_VECTOR_MATH_REFRACT: *vec = refract(a, node_normal(b, flags), s); break;
    /* a if the reference c faces against the incident b, else −a. */
    case PHOS_VECTOR_MATH_FACEFORWARD: *vec = v3_dot(c, b) < 0.0f ? a : v3_neg(a); break;
    case PHOS_VECTOR_MATH_DOT_PRODUCT: *value = v3_dot(a, b); break;
    case PHOS_VECTOR_MATH_DISTANCE: *value = v3_length(v3_sub(a, b)); break;
    case PHOS_VECTOR_MATH_LENGTH: *value = v3_length(a); break;
    case PHOS_VECTOR_MATH_SCALE: *vec = v3_scale(a, s); break;
    case PHOS_VECTOR_MATH_NORMALIZE: *vec = safe_normalize(a); break;
    case PHOS_VECTOR_MATH_ABSOLUTE: *vec = v3(fabsf(a.x), fabsf(a.y), fabsf(a.z)); break;
    case PHOS_VECTOR_MATH_POWER:
        *vec = v3(safe_pow(a.x, b.x, flags), safe_pow(a.y, b.y, flags), safe_pow(a.z, b.z, flags));
        break;
    case PHOS_VECTOR_MATH_SIGN: *vec = v3(sign0(a.x), sign0(a.y), sign0(a.z)); break;
    case PHOS_VECTOR_MATH_MINIMUM: *vec = v3(node_min(a.x, b.x), node_min(a.y, b.y), node_min(a.z, b.z)); break;
    case PHOS_VECTOR_MATH_MAXIMUM: *vec = v3(node_max(a.x, b.x), node_max(a.y, b.y), node_max(a.z, b.z)); break;
    case PHOS_VECTOR_MATH_FLOOR: *vec = v3_floor(a); break;
    case PHOS_VECTOR_MATH_CEIL: *vec = v3(ceilf(a.x), ceilf(a.y), ceilf(a.z)); break;
    case PHOS_VECTOR_MATH_FRACTION: *vec = v3_sub(a, v3_floor(a)); break;
    case PHOS_VECTOR_MATH_MODULO: *vec = v3(safe_mod(a.x, b.x), safe_mod(a.y, b.y), safe_mod(a.z, b.z)); break;
    case PHOS_VECTOR_MATH_WRAP:
        *vec = v3(wrap_component(a.x, b.x, c.x, flags), wrap_component(a.y, b.y, c.y, flags),
                  wrap_component(a.z, b.z, c.z, flags));
        break;
    /* ⌊a/b⌋·b per component, with a/0 = 0. */
    case PHOS_VECTOR_MATH_SNAP:
        *vec = v3_mul(v3_floor(v3(safe_div(a.x, b.x), safe_div(a.y, b.y), safe_div(a.z, b.z))), b);
        break;
    case PHOS_VECTOR_MATH_SINE: *vec = v3(sinf(a.x), sinf(a.y), sinf(a.z)); break;
    case PHOS_VECTOR_MATH_COSINE: *vec = v3(cosf(a.x), cosf(a.y), cosf(a.z)); break;
    case PHOS_VECTOR_MATH_TANGENT: *vec = v3(tanf(a.x), tanf(a.y), tanf(a.z)); break;
    default: break;
    }
}

/* in a(3), b(3), c(3), scale; out vector(3), value. */
void shader_op_vector_math(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 vec = v3s(0.0f);
    float value = 0.0f;
    vector_math_eval(ins->mode, SHADER_IN3(0), SHADER_IN3(1), SHADER_IN3(2), SHADER_IN(3), ins->flags, &vec,
                     &value);
    SHADER_OUT3(0, vec);
    SHADER_OUT(1, value);
}

/* ------------------------------------------------------------- Map Range */

/* Hermite smoothstep between edges e0 < e1: 0 below e0, 1 from e1, else t²(3 − 2t). */
static float smoothstep(float e0, float e1, float x)
{
    if (x < e0)
        return 0.0f;
    if (x >= e1)
        return 1.0f;
    float t = (x - e0) / (e1 - e0);
    return (3.0f - 2.0f * t) * (t * t);
}

/* Perlin's smootherstep: t = clamp((x − e0)/(e1 − e0), 0, 1), t³(t(6t − 15) + 10). */
static float smootherstep(float e0, float e1, float x)
{
    float t = node_clamp(safe_div(x - e0, e1 - e0), 0.0f, 1.0f);
    return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f);
}

/* The stepped factor: ⌊f(steps + 1)⌋/steps, 0 for steps <= 0. */
static inline float stepped(float f, float steps)
{
    return steps > 0.0f ? floorf(f * (steps + 1.0f)) / steps : 0.0f;
}

/* Clamp to the range between lo and hi in either order (Clamp's RANGE). */
static inline float clamp_range(float x, float lo, float hi)
{
    return lo > hi ? node_clamp(x, hi, lo) : node_clamp(x, lo, hi);
}

/* in value, from_min, from_max, to_min, to_max, steps; out value. An empty
 * source range gives 0. Clamp (flags 1) is Cycles' Clamp node (RANGE) on the
 * result whatever the mode: Cycles adds it for every mode, though Blender
 * shows the checkbox for Linear and Stepped only (for the smooth modes the
 * result is in range anyway). */
void shader_op_map_range(const phos_shader_instruction *ins, shader_context *ctx)
{
    float x = SHADER_IN(0), from_min = SHADER_IN(1), from_max = SHADER_IN(2);
    float to_min = SHADER_IN(3), to_max = SHADER_IN(4), steps = SHADER_IN(5);
    float r = 0.0f;
    if (from_max != from_min) {
        float f;
        switch (ins->mode) {
        default:
        case PHOS_MAP_RANGE_LINEAR: f = (x - from_min) / (from_max - from_min); break;
        case PHOS_MAP_RANGE_STEPPED: f = stepped((x - from_min) / (from_max - from_min), steps); break;
        case PHOS_MAP_RANGE_SMOOTHSTEP:
            f = from_min > from_max ? 1.0f - smoothstep(from_max, from_min, x) : smoothstep(from_min, from_max, x);
            break;
        case PHOS_MAP_RANGE_SMOOTHERSTEP:
            f = from_min > from_max ? 1.0f - smootherstep(from_max, from_min, x)
                                    : smootherstep(from_min, from_max, x);
            break;
        }
        r = to_min + f * (to_max - to_min);
    }
    if (ins->flags & MAP_RANGE_CLAMP)
        r = clamp_range(r, to_min, to_max);
    SHADER_OUT(0, r);
}

/* One component of the vector Map Range: the source range divides safely
 * (an empty one gives factor 0); the smooth modes clamp the factor to [0,1]
 * and ignore the Clamp switch. */
static float map_range_component(uint32_t mode, int clamp, float x, float from_min, float from_max, float to_min,
                                 float to_max, float steps)
{
    float f = safe_div(x - from_min, from_max - from_min);
    switch (mode) {
    default:
    case PHOS_MAP_RANGE_LINEAR: break;
    case PHOS_MAP_RANGE_STEPPED: f = stepped(f, steps); break;
    case PHOS_MAP_RANGE_SMOOTHSTEP:
        f = node_clamp(f, 0.0f, 1.0f);
        f = (3.0f - 2.0f * f) * (f * f);
        break;
    case PHOS_MAP_RANGE_SMOOTHERSTEP:
        f = node_clamp(f, 0.0f, 1.0f);
        f = f * f * f * (f * (f * 6.0f - 15.0f) + 10.0f);
        break;
    }
    float r = to_min + f * (to_max - to_min);
    return clamp ? clamp_range(r, to_min, to_max) : r;
}

/* The same, every socket 3 wide, component by component. */
void shader_op_map_range_vector(const phos_shader_instruction *ins, shader_context *ctx)
{
    float in[6][3];
    for (int k = 0; k < 6; k++) {
        vec3 v = SHADER_IN3(k);
        in[k][0] = v.x;
        in[k][1] = v.y;
        in[k][2] = v.z;
    }
    uint32_t mode = ins->mode;
    int clamp = (ins->flags & MAP_RANGE_CLAMP) && mode != PHOS_MAP_RANGE_SMOOTHSTEP &&
                mode != PHOS_MAP_RANGE_SMOOTHERSTEP;
    float r[3];
    for (int i = 0; i < 3; i++)
        r[i] = map_range_component(mode, clamp, in[0][i], in[1][i], in[2][i], in[3][i], in[4][i], in[5][i]);
    SHADER_OUT3(0, v3(r[0], r[1], r[2]));
}

/* ----------------------------------------------------------------- Clamp */

/* in value, min, max; out value. MINMAX: min(max(value, min), max) (max wins
 * when min > max); RANGE: between min and max in either order. */
void shader_op_clamp(const phos_shader_instruction *ins, shader_context *ctx)
{
    float x = SHADER_IN(0), lo = SHADER_IN(1), hi = SHADER_IN(2);
    SHADER_OUT(0, ins->mode == PHOS_CLAMP_RANGE ? clamp_range(x, lo, hi) : node_clamp(x, lo, hi));
}

/* ----------------------------------------------------------- Combine XYZ */

/* in x, y, z; out vector(3). */
void shader_op_combine_xyz(const phos_shader_instruction *ins, shader_context *ctx)
{
    SHADER_OUT3(0, v3(SHADER_IN(0), SHADER_IN(1), SHADER_IN(2)));
}
