/*
 * texture_noise.c — the Noise, Musgrave and White Noise Texture nodes
 * (ops PHOS_OP_TEX_NOISE, _TEX_MUSGRAVE, _TEX_WHITE_NOISE; sockets and
 * flags as phos.h lists them), over the noise library of noise.h.
 *
 * Which Blender computes what:
 *  - Blender 2.81-3.6 Noise Texture (flag 16): fBM of the unsigned noise
 *    at lacunarity 2 divided by the sum of the amplitudes; Detail clamped
 *    to [0, 15], Roughness to [0, 1]; no Lacunarity, Normalize or types.
 *  - Blender 4.0 Noise Texture: fBM of the signed noise with Lacunarity,
 *    and with Normalize mapping it to [0, 1] as 0.5·sum/Σamp + 0.5; it
 *    still clamps Roughness to [0, 1] (without flag 16 this op clamps
 *    only to >= 0, as 4.1+, so a 4.0 tree needs its Roughness <= 1).
 *  - Blender 4.1-5.x Noise Texture: the Musgrave types joined it (fBM,
 *    multifractal, hybrid and ridged multifractal, hetero terrain) with
 *    Roughness (the amplitude ratio, Musgrave's lacunarity^−dimension) in
 *    place of Dimension, and Detail counting octaves beyond the first
 *    (Musgrave's Detail counted them all); Detail clamped to [0, 15],
 *    Roughness to >= 0, Normalize for fBM only. Later releases wrap each
 *    noise coordinate to ±100000 (and shift coordinates beyond 10⁶ by half
 *    a cell) against float precision loss; that changes nothing below
 *    |coordinate| = 100000 and is what this op does for all 4.x/5.x.
 *  - Blender 2.81-4.0 Musgrave Texture (TEX_MUSGRAVE): the same five
 *    types with Dimension H (amplitude ratio lacunarity^−H), Detail =
 *    octaves in all; clamps H >= 1e-5, Detail to [0, 15], Lacunarity >=
 *    1e-5.
 *  - White Noise (all versions): the lookup3 hash of the input's bits.
 *
 * Seeds. The noise has no seed, so Distortion and the Color output read it
 * at points moved by fixed pseudo-random offsets in [100, 200]:
 * offset(seed)_i = 100 + 100·hash(seed, i) (1D: 100 + 100·hash(seed)).
 * With d dimensions, distortion uses seeds 0..d−1 (one displacement per
 * axis, all read at the undistorted point) and Color's green and blue use
 * seeds d and d+1; red is Fac.
 */
#include "shading/nodes/noise.h"
#include "shading/nodes/node_util.h"
#include "shading/shader_program.h"

#define NOISE_FLAG_DIMS 7u
#define NOISE_FLAG_NORMALIZE 8u
#define NOISE_FLAG_BLENDER3 16u

/* The dimension count of an op's flags, or 0 if it is not 1-4. */
NODE_INLINE int flag_dims(uint32_t flags)
{
    int d = (int)(flags & NOISE_FLAG_DIMS);
    return d >= 1 && d <= 4 ? d : 0;
}

/* The node's input point: W alone in 1D, the vector's x, y in 2D, x, y, z
 * in 3D, and (x, y, z, W) in 4D; 1D keeps W in x. */
NODE_INLINE vec4f node_point(vec3 v, float w, int dims)
{
    if (dims == 1)
        return v4f(w, 0.0f, 0.0f, 0.0f);
    return v4f(v.x, v.y, dims >= 3 ? v.z : 0.0f, dims == 4 ? w : 0.0f);
}

/* ------------------------------------------------------- Noise Texture */

NODE_INLINE vec4f random_offset(float seed, int dims)
{
    if (dims == 1)
        return v4f(100.0f + hash_float_to_float(seed) * 100.0f, 0.0f, 0.0f, 0.0f);
    float o[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    for (int i = 0; i < dims; i++)
        o[i] = 100.0f + hash_float2_to_float(seed, (float)i) * 100.0f;
    return v4f(o[0], o[1], o[2], o[3]);
}

NODE_INLINE vec4f v4f_add(vec4f a, vec4f b) { return v4f(a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w); }

NODE_INLINE float component(vec4f p, int i) { return i == 0 ? p.x : i == 1 ? p.y : i == 2 ? p.z : p.w; }

/* p += distortion · (snoise(p + offset(0)), …, snoise(p + offset(d−1))). */
NODE_INLINE vec4f distort(vec4f p, int dims, float distortion, int blender3)
{
    float d[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    for (int i = 0; i < dims; i++) {
        vec4f q = v4f_add(p, random_offset((float)i, dims));
        d[i] = (blender3 ? perlin_signed_legacy(q, dims) : perlin_signed(q, dims)) * distortion;
    }
    float out[4];
    for (int i = 0; i < 4; i++)
        out[i] = i < dims ? component(p, i) + d[i] : component(p, i);
    return v4f(out[0], out[1], out[2], out[3]);
}

typedef struct noise_params {
    uint32_t type;
    int dims, normalize, blender3;
    float detail, roughness, lacunarity, offset, gain;
} noise_params;

NODE_INLINE float noise_value(const noise_params *np, vec4f p)
{
    if (np->blender3)
        return noise_fbm_legacy(p, np->dims, np->detail, np->roughness);
    return noise_fractal(np->type, p, np->dims, np->detail, np->roughness, np->lacunarity, np->offset, np->gain,
                         np->normalize);
}

/* in vector(3), w, scale, detail, roughness, lacunarity, offset, gain,
 * distortion; out fac, color(3). */
NODE_VECTOR_CLONES void shader_op_tex_noise(const phos_shader_instruction *ins, shader_context *ctx)
{
    noise_params np;
    np.dims = flag_dims(ins->flags);
    np.type = ins->mode;
    np.normalize = (ins->flags & NOISE_FLAG_NORMALIZE) != 0;
    np.blender3 = (ins->flags & NOISE_FLAG_BLENDER3) != 0;
    if (np.dims == 0) {
        SHADER_OUT(0, 0.0f);
        SHADER_OUT3(1, v3s(0.0f));
        return;
    }
    float scale = SHADER_IN(2);
    np.detail = SHADER_IN(3);
    np.roughness = SHADER_IN(4);
    np.lacunarity = SHADER_IN(5);
    np.offset = SHADER_IN(6);
    np.gain = SHADER_IN(7);
    float distortion = SHADER_IN(8);
    if (!np.blender3) { /* 3.x clamps inside its fBM (noise_fbm_legacy) */
        np.detail = node_clamp(np.detail, 0.0f, 15.0f);
        np.roughness = fmaxf(np.roughness, 0.0f);
    }

    vec4f p = node_point(v3_scale(SHADER_IN3(0), scale), SHADER_IN(1) * scale, np.dims);
    if (distortion != 0.0f)
        p = distort(p, np.dims, distortion, np.blender3);

    float value = noise_value(&np, p);
    SHADER_OUT(0, value);
    if (ins->outputs[1] != PHOS_SHADER_NO_REGISTER) {
        float g = noise_value(&np, v4f_add(p, random_offset((float)np.dims, np.dims)));
        float b = noise_value(&np, v4f_add(p, random_offset((float)(np.dims + 1), np.dims)));
        SHADER_OUT3(1, v3(value, g, b));
    }
}

/* ---------------------------------------------------- Musgrave Texture */

/* in vector(3), w, scale, detail, dimension, lacunarity, offset, gain;
 * out fac. */
NODE_VECTOR_CLONES void shader_op_tex_musgrave(const phos_shader_instruction *ins, shader_context *ctx)
{
    int dims = flag_dims(ins->flags);
    if (dims == 0) {
        SHADER_OUT(0, 0.0f);
        return;
    }
    float scale = SHADER_IN(2);
    float detail = node_clamp(SHADER_IN(3), 0.0f, 15.0f);
    float dimension = fmaxf(SHADER_IN(4), 1e-5f);
    float lacunarity = fmaxf(SHADER_IN(5), 1e-5f);
    float offset = SHADER_IN(6);
    float gain = SHADER_IN(7);
    vec4f p = node_point(v3_scale(SHADER_IN3(0), scale), SHADER_IN(1) * scale, dims);
    SHADER_OUT(0, musgrave_fractal(ins->mode, p, dims, dimension, lacunarity, detail, offset, gain));
}

/* -------------------------------------------------- White Noise Texture */

/* in vector(3), w; out value, color(3). */
NODE_VECTOR_CLONES void shader_op_tex_white_noise(const phos_shader_instruction *ins, shader_context *ctx)
{
    vec3 v = SHADER_IN3(0);
    float w = SHADER_IN(1);
    float value = 0.0f;
    vec3 color = v3(1.0f, 0.0f, 1.0f); /* magenta for a bad dimension count, as Cycles */
    switch (flag_dims(ins->flags)) {
    case 1:
        value = hash_float_to_float(w);
        color = hash_float_to_float3(w);
        break;
    case 2:
        value = hash_float2_to_float(v.x, v.y);
        color = hash_float2_to_float3(v.x, v.y);
        break;
    case 3:
        value = hash_float3_to_float(v);
        color = hash_float3_to_float3(v);
        break;
    case 4:
        value = hash_float4_to_float(v, w);
        color = hash_float4_to_float3(v, w);
        break;
    default:
        break;
    }
    SHADER_OUT(0, value);
    SHADER_OUT3(1, color);
}
