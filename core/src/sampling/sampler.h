/*
 * sampler.h — counter-based random numbers.
 *
 * Every random number is a pure function of (seed, pixel, sample index,
 * dimension), or (seed, photon index, dimension): no generator state is
 * carried between pixels, so an image does not depend on the thread count,
 * tile order or border region (the pbrt-v4 approach, Hash(pixel, seed)).
 *
 * Dimensions are allocated at fixed offsets per bounce (DIM_BOUNCE_BASE +
 * depth * DIM_BOUNCE_STRIDE) so that optional samples never shift later ones.
 */
#ifndef PHOS_SAMPLER_H
#define PHOS_SAMPLER_H

#include <stdint.h>

/* "lowbias32" integer finaliser (C. Wellons, 2020): full avalanche, cheap.
 * Used for hashing small keys; random numbers come from mix64 below. */
static inline uint32_t hash_u32(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

static inline uint32_t hash_combine(uint32_t seed, uint32_t v)
{
    return hash_u32(seed ^ (v + 0x9e3779b9U + (seed << 6) + (seed >> 2)));
}

/* SplitMix64's finaliser (Steele, Lea & Flood 2014, "Fast splittable
 * pseudorandom number generators"; Stafford's Mix13 constants): a bijection
 * of 64-bit integers with full avalanche. Counter-based use (key + γ·i,
 * then mix) is SplitMix64 itself, which passes BigCrush. */
static inline uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

#define SAMPLER_GAMMA 0x9e3779b97f4a7c15ULL /* 2^64 / golden ratio, odd */

/* Uniform float in [0, 1) from the top 24 bits. */
static inline float u32_to_unit_float(uint32_t x) { return (float)(x >> 8) * (1.0f / 16777216.0f); }
static inline float u64_to_unit_float(uint64_t x) { return (float)(x >> 40) * (1.0f / 16777216.0f); }

/*
 * Owen-scrambled Sobol points with per-dimension padding (Burley 2020,
 * "Practical Hash-based Owen Scrambling", JCGT 9(4); docs/algorithms.md §6):
 * every 1-D or 2-D request ("dimension set") shuffles the sample index and
 * scrambles the first two Sobol dimensions with seeds hashed from the
 * pixel and the dimension, so each set is stratified over a pixel's
 * samples (a (0,2)-sequence for power-of-two counts) while different sets
 * stay decorrelated. Everything is still a pure function of (seed, pixel,
 * sample, dimension).
 */
static inline uint32_t reverse_bits32(uint32_t x)
{
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
    return (x >> 16) | (x << 16);
}

/* Nested uniform (Owen) scramble of a 32-bit fixed-point value, as a hash
 * on the reversed bits (Vegdahl's constants for Laine–Karras, as in Cycles
 * and pbrt-v4). */
static inline uint32_t owen_scramble(uint32_t x, uint32_t seed)
{
    x = reverse_bits32(x);
    x ^= x * 0x3d20adeaU;
    x += seed;
    x *= (seed >> 16) | 1U;
    x ^= x * 0x05526c56U;
    x ^= x * 0x53a22864U;
    return reverse_bits32(x);
}

/* Sobol dimension 1 (dimension 0 is the bit reversal): its direction
 * numbers are the rows of Pascal's triangle mod 2, v_{k+1} = v_k ^ (v_k >> 1),
 * so bit m (from the top) of v_k is C(k, m) mod 2, which by Lucas' theorem
 * is 1 exactly when m's bits are a subset of k's. The product with index i
 * is then, before the bit reversal, bit m = XOR of i's bits k ⊇ m: a
 * superset transform over the five bits of the position, done for all 32
 * positions at once in five shift-and-mask steps instead of a loop over
 * i's bits, whose branches the owen-scrambled indices make unpredictable. */
static inline uint32_t sobol_dim1(uint32_t i)
{
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0f0f0f0fu;
    i ^= (i >> 8) & 0x00ff00ffu;
    i ^= (i >> 16) & 0x0000ffffu;
    return reverse_bits32(i);
}

typedef struct sampler {
    uint64_t key;    /* mix of (seed, pixel) or (seed, stream) */
    uint32_t index;  /* sample index within the pixel, or photon path index */
    uint32_t qmc;    /* 1: scrambled Sobol; 0: independent numbers (statistical tests) */
} sampler;

static inline sampler sampler_for_pixel(uint32_t seed, uint32_t x, uint32_t y, uint32_t sample)
{
    sampler s;
    uint64_t k = mix64((uint64_t)seed * SAMPLER_GAMMA + 0x5eedULL);
    s.key = mix64(k ^ (((uint64_t)y << 32) | x));
    s.index = sample;
    s.qmc = 1;
    return s;
}

/* Photon path `index` of a stream: low-discrepancy over the paths. Indices
 * beyond 2^32 start a fresh sequence. */
static inline sampler sampler_for_index(uint32_t seed, uint32_t stream, uint64_t index)
{
    sampler s;
    uint64_t k = mix64((uint64_t)seed * SAMPLER_GAMMA + 0x9407ULL);
    s.key = mix64(k ^ ((uint64_t)stream << 48) ^ (index >> 32));
    s.index = (uint32_t)index;
    s.qmc = 1;
    return s;
}

/* Independent uniform numbers for (seed, stream, index): what tests that
 * assume independent samples (chi-square) draw from. */
static inline sampler sampler_independent(uint32_t seed, uint32_t stream, uint64_t index)
{
    sampler s;
    uint64_t k = mix64((uint64_t)seed * SAMPLER_GAMMA + 0x1d3eULL);
    k = mix64(k ^ ((uint64_t)stream << 48));
    s.key = mix64(k + index * SAMPLER_GAMMA);
    s.index = 0;
    s.qmc = 0;
    return s;
}

/* Derives an independent set of dimensions (e.g. for the rays of a final
 * gather): same sample index, other scrambles. */
static inline sampler sampler_split(const sampler *s, uint32_t stream)
{
    sampler r = *s;
    r.key = mix64(s->key ^ ((uint64_t)stream * 0xd1b54a32d192ed03ULL));
    return r;
}

static inline uint32_t sampler_dimension_seed(const sampler *s, uint32_t dim)
{
    return (uint32_t)(mix64(s->key + (uint64_t)(dim + 1) * SAMPLER_GAMMA) >> 32);
}

static inline float sampler_1d(const sampler *s, uint32_t dim)
{
    if (!s->qmc)
        return u64_to_unit_float(mix64(s->key + (uint64_t)(dim + 1) * SAMPLER_GAMMA));
    uint32_t seed = sampler_dimension_seed(s, dim);
    uint32_t i = owen_scramble(s->index, seed ^ 0xa511e9b3U);
    return u32_to_unit_float(owen_scramble(reverse_bits32(i), seed ^ 0x63d83595U));
}

typedef struct float2 {
    float x, y;
} float2;

static inline float2 sampler_2d(const sampler *s, uint32_t dim)
{
    float2 r;
    if (!s->qmc) {
        r.x = sampler_1d(s, dim);
        r.y = sampler_1d(s, dim + 1);
        return r;
    }
    uint32_t seed = sampler_dimension_seed(s, dim);
    uint32_t i = owen_scramble(s->index, seed ^ 0xa511e9b3U);
    r.x = u32_to_unit_float(owen_scramble(reverse_bits32(i), seed ^ 0x63d83595U));
    r.y = u32_to_unit_float(owen_scramble(sobol_dim1(i), seed ^ 0x2d358dccU));
    return r;
}

enum {
    DIM_FILM = 0,          /* 2: position in the pixel filter */
    DIM_LENS = 2,          /* 2: aperture */
    DIM_BOUNCE_BASE = 4,
    DIM_LIGHT_PICK = 0,    /* 1: which light for next-event estimation */
    DIM_LIGHT_POINT = 1,   /* 2: where on the light */
    DIM_BSDF_PICK = 3,     /* 1: which closure */
    DIM_BSDF_DIR = 4,      /* 2: direction from that closure */
    DIM_ROULETTE = 6,      /* 1: Russian roulette */
    DIM_SHADOW = 7,        /* 1: spare, e.g. stochastic transparency */
    DIM_BOUNCE_STRIDE = 8
};

static inline uint32_t dim_bounce(uint32_t depth, uint32_t offset)
{
    return DIM_BOUNCE_BASE + depth * DIM_BOUNCE_STRIDE + offset;
}

#endif /* PHOS_SAMPLER_H */
