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

typedef struct sampler {
    uint64_t key; /* mix of (seed, pixel, sample) or (seed, stream, photon) */
} sampler;

static inline sampler sampler_for_pixel(uint32_t seed, uint32_t x, uint32_t y, uint32_t sample)
{
    sampler s;
    uint64_t k = mix64((uint64_t)seed * SAMPLER_GAMMA + 0x5eedULL);
    k = mix64(k ^ (((uint64_t)y << 32) | x));
    s.key = mix64(k + (uint64_t)sample * SAMPLER_GAMMA);
    return s;
}

static inline sampler sampler_for_index(uint32_t seed, uint32_t stream, uint64_t index)
{
    sampler s;
    uint64_t k = mix64((uint64_t)seed * SAMPLER_GAMMA + 0x9407ULL);
    k = mix64(k ^ ((uint64_t)stream << 48));
    s.key = mix64(k + index * SAMPLER_GAMMA);
    return s;
}

/* Derives an independent sampler (e.g. for the rays of a final gather). */
static inline sampler sampler_split(const sampler *s, uint32_t stream)
{
    sampler r;
    r.key = mix64(s->key ^ ((uint64_t)stream * 0xd1b54a32d192ed03ULL));
    return r;
}

static inline float sampler_1d(const sampler *s, uint32_t dim)
{
    return u64_to_unit_float(mix64(s->key + (uint64_t)(dim + 1) * SAMPLER_GAMMA));
}

typedef struct float2 {
    float x, y;
} float2;

static inline float2 sampler_2d(const sampler *s, uint32_t dim)
{
    float2 r = {sampler_1d(s, dim), sampler_1d(s, dim + 1)};
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
