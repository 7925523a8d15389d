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

#include "phos.h"

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

#include "sampling/sobol.h"

/* What a sampler's numbers are (enum phos_sampler's values; docs/algorithms.md §6):
 *   RANDOM      independent numbers for every (pixel, sample, dimension);
 *   STRATIFIED  over a pixel's N samples, each 1-D set in N strata and each
 *               2-D set multi-jittered (Chiu, Shirley & Wang 1994): one
 *               point per cell of an m×n grid, m·n = N, and one per row and
 *               column of the N×N fine grid, so a Latin hypercube as well;
 *   HALTON      the Halton points of bases 2 and 3 (1-D: 2), digits scrambled
 *               by random permutations, each pixel starting its run at its
 *               own offset into the sequence;
 *   SOBOL       Owen-scrambled Sobol (sobol.h). */
enum sampler_kind {
    SAMPLER_RANDOM = PHOS_SAMPLER_RANDOM,
    SAMPLER_STRATIFIED = PHOS_SAMPLER_STRATIFIED,
    SAMPLER_HALTON = PHOS_SAMPLER_HALTON,
    SAMPLER_SOBOL = PHOS_SAMPLER_SOBOL
};

/* Every kind pads: each 1-D or 2-D request ("dimension set") draws from its
 * own scramble of the sequence, seeded by hashing the key with the
 * dimension, so the sets are decorrelated and each is as well distributed
 * over a pixel's samples as the kind makes it (Cycles and pbrt-v4 pad the
 * same way; docs/algorithms.md §6). */
typedef struct sampler {
    uint64_t key;    /* mix of (seed, pixel) or (seed, stream) */
    uint32_t index;  /* sample index within the pixel, or photon path index */
    uint32_t kind;   /* enum sampler_kind */
    uint32_t count;  /* STRATIFIED: the samples the strata are made for (a pixel's samples) */
} sampler;

/* Sample `sample` of `count` of pixel (x, y). */
static inline sampler sampler_for_pixel(uint32_t kind, uint32_t seed, uint32_t x, uint32_t y, uint32_t sample,
                                        uint32_t count)
{
    sampler s;
    uint64_t k = mix64((uint64_t)seed * SAMPLER_GAMMA + 0x5eedULL);
    s.key = mix64(k ^ (((uint64_t)y << 32) | x));
    s.index = sample;
    s.kind = kind;
    s.count = count ? count : 1;
    return s;
}

/* Photon paths of a STRATIFIED stream are stratified in blocks of this
 * many: the count of paths a map takes is not known before it is full. */
#define SAMPLER_PATH_STRATA 4096u

/* Photon path `index` of a stream: well distributed over the paths.
 * Indices beyond 2^32 start a fresh sequence. */
static inline sampler sampler_for_index(uint32_t kind, uint32_t seed, uint32_t stream, uint64_t index)
{
    sampler s;
    uint64_t k = mix64((uint64_t)seed * SAMPLER_GAMMA + 0x9407ULL);
    s.key = mix64(k ^ ((uint64_t)stream << 48) ^ (index >> 32));
    s.index = (uint32_t)index;
    s.kind = kind;
    s.count = SAMPLER_PATH_STRATA;
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
    s.kind = SAMPLER_RANDOM;
    s.count = 1;
    return s;
}

/* Derives an independent set of dimensions (e.g. for the rays of a final
 * gather): same sample index and kind, other scrambles. */
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

/* RANDOM: SplitMix64 at the counter key + index·C + (dimension + 1)·γ, C an
 * odd constant unrelated to γ so that no two (index, dimension) of a pixel
 * share a counter. */
static inline uint64_t sampler_random_bits(const sampler *s, uint32_t dim)
{
    return mix64(s->key + (uint64_t)s->index * 0xd6e8feb86659fd93ULL + (uint64_t)(dim + 1) * SAMPLER_GAMMA);
}

typedef struct float2 {
    float x, y;
} float2;

/* STRATIFIED and HALTON (stratified.c, halton.c). */
float stratified_1d(const sampler *s, uint32_t dim);
float2 stratified_2d(const sampler *s, uint32_t dim);
float halton_1d(const sampler *s, uint32_t dim);
float2 halton_2d(const sampler *s, uint32_t dim);

static inline float sampler_1d(const sampler *s, uint32_t dim)
{
    switch (s->kind) {
    case SAMPLER_SOBOL: return u32_to_unit_float(sobol_owen_1d(s->index, sampler_dimension_seed(s, dim)));
    case SAMPLER_STRATIFIED: return stratified_1d(s, dim);
    case SAMPLER_HALTON: return halton_1d(s, dim);
    default: return u64_to_unit_float(sampler_random_bits(s, dim));
    }
}

static inline float2 sampler_2d(const sampler *s, uint32_t dim)
{
    float2 r;
    switch (s->kind) {
    case SAMPLER_SOBOL: {
        uint32_t x, y;
        sobol_owen_2d(s->index, sampler_dimension_seed(s, dim), &x, &y);
        r.x = u32_to_unit_float(x);
        r.y = u32_to_unit_float(y);
        return r;
    }
    case SAMPLER_STRATIFIED: return stratified_2d(s, dim);
    case SAMPLER_HALTON: return halton_2d(s, dim);
    default:
        r.x = u64_to_unit_float(sampler_random_bits(s, dim));
        r.y = u64_to_unit_float(sampler_random_bits(s, dim + 1));
        return r;
    }
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
