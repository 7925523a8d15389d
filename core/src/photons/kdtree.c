/*
 * kdtree.c — building the left-balanced kd-tree and searching it.
 *
 * Build (docs/algorithms.md §2.3; Jensen 2001 §6.3 balance_segment): the
 * photons are copied to a work array; each segment is split at its
 * left-balanced median by selection along the longest axis of its cell, the
 * median photon is written to its heap slot in the caller's array, and both
 * halves recurse.
 * Writing straight into the heap slots needs no index arrays and no
 * permutation pass, at the price of one 20·n-byte copy during the build.
 *
 * Search (docs/algorithms.md §2.4; Jensen's locate_photons, made iterative
 * as Mitsuba's nnSearch): descend to the near child, push the far child
 * with its squared plane distance, and re-test that distance against the
 * radius at pop time, when the radius may have shrunk. Found photons go into a max-heap of k
 * entries once k are held, so the radius shrinks to the k-th distance.
 */
#include "photons/kdtree.h"

#include <stdlib.h>
#include <string.h>

/* Tree height is at most 31 for n ≤ 2^31 − 1, and each level pushes at most
 * one far child. */
#define KDTREE_STACK_SIZE 64

uint32_t kdtree_left_size(uint32_t n)
{
    if (n <= 1)
        return 0;
    /* p = 2^floor(log2 n): the full levels above the last hold p − 1 nodes,
     * the last level holds r = n − p + 1, filled from the left; the left
     * subtree gets p/2 − 1 of the full levels and up to p/2 of the last. */
    uint32_t p = 1;
    while (p <= n / 2)
        p *= 2;
    uint32_t r = n - p + 1;
    return (p / 2 - 1) + (r < p / 2 ? r : p / 2);
}

/* ---- build --------------------------------------------------------------- */

typedef struct cell_box {
    float lo[3], hi[3];
} cell_box;

static cell_box bounds_of(const photon *p, uint32_t n)
{
    cell_box b;
    for (int a = 0; a < 3; a++) {
        b.lo[a] = p[0].position[a];
        b.hi[a] = p[0].position[a];
    }
    for (uint32_t i = 1; i < n; i++)
        for (int a = 0; a < 3; a++) {
            b.lo[a] = fminf(b.lo[a], p[i].position[a]);
            b.hi[a] = fmaxf(b.hi[a], p[i].position[a]);
        }
    return b;
}

/* Ties go to the lower axis, so the choice is deterministic. */
static int longest_axis(const cell_box *b)
{
    float ex = b->hi[0] - b->lo[0], ey = b->hi[1] - b->lo[1], ez = b->hi[2] - b->lo[2];
    if (ex >= ey && ex >= ez)
        return 0;
    return ey >= ez ? 1 : 2;
}

static inline void swap_photons(photon *a, photon *b)
{
    photon t = *a;
    *a = *b;
    *b = t;
}

static inline float median_of_3(float a, float b, float c)
{
    return fmaxf(fminf(a, b), fminf(fmaxf(a, b), c));
}

/* Ranges of at least this many photons look at the cancel flag first:
 * well under a millisecond of work between two looks. */
#define KDTREE_CANCEL_GRAIN 16384u
/* Photons copied between two looks at it (5 MB, a few milliseconds). */
#define KDTREE_COPY_SLICE (1u << 18)

/* Hoare's FIND (CACM 1961) in Wirth's form: afterwards a[m] holds the key
 * of rank m, everything before it ≤ a[m] ≤ everything after it. The scans
 * stop on keys equal to the pivot, so runs of equal keys (photons on an
 * axis-aligned wall) are split evenly and may end up on both sides of the
 * median. The pivot is the median of the first, middle and last keys:
 * sorted or reverse-sorted input then partitions at the middle instead of
 * degrading to O(n²) as the last-element pivot of Jensen's median_split. */
static int select_median(photon *a, uint32_t n, uint32_t m, int axis, atomic_int *cancel)
{
    ptrdiff_t lo = 0, hi = (ptrdiff_t)n - 1, k = (ptrdiff_t)m;
    while (lo < hi) {
        /* One partition of millions of photons takes milliseconds. */
        if (hi - lo >= (ptrdiff_t)KDTREE_CANCEL_GRAIN && cancel &&
            atomic_load_explicit(cancel, memory_order_relaxed))
            return 0;
        float pivot = median_of_3(a[lo].position[axis], a[lo + (hi - lo) / 2].position[axis],
                                  a[hi].position[axis]);
        ptrdiff_t i = lo, j = hi;
        do {
            while (a[i].position[axis] < pivot)
                i++;
            while (pivot < a[j].position[axis])
                j--;
            if (i <= j) {
                swap_photons(&a[i], &a[j]);
                i++;
                j--;
            }
        } while (i <= j);
        /* Now a[lo..j] ≤ pivot ≤ a[i..hi], and any slot between equals it. */
        if (j < k)
            lo = i;
        if (k < i)
            hi = j;
    }
    return 1;
}

/* Balances work[0..n) into the subtree rooted at heap node `node` of `out`;
 * 0 if cancelled. */
static int balance(photon *work, uint32_t n, photon *out, uint32_t node, cell_box box, atomic_int *cancel)
{
    int axis = longest_axis(&box);
    uint32_t m = kdtree_left_size(n);
    if (!select_median(work, n, m, axis, cancel))
        return 0;

    photon p = work[m];
    p.flags = (uint16_t)((p.flags & ~PHOTON_AXIS_MASK) | axis);
    out[node - 1] = p;

    float split = p.position[axis];
    if (m > 0) {
        cell_box left = box;
        left.hi[axis] = split;
        if (!balance(work, m, out, 2 * node, left, cancel))
            return 0;
    }
    if (n - m - 1 > 0) {
        cell_box right = box;
        right.lo[axis] = split;
        if (!balance(work + m + 1, n - m - 1, out, 2 * node + 1, right, cancel))
            return 0;
    }
    return 1;
}

int kdtree_build(photon *photons, uint32_t n, atomic_int *cancel)
{
    if (n == 0)
        return 1;
    if (n > PHOTON_MAP_MAX_PHOTONS)
        return 0;
    photon *work = malloc(sizeof(photon) * (size_t)n);
    if (!work)
        return 0;
    /* The copy into fresh pages takes tens of milliseconds for millions
     * of photons: it is made in slices, with a look at the cancel flag
     * between them. */
    int done = 1;
    for (uint32_t i = 0; i < n && done; i += KDTREE_COPY_SLICE) {
        uint32_t m = n - i < KDTREE_COPY_SLICE ? n - i : KDTREE_COPY_SLICE;
        memcpy(work + i, photons + i, sizeof(photon) * (size_t)m);
        done = !(cancel && atomic_load_explicit(cancel, memory_order_relaxed));
    }
    done = done && balance(work, n, photons, 1, bounds_of(work, n), cancel);
    free(work);
    return done;
}

/* ---- search -------------------------------------------------------------- */

int kdtree_query_init(kdtree_query *q, uint32_t k)
{
    q->k = k;
    q->found = 0;
    q->radius2 = 0.0f;
    q->index = malloc(sizeof(uint32_t) * (k ? k : 1));
    q->dist2 = malloc(sizeof(float) * (k ? k : 1));
    if (!q->index || !q->dist2) {
        kdtree_query_free(q);
        return 0;
    }
    return 1;
}

void kdtree_query_free(kdtree_query *q)
{
    if (!q)
        return;
    free(q->index);
    free(q->dist2);
    q->index = NULL;
    q->dist2 = NULL;
    q->k = 0;
    q->found = 0;
}

/* Max-heap on dist2 (0-based: children of j are 2j+1, 2j+2): moves the
 * entry at j down to its place. */
static void heap_sift_down(float *dist2, uint32_t *index, uint32_t size, uint32_t j)
{
    float d = dist2[j];
    uint32_t id = index[j];
    for (;;) {
        uint32_t c = 2 * j + 1;
        if (c >= size)
            break;
        if (c + 1 < size && dist2[c + 1] > dist2[c])
            c++;
        if (dist2[c] <= d)
            break;
        dist2[j] = dist2[c];
        index[j] = index[c];
        j = c;
    }
    dist2[j] = d;
    index[j] = id;
}

/* Takes a photon at d2 < current radius². Until k are held they are only
 * appended (Jensen's lazy heap: most searches that do not fill up never pay
 * for heap order); the k-th is followed by an O(k) heapify, after which each
 * new photon replaces the farthest and the radius shrinks to the new
 * farthest. Returns the new radius². */
static inline float knn_add(kdtree_query *q, float d2, uint32_t i, float r2)
{
    if (q->found < q->k) {
        q->dist2[q->found] = d2;
        q->index[q->found] = i;
        if (++q->found < q->k)
            return r2;
        for (uint32_t j = q->k / 2; j-- > 0;)
            heap_sift_down(q->dist2, q->index, q->k, j);
        return q->dist2[0];
    }
    q->dist2[0] = d2;
    q->index[0] = i;
    heap_sift_down(q->dist2, q->index, q->k, 0);
    return q->dist2[0];
}

/* One search for every metric and filter; `disc` and whether `filter` is
 * NULL are constants at each call site, so the compiler specialises the
 * inlined copy. */
static inline __attribute__((always_inline)) uint32_t knn_search(const photon *tree, uint32_t n, uint32_t base,
                                                                 vec3 x, int disc, vec3 normal, float c2m1,
                                                                 const kdtree_filter *filter,
                                                                 float max_radius2, kdtree_query *q)
{
    /* base > 0 or q->found > 0: a further tree of the same search (a map's
     * facing classes): the results so far stay, and so does their radius. */
    if (n == 0 || q->k == 0 || !(max_radius2 > 0.0f))
        return q->found;

    const float xq[3] = {x.x, x.y, x.z};
    uint32_t stack_node[KDTREE_STACK_SIZE];
    float stack_plane2[KDTREE_STACK_SIZE];
    int top = 0;
    float r2 = q->found == q->k ? q->dist2[0] : max_radius2; /* dist2[0]: the heap's farthest */
    uint32_t i = 1;
    for (;;) {
        /* Descend toward x, leaving the far children on the stack. */
        for (;;) {
            const photon *p = &tree[i - 1];
            float d2 = disc ? kdtree_disc_dist2(p, x, normal, c2m1) : kdtree_dist2(p, x);
            if (d2 < r2 && (!filter || kdtree_filter_accepts(filter, p)))
                r2 = knn_add(q, d2, base + i - 1, r2);
            if (2 * i > n) /* a leaf: 2i ≤ n is the internal test (not Jensen's n/2 − 1) */
                break;
            int axis = p->flags & PHOTON_AXIS_MASK;
            float delta = xq[axis] - p->position[axis];
            uint32_t near = 2 * i + (delta > 0.0f), far = 2 * i + (delta <= 0.0f);
            float plane2 = delta * delta;
            if (far <= n && plane2 < r2) {
                stack_node[top] = far;
                stack_plane2[top] = plane2;
                top++;
            }
            if (near > n) /* only the left child exists and it was the far one */
                break;
            i = near;
        }
        /* Resume at the deepest far child still within the (shrunk) radius. */
        do {
            if (top == 0) {
                q->radius2 = r2; /* still max_radius2 unless k were found */
                return q->found;
            }
            top--;
        } while (!(stack_plane2[top] < r2));
        i = stack_node[top];
    }
}

static void query_start(kdtree_query *q, float max_radius2)
{
    q->found = 0;
    q->radius2 = max_radius2;
}

uint32_t kdtree_knn(const photon *tree, uint32_t n, vec3 x, float max_radius2, kdtree_query *q)
{
    query_start(q, max_radius2);
    return knn_search(tree, n, 0, x, 0, v3s(0.0f), 0.0f, NULL, max_radius2, q);
}

uint32_t kdtree_knn_disc(const photon *tree, uint32_t n, vec3 x, vec3 normal, float flatten,
                         float max_radius2, kdtree_query *q)
{
    float c = flatten > 1.0f ? flatten : 1.0f;
    query_start(q, max_radius2);
    return knn_search(tree, n, 0, x, 1, normal, c * c - 1.0f, NULL, max_radius2, q);
}

uint32_t kdtree_knn_surface(const photon *tree, uint32_t n, vec3 x, float flatten, const kdtree_filter *f,
                            float max_radius2, kdtree_query *q)
{
    float c = flatten > 1.0f ? flatten : 1.0f;
    query_start(q, max_radius2);
    return knn_search(tree, n, 0, x, 1, f->normal, c * c - 1.0f, f, max_radius2, q);
}

/* ---- maps: one search over the classes ---------------------------------- */

/* The largest n·m over the unit normals m of facing class c (dominant axis
 * a, sign s: s·m_a ≥ |m_b| for both other axes b). Inside the class it is
 * 1; otherwise the maximum lies on one of the four great-circle arcs that
 * bound it (s·m_a = ±m_b) or at one of its four corners. */
static float facing_class_max_dot(unsigned c, vec3 n)
{
    int a = (int)(c / 2);
    float s = (c & 1) ? -1.0f : 1.0f;
    float nv[3] = {n.x, n.y, n.z};
    int b0 = (a + 1) % 3, b1 = (a + 2) % 3;
    if (s * nv[a] >= fabsf(nv[b0]) && s * nv[a] >= fabsf(nv[b1]))
        return 1.0f;
    float best = -1.0f;
    for (int corner = 0; corner < 4; corner++) {
        float m[3];
        m[a] = s;
        m[b0] = (corner & 1) ? -1.0f : 1.0f;
        m[b1] = (corner & 2) ? -1.0f : 1.0f;
        best = fmaxf(best, (m[0] * nv[0] + m[1] * nv[1] + m[2] * nv[2]) * 0.57735027f);
    }
    for (int arc = 0; arc < 4; arc++) {
        int b = arc < 2 ? b0 : b1, other = arc < 2 ? b1 : b0;
        float sb = (arc & 1) ? -1.0f : 1.0f;
        /* The circle m_b = sb·s·m_a: n without its part along the circle's
         * pole u = (s e_a − sb e_b)/√2, normalised, if it lies on the arc. */
        float u[3] = {0.0f, 0.0f, 0.0f};
        u[a] = s * 0.70710678f;
        u[b] = -sb * 0.70710678f;
        float nu = nv[0] * u[0] + nv[1] * u[1] + nv[2] * u[2];
        float m[3] = {nv[0] - nu * u[0], nv[1] - nu * u[1], nv[2] - nu * u[2]};
        float len = sqrtf(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
        if (!(len > 1e-6f))
            continue;
        if (s * m[a] >= 0.0f && s * m[a] >= fabsf(m[other]))
            best = fmaxf(best, len); /* n·m/|m| = |m| for the projection */
    }
    return best;
}

/* Searches the classes of m in order, skipping those no photon of which a
 * surface filter f (NULL: none) can accept. */
static uint32_t map_search(const photon_map *m, vec3 x, int disc, vec3 normal, float c2m1, const kdtree_filter *f,
                           float max_radius2, kdtree_query *q)
{
    query_start(q, max_radius2);
    if (!m->built)
        return 0;
    /* A surface search visits the facings its normal can accept, nearest
     * first: the class it faces usually holds the nearest photons, and the
     * radius they set prunes the other trees early. */
    unsigned order[PHOTON_FACINGS], facings = 0;
    float best[PHOTON_FACINGS];
    for (unsigned c = 0; c < PHOTON_FACINGS; c++) {
        float d = f ? facing_class_max_dot(c, f->normal) : 1.0f;
        if (f && d < f->min_normal_cos)
            continue;
        unsigned j = facings++;
        for (; j > 0 && best[j - 1] < d; j--) { /* insertion, stable: the same order every time */
            best[j] = best[j - 1];
            order[j] = order[j - 1];
        }
        best[j] = d;
        order[j] = c;
    }
    for (unsigned i = 0; i < facings; i++)
        for (unsigned flags = 0; flags < 4; flags++) {
            unsigned c = order[i] * 4u + flags;
            uint32_t start = m->class_start[c], n = m->class_start[c + 1] - start;
            if (n == 0 || (f && (photon_class_flags(c) & f->exclude_flags)))
                continue;
            if (disc)
                knn_search(m->photons + start, n, start, x, 1, normal, c2m1, f, max_radius2, q);
            else
                knn_search(m->photons + start, n, start, x, 0, normal, 0.0f, NULL, max_radius2, q);
        }
    q->radius2 = q->found == q->k ? q->dist2[0] : max_radius2;
    return q->found;
}

uint32_t photon_map_knn(const photon_map *m, vec3 x, float max_radius2, kdtree_query *q)
{
    return map_search(m, x, 0, v3s(0.0f), 0.0f, NULL, max_radius2, q);
}

uint32_t photon_map_knn_disc(const photon_map *m, vec3 x, vec3 normal, float flatten, float max_radius2,
                             kdtree_query *q)
{
    float c = flatten > 1.0f ? flatten : 1.0f;
    return map_search(m, x, 1, normal, c * c - 1.0f, NULL, max_radius2, q);
}

uint32_t photon_map_knn_surface(const photon_map *m, vec3 x, float flatten, const kdtree_filter *f,
                                float max_radius2, kdtree_query *q)
{
    float c = flatten > 1.0f ? flatten : 1.0f;
    return map_search(m, x, 1, f->normal, c * c - 1.0f, f, max_radius2, q);
}
