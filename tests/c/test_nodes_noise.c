/*
 * test_nodes_noise.c — checks of the noise library (shading/nodes/noise.c)
 * and the Noise, Musgrave and White Noise ops (texture_noise.c):
 *
 *  1. the lookup3 hashes against a plain transcription of Jenkins'
 *     hashword() (loop over 3-word blocks, then the tail), and the
 *     hash-to-float maps' range;
 *  2. Perlin noise: 0 at lattice points, continuous across cell faces,
 *     within about [-1, 1], deterministic; wrap leaves small coordinates
 *     alone; the legacy form agrees with it below 100000;
 *  3. fractal noise: detail 0 is one octave (every type and both
 *     definitions), fractional detail lies between its neighbours;
 *  4. the ops through a hand-built register file: socket order, scale,
 *     distortion off, colour red = fac, flags (dimensions, normalize,
 *     Blender 3.x), white noise against the hashes.
 */
#include <stdint.h>
#include <string.h>

#include "shading/nodes/noise.h"
#include "shading/shader_program.h"
#include "test_util.h"

/* ---------------------------------------------- reference lookup3 */

static uint32_t ref_rot(uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }

/* Jenkins' hashword(k, length, initval) transcribed from lookup3.c. */
static uint32_t ref_hashword(const uint32_t *k, size_t length, uint32_t initval)
{
    uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + ((uint32_t)length << 2) + initval;
    while (length > 3) {
        a += k[0];
        b += k[1];
        c += k[2];
        a -= c; a ^= ref_rot(c, 4);  c += b;
        b -= a; b ^= ref_rot(a, 6);  a += c;
        c -= b; c ^= ref_rot(b, 8);  b += a;
        a -= c; a ^= ref_rot(c, 16); c += b;
        b -= a; b ^= ref_rot(a, 19); a += c;
        c -= b; c ^= ref_rot(b, 4);  b += a;
        length -= 3;
        k += 3;
    }
    switch (length) {
    case 3: c += k[2]; /* fall through */
    case 2: b += k[1]; /* fall through */
    case 1:
        a += k[0];
        c ^= b; c -= ref_rot(b, 14);
        a ^= c; a -= ref_rot(c, 11);
        b ^= a; b -= ref_rot(a, 25);
        c ^= b; c -= ref_rot(b, 16);
        a ^= c; a -= ref_rot(c, 4);
        b ^= a; b -= ref_rot(a, 14);
        c ^= b; c -= ref_rot(b, 24);
        break;
    default: break;
    }
    return c;
}

/* Cycles' hashes are hashword(k, n, 13): the seed 0xdeadbeef + 4n + 13. */
#define REF_INITVAL 13u

static void test_hashes(void)
{
    static const uint32_t keys[][4] = {
        {0, 0, 0, 0}, {1, 2, 3, 4}, {0xffffffffu, 7, 0x80000000u, 12345},
        {0x3f800000u, 0x40000000u, 0xbf800000u, 0x7f7fffffu}, {42, 0xdeadbeefu, 99, 1000000007u},
    };
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
        const uint32_t *k = keys[i];
        CHECK(hash_uint(k[0]) == ref_hashword(k, 1, REF_INITVAL));
        CHECK(hash_uint2(k[0], k[1]) == ref_hashword(k, 2, REF_INITVAL));
        CHECK(hash_uint3(k[0], k[1], k[2]) == ref_hashword(k, 3, REF_INITVAL));
        CHECK(hash_uint4(k[0], k[1], k[2], k[3]) == ref_hashword(k, 4, REF_INITVAL));
    }
    /* Distinct keys give distinct hashes here, and order matters. */
    CHECK(hash_uint2(1, 2) != hash_uint2(2, 1));
    CHECK(hash_uint3(1, 2, 3) != hash_uint3(3, 2, 1));

    /* Float maps: n·2^-32, so 0 → 0 and the top → 1 after rounding. */
    float lo = 1.0f, hi = 0.0f;
    for (uint32_t n = 0; n < 20000; n++) {
        float f = hash_uint_to_float(n * 2654435761u);
        lo = fminf(lo, f);
        hi = fmaxf(hi, f);
    }
    CHECK(lo >= 0.0f && hi <= 1.0f && hi - lo > 0.99f);
    CHECK(hash_float_to_float(1.5f) == hash_uint_to_float(0x3fc00000u));
    CHECK(hash_float_to_float(0.0f) != hash_float_to_float(-0.0f)); /* bit patterns */
    CHECK(hash_float2_to_float(1.0f, 2.0f) == hash_uint2_to_float(0x3f800000u, 0x40000000u));

    /* Vector hashes: the first component is the scalar hash of the key. */
    vec3 k3 = v3(0.25f, -3.0f, 7.5f);
    CHECK(hash_float3_to_float3(k3).x == hash_float3_to_float(k3));
    CHECK(hash_float3_to_float3(k3).y == hash_float4_to_float(k3, 1.0f));
    CHECK(hash_float_to_float3(2.0f).z == hash_float2_to_float(2.0f, 2.0f));
    CHECK(hash_float2_to_float2(1.0f, 2.0f).y == hash_float3_to_float(v3(1.0f, 2.0f, 1.0f)));
    vec4f k4 = v4f(1.0f, 2.0f, 3.0f, 4.0f);
    CHECK(hash_float4_to_float4(k4).y == hash_float4_to_float(v3(4.0f, 1.0f, 2.0f), 3.0f));
    CHECK(hash_float4_to_float3(v3(1.0f, 2.0f, 3.0f), 4.0f).z == hash_float4_to_float(v3(4.0f, 3.0f, 2.0f), 1.0f));

    /* Brick noise: in [0, 1), deterministic. */
    for (uint32_t n = 0; n < 1000; n++) {
        float b = brick_noise(n * 7919u);
        CHECK(b >= 0.0f && b < 1.0f);
    }
    CHECK(brick_noise(12345u) == brick_noise(12345u));
}

/* ------------------------------------------------------ Perlin noise */

static float rnd_state_next(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (float)(*s >> 8) * (1.0f / 16777216.0f);
}

static void test_perlin_lattice(void)
{
    for (int i = -3; i <= 3; i++)
        for (int j = -2; j <= 2; j++) {
            float x = (float)i, y = (float)j, z = (float)(i + j), w = (float)(i - 2 * j);
            CHECK(perlin_signed_1d(x) == 0.0f);
            CHECK(perlin_signed_2d(x, y) == 0.0f);
            CHECK(perlin_signed_3d(v3(x, y, z)) == 0.0f);
            CHECK(perlin_signed_4d(v3(x, y, z), w) == 0.0f);
            CHECK(perlin_3d(v3(x, y, z)) == 0.5f);
        }
}

static void test_perlin_continuity_and_range(void)
{
    uint32_t s = 1;
    int continuous = 1, in_range = 1, nonzero = 0;
    float eps = 1e-4f;
    for (int n = 0; n < 2000; n++) {
        float x = rnd_state_next(&s) * 40.0f - 20.0f, y = rnd_state_next(&s) * 40.0f - 20.0f;
        float z = rnd_state_next(&s) * 40.0f - 20.0f, w = rnd_state_next(&s) * 40.0f - 20.0f;
        float v[4] = {perlin_signed_1d(x), perlin_signed_2d(x, y), perlin_signed_3d(v3(x, y, z)),
                      perlin_signed_4d(v3(x, y, z), w)};
        for (int d = 0; d < 4; d++) {
            in_range &= fabsf(v[d]) <= 1.05f;
            nonzero += v[d] != 0.0f;
        }
        /* Across a cell face: x just below and above an integer. */
        float face = floorf(x) + 1.0f;
        float a3 = perlin_signed_3d(v3(face - eps, y, z)), b3 = perlin_signed_3d(v3(face + eps, y, z));
        float a4 = perlin_signed_4d(v3(x, y, z), floorf(w) + 1.0f - eps);
        float b4 = perlin_signed_4d(v3(x, y, z), floorf(w) + 1.0f + eps);
        float a2 = perlin_signed_2d(x, floorf(y) + 1.0f - eps), b2 = perlin_signed_2d(x, floorf(y) + 1.0f + eps);
        float a1 = perlin_signed_1d(face - eps), b1 = perlin_signed_1d(face + eps);
        continuous &= fabsf(a3 - b3) < 0.01f && fabsf(a4 - b4) < 0.01f && fabsf(a2 - b2) < 0.01f &&
                      fabsf(a1 - b1) < 0.01f;
    }
    CHECK(continuous);
    CHECK(in_range);
    CHECK(nonzero > 7000);

    /* The unsigned form and determinism. */
    vec3 p = v3(0.3f, 1.7f, -2.2f);
    CHECK(perlin_3d(p) == 0.5f * perlin_signed_3d(p) + 0.5f);
    CHECK(perlin_signed_3d(p) == perlin_signed_3d(p));
    CHECK(perlin_signed_4d(p, 0.9f) == perlin_signed(v4f_from3(p, 0.9f), 4));
    CHECK(perlin_signed_1d(0.9f) == perlin_signed(v4f(0.9f, 0.0f, 0.0f, 0.0f), 1));

    /* Below 100000 the wrap changes nothing: legacy and new agree. */
    CHECK(perlin_signed_3d(p) == perlin_signed_legacy_3d(p));
    CHECK(perlin_signed_2d(12345.6f, -999.25f) == perlin_signed_legacy_2d(12345.6f, -999.25f));
    /* Beyond it the new form repeats every 100000. */
    CHECK(perlin_signed_1d(100000.0f + 0.375f) == perlin_signed_1d(0.375f));
    CHECK(isfinite(perlin_signed_3d(v3(3e9f, -1e12f, 5e6f))));
    CHECK(perlin_signed_legacy_3d(v3(NAN, 0.5f, 0.5f)) == 0.0f);

    /* A hand computation in 1D at x = 0.5: fade(0.5) = 0.5, so the noise
     * is 0.25 · (g0·0.5 + g1·(−0.5)) / 2 with the slopes from the hash. */
    uint32_t h0 = hash_uint(0) & 15u, h1 = hash_uint(1) & 15u;
    float g0 = (float)(1u + (h0 & 7u)) * ((h0 & 8u) ? -1.0f : 1.0f);
    float g1 = (float)(1u + (h1 & 7u)) * ((h1 & 8u) ? -1.0f : 1.0f);
    float expect = 0.25f * (0.5f * g0 + 0.5f * (-0.5f * g1 - 0.5f * g0));
    CHECK_REL(perlin_signed_1d(0.5f), expect, 1e-6);
}

/* ----------------------------------------------------- fractal noise */

static void test_fractal(void)
{
    vec4f p = v4f(0.37f, -1.21f, 2.05f, 0.66f);
    for (int d = 1; d <= 4; d++) {
        float s = perlin_signed(p, d);
        /* fBM at detail 0 is one octave; normalised, the unsigned noise. */
        CHECK(noise_fbm(p, d, 0.0f, 0.5f, 2.0f, 0) == s);
        CHECK(noise_fbm(p, d, 0.0f, 0.5f, 2.0f, 1) == 0.5f * s + 0.5f);
        CHECK(noise_fbm_legacy(p, d, 0.0f, 0.5f) == 0.5f * perlin_signed_legacy(p, d) + 0.5f);
        CHECK(noise_multi_fractal(p, d, 0.0f, 0.5f, 2.0f) == s + 1.0f);
        CHECK(noise_hetero_terrain(p, d, 0.0f, 0.5f, 2.0f, 0.25f) == 0.25f + s);
        CHECK(noise_hybrid_multi_fractal(p, d, 0.0f, 0.5f, 2.0f, 0.25f, 1.0f) == s + 0.25f);
        float r = 1.0f - fabsf(s);
        CHECK(noise_ridged_multi_fractal(p, d, 0.0f, 0.5f, 2.0f, 1.0f, 1.0f) == r * r);
        /* Musgrave: one octave is the signed noise itself. */
        CHECK(musgrave_fractal(PHOS_NOISE_FBM, p, d, 1.0f, 2.0f, 1.0f, 0.0f, 1.0f) == perlin_signed_legacy(p, d));
        CHECK(musgrave_fractal(PHOS_NOISE_MULTIFRACTAL, p, d, 1.0f, 2.0f, 1.0f, 0.0f, 1.0f) ==
              perlin_signed_legacy(p, d) + 1.0f);

        /* Fractional detail blends between the neighbouring integers. */
        float f2 = noise_fbm(p, d, 2.0f, 0.5f, 2.0f, 1), f3 = noise_fbm(p, d, 3.0f, 0.5f, 2.0f, 1);
        float f25 = noise_fbm(p, d, 2.5f, 0.5f, 2.0f, 1);
        CHECK(f25 >= fminf(f2, f3) - 1e-6f && f25 <= fmaxf(f2, f3) + 1e-6f);
        float l2 = noise_fbm_legacy(p, d, 2.0f, 0.5f), l3 = noise_fbm_legacy(p, d, 3.0f, 0.5f);
        float l25 = noise_fbm_legacy(p, d, 2.5f, 0.5f);
        CHECK(l25 >= fminf(l2, l3) - 1e-6f && l25 <= fmaxf(l2, l3) + 1e-6f);
        /* Normalised fBM stays in about [0, 1]. */
        float f15 = noise_fbm(p, d, 15.0f, 0.8f, 2.3f, 1);
        CHECK(f15 > -0.05f && f15 < 1.05f);
        /* Same inputs, same bits. */
        CHECK(noise_fractal(PHOS_NOISE_RIDGED_MULTIFRACTAL, p, d, 6.3f, 0.5f, 2.0f, 1.0f, 2.0f, 0) ==
              noise_ridged_multi_fractal(p, d, 6.3f, 0.5f, 2.0f, 1.0f, 2.0f));
    }
    /* 3.x definitions: roughness clamps to 1, lacunarity fixed at 2. */
    CHECK(noise_fbm_legacy(p, 3, 4.0f, 7.0f) == noise_fbm_legacy(p, 3, 4.0f, 1.0f));
    CHECK(noise_fbm_legacy(p, 3, 40.0f, 0.5f) == noise_fbm_legacy(p, 3, 15.0f, 0.5f));
}

/* ------------------------------------------------------------- ops */

enum { R_VEC = 0, R_W = 3, R_SCALE, R_DETAIL, R_ROUGH, R_LAC, R_OFFSET, R_GAIN, R_DIST, R_FAC, R_COL, R_COUNT = R_COL + 3 };

static phos_shader_instruction noise_instruction(uint32_t op, uint32_t mode, uint32_t flags)
{
    phos_shader_instruction ins;
    memset(&ins, 0, sizeof ins);
    ins.op = op;
    ins.mode = mode;
    ins.flags = flags;
    for (int i = 0; i < PHOS_SHADER_MAX_INPUTS; i++)
        ins.inputs[i] = PHOS_SHADER_NO_REGISTER;
    for (int i = 0; i < PHOS_SHADER_MAX_OUTPUTS; i++)
        ins.outputs[i] = PHOS_SHADER_NO_REGISTER;
    static const uint32_t noise_in[9] = {R_VEC, R_W, R_SCALE, R_DETAIL, R_ROUGH, R_LAC, R_OFFSET, R_GAIN, R_DIST};
    if (op == PHOS_OP_TEX_WHITE_NOISE) {
        ins.inputs[0] = R_VEC;
        ins.inputs[1] = R_W;
        ins.outputs[0] = R_FAC;
        ins.outputs[1] = R_COL;
        return ins;
    }
    for (int i = 0; i < (op == PHOS_OP_TEX_NOISE ? 9 : 8); i++)
        ins.inputs[i] = noise_in[i];
    ins.outputs[0] = R_FAC;
    if (op == PHOS_OP_TEX_NOISE)
        ins.outputs[1] = R_COL;
    return ins;
}

static void set_inputs(float *r, vec3 v, float w, float scale, float detail, float rough, float lac, float off,
                       float gain, float dist)
{
    r[R_VEC] = v.x;
    r[R_VEC + 1] = v.y;
    r[R_VEC + 2] = v.z;
    r[R_W] = w;
    r[R_SCALE] = scale;
    r[R_DETAIL] = detail;
    r[R_ROUGH] = rough;
    r[R_LAC] = lac;
    r[R_OFFSET] = off;
    r[R_GAIN] = gain;
    r[R_DIST] = dist;
}

static void test_ops(void)
{
    float r[R_COUNT];
    shader_context ctx = {r, NULL, NULL, NULL};
    vec3 v = v3(0.4f, -0.7f, 1.3f);
    float w = 0.8f, scale = 5.0f;
    vec3 sv = v3_scale(v, scale);

    /* Noise 3D fBM, normalised, no distortion: fac = noise_fbm at v·scale. */
    for (int d = 1; d <= 4; d++) {
        memset(r, 0, sizeof r);
        set_inputs(r, v, w, scale, 3.5f, 0.6f, 2.2f, 0.0f, 1.0f, 0.0f);
        phos_shader_instruction ins = noise_instruction(PHOS_OP_TEX_NOISE, PHOS_NOISE_FBM, (uint32_t)d | 8u);
        shader_op_tex_noise(&ins, &ctx);
        vec4f p = d == 1 ? v4f(w * scale, 0, 0, 0) : v4f(sv.x, sv.y, d >= 3 ? sv.z : 0.0f, d == 4 ? w * scale : 0.0f);
        float expect = noise_fbm(p, d, 3.5f, 0.6f, 2.2f, 1);
        CHECK(r[R_FAC] == expect);
        CHECK(r[R_COL] == expect); /* colour red is fac */
        CHECK(r[R_COL + 1] != r[R_COL + 2]);
        CHECK(r[R_COL + 1] > -0.05f && r[R_COL + 1] < 1.05f);
    }

    /* Detail and roughness clamps (4.1+): detail 40 = 15, roughness −1 = 0. */
    {
        phos_shader_instruction ins = noise_instruction(PHOS_OP_TEX_NOISE, PHOS_NOISE_FBM, 3u);
        set_inputs(r, v, w, scale, 40.0f, -1.0f, 2.0f, 0.0f, 1.0f, 0.0f);
        shader_op_tex_noise(&ins, &ctx);
        CHECK(r[R_FAC] == noise_fbm(v4f_from3(sv, 0.0f), 3, 15.0f, 0.0f, 2.0f, 0));
    }

    /* Every type through the op matches the library. */
    for (uint32_t t = 0; t < PHOS_NOISE_COUNT; t++) {
        phos_shader_instruction ins = noise_instruction(PHOS_OP_TEX_NOISE, t, 3u);
        set_inputs(r, v, w, scale, 4.25f, 0.55f, 1.9f, 0.8f, 1.5f, 0.0f);
        shader_op_tex_noise(&ins, &ctx);
        CHECK(r[R_FAC] == noise_fractal(t, v4f_from3(sv, 0.0f), 3, 4.25f, 0.55f, 1.9f, 0.8f, 1.5f, 0));
        CHECK(isfinite(r[R_FAC]));
    }

    /* Blender 3.x flag: the legacy fBM, lacunarity and type ignored. */
    {
        phos_shader_instruction ins = noise_instruction(PHOS_OP_TEX_NOISE, PHOS_NOISE_RIDGED_MULTIFRACTAL, 3u | 16u);
        set_inputs(r, v, w, scale, 2.0f, 0.5f, 9.0f, 0.0f, 1.0f, 0.0f);
        shader_op_tex_noise(&ins, &ctx);
        CHECK(r[R_FAC] == noise_fbm_legacy(v4f_from3(sv, 0.0f), 3, 2.0f, 0.5f));
    }

    /* Distortion moves the result, deterministically; an unread colour
     * output is left alone. */
    {
        phos_shader_instruction ins = noise_instruction(PHOS_OP_TEX_NOISE, PHOS_NOISE_FBM, 3u | 8u);
        ins.outputs[1] = PHOS_SHADER_NO_REGISTER;
        set_inputs(r, v, w, scale, 2.0f, 0.5f, 2.0f, 0.0f, 1.0f, 0.0f);
        r[R_COL] = -7.0f;
        shader_op_tex_noise(&ins, &ctx);
        float undistorted = r[R_FAC];
        r[R_DIST] = 1.5f;
        shader_op_tex_noise(&ins, &ctx);
        float distorted = r[R_FAC];
        shader_op_tex_noise(&ins, &ctx);
        CHECK(distorted != undistorted);
        CHECK(distorted == r[R_FAC]);
        CHECK(r[R_COL] == -7.0f);
    }

    /* Musgrave: socket order (dimension in slot 4) and clamps. */
    {
        phos_shader_instruction ins = noise_instruction(PHOS_OP_TEX_MUSGRAVE, PHOS_NOISE_HETERO_TERRAIN, 4u);
        set_inputs(r, v, w, scale, 3.0f, 1.2f, 2.1f, 0.7f, 1.0f, 0.0f);
        shader_op_tex_musgrave(&ins, &ctx);
        CHECK(r[R_FAC] == musgrave_fractal(PHOS_NOISE_HETERO_TERRAIN, v4f_from3(sv, w * scale), 4, 1.2f, 2.1f, 3.0f,
                                           0.7f, 1.0f));
        ins.mode = PHOS_NOISE_FBM;
        ins.flags = 2u;
        set_inputs(r, v, w, scale, 1.0f, -3.0f, 2.0f, 0.0f, 1.0f, 0.0f);
        shader_op_tex_musgrave(&ins, &ctx);
        CHECK(r[R_FAC] == perlin_signed_legacy_2d(sv.x, sv.y)); /* one octave, any H */
    }

    /* White noise: the hashes of the input, per dimension count. */
    {
        phos_shader_instruction ins = noise_instruction(PHOS_OP_TEX_WHITE_NOISE, 0, 3u);
        set_inputs(r, v, w, 1.0f, 0, 0, 0, 0, 0, 0);
        shader_op_tex_white_noise(&ins, &ctx);
        CHECK(r[R_FAC] == hash_float3_to_float(v));
        CHECK(r[R_COL] == hash_float3_to_float3(v).x && r[R_COL + 2] == hash_float3_to_float3(v).z);
        float first = r[R_FAC];
        shader_op_tex_white_noise(&ins, &ctx);
        CHECK(r[R_FAC] == first);
        ins.flags = 1u;
        shader_op_tex_white_noise(&ins, &ctx);
        CHECK(r[R_FAC] == hash_float_to_float(w));
        ins.flags = 2u;
        shader_op_tex_white_noise(&ins, &ctx);
        CHECK(r[R_COL + 1] == hash_float2_to_float3(v.x, v.y).y);
        ins.flags = 4u;
        shader_op_tex_white_noise(&ins, &ctx);
        CHECK(r[R_FAC] == hash_float4_to_float(v, w));
        CHECK(r[R_FAC] >= 0.0f && r[R_FAC] <= 1.0f);
    }
}

int main(void)
{
    test_hashes();
    test_perlin_lattice();
    test_perlin_continuity_and_range();
    test_fractal();
    test_ops();
    return test_summary("test_nodes_noise");
}
