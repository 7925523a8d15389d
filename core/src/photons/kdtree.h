/*
 * kdtree.h — the left-balanced kd-tree over photons (Bentley 1975,
 * "Multidimensional binary search trees used for associative searching";
 * Jensen 2001, "Realistic Image Synthesis Using Photon Mapping", §6.3, and
 * Jensen's course notes 2002) and its k-nearest-neighbour search.
 *
 * The tree is the photon array itself, reordered as a 1-based heap: node i
 * is photons[i-1], its children are nodes 2i and 2i+1, node i is internal
 * iff 2i ≤ n, and its split axis lives in the photon's flag bits. No
 * pointers, child indices or bounds are stored (docs/algorithms.md §2.1).
 *
 * After the build the tree is read-only, so any number of threads may query
 * it at once; each brings its own kdtree_query (results and heap).
 */
#ifndef PHOS_KDTREE_H
#define PHOS_KDTREE_H

#include <stdint.h>

#include "photons/photon.h"
#include "util/vec.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Number of nodes in the left subtree of a left-balanced (complete, last
 * level filled from the left) binary tree of n ≥ 1 nodes: the median index
 * of a segment of n photons, 0-based (docs/algorithms.md §2.2). L(1) = 0. */
uint32_t kdtree_left_size(uint32_t n);

/* Reorders photons[0..n) into the left-balanced heap and writes each node's
 * split axis into its flags (the other flag bits are kept). O(n log n): a
 * linear-time selection per level. Splits at the median (kdtree_left_size)
 * along the longest axis of the node's cell: the bounding box of all photons
 * narrowed by the ancestors' split planes, as Jensen's balance_segment does.
 * Temporary memory: one copy of the photons (20·n bytes) for the duration of
 * the call. The result depends only on the input array. Returns 0 if that
 * copy cannot be allocated (the photons are then unchanged), 1 otherwise;
 * n ≤ PHOTON_MAP_MAX_PHOTONS. cancel may be NULL; when *cancel becomes
 * nonzero the build stops within a few milliseconds and returns 0, the
 * array then holding no usable tree. */
int kdtree_build(photon *photons, uint32_t n, atomic_int *cancel);

/* Per-query scratch and results, one per thread, sized for k at init and
 * reused for every query. Results are unordered: index[j] and dist2[j] for
 * j < found (the arrays are the search's max-heap). */
typedef struct kdtree_query {
    uint32_t k;        /* at most k photons are returned */
    uint32_t found;    /* photons found, ≤ k */
    float radius2;     /* search radius² at the end: the k-th distance² if k were
                        * found, otherwise the max radius² (docs/algorithms.md §2.4) */
    uint32_t *index;   /* k entries: 0-based positions in the photon array */
    float *dist2;      /* k entries: squared distances (in the query's metric) */
} kdtree_query;

/* Allocates room for k results (8·k bytes). Returns 0 when memory is exhausted. */
int kdtree_query_init(kdtree_query *q, uint32_t k);
/* NULL is a no-op. */
void kdtree_query_free(kdtree_query *q);

/* The k photons nearest to x with squared distance < max_radius2 (strictly),
 * in the tree of n photons. Fills q and returns q->found. Ties at the k-th
 * distance are broken arbitrarily (but deterministically). */
uint32_t kdtree_knn(const photon *tree, uint32_t n, vec3 x, float max_radius2, kdtree_query *q);

/* As kdtree_knn with the "disc" metric of docs/algorithms.md §4.3: the
 * sphere squashed along the unit normal by `flatten` (c ≥ 1; the radiance
 * estimates use ESTIMATE_DISC_FLATTEN = 4),
 *     d_eff² = |v|² + (c² − 1)·(n·v)²,   v = photon − x,
 * so that photons off the surface's plane (other side of a thin wall, the
 * adjacent wall in a corner) rank as far away. d_eff ≥ |v|, so pruning with
 * the Euclidean plane distance stays conservative. dist2 and radius2 are in
 * d_eff². A flatten below 1 is taken as 1 (plain Euclidean). */
uint32_t kdtree_knn_disc(const photon *tree, uint32_t n, vec3 x, vec3 normal, float flatten,
                         float max_radius2, kdtree_query *q);

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

/* kdtree_knn_disc about f->normal, among the photons f accepts. */
uint32_t kdtree_knn_surface(const photon *tree, uint32_t n, vec3 x, float flatten, const kdtree_filter *f,
                            float max_radius2, kdtree_query *q);

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

/* The same searches on a photon map, over its classes (photon.h):
 * one search whose radius carries from each class's tree to the next, so
 * the result is that of one tree over all the photons. The surface search
 * skips the classes whose photons the filter cannot accept (excluded flags,
 * or normals that cannot pass its normal test). A
 * map not yet built finds nothing. Indices are into m->photons. */
uint32_t photon_map_knn(const photon_map *m, vec3 x, float max_radius2, kdtree_query *q);
uint32_t photon_map_knn_disc(const photon_map *m, vec3 x, vec3 normal, float flatten, float max_radius2,
                             kdtree_query *q);
uint32_t photon_map_knn_surface(const photon_map *m, vec3 x, float flatten, const kdtree_filter *f,
                                float max_radius2, kdtree_query *q);
/* The j-th result (j < q->found) as a photon of the tree. */
static inline const photon *kdtree_result(const photon *tree, const kdtree_query *q, uint32_t j)
{
    return tree + q->index[j];
}

#ifdef __cplusplus
}
#endif

#endif /* PHOS_KDTREE_H */
