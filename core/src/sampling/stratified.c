/*
 * stratified.c — the STRATIFIED sampler: jittered strata over a pixel's
 * N samples (sampler.h), as the course's "Stratified Sampling" slide
 * shows them.
 *
 * A 1-D set puts sample i in stratum π(i) of N, at a random point of it.
 * A 2-D set is multi-jittered (Chiu, Shirley & Wang 1994, "Multi-jittered
 * sampling", Graphics Gems IV): with N = m·n (m the largest divisor of N
 * not above √N), the N samples take the cells of an m×n grid one each, and
 * within its cell a sample sits in the row and column of the N×N fine grid
 * that no other sample takes, so the set is jittered and a Latin
 * hypercube at once (for a prime N, m = 1: a plain Latin hypercube).
 * Which sample takes which cell, and the fine rows and columns, are
 * random permutations hashed from the pixel and the dimension, so sets
 * and pixels are decorrelated.
 *
 * Samples past N (a render of more samples than the strata were made for
 * never asks; a photon stream does, in blocks of SAMPLER_PATH_STRATA)
 * start a fresh set of strata every N.
 */
#include "sampling/sampler.h"

/* A random bijection of [0, 4^half): a balanced Feistel network (Luby &
 * Rackoff 1988) with hashed round functions, which is a permutation
 * whatever the rounds compute. Cheaper constructions (odd multiplies and
 * xor-shifts alone) left some outputs twice as likely as others for a
 * given input over the keys, which biased the strata; so do four rounds
 * on the smallest domains (12 % on 8 elements), where each round mixes
 * only two bits: those take eight. */
static uint32_t feistel_rounds(uint32_t half) { return half < 3 ? 8u : 4u; }
static uint32_t feistel(uint32_t x, uint32_t half, uint32_t key)
{
    uint32_t mask = (1u << half) - 1u, left = x >> half, right = x & mask, rounds = feistel_rounds(half);
    for (uint32_t round = 0; round < rounds; round++) {
        uint32_t next = left ^ (hash_combine(key + round, right) & mask);
        left = right;
        right = next;
    }
    return (left << half) | right;
}

/* Element i of a random permutation of [0, n) (n ≤ 2^30): the Feistel
 * bijection of the smallest power of four ≥ n, walked along its cycle
 * until it lands below n (fewer than four steps on average). */
static uint32_t permutation_element(uint32_t i, uint32_t n, uint32_t key)
{
    if (n <= 1)
        return 0;
    uint32_t bits = 32 - (uint32_t)__builtin_clz(n - 1), half = (bits + 1) / 2;
    do
        i = feistel(i, half, key);
    while (i >= n);
    return i;
}

/* The largest divisor of n not above √n; the search (√n steps) is kept
 * per thread for the n last asked, since every 2-D request of a render
 * asks for the same n. */
static uint32_t grid_columns(uint32_t n)
{
    static _Thread_local uint32_t last_n, last_m;
    if (n == last_n)
        return last_m;
    uint32_t m = 1;
    for (uint32_t d = 1; (uint64_t)d * d <= n; d++)
        if (n % d == 0)
            m = d;
    last_n = n;
    last_m = m;
    return m;
}

/* The sample's index among its N, and the key of its strata (a fresh
 * key every N samples). */
static uint32_t strata_index(const sampler *s, uint32_t dim, uint32_t *key)
{
    uint32_t round = s->index / s->count;
    *key = hash_combine(sampler_dimension_seed(s, dim), round);
    return s->index % s->count;
}

static float jitter(uint32_t key, uint32_t i, uint32_t salt)
{
    return u32_to_unit_float(hash_combine(hash_combine(key, salt), i));
}

float stratified_1d(const sampler *s, uint32_t dim)
{
    uint32_t key, i = strata_index(s, dim, &key), n = s->count;
    uint32_t stratum = permutation_element(i, n, key);
    float u = ((float)stratum + jitter(key, i, 0x6a09e667u)) / (float)n;
    return u < 1.0f ? u : 0x1.fffffep-1f;
}

float2 stratified_2d(const sampler *s, uint32_t dim)
{
    uint32_t key, i = strata_index(s, dim, &key), n = s->count;
    uint32_t cols = grid_columns(n), rows = n / cols;
    uint32_t cell = permutation_element(i, n, key);
    uint32_t col = cell % cols, row = cell / cols;
    /* Within its cell, the sample's fine column (one of `rows` per cell)
     * is its grid row under a permutation of the rows drawn for its grid
     * column, so the samples of one grid column (one per grid row) take
     * different fine columns; its fine row likewise, with the roles
     * swapped. */
    uint32_t fine_x = permutation_element(row, rows, hash_combine(key, 0xbb67ae85u + col));
    uint32_t fine_y = permutation_element(col, cols, hash_combine(key, 0x3c6ef372u + row));
    float2 u;
    u.x = ((float)col + ((float)fine_x + jitter(key, i, 0xa54ff53au)) / (float)rows) / (float)cols;
    u.y = ((float)row + ((float)fine_y + jitter(key, i, 0x510e527fu)) / (float)cols) / (float)rows;
    u.x = u.x < 1.0f ? u.x : 0x1.fffffep-1f;
    u.y = u.y < 1.0f ? u.y : 0x1.fffffep-1f;
    return u;
}
