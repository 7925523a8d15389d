/*
 * kdtree.h — the photon map's kd-tree (Bentley 1975, "Multidimensional
 * binary search trees used for associative searching"; Jensen 2001,
 * "Realistic Image Synthesis Using Photon Mapping", §6.3, and Jensen's
 * course notes 2002) and its k-nearest-neighbour searches.
 *
 * One tree per map (docs/algorithms.md §2). Its root splits the photons
 * by class (photon.h): each class's subtree is entered only if the search
 * accepts the class and the class's bounding box lies within the radius.
 * Below, each subtree is balanced as Jensen's is — every node splits its
 * photons at their median, along the longest axis of its cell — but ends
 * in buckets of at most KDTREE_BUCKET photons instead of single photons,
 * as nanoflann's and Mitsuba's trees do. The photon array itself is the
 * leaves, in bucket order; the split planes are a small side array, and
 * the tree's shape follows from the class's photon count alone, so it
 * needs no pointers (docs/algorithms.md §2.1).
 *
 * After the build the tree is read-only, so any number of threads may query
 * it at once; each brings its own kdtree_query (results and heap), which
 * lies on cache lines of its own so that two threads' searches never
 * write the same line (util/parallel.h, PARALLEL_CACHE_LINE).
 */
#ifndef PHOS_KDTREE_H
#define PHOS_KDTREE_H

#include <stdint.h>
#include <string.h>

#include "photons/photon.h"
#include "util/parallel.h"
#include "util/vec.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The most photons a bucket holds. A search scans a bucket's photons in
 * order, from contiguous memory; smaller buckets prune more finely but
 * cost a split plane (12 bytes), a node visit and a level of the build's
 * selection each. 8 and 16 searched alike; 16 builds faster (measured in
 * docs/benchmarks.md, "The kd-tree against nanoflann"). */
#define KDTREE_BUCKET 16

/* Builds the trees of `count` maps over their photons, which
 * photon_map_build has sorted into classes (m->classes' start and count):
 * reorders each class's photons into bucket order and fills the split
 * planes and the classes' depths and bounding boxes. O(n log n): a
 * linear-time selection per level. The top levels of each large class are
 * built on one thread, the subtrees below them on `threads` threads (0:
 * one per core), largest first; each tree depends only on its map's
 * photon array, never on the thread count. Returns 0 when memory runs
 * out, or when *cancel (NULL: never) becomes nonzero, which it looks at
 * every few milliseconds; the maps then hold no usable tree. */
int kdtree_build(photon_map *const *maps, unsigned count, uint32_t threads, atomic_int *cancel);

/* The depth of a class's subtree of n photons: the least d with
 * ⌈n/2^d⌉ ≤ KDTREE_BUCKET (0 for n ≤ KDTREE_BUCKET). */
uint32_t kdtree_depth(uint32_t n);

/* Per-query scratch and results, one per thread, sized for k at init and
 * reused for every query. Result j < found is heap[j], read with
 * kdtree_result_index and kdtree_result_dist2; the results are unordered,
 * except that when k were found the k-th nearest is the first, j = 0
 * (the array is the search's max-heap).
 *
 * A heap entry is one 64-bit key: the bits of dist2 above, the photon's
 * index below. IEEE floats ≥ +0 order as their bit patterns, so keys
 * order by distance (then by index): a sift-down moves one word a level
 * where parallel distance and index arrays moved two. On 200 k photons
 * in a render's order, k = 50, that took the search from 1.25–1.38× to
 * 1.41–1.53× nanoflann's speed (docs/benchmarks.md, "The kd-tree against
 * nanoflann"). */
typedef struct kdtree_query {
    PARALLEL_LINE_ALIGNED uint32_t k; /* at most k photons are returned */
    uint32_t found;    /* photons found, ≤ k */
    float radius2;     /* search radius² at the end: the k-th distance² if k were
                        * found, otherwise the max radius² (docs/algorithms.md §2.4) */
    uint64_t *heap;    /* k + 1 keys (dist2 bits << 32 | index), the last the heap's
                        * sentinel; dist2 in the query's metric, index 0-based into the
                        * photon array */
} kdtree_query;

/* Allocates room for k results (8·(k + 1) bytes, rounded up to whole cache
 * lines and starting on one). An array of queries, one per thread, is
 * allocated with parallel_scratch_calloc. Returns 0 when memory is
 * exhausted. q->k may be lowered later (a nearest photon search with
 * k = 1 on a query made for more), not raised. */
int kdtree_query_init(kdtree_query *q, uint32_t k);
/* NULL is a no-op. */
void kdtree_query_free(kdtree_query *q);

/* The metrics (docs/algorithms.md §4.3). Euclidean, or the "disc": the
 * sphere squashed along the unit normal by `flatten` (c ≥ 1; the radiance
 * estimates use ESTIMATE_DISC_FLATTEN = 4),
 *     d_eff² = |v|² + (c² − 1)·(n·v)²,   v = photon − x,
 * so that photons off the surface's plane (other side of a thin wall, the
 * adjacent wall in a corner) rank as far away. d_eff ≥ |v|, so pruning with
 * the Euclidean distance to a cell stays conservative. dist2 and radius2
 * are in d_eff². A flatten below 1 is taken as 1 (plain Euclidean). */

/* The photons a surface search takes (docs/algorithms.md §4.3): only they
 * are ranked, so the k found are k the estimate can use. Filtering after
 * the search instead would let photons that do not count (on the sunlit
 * outside of a thin wall, say, 50 times denser than inside) set the
 * radius, and the estimate would be made of the one or two that do. */
typedef struct kdtree_filter {
    vec3 normal;            /* unit: the surface's, where the search is made */
    float min_normal_cos;   /* photon_normal(p) · normal ≥ this */
    uint16_t exclude_flags; /* photons with any of these flags are skipped */
    uint16_t from_above;    /* 1: only photons that travelled into the surface (d · normal < 0) */
} kdtree_filter;

static inline int kdtree_filter_accepts(const kdtree_filter *f, const photon *p)
{
    return !(p->flags & f->exclude_flags) && !(f->from_above && v3_dot(photon_direction(p), f->normal) >= 0.0f) &&
           v3_dot(photon_normal(p), f->normal) >= f->min_normal_cos;
}

/* The metrics, exactly as the searches compute them (tests compare against
 * brute force with these, so ties agree bit for bit). */
static inline float kdtree_dist2(const photon *p, vec3 x)
{
    float dx = p->position[0] - x.x, dy = p->position[1] - x.y, dz = p->position[2] - x.z;
    return dx * dx + dy * dy + dz * dz;
}
/* c2m1 = flatten² − 1. */
static inline float kdtree_disc_dist2(const photon *p, vec3 x, vec3 normal, float c2m1)
{
    float dx = p->position[0] - x.x, dy = p->position[1] - x.y, dz = p->position[2] - x.z;
    float dn = dx * normal.x + dy * normal.y + dz * normal.z;
    return dx * dx + dy * dy + dz * dz + c2m1 * (dn * dn);
}

/* The k photons of m nearest to x with squared distance < max_radius2
 * (strictly): fills q and returns q->found. Ties at the k-th distance are
 * broken arbitrarily (but deterministically). _disc ranks by the disc
 * metric; _surface by the disc about f->normal, among the photons f
 * accepts, and skips the classes none of whose photons it can accept
 * (excluded flags, or normals that cannot pass its normal test). A map
 * not yet built finds nothing. Indices are into m->photons. */
uint32_t photon_map_knn(const photon_map *m, vec3 x, float max_radius2, kdtree_query *q);
uint32_t photon_map_knn_disc(const photon_map *m, vec3 x, vec3 normal, float flatten, float max_radius2,
                             kdtree_query *q);
uint32_t photon_map_knn_surface(const photon_map *m, vec3 x, float flatten, const kdtree_filter *f,
                                float max_radius2, kdtree_query *q);
/* Every photon of m the filter accepts with disc distance² < radius2
 * (strictly), handed to visit(ctx, photon, d2) in the search's order,
 * which depends on the map alone; returns how many. A fixed-radius
 * search: progressive photon mapping's estimate (radiance_estimate.h). */
typedef void (*kdtree_visit)(void *ctx, const photon *p, float d2);
uint32_t photon_map_range_surface(const photon_map *m, vec3 x, float flatten, const kdtree_filter *f,
                                  float radius2, kdtree_visit visit, void *ctx);
/* Result j < q->found: its photon's index in the photon array, its
 * squared distance (from its heap key), and the photon itself. */
static inline uint32_t kdtree_result_index(const kdtree_query *q, uint32_t j)
{
    return (uint32_t)q->heap[j];
}
static inline float kdtree_key_dist2(uint64_t key)
{
    uint32_t bits = (uint32_t)(key >> 32);
    float d2;
    memcpy(&d2, &bits, sizeof d2);
    return d2;
}
static inline float kdtree_result_dist2(const kdtree_query *q, uint32_t j)
{
    return kdtree_key_dist2(q->heap[j]);
}
static inline const photon *kdtree_result(const photon *tree, const kdtree_query *q, uint32_t j)
{
    return tree + kdtree_result_index(q, j);
}

#ifdef __cplusplus
}
#endif

#endif /* PHOS_KDTREE_H */
