/*
 * vec.h — small 3-vector, colour and frame helpers shared by the core.
 * vec3 holds positions (scene units), directions (unit length) and linear
 * RGB quantities alike; the comment at each use says which.
 */
#ifndef PHOS_VEC_H
#define PHOS_VEC_H

#include <math.h>
#include <stdint.h>

#define PHOS_PI 3.14159265358979323846f
#define PHOS_INV_PI 0.31830988618379067154f
#define PHOS_INV_2PI 0.15915494309189533577f
#define PHOS_INV_4PI 0.07957747154594766788f

typedef struct vec3 {
    float x, y, z;
} vec3;

static inline vec3 v3(float x, float y, float z) { vec3 r = {x, y, z}; return r; }
static inline vec3 v3s(float s) { return v3(s, s, s); }
static inline vec3 v3_load(const float *p) { return v3(p[0], p[1], p[2]); }
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_mul(vec3 a, vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline vec3 v3_scale(vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline vec3 v3_neg(vec3 a) { return v3(-a.x, -a.y, -a.z); }
static inline vec3 v3_madd(vec3 a, vec3 b, float s) { return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s); }
static inline float v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline float v3_length2(vec3 a) { return v3_dot(a, a); }
static inline float v3_length(vec3 a) { return sqrtf(v3_dot(a, a)); }
static inline vec3 v3_normalize(vec3 a)
{
    float l = v3_length(a);
    return l > 0.0f ? v3_scale(a, 1.0f / l) : a;
}
/* fmaxf and fminf as comparisons the compiler keeps inline (one instruction
 * and a NaN test instead of a library call): a NaN operand is ignored, as
 * C99 F.9.9.2 defines them; only the sign of a zero result may differ. */
static inline float maxf(float a, float b) { return (a > b || b != b) ? a : b; }
static inline float minf(float a, float b) { return (a < b || b != b) ? a : b; }
static inline float v3_max_component(vec3 a) { return maxf(a.x, maxf(a.y, a.z)); }
static inline float v3_average(vec3 a) { return (a.x + a.y + a.z) * (1.0f / 3.0f); }
static inline int v3_is_zero(vec3 a) { return a.x == 0.0f && a.y == 0.0f && a.z == 0.0f; }
static inline int v3_is_finite(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
static inline vec3 v3_div(vec3 a, vec3 b) { return v3(a.x / b.x, a.y / b.y, a.z / b.z); }
static inline vec3 v3_min(vec3 a, vec3 b) { return v3(minf(a.x, b.x), minf(a.y, b.y), minf(a.z, b.z)); }
static inline vec3 v3_max(vec3 a, vec3 b) { return v3(maxf(a.x, b.x), maxf(a.y, b.y), maxf(a.z, b.z)); }
static inline float v3_component(vec3 a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }
/* Rec. 709 luminance of linear RGB. */
static inline float rgb_luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

static inline float clampf(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }
static inline float sqr(float x) { return x * x; }
static inline float safe_sqrtf(float x) { return sqrtf(maxf(x, 0.0f)); }

/* Orthonormal frame around n (Duff et al. 2017, "Building an Orthonormal
 * Basis, Revisited", JCGT 6(1)): branchless and continuous except at one
 * sign flip. */
typedef struct frame {
    vec3 t, b, n;
} frame;

static inline frame frame_from_normal(vec3 n)
{
    float sign = copysignf(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    frame f;
    f.t = v3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.b = v3(b, sign + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}
static inline vec3 frame_to_local(const frame *f, vec3 v)
{
    return v3(v3_dot(v, f->t), v3_dot(v, f->b), v3_dot(v, f->n));
}
static inline vec3 frame_to_world(const frame *f, vec3 v)
{
    return v3_add(v3_add(v3_scale(f->t, v.x), v3_scale(f->b, v.y)), v3_scale(f->n, v.z));
}

/* Row-major 3x4 affine transform. */
static inline vec3 xform_point(const float m[12], vec3 p)
{
    return v3(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3],
              m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
              m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}
static inline vec3 xform_vector(const float m[12], vec3 v)
{
    return v3(m[0] * v.x + m[1] * v.y + m[2] * v.z,
              m[4] * v.x + m[5] * v.y + m[6] * v.z,
              m[8] * v.x + m[9] * v.y + m[10] * v.z);
}

/* Power heuristic with β = 2 (Veach 1997, §9.2). */
static inline float mis_power_heuristic(float pdf_a, float pdf_b)
{
    float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
    return a + b > 0.0f ? a / (a + b) : 0.0f;
}

#endif /* PHOS_VEC_H */
