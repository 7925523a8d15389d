/*
 * sobol.h — Owen-scrambled Sobol points, the SOBOL sampler's numbers and
 * the default (sampler.h).
 */
#ifndef PHOS_SOBOL_H
#define PHOS_SOBOL_H

#include <stdint.h>

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

/* Nested uniform (Owen) scramble, as a hash on the bits in reversed order
 * (Vegdahl's constants for Laine–Karras, as in Cycles and pbrt-v4): the
 * scramble of a 32-bit fixed-point value x is
 * reverse_bits32(laine_karras(reverse_bits32(x), seed)). The functions
 * below stay in the reversed order between scrambles, so that a point
 * costs two bit reversals fewer per dimension. */
static inline uint32_t laine_karras(uint32_t x, uint32_t seed)
{
    x ^= x * 0x3d20adeaU;
    x += seed;
    x *= (seed >> 16) | 1U;
    x ^= x * 0x05526c56U;
    x ^= x * 0x53a22864U;
    return x;
}

static inline uint32_t owen_scramble(uint32_t x, uint32_t seed)
{
    return reverse_bits32(laine_karras(reverse_bits32(x), seed));
}

/* Sobol dimension 1 (dimension 0 is the bit reversal): its direction
 * numbers are the rows of Pascal's triangle mod 2, v_{k+1} = v_k ^ (v_k >> 1),
 * so bit m (from the top) of v_k is C(k, m) mod 2, which by Lucas' theorem
 * is 1 exactly when m's bits are a subset of k's. The product with index i
 * is then, before the bit reversal, bit m = XOR of i's bits k ⊇ m: a
 * superset transform over the five bits of the position, done for all 32
 * positions at once in five shift-and-mask steps instead of a loop over
 * i's bits, whose branches the owen-scrambled indices make unpredictable.
 * This returns the point before its bit reversal. */
static inline uint32_t sobol_dim1_reversed(uint32_t i)
{
    i ^= (i >> 1) & 0x55555555u;
    i ^= (i >> 2) & 0x33333333u;
    i ^= (i >> 4) & 0x0f0f0f0fu;
    i ^= (i >> 8) & 0x00ff00ffu;
    i ^= (i >> 16) & 0x0000ffffu;
    return i;
}

/* One point of a dimension set whose seed is `seed`: the sample index is
 * shuffled by a nested scramble, then Sobol dimension 0 (and 1) of it is
 * scrambled again, each with its own constant. Sobol dimension 0 of the
 * shuffled index i is reverse_bits32(i), whose scramble is
 * reverse_bits32(laine_karras(i, ·)); dimension 1's is likewise
 * reverse_bits32(laine_karras(sobol_dim1_reversed(i), ·)). */
static inline uint32_t sobol_shuffled_index(uint32_t index, uint32_t seed)
{
    return owen_scramble(index, seed ^ 0xa511e9b3U);
}

static inline uint32_t sobol_owen_1d(uint32_t index, uint32_t seed)
{
    return reverse_bits32(laine_karras(sobol_shuffled_index(index, seed), seed ^ 0x63d83595U));
}

static inline void sobol_owen_2d(uint32_t index, uint32_t seed, uint32_t *x, uint32_t *y)
{
    uint32_t i = sobol_shuffled_index(index, seed);
    *x = reverse_bits32(laine_karras(i, seed ^ 0x63d83595U));
    *y = reverse_bits32(laine_karras(sobol_dim1_reversed(i), seed ^ 0x2d358dccU));
}

#endif /* PHOS_SOBOL_H */
