/*
 * texture_pattern.c — the pattern texture nodes: Voronoi, Wave, Brick,
 * Checker, Magic and Gradient, as Blender's Cycles computes them (Blender
 * manual, "Texture" nodes), in Cycles' arithmetic order so a texture seen
 * through an Emission shader lines up with a Cycles render.
 *
 * Which Blender versions use which definition (checked against the Cycles
 * kernels of Blender 3.4, 4.2/4.3, 4.5, 5.0 and 5.3):
 *
 *  Voronoi   3.4 (flags 16): one octave; searches start at distance 8;
 *            Smooth F1 starts from distance 8 with a smoothstep weight.
 *            4.0-4.5 (default): fractal octaves (detail, roughness,
 *            lacunarity, normalize); searches start at FLT_MAX; Smooth F1
 *            takes the first cell with weight 1; a smoothness of 0 makes
 *            Smooth F1 plain F1. 4.5 picks the F1 cell by a cheaper bound
 *            (squared length, Minkowski sum without the root) and the
 *            N-Sphere cells by squared length; 4.0-4.3 compared the
 *            distances themselves, which can pick another cell only where
 *            two candidates tie after rounding. We follow 4.5.
 *            5.0+ (flags 128): as 4.5, but the 2D-4D cells are hashed as
 *            integers with PCG (Jarzynski & Olano 2020, "Hash Functions for
 *            GPU Rendering", JCGT 9(3)) instead of by their float bits, so
 *            the pattern differs from 4.x. 1D is unchanged.
 *            In 4.0+ the 3D W output is not 0 but the fractal blend of
 *            1/frequency divided by the scale (Cycles' float4 position has
 *            w = 1); we reproduce it.
 *  Wave      3.4 (flags 16 << 8): distortion by the 3.x fractal noise
 *            (unsigned noise, octaves and roughness clamped);
 *            4.0+: by the signed fBM, normalized, lacunarity 2, unclamped.
 *  Magic     3.4-5.0: sin/cos of 5·scale·(p mod 2π); 5.3 (flags 1; the
 *            first 5.x release with it is not known here): of
 *            5·((scale·p) mod 2π).
 *  Brick     4.0+. 3.4 differs only for a negative Mortar Smooth (3.4:
 *            full mortar; 4.x: none); not selectable here.
 *  Checker, Gradient: unchanged from 3.4 to 5.3.
 *
 * Cycles' vector arithmetic matters to the last bit: a float3 divided by a
 * scalar divides each component (SSE), while float2 and float4 multiply by
 * the reciprocal, and so does float3 /= scalar; 4-wide sums pair as
 * (x + y) + (z + w) (SSE dot product and horizontal adds), 3-wide ones go
 * left to right. The helpers below follow that per dimension.
 *
 * Voronoi is Worley's cellular texture (Worley 1996, "A Cellular Texture
 * Basis Function", SIGGRAPH): one feature point per unit cell, jittered by
 * a hash of the cell, and F1/F2 the distances to the nearest and second
 * nearest. Smooth F1 blends the cells with a polynomial smooth minimum,
 * Distance to Edge measures to the bisector planes of the nearest point and
 * its neighbours, N-Sphere Radius is half the distance from the nearest
 * point to its own nearest neighbour.
 */
#include <float.h>
#include <limits.h>
#include <stdint.h>

#include "shading/shader_program.h"
#include "shading/nodes/noise.h"
#include "shading/nodes/node_util.h"

/* float literals of Cycles' constants */
#define TWO_PI_F 6.28318530717958647692f
#define HALF_PI_F 1.57079632679489661923f

/* ------------------------------------------------------------ scalars */

NODE_INLINE float saturatef(float a) { return node_clamp(a, 0.0f, 1.0f); }
NODE_INLINE float mixf(float a, float b, float t) { return a + t * (b - a); }

/* smoothstep(0, 1, x): 0 below 0, 1 from 1 on, (3 − 2x)x² between (NaN stays NaN). */
NODE_INLINE float smoothstep01(float x)
{
    if (x < 0.0f)
        return 0.0f;
    if (x >= 1.0f)
        return 1.0f;
    return (3.0f - 2.0f * x) * (x * x);
}

/* Cycles' smoothstepf (Brick): 3f² − 2f³ on (0, 1). */
NODE_INLINE float smoothstepf_c(float f)
{
    if (f <= 0.0f)
        return 0.0f;
    if (f >= 1.0f)
        return 1.0f;
    float ff = f * f;
    return 3.0f * ff - 2.0f * ff * f;
}

/* float → int as x86's conversions do: truncation, and INT_MIN for NaN or
 * out of range (where a C cast is undefined). */
NODE_INLINE int32_t float_to_int_x86(float f)
{
    if (!(f > -2147483904.0f && f < 2147483648.0f))
        return INT32_MIN;
    return (int32_t)f;
}

NODE_INLINE vec3 v3_mix(vec3 a, vec3 b, float t) { return v3_add(a, v3_scale(v3_sub(b, a), t)); }

/* ------------------------------------------------------------ Checker */

/* Parity of the unit cell of p: 1 where the cell's integer coordinates
 * satisfy (x even ⇔ y even) ⇔ z odd, so neighbouring cells alternate.
 * p is nudged by (p + 1e-6)·0.999999 so unit coordinates stay stable. */
NODE_INLINE float checker(vec3 p)
{
    p.x = (p.x + 0.000001f) * 0.999999f;
    p.y = (p.y + 0.000001f) * 0.999999f;
    p.z = (p.z + 0.000001f) * 0.999999f;
    uint32_t xi = (uint32_t)float_to_int_x86(floorf(p.x)) & 1u; /* |n| mod 2 = n mod 2 */
    uint32_t yi = (uint32_t)float_to_int_x86(floorf(p.y)) & 1u;
    uint32_t zi = (uint32_t)float_to_int_x86(floorf(p.z)) & 1u;
    return ((uint32_t)(xi == yi) == zi) ? 1.0f : 0.0f;
}

/* in vector(3), color1(3), color2(3), scale; out color(3), fac */
NODE_VECTOR_CLONES void shader_op_tex_checker(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 co = SHADER_IN3(0), c1 = SHADER_IN3(1), c2 = SHADER_IN3(2);
    float f = checker(v3_scale(co, SHADER_IN(3)));
    SHADER_OUT3(0, f == 1.0f ? c1 : c2);
    SHADER_OUT(1, f);
}

/* ----------------------------------------------------------- Gradient */

NODE_INLINE float gradient(vec3 p, uint32_t type)
{
    float x = p.x, y = p.y, z = p.z;
    switch (type) {
    case PHOS_GRADIENT_LINEAR:
        return x;
    case PHOS_GRADIENT_QUADRATIC: {
        float r = fmaxf(x, 0.0f);
        return r * r;
    }
    case PHOS_GRADIENT_EASING: { /* 3r² − 2r³ of x clamped to [0, 1] */
        float r = fminf(fmaxf(x, 0.0f), 1.0f);
        float t = r * r;
        return 3.0f * t - 2.0f * t * r;
    }
    case PHOS_GRADIENT_DIAGONAL:
        return (x + y) * 0.5f;
    case PHOS_GRADIENT_RADIAL: /* angle around z, one turn = [0, 1] */
        return atan2f(y, x) / TWO_PI_F + 0.5f;
    case PHOS_GRADIENT_SPHERICAL:
    case PHOS_GRADIENT_QUADRATIC_SPHERE: {
        /* 1 − |p|, biased so a unit vector gives exactly 0 */
        float r = fmaxf(0.999999f - sqrtf(x * x + y * y + z * z), 0.0f);
        return type == PHOS_GRADIENT_SPHERICAL ? r : r * r;
    }
    default:
        return 0.0f;
    }
}

/* in vector(3); out color(3), fac. mode enum phos_gradient */
NODE_VECTOR_CLONES void shader_op_tex_gradient(const phos_shader_instruction *ins, shader_context *ctx)
{
    float f = saturatef(gradient(SHADER_IN3(0), ins->mode));
    SHADER_OUT3(0, v3s(f));
    SHADER_OUT(1, f);
}

/* -------------------------------------------------------------- Magic */

#define MAGIC_FLAG_SCALE_IN_WRAP 1u /* Blender 5.3: (scale·p) mod 2π */

/* Magic texture: three sines of the coordinates, then up to ten rounds of
 * feeding them back through sin/cos ("turbulence depth"), each scaled by
 * the distortion. */
NODE_INLINE vec3 magic(vec3 p, float scale, int depth, float distortion, int scale_in_wrap)
{
    /* the coordinates wrapped to [0, 2π) against precision loss (and the
     * NaNs of sin/cos of huge arguments); 3.4-5.0 scale after the wrap */
    float s = scale_in_wrap ? scale : 1.0f;
    float px = fmodf(p.x * s, TWO_PI_F);
    float py = fmodf(p.y * s, TWO_PI_F);
    float pz = fmodf(p.z * s, TWO_PI_F);
    float x, y, z;
    if (scale_in_wrap) {
        x = sinf((px + py + pz) * 5.0f);
        y = cosf((-px + py - pz) * 5.0f);
        z = -cosf((-px - py + pz) * 5.0f);
    } else {
        x = sinf((px + py + pz) * 5.0f * scale);
        y = cosf((-px + py - pz) * 5.0f * scale);
        z = -cosf((-px - py + pz) * 5.0f * scale);
    }
    float d = distortion;
    if (depth > 0) {
        x *= d, y *= d, z *= d;
        y = -cosf(x - y + z) * d;
        if (depth > 1)
            x = cosf(x - y - z) * d;
        if (depth > 2)
            z = sinf(-x - y - z) * d;
        if (depth > 3)
            x = -cosf(-x + y - z) * d;
        if (depth > 4)
            y = -sinf(-x + y + z) * d;
        if (depth > 5)
            y = -cosf(-x + y + z) * d;
        if (depth > 6)
            x = cosf(x + y + z) * d;
        if (depth > 7)
            z = sinf(x + y - z) * d;
        if (depth > 8)
            x = -cosf(-x - y + z) * d;
        if (depth > 9)
            y = -sinf(x - y + z) * d;
    }
    if (d != 0.0f) {
        float d2 = d * 2.0f;
        x /= d2, y /= d2, z /= d2;
    }
    return v3(0.5f - x, 0.5f - y, 0.5f - z);
}

/* in vector(3), scale, distortion; out color(3), fac. mode depth (0-10);
 * flags 1 = Blender 5.3's wrap of the scaled point */
NODE_VECTOR_CLONES void shader_op_tex_magic(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 c = magic(SHADER_IN3(0), SHADER_IN(1), (int)ins->mode, SHADER_IN(2),
                   (ins->flags & MAGIC_FLAG_SCALE_IN_WRAP) != 0);
    SHADER_OUT3(0, c);
    SHADER_OUT(1, (c.x + c.y + c.z) * (1.0f / 3.0f));
}

/* -------------------------------------------------------------- Brick */

/* A float node setting that Blender stores as an int (the frequencies). */
NODE_INLINE int param_int(float f) { return (int)fminf(fmaxf(f, -1.0e9f), 1.0e9f); }

/* a % b as C computes it, without INT_MIN % −1's trap. */
NODE_INLINE int32_t rem_i32(int32_t a, int32_t b) { return b == -1 ? 0 : a % b; }

typedef struct brick_result {
    float tint;   /* brick colour blend, [0, 1] */
    float mortar; /* 1 in the mortar, 0 inside a brick, smooth between */
} brick_result;

/* Rows of height row_height; every squash_frequency-th row has bricks
 * squash times as wide and every offset_frequency-th row is shifted by
 * offset bricks. Each brick gets a tint from the integer noise of its
 * (row, brick) number; the mortar is the band within mortar_size of the
 * brick's border. */
/* The mortar's edge: f = 1 − min_dist/mortar_size runs from 0 at the
 * mortar's inner border to 1 on the brick's edge, and the mortar is
 * smoothstep(f / mortar_smooth). Blender 3.x applies the smoothstep only
 * where f < mortar_smooth and is 1 elsewhere, so a negative smoothing
 * gives solid mortar; from 4.0 the smoothstep is clamped, and a negative
 * smoothing gives none. */
NODE_INLINE float mortar_edge(float f, float mortar_smooth, int blender3)
{
    if (blender3) {
        if (!(f < mortar_smooth))
            return 1.0f;
        float x = f / mortar_smooth, xx = x * x;
        return 3.0f * xx - 2.0f * xx * x;
    }
    return smoothstepf_c(f / mortar_smooth);
}

NODE_INLINE brick_result brick(vec3 p, float mortar_size, float mortar_smooth, float bias, float brick_width,
                          float row_height, float offset_amount, int offset_frequency, float squash_amount,
                          int squash_frequency, int blender3)
{
    int32_t rownum = float_to_int_x86(floorf(p.y / row_height));
    float offset = 0.0f;
    if (offset_frequency && squash_frequency) {
        brick_width *= rem_i32(rownum, squash_frequency) ? 1.0f : squash_amount;
        offset = rem_i32(rownum, offset_frequency) ? 0.0f : brick_width * offset_amount;
    }
    int32_t bricknum = float_to_int_x86(floorf((p.x + offset) / brick_width));
    float x = (p.x + offset) - brick_width * (float)bricknum;
    float y = p.y - row_height * (float)rownum;

    brick_result r;
    uint32_t key = ((uint32_t)rownum << 16) + ((uint32_t)bricknum & 0xFFFFu);
    r.tint = saturatef(brick_noise(key) + bias);
    float min_dist = node_min(node_min(x, y), node_min(brick_width - x, row_height - y));
    if (min_dist >= mortar_size)
        r.mortar = 0.0f;
    else if (mortar_smooth == 0.0f)
        r.mortar = 1.0f;
    else
        r.mortar = mortar_edge(1.0f - min_dist / mortar_size, mortar_smooth, blender3);
    return r;
}

/* in vector(3), color1(3), color2(3), mortar(3), scale, mortar_size,
 * mortar_smooth, bias, brick_width, row_height; out color(3), fac.
 * param: offset, offset_frequency, squash, squash_frequency; flags 1:
 * Blender 3.x's mortar smoothing (mortar_edge) */
NODE_VECTOR_CLONES void shader_op_tex_brick(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 co = SHADER_IN3(0), color1 = SHADER_IN3(1), color2 = SHADER_IN3(2), mortar = SHADER_IN3(3);
    brick_result b = brick(v3_scale(co, SHADER_IN(4)), SHADER_IN(5), SHADER_IN(6), SHADER_IN(7), SHADER_IN(8),
                           SHADER_IN(9), ins->param[0], param_int(ins->param[1]), ins->param[2],
                           param_int(ins->param[3]), (ins->flags & 1) != 0);
    float f = b.mortar;
    if (f != 1.0f) {
        float facm = 1.0f - b.tint;
        color1 = v3_add(v3_scale(color1, facm), v3_scale(color2, b.tint));
    }
    SHADER_OUT3(0, v3_add(v3_scale(color1, 1.0f - f), v3_scale(mortar, f)));
    SHADER_OUT(1, f);
}

/* --------------------------------------------------------------- Wave */

#define WAVE_FLAG_LEGACY_NOISE (16u << 8)

/* The wave's phase n at p: 20 per unit along an axis (10 along the
 * diagonal) for bands, 20 per unit of distance from an axis (or the
 * origin) for rings; distortion adds fractal noise; the profile maps n to
 * [0, 1] as a sine, a saw or a triangle of period 2π. */
NODE_INLINE float wave(uint32_t type, uint32_t bands_dir, uint32_t rings_dir, uint32_t profile, vec3 p,
                  float distortion, float detail, float dscale, float droughness, float phase, int legacy)
{
    p.x = (p.x + 0.000001f) * 0.999999f; /* stable at unit coordinates */
    p.y = (p.y + 0.000001f) * 0.999999f;
    p.z = (p.z + 0.000001f) * 0.999999f;

    float n;
    if (type == PHOS_WAVE_BANDS) {
        if (bands_dir == PHOS_WAVE_X)
            n = p.x * 20.0f;
        else if (bands_dir == PHOS_WAVE_Y)
            n = p.y * 20.0f;
        else if (bands_dir == PHOS_WAVE_Z)
            n = p.z * 20.0f;
        else
            n = (p.x + p.y + p.z) * 10.0f;
    } else {
        vec3 rp = p;
        if (rings_dir == PHOS_WAVE_X)
            rp = v3_mul(rp, v3(0.0f, 1.0f, 1.0f));
        else if (rings_dir == PHOS_WAVE_Y)
            rp = v3_mul(rp, v3(1.0f, 0.0f, 1.0f));
        else if (rings_dir == PHOS_WAVE_Z)
            rp = v3_mul(rp, v3(1.0f, 1.0f, 0.0f));
        n = sqrtf(rp.x * rp.x + rp.y * rp.y + rp.z * rp.z) * 20.0f;
    }
    n += phase;

    if (distortion != 0.0f) {
        vec4f q = v4f_from3(v3_scale(p, dscale), 0.0f);
        float fbm = legacy ? noise_fbm_legacy(q, 3, detail, droughness)
                           : noise_fbm(q, 3, detail, droughness, 2.0f, 1);
        n += distortion * (fbm * 2.0f - 1.0f);
    }

    if (profile == PHOS_WAVE_SIN)
        return 0.5f + 0.5f * sinf(n - HALF_PI_F);
    n /= TWO_PI_F;
    if (profile == PHOS_WAVE_SAW)
        return n - floorf(n);
    return fabsf(n - floorf(n + 0.5f)) * 2.0f; /* PHOS_WAVE_TRI */
}

/* in vector(3), scale, distortion, detail, detail_scale, detail_roughness,
 * phase; out color(3), fac. mode enum phos_wave_type; flags: bits 0-3 bands
 * direction, 4-7 rings direction, 8-11 profile, 16 << 8 = 3.x noise */
NODE_VECTOR_CLONES void shader_op_tex_wave(const phos_shader_instruction *ins, shader_context *ctx)
{
    uint32_t fl = ins->flags;
    float f = wave(ins->mode, fl & 15u, (fl >> 4) & 15u, (fl >> 8) & 15u, v3_scale(SHADER_IN3(0), SHADER_IN(1)),
                   SHADER_IN(2), SHADER_IN(3), SHADER_IN(4), SHADER_IN(5), SHADER_IN(6),
                   (fl & WAVE_FLAG_LEGACY_NOISE) != 0);
    SHADER_OUT3(0, v3s(f));
    SHADER_OUT(1, f);
}

/* ------------------------------------------------------------ Voronoi */

/* TEX_VORONOI flags. phos.h gives the metric "bits 4-5" and Blender 3.x
 * the value 16 (bit 4): they collide; the metric is read from bits 5-6
 * here until phos.h settles it (see the report to the lead). */
#define VORONOI_DIMS_MASK 7u
#define VORONOI_FLAG_NORMALIZE 8u
#define VORONOI_FLAG_LEGACY 16u      /* Blender 3.x: one octave */
#define VORONOI_METRIC_SHIFT 5u
#define VORONOI_FLAG_INT_CELLS 128u  /* Blender 5.0+: PCG hashes of integer cells (2D-4D) */

/* PCG hashes of integer cells (Jarzynski & Olano 2020) as Blender 5.0's
 * Voronoi uses them: an LCG step per component, then the components mix
 * by products (by a constant in 2D) before and after an xorshift by 16
 * (arithmetic: the sign bit fills); 31 bits are kept and mapped to [0, 1]
 * by 2^−31. These belong in noise.h (asked for in the report). */
#define PCG_MUL 1664525u
#define PCG_ADD 1013904223u

NODE_INLINE uint32_t sar16(uint32_t v) { return (v >> 16) | ((v & 0x80000000u) ? 0xFFFF0000u : 0u); }
NODE_INLINE float pcg_unit(uint32_t h) { return (float)(int32_t)(h & 0x7FFFFFFFu) * (1.0f / 2147483648.0f); }

NODE_INLINE void pcg2(const int32_t k[2], float out[2])
{
    uint32_t x = (uint32_t)k[0] * PCG_MUL + PCG_ADD, y = (uint32_t)k[1] * PCG_MUL + PCG_ADD;
    x += y * PCG_MUL;
    y += x * PCG_MUL;
    x ^= sar16(x);
    y ^= sar16(y);
    x += y * PCG_MUL;
    y += x * PCG_MUL;
    out[0] = pcg_unit(x), out[1] = pcg_unit(y);
}

NODE_INLINE void pcg3(const int32_t k[3], float out[3])
{
    uint32_t x = (uint32_t)k[0] * PCG_MUL + PCG_ADD, y = (uint32_t)k[1] * PCG_MUL + PCG_ADD,
             z = (uint32_t)k[2] * PCG_MUL + PCG_ADD;
    x += y * z;
    y += z * x;
    z += x * y;
    x ^= sar16(x);
    y ^= sar16(y);
    z ^= sar16(z);
    x += y * z;
    y += z * x;
    z += x * y;
    out[0] = pcg_unit(x), out[1] = pcg_unit(y), out[2] = pcg_unit(z);
}

NODE_INLINE void pcg4(const int32_t k[4], float out[4])
{
    uint32_t x = (uint32_t)k[0] * PCG_MUL + PCG_ADD, y = (uint32_t)k[1] * PCG_MUL + PCG_ADD,
             z = (uint32_t)k[2] * PCG_MUL + PCG_ADD, w = (uint32_t)k[3] * PCG_MUL + PCG_ADD;
    x += y * w;
    y += z * x;
    z += x * y;
    w += y * z;
    x ^= sar16(x);
    y ^= sar16(y);
    z ^= sar16(z);
    w ^= sar16(w);
    x += y * w;
    y += z * x;
    z += x * y;
    w += y * z;
    out[0] = pcg_unit(x), out[1] = pcg_unit(y), out[2] = pcg_unit(z), out[3] = pcg_unit(w);
}

/* How one Voronoi evaluation is defined. Points are float[4] of which the
 * first `dims` components count (1D: the W coordinate in [0]). */
typedef struct voronoi_params {
    int dims;
    uint32_t feature, metric;
    float exponent, randomness, smoothness;
    float detail, roughness, lacunarity, max_distance;
    int normalize;
    int legacy;    /* Blender 3.x: searches from 8, Smooth F1 from 8, 3.x sums */
    int int_cells; /* Blender 5.0+: integer cell hashes in 2D-4D */
} voronoi_params;

/* The unit cell around a point. */
typedef struct voronoi_cell {
    float cell[4];    /* floor of the point */
    float local[4];   /* the point within the cell, [0, 1) */
    int32_t icell[4]; /* the cell as integers */
} voronoi_cell;

typedef struct voronoi_result {
    float distance;
    vec3 color;
    float position[4]; /* the feature point (1D: in [0]) */
} voronoi_result;

NODE_INLINE voronoi_cell voronoi_cell_of(const voronoi_params *v, const float p[4])
{
    voronoi_cell c = {{0}, {0}, {0}};
    for (int k = 0; k < v->dims; k++) {
        c.cell[k] = floorf(p[k]);
        c.local[k] = p[k] - c.cell[k];
        c.icell[k] = float_to_int_x86(c.cell[k]);
    }
    return c;
}

/* Next neighbour offset in [lo, hi]^dims, x fastest (Cycles' loop order:
 * the last axis outermost). Returns 0 after the last. */
NODE_INLINE int next_offset(int off[4], int dims, int lo, int hi)
{
    for (int k = 0; k < dims; k++) {
        if (off[k] < hi) {
            off[k]++;
            return 1;
        }
        off[k] = lo;
    }
    return 0;
}

NODE_INLINE void first_offset(int off[4], int dims, int lo)
{
    for (int k = 0; k < 4; k++)
        off[k] = k < dims ? lo : 0;
}

/* The feature point's jitter in [0, 1]^dims for cell + off. */
NODE_INLINE void cell_jitter(const voronoi_params *v, const voronoi_cell *c, const int off[4], float h[4])
{
    if (v->int_cells && v->dims >= 2) {
        int32_t k[4];
        for (int i = 0; i < v->dims; i++)
            k[i] = (int32_t)((uint32_t)c->icell[i] + (uint32_t)off[i]);
        if (v->dims == 2)
            pcg2(k, h);
        else if (v->dims == 3)
            pcg3(k, h);
        else
            pcg4(k, h);
        return;
    }
    float k[4] = {0.0f, 0.0f, 0.0f, 0.0f}; /* dims of them read; all set for the compiler's flow check */
    for (int i = 0; i < v->dims; i++)
        k[i] = c->cell[i] + (float)off[i];
    if (v->dims == 1) {
        h[0] = hash_float_to_float(k[0]);
    } else if (v->dims == 2) {
        vec2f r = hash_float2_to_float2(k[0], k[1]);
        h[0] = r.x, h[1] = r.y;
    } else if (v->dims == 3) {
        vec3 r = hash_float3_to_float3(v3(k[0], k[1], k[2]));
        h[0] = r.x, h[1] = r.y, h[2] = r.z;
    } else {
        vec4f r = hash_float4_to_float4(v4f(k[0], k[1], k[2], k[3]));
        h[0] = r.x, h[1] = r.y, h[2] = r.z, h[3] = r.w;
    }
}

/* The cell's colour output, [0, 1]³. */
NODE_INLINE vec3 cell_color(const voronoi_params *v, const voronoi_cell *c, const int off[4])
{
    if (v->int_cells && v->dims >= 2) {
        int32_t k[4] = {0, 0, 0, 0};
        float h[4];
        for (int i = 0; i < v->dims; i++)
            k[i] = (int32_t)((uint32_t)c->icell[i] + (uint32_t)off[i]);
        if (v->dims == 4)
            pcg4(k, h);
        else
            pcg3(k, h); /* 2D: (x, y, 0) */
        return v3(h[0], h[1], h[2]);
    }
    float k[4];
    for (int i = 0; i < v->dims; i++)
        k[i] = c->cell[i] + (float)off[i];
    switch (v->dims) {
    case 1: return hash_float_to_float3(k[0]);
    case 2: return hash_float2_to_float3(k[0], k[1]);
    case 3: return hash_float3_to_float3(v3(k[0], k[1], k[2]));
    default: return hash_float4_to_float3(v3(k[0], k[1], k[2]), k[3]);
    }
}

/* The feature point of cell + off, relative to the cell: off + jitter·randomness. */
NODE_INLINE void feature_point(const voronoi_params *v, const voronoi_cell *c, const int off[4], float pp[4])
{
    float h[4] = {0, 0, 0, 0};
    cell_jitter(v, c, off, h);
    for (int k = 0; k < 4; k++)
        pp[k] = k < v->dims ? (float)off[k] + h[k] * v->randomness : 0.0f;
}

/* Σ a in Cycles' order: 4-wide pairs (x + y) + (z + w), except 3.x's
 * componentwise 4D Manhattan/Minkowski sums, left to right. */
NODE_INLINE float vsum(const float *a, int dims, int legacy)
{
    switch (dims) {
    case 1: return a[0];
    case 2: return a[0] + a[1];
    case 3: return a[0] + a[1] + a[2];
    default: return legacy ? a[0] + a[1] + a[2] + a[3] : (a[0] + a[1]) + (a[2] + a[3]);
    }
}

/* a·b in Cycles' order (SSE dot product: (x² + y²) + (z² + w²)). */
NODE_INLINE float vdot(const float *a, const float *b, int dims)
{
    switch (dims) {
    case 1: return a[0] * b[0];
    case 2: return a[0] * b[0] + a[1] * b[1];
    case 3: return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    default: return (a[0] * b[0] + a[1] * b[1]) + (a[2] * b[2] + a[3] * b[3]);
    }
}

NODE_INLINE float vmax(const float *a, int dims)
{
    float m = a[0];
    for (int k = 1; k < dims; k++)
        m = node_max(m, a[k]);
    return m;
}

/* Distance from a to b in the metric: Euclidean ‖a − b‖₂, Manhattan
 * ‖a − b‖₁, Chebychev ‖a − b‖∞, Minkowski (Σ|aᵢ − bᵢ|^e)^(1/e). 1D is
 * always |b − a|. With `bound`, a monotone stand-in that ranks candidates
 * the same (squared length, Minkowski without the root; Blender 4.5+'s F1). */
NODE_INLINE float voronoi_distance(const voronoi_params *v, const float *a, const float *b, int bound)
{
    int d = v->dims;
    if (d == 1)
        return fabsf(b[0] - a[0]);
    float t[4] = {0, 0, 0, 0};
    switch (v->metric) {
    case PHOS_VORONOI_EUCLIDEAN: {
        for (int k = 0; k < d; k++)
            t[k] = a[k] - b[k];
        float s = vdot(t, t, d);
        return bound ? s : sqrtf(s);
    }
    case PHOS_VORONOI_MANHATTAN:
        for (int k = 0; k < d; k++)
            t[k] = fabsf(a[k] - b[k]);
        return vsum(t, d, v->legacy);
    case PHOS_VORONOI_CHEBYCHEV:
        for (int k = 0; k < d; k++)
            t[k] = fabsf(a[k] - b[k]);
        return vmax(t, d);
    case PHOS_VORONOI_MINKOWSKI: {
        for (int k = 0; k < d; k++)
            t[k] = powf(fabsf(a[k] - b[k]), v->exponent);
        float s = vsum(t, d, v->legacy);
        return bound ? s : powf(s, 1.0f / v->exponent);
    }
    default:
        return 0.0f;
    }
}

/* Euclidean distance, or its square (N-Sphere Radius in 4.5+). */
NODE_INLINE float euclid(const voronoi_params *v, const float *a, const float *b, int squared)
{
    float t[4] = {0, 0, 0, 0};
    for (int k = 0; k < v->dims; k++)
        t[k] = a[k] - b[k];
    float s = vdot(t, t, v->dims);
    return squared ? s : sqrtf(s);
}

NODE_INLINE float search_start(const voronoi_params *v) { return v->legacy ? 8.0f : FLT_MAX; }

NODE_INLINE void copy4(float *dst, const float *src) { dst[0] = src[0], dst[1] = src[1], dst[2] = src[2], dst[3] = src[3]; }

/* Cycles 4.0+ carries every position as a float4, and a 3D one gets w = 1
 * (make_float4 of a float3), which reaches the W output through the
 * fractal sums and the division by the scale. */
NODE_INLINE float position_w3(const voronoi_params *v) { return v->dims == 3 && !v->legacy ? 1.0f : 0.0f; }

NODE_INLINE void set_position(const voronoi_params *v, const voronoi_cell *c, const float *pp, voronoi_result *r)
{
    for (int k = 0; k < 4; k++)
        r->position[k] = k < v->dims ? pp[k] + c->cell[k] : 0.0f;
    if (v->dims == 3)
        r->position[3] = position_w3(v);
}

/* F1 (Worley 1996): the nearest feature point among the 3^dims cells. */
NODE_INLINE voronoi_result voronoi_f1(const voronoi_params *v, const float p[4])
{
    voronoi_cell c = voronoi_cell_of(v, p);
    int bound = !v->legacy && v->dims >= 2;
    float best = search_start(v), best_pp[4] = {0, 0, 0, 0};
    int off[4], best_off[4] = {0, 0, 0, 0};
    first_offset(off, v->dims, -1);
    do {
        float pp[4];
        feature_point(v, &c, off, pp);
        float d = voronoi_distance(v, pp, c.local, bound);
        if (d < best) {
            best = d;
            copy4(best_pp, pp);
            for (int k = 0; k < 4; k++)
                best_off[k] = off[k];
        }
    } while (next_offset(off, v->dims, -1, 1));
    voronoi_result r;
    r.distance = bound ? voronoi_distance(v, best_pp, c.local, 0) : best;
    r.color = cell_color(v, &c, best_off);
    set_position(v, &c, best_pp, &r);
    return r;
}

/* F2: the second nearest feature point. */
NODE_INLINE voronoi_result voronoi_f2(const voronoi_params *v, const float p[4])
{
    voronoi_cell c = voronoi_cell_of(v, p);
    float d1 = search_start(v), d2 = d1, pp1[4] = {0, 0, 0, 0}, pp2[4] = {0, 0, 0, 0};
    int off[4], off1[4] = {0, 0, 0, 0}, off2[4] = {0, 0, 0, 0};
    first_offset(off, v->dims, -1);
    do {
        float pp[4];
        feature_point(v, &c, off, pp);
        float d = voronoi_distance(v, pp, c.local, 0);
        if (d < d1) {
            d2 = d1, copy4(pp2, pp1);
            for (int k = 0; k < 4; k++)
                off2[k] = off1[k], off1[k] = off[k];
            d1 = d, copy4(pp1, pp);
        } else if (d < d2) {
            d2 = d, copy4(pp2, pp);
            for (int k = 0; k < 4; k++)
                off2[k] = off[k];
        }
    } while (next_offset(off, v->dims, -1, 1));
    voronoi_result r;
    r.distance = d2;
    r.color = cell_color(v, &c, off2);
    set_position(v, &c, pp2, &r);
    return r;
}

/* Smooth F1: the 5^dims cells folded in with a polynomial smooth minimum
 * of width s (Quilez' smin): h = smoothstep(½ + ½(D − d)/s),
 * D ← mix(D, d, h) − s·h(1 − h); colour and position follow with the
 * correction divided by 1 + 3s. */
NODE_INLINE voronoi_result voronoi_smooth_f1(const voronoi_params *v, const float p[4])
{
    voronoi_cell c = voronoi_cell_of(v, p);
    float s = v->smoothness;
    float sd = v->legacy ? 8.0f : 0.0f, spos[4] = {0, 0, 0, 0};
    vec3 scol = v3s(0.0f);
    int first = 1;
    int off[4];
    first_offset(off, v->dims, -2);
    do {
        float pp[4];
        feature_point(v, &c, off, pp);
        float d = voronoi_distance(v, pp, c.local, 0);
        float h = (first && !v->legacy) ? 1.0f : smoothstep01(0.5f + 0.5f * (sd - d) / s);
        first = 0;
        float corr = s * h * (1.0f - h);
        sd = mixf(sd, d, h) - corr;
        corr /= 1.0f + 3.0f * s;
        vec3 col = cell_color(v, &c, off);
        scol = v3_sub(v3_mix(scol, col, h), v3s(corr));
        for (int k = 0; k < v->dims; k++)
            spos[k] = mixf(spos[k], pp[k], h) - corr;
    } while (next_offset(off, v->dims, -2, 2));
    voronoi_result r;
    r.distance = sd;
    r.color = scol;
    for (int k = 0; k < 4; k++)
        r.position[k] = k < v->dims ? c.cell[k] + spos[k] : 0.0f;
    if (v->dims == 3)
        r.position[3] = position_w3(v);
    return r;
}

/* Distance to Edge, 1D: to the midpoints between this cell's point and its
 * neighbours'. */
NODE_INLINE float voronoi_edge_1d(const voronoi_params *v, float p)
{
    float cell = floorf(p), local = p - cell;
    float mid = hash_float_to_float(cell) * v->randomness;
    float left = -1.0f + hash_float_to_float(cell - 1.0f) * v->randomness;
    float right = 1.0f + hash_float_to_float(cell + 1.0f) * v->randomness;
    float dl = fabsf((mid + left) / 2.0f - local);
    float dr = fabsf((mid + right) / 2.0f - local);
    return node_min(dl, dr);
}

/* Distance to Edge (Euclidean): find the nearest point's vector c, then
 * for every other point q the distance to the bisector of c and q,
 * ((c + q)/2)·(q − c)/‖q − c‖; the least of them. */
NODE_INLINE float voronoi_edge(const voronoi_params *v, const float p[4])
{
    if (v->dims == 1)
        return voronoi_edge_1d(v, p[0]);
    int d = v->dims;
    voronoi_cell c = voronoi_cell_of(v, p);
    float best = search_start(v), closest[4] = {0, 0, 0, 0};
    int off[4];
    first_offset(off, d, -1);
    do {
        float pp[4], vp[4] = {0, 0, 0, 0};
        feature_point(v, &c, off, pp);
        for (int k = 0; k < d; k++)
            vp[k] = pp[k] - c.local[k];
        float dist = vdot(vp, vp, d);
        if (dist < best)
            best = dist, copy4(closest, vp);
    } while (next_offset(off, d, -1, 1));

    best = search_start(v);
    first_offset(off, d, -1);
    do {
        float pp[4], vp[4] = {0, 0, 0, 0}, perp[4] = {0, 0, 0, 0}, mid[4] = {0, 0, 0, 0};
        feature_point(v, &c, off, pp);
        for (int k = 0; k < d; k++) {
            vp[k] = pp[k] - c.local[k];
            perp[k] = vp[k] - closest[k];
        }
        float len2 = vdot(perp, perp, d);
        if (len2 > 0.0001f) {
            float len = sqrtf(len2), inv = 1.0f / len;
            for (int k = 0; k < d; k++) {
                mid[k] = (closest[k] + vp[k]) * 0.5f;
                perp[k] = d == 3 ? perp[k] / len : perp[k] * inv; /* float3 divides, float2/4 multiply */
            }
            best = node_min(best, vdot(mid, perp, d));
        }
    } while (next_offset(off, d, -1, 1));
    return best;
}

/* N-Sphere Radius: half the (Euclidean) distance from the nearest point to
 * the point nearest to it, the largest sphere around it inside its cell. */
NODE_INLINE float voronoi_n_sphere_radius(const voronoi_params *v, const float p[4])
{
    int d = v->dims, squared = !v->legacy;
    voronoi_cell c = voronoi_cell_of(v, p);
    float best = search_start(v), closest[4] = {0, 0, 0, 0};
    int off[4], closest_off[4] = {0, 0, 0, 0};
    first_offset(off, d, -1);
    do {
        float pp[4];
        feature_point(v, &c, off, pp);
        float dist = d == 1 ? fabsf(pp[0] - c.local[0]) : euclid(v, pp, c.local, squared);
        if (dist < best) {
            best = dist, copy4(closest, pp);
            for (int k = 0; k < 4; k++)
                closest_off[k] = off[k];
        }
    } while (next_offset(off, d, -1, 1));

    best = search_start(v);
    float other[4] = {0, 0, 0, 0};
    first_offset(off, d, -1);
    do {
        int zero = 1, o[4] = {0, 0, 0, 0};
        for (int k = 0; k < d; k++) {
            zero &= off[k] == 0;
            o[k] = off[k] + closest_off[k];
        }
        if (zero)
            continue;
        float pp[4];
        feature_point(v, &c, o, pp);
        float dist = d == 1 ? fabsf(closest[0] - pp[0]) : euclid(v, closest, pp, squared);
        if (dist < best)
            best = dist, copy4(other, pp);
    } while (next_offset(off, d, -1, 1));
    if (d == 1)
        return fabsf(other[0] - closest[0]) / 2.0f;
    return euclid(v, other, closest, 0) / 2.0f;
}

NODE_INLINE voronoi_result voronoi_octave_of(const voronoi_params *v, const float p[4])
{
    if (v->feature == PHOS_VORONOI_F2)
        return voronoi_f2(v, p);
    if (v->feature == PHOS_VORONOI_SMOOTH_F1 && (v->legacy || v->smoothness != 0.0f))
        return voronoi_smooth_f1(v, p);
    return voronoi_f1(v, p);
}

/* One octave, compiled apart for 2D and 3D with the dimension a constant:
 * the searches over 3^dims cells and the loops over components then
 * unroll, as Cycles' per-dimension code does (the same arithmetic). */
static NODE_VECTOR_CLONES voronoi_result voronoi_octave(const voronoi_params *v, const float p[4])
{
    voronoi_params fixed = *v;
    switch (v->dims) {
    case 2:
        fixed.dims = 2;
        return voronoi_octave_of(&fixed, p);
    case 3:
        fixed.dims = 3;
        return voronoi_octave_of(&fixed, p);
    default:
        return voronoi_octave_of(v, p);
    }
}

NODE_INLINE void scale4(float *out, const float *p, float s, int dims)
{
    for (int k = 0; k < 4; k++)
        out[k] = k < dims ? p[k] * s : 0.0f;
}

/* Blender 4.0+ fractal Voronoi: octave i at frequency lacunarity^i with
 * weight roughness^i, summed like fBM noise (the positions blended by
 * lerps), the fraction of `detail` blending in one more octave;
 * `normalize` divides by the total weight (and the distance by its
 * largest value). */
NODE_INLINE voronoi_result voronoi_fractal(const voronoi_params *v, const float p[4])
{
    float amp = 1.0f, max_amp = 0.0f, scale = 1.0f;
    voronoi_result out = {0.0f, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f, 0.0f}};
    int zero_input = v->detail == 0.0f || v->roughness == 0.0f;
    for (int i = 0; (float)i <= ceilf(v->detail); ++i) {
        float q[4];
        scale4(q, p, scale, v->dims);
        voronoi_result o = voronoi_octave(v, q);
        if (zero_input) {
            max_amp = 1.0f;
            out = o;
            break;
        }
        float inv = 1.0f / scale, opos[4];
        for (int k = 0; k < 4; k++)
            opos[k] = o.position[k] * inv;
        if ((float)i <= v->detail) {
            max_amp += amp;
            out.distance += o.distance * amp;
            out.color = v3_add(out.color, v3_scale(o.color, amp));
            for (int k = 0; k < 4; k++)
                out.position[k] = mixf(out.position[k], opos[k], amp);
            scale *= v->lacunarity;
            amp *= v->roughness;
        } else {
            float rem = v->detail - floorf(v->detail);
            if (rem != 0.0f) {
                max_amp = mixf(max_amp, max_amp + amp, rem);
                out.distance = mixf(out.distance, out.distance + o.distance * amp, rem);
                out.color = v3_mix(out.color, v3_add(out.color, v3_scale(o.color, amp)), rem);
                for (int k = 0; k < 4; k++)
                    out.position[k] = mixf(out.position[k], mixf(out.position[k], opos[k], amp), rem);
            }
        }
    }
    if (v->normalize) {
        out.distance /= max_amp * v->max_distance;
        out.color = v3_scale(out.color, 1.0f / max_amp); /* float3 /= scalar multiplies */
    }
    return out;
}

/* Fractal Distance to Edge: the least edge distance over the octaves (each
 * divided by its frequency), blended in by the octave weights. */
NODE_INLINE float voronoi_fractal_edge(const voronoi_params *v, const float p[4])
{
    float amp = 1.0f, max_amp = v->max_distance, scale = 1.0f, dist = 8.0f;
    int zero_input = v->detail == 0.0f || v->roughness == 0.0f;
    for (int i = 0; (float)i <= ceilf(v->detail); ++i) {
        float q[4];
        scale4(q, p, scale, v->dims);
        float od = voronoi_edge(v, q);
        if (zero_input) {
            dist = od;
            break;
        }
        if ((float)i <= v->detail) {
            max_amp = mixf(max_amp, v->max_distance / scale, amp);
            dist = mixf(dist, node_min(dist, od / scale), amp);
            scale *= v->lacunarity;
            amp *= v->roughness;
        } else {
            float rem = v->detail - floorf(v->detail);
            if (rem != 0.0f) {
                float lerp_amp = mixf(max_amp, v->max_distance / scale, amp);
                max_amp = mixf(max_amp, lerp_amp, rem);
                float lerp_dist = mixf(dist, node_min(dist, od / scale), amp);
                dist = mixf(dist, node_min(dist, lerp_dist), rem);
            }
        }
    }
    if (v->normalize)
        dist /= max_amp;
    return dist;
}

/* The outputs of the node. */
typedef struct voronoi_outputs {
    float distance;
    vec3 color, position;
    float w, radius;
} voronoi_outputs;

/* Copies a feature position to the node's Position and W outputs, divided
 * by the scale (safe: 0 for scale 0) as the float width of each dimension
 * divides in Cycles: 1D and 3D per component in 3.x, otherwise by the
 * reciprocal. */
NODE_INLINE void position_outputs(const voronoi_params *v, const float pos[4], float scale, int true_div,
                             voronoi_outputs *o)
{
    float q[4] = {0, 0, 0, 0};
    if (scale != 0.0f) {
        float inv = 1.0f / scale;
        for (int k = 0; k < 4; k++)
            q[k] = true_div ? pos[k] / scale : pos[k] * inv;
    }
    switch (v->dims) {
    case 1: o->w = q[0]; break;
    case 2: o->position = v3(q[0], q[1], 0.0f); break;
    case 3: o->position = v3(q[0], q[1], q[2]), o->w = q[3]; break; /* q[3]: 0 in 3.x, see position_w3 */
    default: o->position = v3(q[0], q[1], q[2]), o->w = q[3]; break;
    }
}

/* Blender 3.x: one octave of the feature at the scaled point. */
NODE_INLINE voronoi_outputs voronoi_legacy(const voronoi_params *v, const float p[4], float scale)
{
    voronoi_outputs o = {0.0f, {0, 0, 0}, {0, 0, 0}, 0.0f, 0.0f};
    if (v->feature == PHOS_VORONOI_DISTANCE_TO_EDGE) {
        o.distance = voronoi_edge(v, p);
    } else if (v->feature == PHOS_VORONOI_N_SPHERE_RADIUS) {
        o.radius = voronoi_n_sphere_radius(v, p);
    } else {
        voronoi_result r = voronoi_octave(v, p); /* 3.x: Smooth F1 whatever the smoothness */
        o.distance = r.distance;
        o.color = r.color;
        position_outputs(v, r.position, scale, v->dims == 1 || v->dims == 3, &o);
    }
    return o;
}

/* Blender 4.0+: fractal features; N-Sphere Radius stays one octave. */
NODE_INLINE voronoi_outputs voronoi_modern(voronoi_params *v, const float p[4], float scale)
{
    voronoi_outputs o = {0.0f, {0, 0, 0}, {0, 0, 0}, 0.0f, 0.0f};
    float m = 0.5f + 0.5f * v->randomness;
    if (v->feature == PHOS_VORONOI_DISTANCE_TO_EDGE) {
        v->max_distance = m;
        o.distance = voronoi_fractal_edge(v, p);
    } else if (v->feature == PHOS_VORONOI_N_SPHERE_RADIUS) {
        o.radius = voronoi_n_sphere_radius(v, p);
    } else {
        /* the largest F1: from a cell corner to the farthest jitter, in the metric */
        float zero[4] = {0, 0, 0, 0}, corner[4] = {m, m, m, m};
        float md = v->dims == 1 ? m : voronoi_distance(v, zero, corner, 0);
        v->max_distance = md * (v->feature == PHOS_VORONOI_F2 ? 2.0f : 1.0f);
        voronoi_result r = voronoi_fractal(v, p);
        o.distance = r.distance;
        o.color = r.color;
        position_outputs(v, r.position, scale, 0, &o);
    }
    return o;
}

/* in vector(3), w, scale, detail, roughness, lacunarity, smoothness,
 * exponent, randomness; out distance, color(3), position(3), w, radius.
 * mode enum phos_voronoi_feature; flags: bits 0-2 dimensions, 8 =
 * normalize, 16 = Blender 3.x, bits 5-6 metric, 128 = Blender 5.0+ */
NODE_VECTOR_CLONES void shader_op_tex_voronoi(const phos_shader_instruction *ins, shader_context *ctx)
{
    uint32_t fl = ins->flags;
    voronoi_params v;
    v.dims = (int)(fl & VORONOI_DIMS_MASK);
    v.feature = ins->mode;
    v.metric = (fl >> VORONOI_METRIC_SHIFT) & 3u;
    v.legacy = (fl & VORONOI_FLAG_LEGACY) != 0;
    v.int_cells = !v.legacy && (fl & VORONOI_FLAG_INT_CELLS) != 0;
    v.normalize = (fl & VORONOI_FLAG_NORMALIZE) != 0;

    vec3 co = SHADER_IN3(0);
    float w = SHADER_IN(1), scale = SHADER_IN(2);
    v.detail = node_clamp(SHADER_IN(3), 0.0f, 15.0f);
    v.roughness = node_clamp(SHADER_IN(4), 0.0f, 1.0f);
    v.lacunarity = SHADER_IN(5);
    v.smoothness = node_clamp(SHADER_IN(6) / 2.0f, 0.0f, 0.5f);
    v.exponent = SHADER_IN(7);
    v.randomness = node_clamp(SHADER_IN(8), 0.0f, 1.0f);
    v.max_distance = 0.0f;

    voronoi_outputs o = {0.0f, {0, 0, 0}, {0, 0, 0}, 0.0f, 0.0f};
    if (v.dims >= 1 && v.dims <= 4 && v.feature < PHOS_VORONOI_FEATURE_COUNT) {
        co = v3_scale(co, scale);
        w *= scale;
        float p[4] = {co.x, co.y, co.z, w};
        if (v.dims == 1)
            p[0] = w, p[1] = p[2] = p[3] = 0.0f;
        o = v.legacy ? voronoi_legacy(&v, p, scale) : voronoi_modern(&v, p, scale);
    }
    SHADER_OUT(0, o.distance);
    SHADER_OUT3(1, o.color);
    SHADER_OUT3(2, o.position);
    SHADER_OUT(3, o.w);
    SHADER_OUT(4, o.radius);
}
