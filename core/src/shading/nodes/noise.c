/*
 * noise.c — gradient noise and its fractal sums (noise.h), as Cycles
 * computes them.
 *
 * Perlin noise (Perlin 2002, "Improving Noise"): the point p splits into
 * the lattice cell P = ⌊p⌋ and the offset f = p − P; each corner c of the
 * cell contributes g_c · (f − c), with the gradient g_c picked by hashing
 * c, and the contributions blend with the quintic fade
 * s(t) = 6t⁵ − 15t⁴ + 10t³, so the noise is C² and 0 at lattice points.
 *
 * Float order. Cycles' CPU kernels compute the 2-4D noise with SIMD code
 * whose rounding differs from its scalar fallback; this file follows the
 * AVX2 kernel (the one x86-64 CPUs of the last decade run):
 *  - fade as (t·t)·(t·b) with a = fma(t, 6, −15), b = fma(t, a, 10);
 *  - linear blends as a + t(b − a), along x, then y, then z, and in 4D
 *    along w first (the SSE4.2 kernel and ARM blend w last);
 *  - 1D stays scalar: t·t·t·(t(6t − 15) + 10).
 * Cycles builds its kernels with -ffast-math, so its compiler may fuse
 * some of the other multiply-adds; results can differ in the last bits.
 */
#include "shading/nodes/noise.h"

#include "phos.h"
#include "shading/nodes/node_util.h"

/* ------------------------------------------------------------ helpers */


/* a·b + c rounded once: fmaf where the hardware has it, else in double,
 * whose product of two floats is exact. */
NODE_INLINE float fused_madd(float a, float b, float c)
{
#ifdef FP_FAST_FMAF
    return fmaf(a, b, c);
#else
    return (float)((double)a * (double)b + (double)c);
#endif
}

NODE_INLINE float lerp(float a, float b, float t) { return a + t * (b - a); }

/* Cell index and offset within the cell; the index wraps as x86's
 * conversion gives it (INT_MIN for NaN and beyond ±2^31). */
NODE_INLINE float floorfrac(float x, uint32_t *cell)
{
    float f = floorf(x);
    *cell = (uint32_t)node_float_to_int(f);
    return x - f;
}

NODE_INLINE float fade_scalar(float t) { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }

NODE_INLINE float fade_simd(float t)
{
    float a = fused_madd(t, 6.0f, -15.0f);
    float b = fused_madd(t, a, 10.0f);
    return (t * t) * (t * b);
}

NODE_INLINE float negate_if(float v, uint32_t cond) { return cond ? -v : v; }

/* Gradients (Perlin 2002 §3, as in Cycles/OSL): 1D slopes ±1..±8; 2D the
 * eight (±1, ±2), (±2, ±1); 3D the twelve cube edge midpoints (four
 * repeated); 4D the thirty-two (0, ±1, ±1, ±1) permutations. */
NODE_INLINE float grad1(uint32_t hash, float x)
{
    uint32_t h = hash & 15u;
    float g = (float)(1u + (h & 7u));
    return negate_if(g, h & 8u) * x;
}

NODE_INLINE float grad2(uint32_t hash, float x, float y)
{
    uint32_t h = hash & 7u;
    float u = h < 4u ? x : y;
    float v = 2.0f * (h < 4u ? y : x);
    return negate_if(u, h & 1u) + negate_if(v, h & 2u);
}

/* The 3D gradient without branches, on the bit patterns: u is x for
 * h < 8, else y; v is y for h < 4, x for h = 12 or 14, else z; each is
 * negated (its sign bit flipped, exactly −v) by bits 0 and 1 of h. Masks
 * instead of branches let the eight corners run in vector lanes. */
NODE_INLINE float grad3_select(uint32_t hash, float x, float y, float z)
{
    uint32_t h = hash & 15u;
    uint32_t bx = noise_float_bits(x), by = noise_float_bits(y), bz = noise_float_bits(z);
    uint32_t u_is_x = 0u - (uint32_t)(h < 8u);
    uint32_t v_is_y = 0u - (uint32_t)(h < 4u);
    uint32_t v_is_x = 0u - (uint32_t)(h == 12u || h == 14u);
    uint32_t u = (bx & u_is_x) | (by & ~u_is_x);
    uint32_t vt = (bx & v_is_x) | (bz & ~v_is_x);
    uint32_t v = (by & v_is_y) | (vt & ~v_is_y);
    u ^= (h & 1u) << 31;
    v ^= (h & 2u) << 30;
    float fu, fv;
    memcpy(&fu, &u, sizeof fu);
    memcpy(&fv, &v, sizeof fv);
    return fu + fv;
}

NODE_INLINE float grad4(uint32_t hash, float x, float y, float z, float w)
{
    uint32_t h = hash & 31u;
    float u = h < 24u ? x : y;
    float v = h < 16u ? y : z;
    float s = h < 8u ? z : w;
    return negate_if(u, h & 1u) + negate_if(v, h & 2u) + negate_if(s, h & 4u);
}

/* ------------------------------------------------ lattice noise, 1D-4D */

NODE_INLINE float perlin_lattice_1d_inline(float x)
{
    uint32_t X;
    float fx = floorfrac(x, &X);
    float u = fade_scalar(fx);
    return lerp(grad1(hash_uint(X), fx), grad1(hash_uint(X + 1u), fx - 1.0f), u);
}

NODE_INLINE float perlin_lattice_2d_inline(float x, float y)
{
    uint32_t X, Y;
    float fx = floorfrac(x, &X), fy = floorfrac(y, &Y);
    float u = fade_simd(fx), v = fade_simd(fy);
    float g00 = grad2(hash_uint2(X, Y), fx, fy);
    float g01 = grad2(hash_uint2(X, Y + 1u), fx, fy - 1.0f);
    float g10 = grad2(hash_uint2(X + 1u, Y), fx - 1.0f, fy);
    float g11 = grad2(hash_uint2(X + 1u, Y + 1u), fx - 1.0f, fy - 1.0f);
    return lerp(lerp(g00, g10, u), lerp(g01, g11, u), v);
}

/* Trilinear blend of corner values c[x][y][z]: x, then y, then z. */
NODE_INLINE float blend3(const float c[2][2][2], float u, float v, float w)
{
    float s00 = lerp(c[0][0][0], c[1][0][0], u);
    float s01 = lerp(c[0][0][1], c[1][0][1], u);
    float s10 = lerp(c[0][1][0], c[1][1][0], u);
    float s11 = lerp(c[0][1][1], c[1][1][1], u);
    return lerp(lerp(s00, s10, v), lerp(s01, s11, v), w);
}

/* The eight corners' hashes and gradients are computed lane by lane over
 * arrays, the way Cycles' SIMD kernel does, so that the compiler keeps
 * them in vector registers (lookup3 needs only add, xor and rotate); the
 * values are the same as corner by corner. */
NODE_INLINE float perlin_lattice_3d_inline(float x, float y, float z)
{
    uint32_t X, Y, Z;
    float fx = floorfrac(x, &X), fy = floorfrac(y, &Y), fz = floorfrac(z, &Z);
    uint32_t h[8];
    float dx[8], dy[8], dz[8], g[8];
    for (uint32_t n = 0; n < 8; n++) { /* corner n = (i, j, k) = bits 2, 1, 0 */
        uint32_t i = n >> 2, j = (n >> 1) & 1u, k = n & 1u;
        uint32_t a, b, c;
        a = b = c = 0xdeadbeefu + (3u << 2) + 13u;
        c += Z + k;
        b += Y + j;
        a += X + i;
        NOISE_LOOKUP3_FINAL(a, b, c);
        h[n] = c;
        dx[n] = fx - (float)i;
        dy[n] = fy - (float)j;
        dz[n] = fz - (float)k;
    }
    for (uint32_t n = 0; n < 8; n++)
        g[n] = grad3_select(h[n], dx[n], dy[n], dz[n]);
    float c[2][2][2];
    memcpy(c, g, sizeof c);
    return blend3(c, fade_simd(fx), fade_simd(fy), fade_simd(fz));
}

NODE_INLINE float perlin_lattice_4d_inline(float x, float y, float z, float w)
{
    uint32_t X, Y, Z, W;
    float fx = floorfrac(x, &X), fy = floorfrac(y, &Y), fz = floorfrac(z, &Z), fw = floorfrac(w, &W);
    float s = fade_simd(fw);
    float c[2][2][2];
    for (uint32_t i = 0; i < 2; i++)
        for (uint32_t j = 0; j < 2; j++)
            for (uint32_t k = 0; k < 2; k++) {
                float dx = fx - (float)i, dy = fy - (float)j, dz = fz - (float)k;
                float g0 = grad4(hash_uint4(X + i, Y + j, Z + k, W), dx, dy, dz, fw);
                float g1 = grad4(hash_uint4(X + i, Y + j, Z + k, W + 1u), dx, dy, dz, fw - 1.0f);
                c[i][j][k] = lerp(g0, g1, s); /* w first, as the AVX2 kernel */
            }
    return blend3(c, fade_simd(fx), fade_simd(fy), fade_simd(fz));
}

/* ------------------------------------------------ scaled signed noise */

/* Wrap a coordinate to (−10⁵, 10⁵), shifting those beyond 10⁶ by half a
 * cell so the wrapped lattice does not line up with the original. */
NODE_INLINE float wrap_coordinate(float p)
{
    if (fabsf(p) < 100000.0f) /* fmodf is then p itself, exactly: skip the call */
        return p;
    float correction = fabsf(p) >= 1000000.0f ? 0.5f : 0.0f;
    return fmodf(p, 100000.0f) + correction;
}

NODE_INLINE float finite_or_zero(float x) { return isfinite(x) ? x : 0.0f; }

#define NOISE_SCALE_1D 0.2500f
#define NOISE_SCALE_2D 0.6616f
#define NOISE_SCALE_3D 0.9820f
#define NOISE_SCALE_4D 0.8344f

NODE_INLINE float perlin_signed_1d_inline(float p) { return NOISE_SCALE_1D * perlin_lattice_1d_inline(wrap_coordinate(p)); }

NODE_INLINE float perlin_signed_2d_inline(float x, float y)
{
    return NOISE_SCALE_2D * perlin_lattice_2d_inline(wrap_coordinate(x), wrap_coordinate(y));
}

NODE_INLINE float perlin_signed_3d_inline(vec3 p)
{
    return NOISE_SCALE_3D * perlin_lattice_3d_inline(wrap_coordinate(p.x), wrap_coordinate(p.y), wrap_coordinate(p.z));
}

NODE_INLINE float perlin_signed_4d_inline(vec3 p, float w)
{
    return NOISE_SCALE_4D * perlin_lattice_4d_inline(wrap_coordinate(p.x), wrap_coordinate(p.y), wrap_coordinate(p.z),
                                              wrap_coordinate(w));
}

NODE_INLINE float perlin_1d_inline(float p) { return 0.5f * perlin_signed_1d_inline(p) + 0.5f; }
NODE_INLINE float perlin_2d_inline(float x, float y) { return 0.5f * perlin_signed_2d_inline(x, y) + 0.5f; }
NODE_INLINE float perlin_3d_inline(vec3 p) { return 0.5f * perlin_signed_3d_inline(p) + 0.5f; }
NODE_INLINE float perlin_4d_inline(vec3 p, float w) { return 0.5f * perlin_signed_4d_inline(p, w) + 0.5f; }

NODE_INLINE float perlin_signed_legacy_1d_inline(float p) { return NOISE_SCALE_1D * finite_or_zero(perlin_lattice_1d_inline(p)); }

NODE_INLINE float perlin_signed_legacy_2d_inline(float x, float y)
{
    return NOISE_SCALE_2D * finite_or_zero(perlin_lattice_2d_inline(x, y));
}

NODE_INLINE float perlin_signed_legacy_3d_inline(vec3 p)
{
    return NOISE_SCALE_3D * finite_or_zero(perlin_lattice_3d_inline(p.x, p.y, p.z));
}

NODE_INLINE float perlin_signed_legacy_4d_inline(vec3 p, float w)
{
    return NOISE_SCALE_4D * finite_or_zero(perlin_lattice_4d_inline(p.x, p.y, p.z, w));
}

NODE_INLINE float perlin_signed_inline(vec4f p, int dims)
{
    switch (dims) {
    case 1: return perlin_signed_1d_inline(p.x);
    case 2: return perlin_signed_2d_inline(p.x, p.y);
    case 3: return perlin_signed_3d_inline(v3(p.x, p.y, p.z));
    case 4: return perlin_signed_4d_inline(v3(p.x, p.y, p.z), p.w);
    default: return 0.0f;
    }
}

NODE_INLINE float perlin_signed_legacy_inline(vec4f p, int dims)
{
    switch (dims) {
    case 1: return perlin_signed_legacy_1d_inline(p.x);
    case 2: return perlin_signed_legacy_2d_inline(p.x, p.y);
    case 3: return perlin_signed_legacy_3d_inline(v3(p.x, p.y, p.z));
    case 4: return perlin_signed_legacy_4d_inline(v3(p.x, p.y, p.z), p.w);
    default: return 0.0f;
    }
}

/* The entry points other files call, each compiled for the CPU's vector
 * width (node_util.h); within this file the inline forms above are used,
 * so a fractal sum's octaves run inside one compiled copy. */
NODE_VECTOR_CLONES float perlin_lattice_1d(float x) { return perlin_lattice_1d_inline(x); }
NODE_VECTOR_CLONES float perlin_lattice_2d(float x, float y) { return perlin_lattice_2d_inline(x, y); }
NODE_VECTOR_CLONES float perlin_lattice_3d(float x, float y, float z) { return perlin_lattice_3d_inline(x, y, z); }
NODE_VECTOR_CLONES float perlin_lattice_4d(float x, float y, float z, float w) { return perlin_lattice_4d_inline(x, y, z, w); }
NODE_VECTOR_CLONES float perlin_signed_1d(float p) { return perlin_signed_1d_inline(p); }
NODE_VECTOR_CLONES float perlin_signed_2d(float x, float y) { return perlin_signed_2d_inline(x, y); }
NODE_VECTOR_CLONES float perlin_signed_3d(vec3 p) { return perlin_signed_3d_inline(p); }
NODE_VECTOR_CLONES float perlin_signed_4d(vec3 p, float w) { return perlin_signed_4d_inline(p, w); }
NODE_VECTOR_CLONES float perlin_1d(float p) { return perlin_1d_inline(p); }
NODE_VECTOR_CLONES float perlin_2d(float x, float y) { return perlin_2d_inline(x, y); }
NODE_VECTOR_CLONES float perlin_3d(vec3 p) { return perlin_3d_inline(p); }
NODE_VECTOR_CLONES float perlin_4d(vec3 p, float w) { return perlin_4d_inline(p, w); }
NODE_VECTOR_CLONES float perlin_signed_legacy_1d(float p) { return perlin_signed_legacy_1d_inline(p); }
NODE_VECTOR_CLONES float perlin_signed_legacy_2d(float x, float y) { return perlin_signed_legacy_2d_inline(x, y); }
NODE_VECTOR_CLONES float perlin_signed_legacy_3d(vec3 p) { return perlin_signed_legacy_3d_inline(p); }
NODE_VECTOR_CLONES float perlin_signed_legacy_4d(vec3 p, float w) { return perlin_signed_legacy_4d_inline(p, w); }
NODE_VECTOR_CLONES float perlin_signed(vec4f p, int dims) { return perlin_signed_inline(p, dims); }
NODE_VECTOR_CLONES float perlin_signed_legacy(vec4f p, int dims) { return perlin_signed_legacy_inline(p, dims); }

/* ----------------------------------------------------- fractal noise */

NODE_INLINE vec4f v4f_scale(vec4f p, float s) { return v4f(p.x * s, p.y * s, p.z * s, p.w * s); }

/* detail's integer part, the loop bound of the octaves (callers clamp
 * detail to [0, 15]; NaN and out-of-range values give 0, defined). */
NODE_INLINE int whole_octaves(float detail) { return detail >= 0.0f && detail < 1024.0f ? (int)detail : 0; }

NODE_VECTOR_CLONES float noise_fbm(vec4f p, int dims, float detail, float roughness, float lacunarity, int normalize)
{
    float fscale = 1.0f, amp = 1.0f, maxamp = 0.0f, sum = 0.0f;
    int n = whole_octaves(detail);
    for (int i = 0; i <= n; i++) {
        float t = perlin_signed_inline(v4f_scale(p, fscale), dims);
        sum += t * amp;
        maxamp += amp;
        amp *= roughness;
        fscale *= lacunarity;
    }
    float rmd = detail - floorf(detail);
    if (rmd != 0.0f) {
        float t = perlin_signed_inline(v4f_scale(p, fscale), dims);
        float sum2 = sum + t * amp;
        return normalize ? lerp(0.5f * sum / maxamp + 0.5f, 0.5f * sum2 / (maxamp + amp) + 0.5f, rmd)
                         : lerp(sum, sum2, rmd);
    }
    return normalize ? 0.5f * sum / maxamp + 0.5f : sum;
}

NODE_VECTOR_CLONES float noise_multi_fractal(vec4f p, int dims, float detail, float roughness, float lacunarity)
{
    float value = 1.0f, pwr = 1.0f;
    int n = whole_octaves(detail);
    for (int i = 0; i <= n; i++) {
        value *= pwr * perlin_signed_inline(p, dims) + 1.0f;
        pwr *= roughness;
        p = v4f_scale(p, lacunarity);
    }
    float rmd = detail - floorf(detail);
    if (rmd != 0.0f)
        value *= rmd * pwr * perlin_signed_inline(p, dims) + 1.0f;
    return value;
}

NODE_VECTOR_CLONES float noise_hetero_terrain(vec4f p, int dims, float detail, float roughness, float lacunarity, float offset)
{
    float pwr = roughness;
    float value = offset + perlin_signed_inline(p, dims); /* the first octave is unscaled */
    p = v4f_scale(p, lacunarity);
    int n = whole_octaves(detail);
    for (int i = 1; i <= n; i++) {
        float increment = (perlin_signed_inline(p, dims) + offset) * pwr * value;
        value += increment;
        pwr *= roughness;
        p = v4f_scale(p, lacunarity);
    }
    float rmd = detail - floorf(detail);
    if (rmd != 0.0f) {
        float increment = (perlin_signed_inline(p, dims) + offset) * pwr * value;
        value += rmd * increment;
    }
    return value;
}

NODE_VECTOR_CLONES float noise_hybrid_multi_fractal(vec4f p, int dims, float detail, float roughness, float lacunarity,
                                 float offset, float gain)
{
    float pwr = 1.0f, value = 0.0f, weight = 1.0f;
    int n = whole_octaves(detail);
    for (int i = 0; weight > 0.001f && i <= n; i++) {
        if (weight > 1.0f)
            weight = 1.0f;
        float signal = (perlin_signed_inline(p, dims) + offset) * pwr;
        pwr *= roughness;
        value += weight * signal;
        weight *= gain * signal;
        p = v4f_scale(p, lacunarity);
    }
    float rmd = detail - floorf(detail);
    if (rmd != 0.0f && weight > 0.001f) {
        if (weight > 1.0f)
            weight = 1.0f;
        float signal = (perlin_signed_inline(p, dims) + offset) * pwr;
        value += rmd * weight * signal;
    }
    return value;
}

NODE_INLINE float saturate(float x) { return node_clamp(x, 0.0f, 1.0f); }

NODE_VECTOR_CLONES float noise_ridged_multi_fractal(vec4f p, int dims, float detail, float roughness, float lacunarity,
                                 float offset, float gain)
{
    float pwr = roughness;
    float signal = offset - fabsf(perlin_signed_inline(p, dims));
    signal *= signal;
    float value = signal;
    int n = whole_octaves(detail);
    for (int i = 1; i <= n; i++) {
        p = v4f_scale(p, lacunarity);
        float weight = saturate(signal * gain);
        signal = offset - fabsf(perlin_signed_inline(p, dims));
        signal *= signal;
        signal *= weight;
        value += signal * pwr;
        pwr *= roughness;
    }
    return value;
}

NODE_VECTOR_CLONES float noise_fractal(uint32_t type, vec4f p, int dims, float detail, float roughness, float lacunarity,
                    float offset, float gain, int normalize)
{
    switch (type) {
    case PHOS_NOISE_FBM: return noise_fbm(p, dims, detail, roughness, lacunarity, normalize);
    case PHOS_NOISE_MULTIFRACTAL: return noise_multi_fractal(p, dims, detail, roughness, lacunarity);
    case PHOS_NOISE_HYBRID_MULTIFRACTAL:
        return noise_hybrid_multi_fractal(p, dims, detail, roughness, lacunarity, offset, gain);
    case PHOS_NOISE_RIDGED_MULTIFRACTAL:
        return noise_ridged_multi_fractal(p, dims, detail, roughness, lacunarity, offset, gain);
    case PHOS_NOISE_HETERO_TERRAIN: return noise_hetero_terrain(p, dims, detail, roughness, lacunarity, offset);
    default: return 0.0f;
    }
}

/* ------------------------------------------ Blender 3.x Noise Texture */

NODE_INLINE float perlin_unsigned_legacy(vec4f p, int dims) { return 0.5f * perlin_signed_legacy_inline(p, dims) + 0.5f; }

NODE_VECTOR_CLONES float noise_fbm_legacy(vec4f p, int dims, float octaves, float roughness)
{
    float fscale = 1.0f, amp = 1.0f, maxamp = 0.0f, sum = 0.0f;
    octaves = node_clamp(octaves, 0.0f, 15.0f);
    roughness = node_clamp(roughness, 0.0f, 1.0f);
    int n = whole_octaves(octaves);
    for (int i = 0; i <= n; i++) {
        float t = perlin_unsigned_legacy(v4f_scale(p, fscale), dims);
        sum += t * amp;
        maxamp += amp;
        amp *= roughness;
        fscale *= 2.0f;
    }
    float rmd = octaves - floorf(octaves);
    if (rmd != 0.0f) {
        float t = perlin_unsigned_legacy(v4f_scale(p, fscale), dims);
        float sum2 = sum + t * amp;
        sum /= maxamp;
        sum2 /= maxamp + amp;
        return (1.0f - rmd) * sum + rmd * sum2;
    }
    return sum / maxamp;
}

/* ------------------------------------- Blender 3.x/4.0 Musgrave Texture */

/* fBM: Σ_{i<octaves} lacunarity^(−iH) · snoise(lacunarity^i · p). */
NODE_INLINE float musgrave_fbm(vec4f p, int dims, float H, float lacunarity, float octaves)
{
    float value = 0.0f, pwr = 1.0f, pwHL = powf(lacunarity, -H);
    int n = whole_octaves(octaves);
    for (int i = 0; i < n; i++) {
        value += perlin_signed_legacy_inline(p, dims) * pwr;
        pwr *= pwHL;
        p = v4f_scale(p, lacunarity);
    }
    float rmd = octaves - floorf(octaves);
    if (rmd != 0.0f)
        value += rmd * perlin_signed_legacy_inline(p, dims) * pwr;
    return value;
}

NODE_INLINE float musgrave_multi_fractal(vec4f p, int dims, float H, float lacunarity, float octaves)
{
    float value = 1.0f, pwr = 1.0f, pwHL = powf(lacunarity, -H);
    int n = whole_octaves(octaves);
    for (int i = 0; i < n; i++) {
        value *= pwr * perlin_signed_legacy_inline(p, dims) + 1.0f;
        pwr *= pwHL;
        p = v4f_scale(p, lacunarity);
    }
    float rmd = octaves - floorf(octaves);
    if (rmd != 0.0f)
        value *= rmd * pwr * perlin_signed_legacy_inline(p, dims) + 1.0f;
    return value;
}

NODE_INLINE float musgrave_hetero_terrain(vec4f p, int dims, float H, float lacunarity, float octaves, float offset)
{
    float pwHL = powf(lacunarity, -H);
    float pwr = pwHL;
    float value = offset + perlin_signed_legacy_inline(p, dims);
    p = v4f_scale(p, lacunarity);
    int n = whole_octaves(octaves);
    for (int i = 1; i < n; i++) {
        float increment = (perlin_signed_legacy_inline(p, dims) + offset) * pwr * value;
        value += increment;
        pwr *= pwHL;
        p = v4f_scale(p, lacunarity);
    }
    float rmd = octaves - floorf(octaves);
    if (rmd != 0.0f) {
        float increment = (perlin_signed_legacy_inline(p, dims) + offset) * pwr * value;
        value += rmd * increment;
    }
    return value;
}

NODE_INLINE float musgrave_hybrid_multi_fractal(vec4f p, int dims, float H, float lacunarity, float octaves,
                                           float offset, float gain)
{
    float pwHL = powf(lacunarity, -H);
    float pwr = 1.0f, value = 0.0f, weight = 1.0f;
    int n = whole_octaves(octaves);
    for (int i = 0; weight > 0.001f && i < n; i++) {
        if (weight > 1.0f)
            weight = 1.0f;
        float signal = (perlin_signed_legacy_inline(p, dims) + offset) * pwr;
        pwr *= pwHL;
        value += weight * signal;
        weight *= gain * signal;
        p = v4f_scale(p, lacunarity);
    }
    float rmd = octaves - floorf(octaves);
    if (rmd != 0.0f && weight > 0.001f) {
        if (weight > 1.0f)
            weight = 1.0f;
        float signal = (perlin_signed_legacy_inline(p, dims) + offset) * pwr;
        value += rmd * weight * signal;
    }
    return value;
}

NODE_INLINE float musgrave_ridged_multi_fractal(vec4f p, int dims, float H, float lacunarity, float octaves,
                                           float offset, float gain)
{
    float pwHL = powf(lacunarity, -H);
    float pwr = pwHL;
    float signal = offset - fabsf(perlin_signed_legacy_inline(p, dims));
    signal *= signal;
    float value = signal;
    int n = whole_octaves(octaves);
    for (int i = 1; i < n; i++) {
        p = v4f_scale(p, lacunarity);
        float weight = saturate(signal * gain);
        signal = offset - fabsf(perlin_signed_legacy_inline(p, dims));
        signal *= signal;
        signal *= weight;
        value += signal * pwr;
        pwr *= pwHL;
    }
    return value;
}

NODE_VECTOR_CLONES float musgrave_fractal(uint32_t type, vec4f p, int dims, float H, float lacunarity, float octaves, float offset,
                       float gain)
{
    switch (type) {
    case PHOS_NOISE_FBM: return musgrave_fbm(p, dims, H, lacunarity, octaves);
    case PHOS_NOISE_MULTIFRACTAL: return musgrave_multi_fractal(p, dims, H, lacunarity, octaves);
    case PHOS_NOISE_HYBRID_MULTIFRACTAL:
        return musgrave_hybrid_multi_fractal(p, dims, H, lacunarity, octaves, offset, gain);
    case PHOS_NOISE_RIDGED_MULTIFRACTAL:
        return musgrave_ridged_multi_fractal(p, dims, H, lacunarity, octaves, offset, gain);
    case PHOS_NOISE_HETERO_TERRAIN: return musgrave_hetero_terrain(p, dims, H, lacunarity, octaves, offset);
    default: return 0.0f;
    }
}
