/*
 * halton.c — the HALTON sampler (sampler.h): the Halton sequence (Halton
 * 1964), as the course's "Quasi Monte-Carlo" slide shows it, in bases 2
 * and 3 for every dimension set.
 *
 * Point i of the sequence in base b is the radical inverse Φ_b(i): i's
 * digits in base b mirrored about the radix point. Any b^k consecutive
 * indices put one point in each interval of length b^−k, and (Φ_2, Φ_3)
 * one point in each box 2^−j × 3^−k of any 2^j·3^k consecutive indices.
 * Two things make it a sampler for a whole image:
 *  - scrambling: each digit position has its own random permutation of
 *    the digits (random digit scrambling; in base 2 an xor), drawn per
 *    pixel and dimension set, which keeps those properties and removes
 *    the sequence's regular structure;
 *  - per-pixel offsets: each pixel and set starts at its own hashed index
 *    into the sequence (consecutive runs keep the stratification), so
 *    neighbouring pixels do not repeat each other's points;
 *  - a shuffle of the sample index per pixel and set (the nested base-2
 *    scramble Sobol's sets use, sobol.h), which maps the first 2^k indices
 *    onto themselves and so keeps each power-of-two prefix's points.
 *    Without it, two sets of one pixel differed only by their offsets,
 *    and Φ(i + o₂) is a fixed function of Φ(i + o₁): the light sample and
 *    the BSDF sample of a vertex lay on a curve instead of filling the
 *    square, and direct light stopped converging (relative MSE flat from
 *    32 to 512 samples on the Cornell box, docs/benchmarks.md).
 * Every set uses the two best-distributed bases, 2 and 3, rather than the
 * d-th prime for dimension d, whose high bases are strongly correlated
 * over few samples (docs/algorithms.md §6).
 */
#include "sampling/sampler.h"

/* Digits of a 32-bit index in base 3: 3^21 > 2^32. */
#define BASE3_DIGITS 21

/* The six permutations of {0, 1, 2}, as digit tables. */
static const uint8_t base3_permutations[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                                 {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};

static uint32_t offset_index(const sampler *s, uint32_t seed)
{
    return sobol_shuffled_index(s->index, seed) + hash_u32(seed ^ 0x9b05688cu);
}

/* Φ_2 with every digit flipped where `flip` has a bit: the random digit
 * permutations of base 2. */
static float radical_inverse_2(uint32_t i, uint32_t flip)
{
    return u32_to_unit_float(reverse_bits32(i) ^ flip);
}

/* Φ_3 with digit position k permuted by a table drawn from (seed, k).
 * Positions past i's last digit hold permuted zeros, which fills the
 * points' low digits at random instead of leaving them 0. */
static float radical_inverse_3(uint32_t i, uint32_t seed)
{
    double value = 0.0, scale = 1.0 / 3.0;
    for (uint32_t k = 0; k < BASE3_DIGITS; k++) {
        const uint8_t *perm = base3_permutations[hash_combine(seed, k) % 6u];
        value += perm[i % 3u] * scale;
        i /= 3u;
        scale *= 1.0 / 3.0;
    }
    float u = (float)value;
    return u < 1.0f ? u : 0x1.fffffep-1f;
}

float halton_1d(const sampler *s, uint32_t dim)
{
    uint32_t seed = sampler_dimension_seed(s, dim);
    return radical_inverse_2(offset_index(s, seed), hash_u32(seed ^ 0x1f83d9abu));
}

float2 halton_2d(const sampler *s, uint32_t dim)
{
    uint32_t seed = sampler_dimension_seed(s, dim);
    uint32_t i = offset_index(s, seed);
    float2 u;
    u.x = radical_inverse_2(i, hash_u32(seed ^ 0x1f83d9abu));
    u.y = radical_inverse_3(i, hash_u32(seed ^ 0x5be0cd19u));
    return u;
}
