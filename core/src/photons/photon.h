/*
 * photon.h — the 20-byte photon record and the photon map that holds them.
 *
 * The record is Jensen's compact layout (Jensen 2001, "Realistic Image
 * Synthesis Using Photon Mapping", §6; Jensen's course notes 2002, "The
 * photon map datastructure"): position as three floats, power as Ward's
 * shared-exponent RGBE (Ward 1991, "Real Pixels", Graphics Gems II), the
 * incoming direction as two bytes decoded through lookup tables, and a
 * 16-bit flag word that carries the photon's kind and, in 12 bits, the
 * normal of the surface the photon landed on.
 *
 * A photon map has an explicit lifecycle (as Mitsuba's): reserve → append →
 * build → read-only queries (kdtree.h). After the build it holds exactly
 * 20·N bytes of photons, its kd-tree's split planes (12 bytes per bucket
 * of 8 to 16 photons) and sizeof(photon_map); nothing else.
 */
#ifndef PHOS_PHOTON_H
#define PHOS_PHOTON_H

#include <stddef.h>
#include <stdint.h>
#ifdef __cplusplus
/* bench/bench_kdtree.cpp (C++) includes this header: the cancel flag is
 * the same lock-free int there. */
#include <atomic>
typedef std::atomic_int atomic_int;
#else
#include <stdatomic.h>
#endif

#include "util/vec.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct photon {
    float position[3];  /* world space, scene units */
    uint8_t power[4];   /* RGBE (rgbe_encode), W; already divided by the photons emitted */
    uint8_t theta, phi; /* travel direction (direction_encode), world space */
    uint16_t flags;     /* PHOTON_CAUSTIC | PHOTON_DIRECT | normal << 4; bits 0-1 zero */
} photon;

/* 12 + 4 + 2 + 2 bytes, alignment 4: no padding (docs/algorithms.md §1.1). */
#ifdef __cplusplus
static_assert(sizeof(photon) == 20, "the photon record is 20 bytes");
#else
_Static_assert(sizeof(photon) == 20, "the photon record is 20 bytes");
#endif

/* The flag word. The slides declare it `short`; it is unsigned here, as
 * the normal fills its top bits. */
enum {
    PHOTON_SPARE_MASK = 0x3,  /* unused, always zero (Jensen's split axis; the tree keeps its own) */
    PHOTON_CAUSTIC = 1 << 2,  /* path L S+ D: also stored in the caustic map */
    PHOTON_DIRECT = 1 << 3,   /* first hit after leaving the light */
    PHOTON_NORMAL_SHIFT = 4,  /* bits 4-15: the surface normal (normal_encode) */
    PHOTON_NORMAL_MASK = 0xfff0
};

/* RGBE (Ward 1991): the three channels share the exponent of the largest.
 * Negative and NaN channels encode as 0; powers below 1e-32 encode as all
 * zero; powers at or above 2^127 saturate. The error of every channel is at
 * most 1/256 of the largest channel, so a channel weaker than about 1/128 of
 * the largest keeps no information of its own: it decodes as half the
 * smallest step (see rgbe_decode). */
void rgbe_encode(vec3 power, uint8_t rgbe[4]);
/* Adds half a step to each mantissa, as Radiance's colr_color does: the
 * encoder truncates, so decoding the bin's lower edge (byte·2^(E-136), as
 * Mitsuba and Walter's rgbe.c do) darkens by half a step on average, a few
 * per mille. Only E = 0 decodes to exact zero. Never negative. */
vec3 rgbe_decode(const uint8_t rgbe[4]);

/* Direction bytes (Jensen 2001 §6; docs/algorithms.md §1.3): theta = polar
 * angle from +z in 256 bins over [0, π], phi = azimuth from +x toward +y in
 * 256 bins over [−π, π) wrapped to [0, 2π). Decoding returns the bin centre,
 * (i + 0.5) of a bin, so the angular error is at most about 0.79°.
 * `d` should be unit length; a slightly longer z is clamped, not NaN. */
void direction_encode(vec3 d, uint8_t *theta, uint8_t *phi);
vec3 direction_decode(uint8_t theta, uint8_t phi);

/* Unit normal in 12 bits: the octahedral map (Meyer et al. 2010, "On
 * Floating-Point Normal Vectors"; docs/algorithms.md §1.4), 6 bits per
 * coordinate, angular error below 2.6°. A density estimate compares it with
 * the normal where it is read, so that photons of another surface (the
 * adjacent wall of a corner, the outside of a thin wall) are not counted. */
uint16_t normal_encode(vec3 n);
vec3 normal_decode(uint16_t code);

/* The lookup tables behind direction_decode, exported for the test that
 * checks them against libm: cos and sin of the bin centres (i + 0.5)·π/256
 * (theta) and (i + 0.5)·2π/256 (phi). */
extern const float photon_cos_theta[256], photon_sin_theta[256];
extern const float photon_cos_phi[256], photon_sin_phi[256];

/* A photon at `position` (scene units) carrying `power` (W, already scaled by
 * 1/emitted) that travelled along unit `direction` onto a surface of unit
 * `normal` (on the side it arrived from); `flags` is a combination of
 * PHOTON_CAUSTIC and PHOTON_DIRECT. */
photon photon_make(vec3 position, vec3 power, vec3 direction, vec3 normal, unsigned flags);

static inline vec3 photon_position(const photon *p) { return v3_load(p->position); }
static inline vec3 photon_power(const photon *p) { return rgbe_decode(p->power); }
static inline vec3 photon_direction(const photon *p) { return direction_decode(p->theta, p->phi); }
/* normal_decode of every 12-bit code, filled when the library loads: the
 * searches test the normal of every photon they meet (48 KB, which stays
 * in cache, against a square root and a division per photon). */
extern vec3 photon_normal_table[4096];
static inline vec3 photon_normal(const photon *p) { return photon_normal_table[p->flags >> PHOTON_NORMAL_SHIFT]; }
static inline int photon_is_caustic(const photon *p) { return (p->flags & PHOTON_CAUSTIC) != 0; }
static inline int photon_is_direct(const photon *p) { return (p->flags & PHOTON_DIRECT) != 0; }

/* ---- photon map ---------------------------------------------------------
 * Lifecycle: photon_map_init → photon_map_reserve (optional) → append ... →
 * photon_map_build → read-only queries from any number of threads
 * (photon_map_knn and the others in kdtree.h) → photon_map_free.
 * Appending is single-threaded: a parallel tracer collects per-thread
 * batches and appends them in photon-index order (photon_map_extend lets
 * its threads write their own slots), and the built map then
 * depends only on that sequence of photons (not on the reserve size, the
 * growth pattern or the thread count). */
/* Photons are kept in classes: by the dominant axis of their normal (+x,
 * −x, +y, −y, +z, −z: photon_facing) and by their direct and caustic flags
 * (photon_class). The map's one kd-tree splits them by class at its root
 * (kdtree.h), so a surface search never walks photons it would reject:
 * those of a surface facing away (the sunlit outside of a thin wall, many
 * times denser than the inside), or the direct photons an estimate leaves
 * out (a sunlit patch's thousands, around every site of a radiance photon
 * there). Filtering them one by one made a radiance precomputation 20
 * times slower. */
#define PHOTON_FACINGS 6
#define PHOTON_CLASSES (PHOTON_FACINGS * 4)
unsigned photon_facing(vec3 n);
/* facing · 4 + direct + 2 · caustic */
unsigned photon_class(const photon *p);
/* The flags (PHOTON_DIRECT, PHOTON_CAUSTIC) every photon of class c has. */
static inline uint16_t photon_class_flags(unsigned c)
{
    return (uint16_t)(((c & 1u) ? PHOTON_DIRECT : 0) | ((c & 2u) ? PHOTON_CAUSTIC : 0));
}

/* A split plane of the kd-tree (kdtree.h): along `axis`, the left
 * subtree's photons lie at or below lo, the right subtree's at or above
 * hi (lo ≤ hi; the gap between them is empty space the search can skip,
 * as nanoflann's divlow/divhigh). */
typedef struct kdtree_split {
    float lo, hi;  /* scene units */
    uint32_t axis; /* 0, 1, 2 */
} kdtree_split;

/* One class's subtree: a perfect binary tree of 2^depth buckets over
 * photons[start .. start + count), bucket j holding the photons from
 * start + ⌊j·count/2^depth⌋ on; its 2^depth − 1 split planes in heap
 * order (node h's children are 2h and 2h + 1) from splits[first_split]. */
typedef struct photon_class_tree {
    uint32_t start, count;
    uint32_t depth;
    uint32_t first_split;
    float lo[3], hi[3]; /* bounding box of its photons; empty class: unused */
} photon_class_tree;

typedef struct photon_map {
    photon *photons;   /* count photons; after the build by class, each class in bucket order */
    uint32_t count;    /* photons stored */
    uint32_t capacity; /* photons allocated; equal to count after the build */
    int built;         /* 1 after photon_map_build: read-only from then on */
    photon_class_tree classes[PHOTON_CLASSES];
    kdtree_split *splits;
    uint32_t split_count;
} photon_map;

#define PHOTON_MAP_MAX_PHOTONS 0x7fffffffu

void photon_map_init(photon_map *m);
/* Frees the photons and returns to the state after photon_map_init. NULL is a no-op. */
void photon_map_free(photon_map *m);
/* Room for `capacity` photons in total, so appends do not reallocate.
 * Returns 0 when memory is exhausted, the map is built, or capacity is too large. */
int photon_map_reserve(photon_map *m, uint32_t capacity);
/* Appends count photons (grows ×1.5 when full). A photon whose position is not
 * finite is rejected, and so is the whole call, before anything is stored.
 * Returns 0 on rejection, exhausted memory or an already built map. */
int photon_map_append(photon_map *m, const photon *photons, uint32_t count);
/* Room for count more photons at the map's end (grown as append grows it),
 * counted as stored at once: the caller writes each of them, with a finite
 * position, before any other call on the map. It may do so from several
 * threads, each into slots of its own (the tracer packs its batches in
 * parallel). NULL when count is 0, memory is exhausted, the map is built
 * or it would pass PHOTON_MAP_MAX_PHOTONS. */
photon *photon_map_extend(photon_map *m, uint32_t count);
/* Sorts the photons into their classes (stably: the result depends
 * only on the appended sequence), builds the kd-tree (kdtree_build) and
 * shrinks the storage to exactly 20·count bytes. Returns 0 when memory is
 * exhausted, in which case the map keeps its photons unbuilt. Building
 * twice is a no-op. cancel may be NULL: when *cancel becomes nonzero it
 * returns 0 soon, the map unusable. */
int photon_map_build(photon_map *m, atomic_int *cancel);
/* photon_map_build for several maps at once, on `threads` threads (0: one
 * per core): their sorts side by side, then their trees' subtrees
 * (kdtree_build). Each map comes out exactly as photon_map_build alone
 * would leave it. Returns 0 as photon_map_build does. */
int photon_map_build_many(photon_map *const *maps, unsigned count, uint32_t threads, atomic_int *cancel);
/* Bytes the map occupies: sizeof(photon_map) + 20·capacity (= 20·count
 * once built) + 12 per split plane. */
size_t photon_map_memory(const photon_map *m);

#ifdef __cplusplus
}
#endif

#endif /* PHOS_PHOTON_H */
