/*
 * noise.h — the noise library of the procedural texture nodes, defined as
 * Blender's Cycles defines it so textures line up with Cycles renders:
 *
 *  - integer hashes: Bob Jenkins' lookup3 (hashword with initval 13, 2006,
 *    http://burtleburtle.net/bob/c/lookup3.c) over 1-4 32-bit words, and
 *    hashes of floats by their bit patterns;
 *  - gradient (Perlin) noise in 1-4 dimensions: Perlin 2002, "Improving
 *    Noise" (quintic fade, gradients picked from the hash), in the
 *    arithmetic order of Cycles' x86 SIMD kernels, scaled to about [-1, 1];
 *  - fractal sums of it (Musgrave, "Texturing and Modeling: A Procedural
 *    Approach", Ebert et al., ch. 16): fBM, multifractal, hybrid
 *    multifractal, ridged multifractal and heterogeneous terrain, in
 *    Blender 4.1+'s form (roughness, lacunarity) and in the older forms of
 *    the 3.x Noise Texture and of the 3.x/4.0 Musgrave Texture.
 *
 * Points of any dimension travel as vec4f with a dimension count `dims`
 * (1: x only, 2: x, y, 3: x, y, z, 4: all); unused components are ignored.
 */
#ifndef PHOS_NODES_NOISE_H
#define PHOS_NODES_NOISE_H

#include <stdint.h>
#include <string.h>

#include "util/vec.h"

typedef struct { float x, y; } vec2f;
typedef struct { float x, y, z, w; } vec4f;

static inline vec2f v2f(float x, float y) { vec2f r = {x, y}; return r; }
static inline vec4f v4f(float x, float y, float z, float w) { vec4f r = {x, y, z, w}; return r; }
static inline vec4f v4f_from3(vec3 p, float w) { return v4f(p.x, p.y, p.z, w); }

/* ------------------------------------------------------------ lookup3 */

static inline uint32_t noise_rot(uint32_t x, int k) { return (x << k) | (x >> (32 - k)); }

/* lookup3's mix(): reversibly mixes three words (used between blocks of 3). */
#define NOISE_LOOKUP3_MIX(a, b, c)                      \
    do {                                                \
        a -= c; a ^= noise_rot(c, 4); c += b;           \
        b -= a; b ^= noise_rot(a, 6); a += c;           \
        c -= b; c ^= noise_rot(b, 8); b += a;           \
        a -= c; a ^= noise_rot(c, 16); c += b;          \
        b -= a; b ^= noise_rot(a, 19); a += c;          \
        c -= b; c ^= noise_rot(b, 4); b += a;           \
    } while (0)

/* lookup3's final(): avalanches the last block into c. */
#define NOISE_LOOKUP3_FINAL(a, b, c)                    \
    do {                                                \
        c ^= b; c -= noise_rot(b, 14);                  \
        a ^= c; a -= noise_rot(c, 11);                  \
        b ^= a; b -= noise_rot(a, 25);                  \
        c ^= b; c -= noise_rot(b, 16);                  \
        a ^= c; a -= noise_rot(c, 4);                   \
        b ^= a; b -= noise_rot(a, 14);                  \
        c ^= b; c -= noise_rot(b, 24);                  \
    } while (0)

/* hashword(k, n, 13): every state word starts at 0xdeadbeef + 4n + 13. */
static inline uint32_t hash_uint(uint32_t kx)
{
    uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + (1u << 2) + 13u;
    a += kx;
    NOISE_LOOKUP3_FINAL(a, b, c);
    return c;
}

static inline uint32_t hash_uint2(uint32_t kx, uint32_t ky)
{
    uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + (2u << 2) + 13u;
    b += ky;
    a += kx;
    NOISE_LOOKUP3_FINAL(a, b, c);
    return c;
}

static inline uint32_t hash_uint3(uint32_t kx, uint32_t ky, uint32_t kz)
{
    uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + (3u << 2) + 13u;
    c += kz;
    b += ky;
    a += kx;
    NOISE_LOOKUP3_FINAL(a, b, c);
    return c;
}

/* Four words: one full block of three goes through mix(), the fourth
 * through final(). */
static inline uint32_t hash_uint4(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw)
{
    uint32_t a, b, c;
    a = b = c = 0xdeadbeefu + (4u << 2) + 13u;
    a += kx;
    b += ky;
    c += kz;
    NOISE_LOOKUP3_MIX(a, b, c);
    a += kw;
    NOISE_LOOKUP3_FINAL(a, b, c);
    return c;
}

/* [0, 2^32 − 1] → [0, 1]: n · 2^−32 after rounding n to a float (so the
 * top values round to 1). */
static inline float noise_uint_to_unit(uint32_t n) { return (float)n * (1.0f / 4294967296.0f); }

static inline float hash_uint_to_float(uint32_t kx) { return noise_uint_to_unit(hash_uint(kx)); }
static inline float hash_uint2_to_float(uint32_t kx, uint32_t ky) { return noise_uint_to_unit(hash_uint2(kx, ky)); }
static inline float hash_uint3_to_float(uint32_t kx, uint32_t ky, uint32_t kz)
{
    return noise_uint_to_unit(hash_uint3(kx, ky, kz));
}
static inline float hash_uint4_to_float(uint32_t kx, uint32_t ky, uint32_t kz, uint32_t kw)
{
    return noise_uint_to_unit(hash_uint4(kx, ky, kz, kw));
}

/* --------------------------------------------------- hashes of floats */

static inline uint32_t noise_float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* Floats hash by their bit patterns, so 0 and −0 differ. All in [0, 1]. */
static inline float hash_float_to_float(float k) { return hash_uint_to_float(noise_float_bits(k)); }
static inline float hash_float2_to_float(float x, float y)
{
    return hash_uint2_to_float(noise_float_bits(x), noise_float_bits(y));
}
static inline float hash_float3_to_float(vec3 k)
{
    return hash_uint3_to_float(noise_float_bits(k.x), noise_float_bits(k.y), noise_float_bits(k.z));
}
static inline float hash_float4_to_float(vec3 xyz, float w)
{
    return hash_uint4_to_float(noise_float_bits(xyz.x), noise_float_bits(xyz.y), noise_float_bits(xyz.z),
                               noise_float_bits(w));
}

/* Vector-valued hashes: further components hash the key with an extra
 * constant or with its components permuted (Cycles' choices, shared with
 * its OSL shaders). Every component is in [0, 1]. */
static inline vec2f hash_float_to_float2(float k)
{
    return v2f(hash_float_to_float(k), hash_float2_to_float(k, 1.0f));
}
static inline vec3 hash_float_to_float3(float k)
{
    return v3(hash_float_to_float(k), hash_float2_to_float(k, 1.0f), hash_float2_to_float(k, 2.0f));
}
static inline vec2f hash_float2_to_float2(float x, float y)
{
    return v2f(hash_float2_to_float(x, y), hash_float3_to_float(v3(x, y, 1.0f)));
}
static inline vec3 hash_float2_to_float3(float x, float y)
{
    return v3(hash_float2_to_float(x, y), hash_float3_to_float(v3(x, y, 1.0f)),
              hash_float3_to_float(v3(x, y, 2.0f)));
}
static inline vec2f hash_float3_to_float2(vec3 k)
{
    return v2f(hash_float3_to_float(k), hash_float3_to_float(v3(k.z, k.x, k.y)));
}
static inline vec3 hash_float3_to_float3(vec3 k)
{
    return v3(hash_float3_to_float(k), hash_float4_to_float(k, 1.0f), hash_float4_to_float(k, 2.0f));
}
static inline vec2f hash_float4_to_float2(vec3 xyz, float w)
{
    return v2f(hash_float4_to_float(xyz, w), hash_float4_to_float(v3(xyz.z, xyz.x, w), xyz.y));
}
static inline vec3 hash_float4_to_float3(vec3 xyz, float w)
{
    return v3(hash_float4_to_float(xyz, w), hash_float4_to_float(v3(xyz.z, xyz.x, w), xyz.y),
              hash_float4_to_float(v3(w, xyz.z, xyz.y), xyz.x));
}
static inline vec4f hash_float4_to_float4(vec4f k)
{
    return v4f(hash_float4_to_float(v3(k.x, k.y, k.z), k.w), hash_float4_to_float(v3(k.w, k.x, k.y), k.z),
               hash_float4_to_float(v3(k.z, k.w, k.x), k.y), hash_float4_to_float(v3(k.y, k.z, k.w), k.x));
}

/* The Brick Texture's own integer noise (Blender's, after Hugo Elias'
 * integer noise): n ↦ n(n²·60493 + 19990303) + 1376312589 in 31 bits,
 * mapped to [0, 1). */
static inline float brick_noise(uint32_t n)
{
    n = (n + 1013u) & 0x7fffffffu;
    n = (n >> 13) ^ n;
    uint32_t nn = (n * (n * n * 60493u + 19990303u) + 1376312589u) & 0x7fffffffu;
    return 0.5f * ((float)nn / 1073741824.0f);
}

/* ------------------------------------------------------- Perlin noise */

/* Gradient noise with lattice values 0 (Perlin 2002), unscaled: the raw
 * lattice sums, used by the scaled forms below. */
float perlin_lattice_1d(float x);
float perlin_lattice_2d(float x, float y);
float perlin_lattice_3d(float x, float y, float z);
float perlin_lattice_4d(float x, float y, float z, float w);

/* Signed noise in about [-1, 1]: the lattice noise times Cycles' (OSL's)
 * per-dimension factors 0.2500, 0.6616, 0.9820, 0.8344, with the point
 * first wrapped to (-100000, 100000) on each axis (and offset by 0.5 where
 * |coordinate| >= 10^6) as Blender 4.x/5.x do against float precision
 * loss. */
float perlin_signed_1d(float p);
float perlin_signed_2d(float x, float y);
float perlin_signed_3d(vec3 p);
float perlin_signed_4d(vec3 p, float w);
/* Unsigned noise 0.5·signed + 0.5, in about [0, 1]. */
float perlin_1d(float p);
float perlin_2d(float x, float y);
float perlin_3d(vec3 p);
float perlin_4d(vec3 p, float w);

/* Blender 3.x's (and the 4.0 Musgrave Texture's) signed noise: no wrap,
 * and 0 where the lattice noise is not finite. */
float perlin_signed_legacy_1d(float p);
float perlin_signed_legacy_2d(float x, float y);
float perlin_signed_legacy_3d(vec3 p);
float perlin_signed_legacy_4d(vec3 p, float w);

/* The same by dimension count (1-4; anything else gives 0). */
float perlin_signed(vec4f p, int dims);
float perlin_signed_legacy(vec4f p, int dims);

/* ------------------------------------------------------ fractal noise */

/* Blender 4.1+ (Noise Texture, and Voronoi/Wave detail). `detail` counts
 * octaves beyond the first (its fraction blends one more octave in);
 * octave i has frequency lacunarity^i and amplitude roughness^i. Callers
 * clamp as the node does: detail to [0, 15], roughness to >= 0. */

/* fBM: Σ roughness^i · snoise(lacunarity^i · p); normalize maps it to
 * [0, 1] as 0.5·sum/Σamplitudes + 0.5. */
float noise_fbm(vec4f p, int dims, float detail, float roughness, float lacunarity, int normalize);
/* Multifractal: Π (1 + roughness^i · snoise(lacunarity^i · p)). */
float noise_multi_fractal(vec4f p, int dims, float detail, float roughness, float lacunarity);
/* Heterogeneous terrain: v₀ = offset + snoise(p), each next octave adds
 * roughness^i · (snoise + offset) · v (smooth valleys, rough peaks). */
float noise_hetero_terrain(vec4f p, int dims, float detail, float roughness, float lacunarity, float offset);
/* Hybrid multifractal: octaves weighted by gain · the previous signal,
 * the weight capped at 1, stopping once it falls to 0.001. */
float noise_hybrid_multi_fractal(vec4f p, int dims, float detail, float roughness, float lacunarity,
                                 float offset, float gain);
/* Ridged multifractal: (offset − |snoise|)² per octave, weighted by
 * clamp(gain · previous signal, 0, 1). No fractional octave. */
float noise_ridged_multi_fractal(vec4f p, int dims, float detail, float roughness, float lacunarity,
                                 float offset, float gain);
/* One of the above by enum phos_noise_type (0 for an unknown type). */
float noise_fractal(uint32_t type, vec4f p, int dims, float detail, float roughness, float lacunarity,
                    float offset, float gain, int normalize);

/* Blender 3.x Noise Texture (and Wave detail): fBM of the unsigned legacy
 * noise at lacunarity 2, normalised by Σ amplitudes; octaves clamped to
 * [0, 15] and roughness to [0, 1] here, as 3.x did. */
float noise_fbm_legacy(vec4f p, int dims, float octaves, float roughness);

/* Blender 3.x/4.0 Musgrave Texture (legacy noise): amplitude ratio
 * lacunarity^−H per octave, `octaves` octaves in all (its fraction blends
 * the last); callers clamp as the node does (H >= 1e-5, octaves to
 * [0, 15], lacunarity >= 1e-5). `type` is an enum phos_noise_type. */
float musgrave_fractal(uint32_t type, vec4f p, int dims, float H, float lacunarity, float octaves,
                       float offset, float gain);

#endif /* PHOS_NODES_NOISE_H */
