/*
 * kdtree.c — building the photon map's kd-tree and searching it.
 *
 * Build (docs/algorithms.md §2.3; Jensen 2001 §6.3 balance_segment, with
 * buckets): within each class, a node's photons are partitioned in place
 * at the boundary between its two halves of buckets, by selection along
 * the longest axis of its cell; the halves recurse until a node is one
 * bucket. The cell starts as the class's bounding box and is narrowed by
 * each split's planes. No copy of the photons is made.
 *
 * Search (docs/algorithms.md §2.4): the classes' subtrees are entered
 * nearest box first; within one, descend to the near child and push the
 * far child with the squared distance from x to its cell, kept
 * incrementally per axis (Arya & Mount 1993, "Algorithms for fast vector
 * quantization", as nanoflann does), and re-test it at pop time, when the
 * radius may have shrunk. Found photons go into a max-heap of k entries
 * once k are held, so the radius shrinks to the k-th distance.
 */
#include "photons/kdtree.h"

#include <stdlib.h>
#include <string.h>

#include "util/parallel.h"

/* Classes of fewer photons are built whole by one thread. */
#define KDTREE_PARALLEL_MIN 65536u
/* Subtrees per thread the top levels are cut into (below the top, each is
 * built by one thread). */
#define KDTREE_PARALLEL_ITEMS_PER_THREAD 4u

/* A subtree is at most 31 levels deep (n ≤ 2^31 − 1 in buckets of ≥ 1),
 * so a descent pushes at most 31 far children, and popped last in,
 * first out the entries above any base lie at increasing levels: at most
 * 31 of them. The nearest-first picks of a search's first phase
 * (map_search) break that order, so they are made only while
 * KDTREE_NEAREST_FIRST_ROOM entries are free; the 24 class roots come
 * first. */
#define KDTREE_STACK_SIZE 256
#define KDTREE_NEAREST_FIRST_ROOM 64

uint32_t kdtree_depth(uint32_t n)
{
    uint32_t d = 0;
    while (((uint64_t)n + ((uint64_t)1 << d) - 1) >> d > KDTREE_BUCKET)
        d++;
    return d;
}

/* The first photon of bucket j (0 ≤ j ≤ 2^depth) of a class of n photons,
 * relative to the class's start. */
static inline uint32_t bucket_start(uint32_t n, uint32_t depth, uint32_t j)
{
    return (uint32_t)(((uint64_t)j * n) >> depth);
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
            b.lo[a] = p[i].position[a] < b.lo[a] ? p[i].position[a] : b.lo[a];
            b.hi[a] = p[i].position[a] > b.hi[a] ? p[i].position[a] : b.hi[a];
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

/* Ranges of at least this many photons look at the cancel flag first:
 * well under a millisecond of work between two looks. */
#define KDTREE_CANCEL_GRAIN 16384u

/* Floyd & Rivest's SELECT (CACM 1975, Algorithm 489): afterwards a[m]
 * holds the key of rank m, everything before it ≤ a[m] ≤ everything after
 * it. A range of more than FR_SAMPLE_MIN photons first selects within a
 * sample of about n^(2/3)/2 around the rank, so that the pivot it then
 * partitions about lies a few sample deviations from the rank: the big
 * range is partitioned about once, n + min(m, n − m) + o(n) comparisons,
 * where Hoare's FIND with a median-of-three pivot makes about 2.75n and
 * as many passes over the photons (docs/algorithms.md §2.3). The sample's
 * size and bounds are integer arithmetic and correctly rounded square
 * roots only, so the tree is the same on every machine. The scans stop on
 * keys equal to the pivot, so runs of equal keys (photons on an
 * axis-aligned wall) are split evenly. */
#define FR_SAMPLE_MIN 600

static inline float key(const photon *a, ptrdiff_t i, int axis) { return a[i].position[axis]; }

/* ⌊log2 n⌋ + 1 for n ≥ 1. */
static int bit_length(uint64_t n) { return 64 - __builtin_clzll(n); }

/* The sample's bounds [*lo, *hi] around rank k of [left, right]:
 * s = n^(2/3)/2 photons, offset toward the middle by sd = √(ln n · s(n − s)/n)/2
 * (Floyd & Rivest's constants), with n^(2/3) taken as 2^⌊(2/3)·bits⌋ and
 * ln n as 0.69·bits (bits = ⌊log2 n⌋ + 1): any s near theirs works. In
 * integers but for one correctly rounded square root, so the bounds are
 * the same on every machine. */
static void sample_bounds(ptrdiff_t left, ptrdiff_t right, ptrdiff_t k, ptrdiff_t *lo, ptrdiff_t *hi)
{
    uint64_t n = (uint64_t)(right - left + 1), i = (uint64_t)(k - left + 1);
    int bits = bit_length(n);
    uint64_t s = (uint64_t)1 << (2 * bits / 3 - 1);  /* n ≤ 2^31: s ≤ 2^20, s·n < 2^52 */
    uint64_t spread = s * (n - s) / n;               /* s(n − s)/n ≤ s */
    ptrdiff_t sd = (ptrdiff_t)(sqrt((double)(69u * (uint64_t)bits * spread / 100u)) / 2.0);
    if (2 * i < n)
        sd = -sd;
    ptrdiff_t new_lo = k - (ptrdiff_t)(i * s / n) + sd, new_hi = k + (ptrdiff_t)((n - i) * s / n) + sd;
    *lo = new_lo > left ? new_lo : left;
    *hi = new_hi < right ? new_hi : right;
}

static int select_rank(photon *a, ptrdiff_t left, ptrdiff_t right, ptrdiff_t k, int axis, atomic_int *cancel)
{
    while (right > left) {
        /* One partition of millions of photons takes milliseconds. */
        if (right - left >= (ptrdiff_t)KDTREE_CANCEL_GRAIN && cancel &&
            atomic_load_explicit(cancel, memory_order_relaxed))
            return 0;
        if (right - left > FR_SAMPLE_MIN) {
            ptrdiff_t lo, hi;
            sample_bounds(left, right, k, &lo, &hi);
            if (!select_rank(a, lo, hi, k, axis, cancel))
                return 0;
        }
        /* Partition [left, right] about t = a[k], which ends at j. */
        float t = key(a, k, axis);
        ptrdiff_t i = left, j = right;
        swap_photons(&a[left], &a[k]);
        if (key(a, right, axis) > t)
            swap_photons(&a[right], &a[left]);
        while (i < j) {
            swap_photons(&a[i], &a[j]);
            i++;
            j--;
            while (key(a, i, axis) < t)
                i++;
            while (key(a, j, axis) > t)
                j--;
        }
        if (key(a, left, axis) == t)
            swap_photons(&a[left], &a[j]);
        else {
            j++;
            swap_photons(&a[j], &a[right]);
        }
        if (j <= k)
            left = j + 1;
        if (k <= j)
            right = j - 1;
    }
    return 1;
}

static int select_median(photon *a, uint32_t n, uint32_t m, int axis, atomic_int *cancel)
{
    return n == 0 || select_rank(a, 0, (ptrdiff_t)n - 1, (ptrdiff_t)m, axis, cancel);
}

/* One class's build: its photons p[0..n) in 2^depth buckets, and its
 * split planes. */
typedef struct class_build {
    photon *p;
    uint32_t n, depth;
    kdtree_split *splits; /* the class's, in heap order: node h at splits[h − 1] */
    atomic_int *cancel;
} class_build;

/* A node still to be built: node h (1-based heap index) of a class's
 * subtree, covering buckets [j0, j1), so photons from bucket_start(j0) to
 * bucket_start(j1), inside `cell`. */
typedef struct build_node_job {
    const class_build *cb;
    uint32_t node, j0, j1;
    cell_box cell;
} build_node_job;

/* Splits node t (not a bucket): selects its photons' median along its
 * cell's longest axis, writes its split plane, and returns its two
 * children in child[0] (left) and child[1]. 0 if cancelled. */
static int split_node(const build_node_job *t, build_node_job child[2])
{
    const class_build *cb = t->cb;
    uint32_t jm = t->j0 + (t->j1 - t->j0) / 2;
    uint32_t s = bucket_start(cb->n, cb->depth, t->j0), e = bucket_start(cb->n, cb->depth, t->j1);
    uint32_t m = bucket_start(cb->n, cb->depth, jm);
    int axis = longest_axis(&t->cell);
    if (!select_median(cb->p + s, e - s, m - s, axis, cb->cancel))
        return 0;
    /* After the selection p[m] is the least of the right half along the
     * axis; the left half's greatest takes one pass. */
    float lo = cb->p[s].position[axis];
    for (uint32_t i = s + 1; i < m; i++)
        lo = cb->p[i].position[axis] > lo ? cb->p[i].position[axis] : lo;
    float hi = cb->p[m].position[axis];
    cb->splits[t->node - 1] = (kdtree_split){lo, hi, (uint32_t)axis};
    child[0] = child[1] = *t;
    child[0].node = 2 * t->node;
    child[0].j1 = jm;
    child[0].cell.hi[axis] = lo;
    child[1].node = 2 * t->node + 1;
    child[1].j0 = jm;
    child[1].cell.lo[axis] = hi;
    return 1;
}

/* Builds the subtree of t, down to its buckets. 0 if cancelled. */
static int build_subtree(const build_node_job *t)
{
    if (t->j1 - t->j0 == 1)
        return 1; /* a bucket */
    build_node_job child[2];
    return split_node(t, child) && build_subtree(&child[0]) && build_subtree(&child[1]);
}

/* The nodes of a build still to be made, level by level. */
typedef struct build_plan {
    build_node_job *items, *next; /* this level's nodes; the next level's (2 per node) */
    uint32_t count;
    uint32_t top_levels;          /* the levels split node by node across threads */
    atomic_int failed;            /* a node was cancelled */
} build_plan;

/* A node splits at a top level only if its class is large enough to share
 * out, and it is not a bucket. */
static int splits_at_top(const build_node_job *t)
{
    return t->cb->n >= KDTREE_PARALLEL_MIN && t->j1 - t->j0 > 1;
}

static void split_top(void *ctx, uint32_t item, uint32_t thread)
{
    (void)thread;
    build_plan *plan = ctx;
    const build_node_job *t = &plan->items[item];
    build_node_job *child = &plan->next[2 * item];
    if (!splits_at_top(t))
        child[0] = *t;
    else if (!split_node(t, child))
        atomic_store(&plan->failed, 1);
}

static void build_pending(void *ctx, uint32_t item, uint32_t thread)
{
    (void)thread;
    build_plan *plan = ctx;
    if (!build_subtree(&plan->items[item]))
        atomic_store(&plan->failed, 1);
}

static uint32_t job_photons(const build_node_job *t)
{
    return bucket_start(t->cb->n, t->cb->depth, t->j1) - bucket_start(t->cb->n, t->cb->depth, t->j0);
}

/* Largest first, so that no thread is left with a big one at the end;
 * ties by position in the plan, so the order is the same every time (the
 * tree does not depend on it: subtrees own disjoint photons and planes). */
static int compare_jobs(const void *a, const void *b)
{
    const build_node_job *x = a, *y = b;
    uint32_t nx = job_photons(x), ny = job_photons(y);
    if (nx != ny)
        return nx < ny ? 1 : -1;
    return x < y ? -1 : (x > y);
}

/* The split planes and class boxes of one map. */
static int prepare_map(photon_map *m, atomic_int *cancel)
{
    uint64_t total = 0;
    for (unsigned c = 0; c < PHOTON_CLASSES; c++) {
        photon_class_tree *t = &m->classes[c];
        t->depth = kdtree_depth(t->count);
        t->first_split = (uint32_t)total;
        total += ((uint64_t)1 << t->depth) - 1;
    }
    free(m->splits);
    m->splits = NULL;
    m->split_count = 0;
    if (total > 0) {
        m->splits = malloc(sizeof(kdtree_split) * (size_t)total);
        if (!m->splits)
            return 0;
        m->split_count = (uint32_t)total;
    }
    for (unsigned c = 0; c < PHOTON_CLASSES; c++) {
        photon_class_tree *t = &m->classes[c];
        if (t->count == 0)
            continue;
        if (cancel && atomic_load_explicit(cancel, memory_order_relaxed))
            return 0;
        cell_box box = bounds_of(m->photons + t->start, t->count);
        memcpy(t->lo, box.lo, sizeof(t->lo));
        memcpy(t->hi, box.hi, sizeof(t->hi));
    }
    return 1;
}

int kdtree_build(photon_map *const *maps, unsigned count, uint32_t threads, atomic_int *cancel)
{
    threads = parallel_thread_count(threads);
    uint32_t classes = 0;
    for (unsigned i = 0; i < count; i++) {
        if (!prepare_map(maps[i], cancel))
            return 0;
        for (unsigned c = 0; c < PHOTON_CLASSES; c++)
            classes += maps[i]->classes[c].count > 0;
    }
    /* The top levels are split node by node, each level's nodes side by
     * side (the root's selection alone runs on one thread), until every
     * thread has several subtrees; the subtrees below are then built
     * whole, largest first. */
    build_plan plan = {NULL, NULL, 0, 0, 0};
    while (threads > 1 && (1u << plan.top_levels) < KDTREE_PARALLEL_ITEMS_PER_THREAD * threads)
        plan.top_levels++;
    uint32_t room = classes << plan.top_levels;
    class_build *builds = malloc(sizeof(class_build) * (classes ? classes : 1));
    plan.items = malloc(sizeof(build_node_job) * (room ? room : 1));
    plan.next = malloc(sizeof(build_node_job) * (room ? room : 1));
    int ok = builds && plan.items && plan.next;
    for (unsigned i = 0; ok && i < count; i++) {
        photon_map *m = maps[i];
        for (unsigned c = 0; c < PHOTON_CLASSES; c++) {
            const photon_class_tree *t = &m->classes[c];
            if (t->count == 0)
                continue;
            /* A map whose classes all fit in one bucket has no split array
             * (NULL, which no offset may be added to, even zero). */
            kdtree_split *splits = m->splits ? m->splits + t->first_split : NULL;
            builds[plan.count] = (class_build){m->photons + t->start, t->count, t->depth, splits, cancel};
            cell_box box;
            memcpy(box.lo, t->lo, sizeof(box.lo));
            memcpy(box.hi, t->hi, sizeof(box.hi));
            plan.items[plan.count] = (build_node_job){&builds[plan.count], 1, 0, 1u << t->depth, box};
            plan.count++;
        }
    }
    for (uint32_t level = 0; ok && level < plan.top_levels; level++) {
        /* Each node leaves its children (or itself, if it does not split)
         * at 2i, 2i + 1 of the next level, then the gaps are closed in
         * order: the next level's list depends only on this one's. */
        for (uint32_t i = 0; i < plan.count; i++)
            plan.next[2 * i + 1].cb = NULL;
        ok = parallel_for(plan.count, threads, split_top, &plan, cancel) && !atomic_load(&plan.failed);
        uint32_t n = 0;
        for (uint32_t i = 0; ok && i < plan.count; i++) {
            plan.items[n++] = plan.next[2 * i];
            if (plan.next[2 * i + 1].cb)
                plan.items[n++] = plan.next[2 * i + 1];
        }
        plan.count = n;
    }
    if (ok && plan.count) {
        qsort(plan.items, plan.count, sizeof(build_node_job), compare_jobs);
        ok = parallel_for(plan.count, threads, build_pending, &plan, cancel) && !atomic_load(&plan.failed);
    }
    free(builds);
    free(plan.items);
    free(plan.next);
    return ok;
}

/* ---- search -------------------------------------------------------------- */

int kdtree_query_init(kdtree_query *q, uint32_t k)
{
    q->k = k;
    q->found = 0;
    q->radius2 = 0.0f;
    /* On cache lines of its own: the heap is written on every
     * replacement, and queries are made one per thread (util/parallel.h,
     * PARALLEL_CACHE_LINE). */
    q->heap = parallel_scratch_calloc(1, sizeof(uint64_t) * ((size_t)k + 1));
    return q->heap != NULL;
}

void kdtree_query_free(kdtree_query *q)
{
    if (!q)
        return;
    free(q->heap);
    q->heap = NULL;
    q->k = 0;
    q->found = 0;
}

/* A heap key (kdtree.h; read back with kdtree_key_dist2): d2 ≥ +0 (a sum
 * of squares, never −0), whose bit pattern orders as the float does. */
static inline uint64_t heap_key(float d2, uint32_t index)
{
    uint32_t bits;
    memcpy(&bits, &d2, sizeof bits);
    return (uint64_t)bits << 32 | index;
}

/* Max-heap of keys (0-based: children of j are 2j+1, 2j+2): moves `key`
 * down from j to its place. heap[size] is 0, below every key but an equal
 * one, so the last parent's missing right child is never taken and the
 * loop tests no bound but the first child's. */
static inline void heap_sift_down(uint64_t *heap, uint32_t size, uint32_t j, uint64_t key)
{
    for (uint32_t c = 2 * j + 1; c < size; c = 2 * j + 1) {
        uint64_t left = heap[c], right = heap[c + 1];
        int take_right = right > left; /* the larger child, without a branch to mispredict */
        uint64_t larger = take_right ? right : left;
        if (larger <= key)
            break;
        heap[j] = larger;
        j = c + take_right;
    }
    heap[j] = key;
}

/* Takes a photon at d2 < current radius². Until k are held they are only
 * appended (Jensen's lazy heap: most searches that do not fill up never pay
 * for heap order); the k-th is followed by an O(k) heapify, after which each
 * new photon replaces the farthest and the radius shrinks to the new
 * farthest. Returns the new radius². */
static inline float knn_add(kdtree_query *q, float d2, uint32_t i, float r2)
{
    uint64_t key = heap_key(d2, i);
    if (q->found < q->k) {
        q->heap[q->found] = key;
        if (++q->found < q->k)
            return r2;
        q->heap[q->k] = 0;
        for (uint32_t j = q->k / 2; j-- > 0;)
            heap_sift_down(q->heap, q->k, j, q->heap[j]);
        return kdtree_key_dist2(q->heap[0]);
    }
    heap_sift_down(q->heap, q->k, 0, key);
    return kdtree_key_dist2(q->heap[0]);
}

/* The largest n·m over the unit normals m of facing c (dominant axis
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

/* A search near the bottom of a subtree scans most of the few buckets
 * below the node it reaches (at k = 50, some 36 buckets a search): their
 * photons are asked for from memory at once, when the node of
 * 2^KDTREE_PREFETCH_LEVELS buckets is entered, instead of one bucket's
 * cache lines at a time as the scan gets to them. */
#define KDTREE_PREFETCH_LEVELS 2u
static inline void prefetch_buckets(const photon *p, uint32_t n, uint32_t depth, uint32_t h, uint32_t below)
{
    uint32_t j0 = (h << below) - (1u << depth), j1 = j0 + (1u << below);
    const char *a = (const char *)(p + bucket_start(n, depth, j0)), *b = (const char *)(p + bucket_start(n, depth, j1));
    for (; a < b; a += 64)
        __builtin_prefetch(a);
}

/* One search for every metric and filter; `disc` and whether `filter` is
 * NULL are constants at each call site, so the compiler specialises the
 * inlined copy. */
typedef struct search_entry {
    uint32_t cls, node; /* node: heap index within the class's subtree */
    float d2;           /* squared distance from x to the node's cell */
    float off[3];       /* its per-axis parts: d2 = Σ off² */
} search_entry;

static inline __attribute__((always_inline)) uint32_t map_search(const photon_map *m, vec3 x, int disc,
                                                                 vec3 normal, float c2m1,
                                                                 const kdtree_filter *f, float max_radius2,
                                                                 kdtree_query *q, kdtree_visit visit,
                                                                 void *ctx)
{
    /* visit non-NULL: a range search, which hands every photon inside
     * the radius to visit and keeps none (q is unused). */
    uint32_t visited = 0;
    if (!visit) {
        q->found = 0;
        q->radius2 = max_radius2;
    }
    if (!m->built || (!visit && q->k == 0) || !(max_radius2 > 0.0f))
        return 0;
    const float xq[3] = {x.x, x.y, x.z};
    float r2 = max_radius2;
    search_entry stack[KDTREE_STACK_SIZE];
    int top = 0;
    /* Whether the filter can accept a facing's photons: 1 yes, 0 no, −1
     * not asked yet. Asked only of the classes near enough to enter, so
     * a query far from any wall pays only for its own facing's. */
    int facing_ok[PHOTON_FACINGS];
    for (unsigned c = 0; c < PHOTON_FACINGS; c++)
        facing_ok[c] = f ? -1 : 1;
    /* The classes' roots, farthest first on the stack so that the
     * nearest is searched first and sets the radius for the rest. */
    for (unsigned c = 0; c < PHOTON_CLASSES; c++) {
        const photon_class_tree *t = &m->classes[c];
        if (t->count == 0 || (f && (photon_class_flags(c) & f->exclude_flags)))
            continue;
        search_entry e = {c, 1, 0.0f, {0.0f, 0.0f, 0.0f}};
        for (int a = 0; a < 3; a++) {
            float below = t->lo[a] - xq[a], above = xq[a] - t->hi[a];
            e.off[a] = below > 0.0f ? below : above > 0.0f ? above : 0.0f;
            e.d2 += e.off[a] * e.off[a];
        }
        if (!(e.d2 < r2))
            continue;
        int *ok = &facing_ok[c / 4u];
        if (*ok < 0)
            *ok = !(facing_class_max_dot(c / 4u, f->normal) < f->min_normal_cos);
        if (!*ok)
            continue;
        int j = top++;
        for (; j > 0 && stack[j - 1].d2 < e.d2; j--) /* stable: equal distances keep class order */
            stack[j] = stack[j - 1];
        stack[j] = e;
    }
    while (top > 0) {
        /* Until k photons are held the radius is the maximum, and the
         * farthest of the first k found sets where it shrinks to: so take
         * the nearest cell waiting, not the last pushed (best-first, as
         * Arya & Mount's priority search), and the first k are near x.
         * At k = 50 and a maximum radius five times the k-th distance,
         * heap replacements fell from 90 to 42 a search and photons
         * scanned from 270 to 188 (docs/algorithms.md §2.4). Once k are
         * held, last in, first out. */
        if (!visit && q->found < q->k && top > 1 && top <= KDTREE_STACK_SIZE - KDTREE_NEAREST_FIRST_ROOM) {
            int nearest = top - 1;
            for (int j = top - 2; j >= 0; j--)
                nearest = stack[j].d2 < stack[nearest].d2 ? j : nearest;
            if (nearest != top - 1) {
                search_entry e = stack[nearest];
                stack[nearest] = stack[top - 1];
                stack[top - 1] = e;
            }
        }
        /* Read field by field: the entry's slot is reused by the first
         * far child pushed, and a whole-struct copy went through memory
         * (a stalled store-to-load forward at every push). */
        const search_entry *popped = &stack[--top];
        float cell_d2 = popped->d2;
        if (!(cell_d2 < r2))
            continue;
        uint32_t cls = popped->cls, h = popped->node;
        float off[3] = {popped->off[0], popped->off[1], popped->off[2]};
        const photon_class_tree *t = &m->classes[cls];
        const kdtree_split *splits = m->splits ? m->splits + t->first_split : NULL; /* NULL: no class splits */
        uint32_t leaves = 1u << t->depth;
        const photon *class_photons = m->photons + t->start;
        /* Levels from h to its buckets. A cell popped below the prefetch
         * level lies under a node whose buckets the descent that pushed it
         * asked for, and asking again on every pop at or below that level
         * cost 5–10 % of a search whose photons are in cache. The cells
         * popped at that level (a sibling of a node the descent asked for,
         * or a class of at most 4 buckets) are not asked for at all:
         * asking for those alone measured no faster (docs/benchmarks.md). */
        uint32_t below = t->depth - (31u - (uint32_t)__builtin_clz(h));
        /* Descend toward x, leaving the far children on the stack. */
        while (h < leaves) {
            const kdtree_split *sp = &splits[h - 1];
            uint32_t a = sp->axis;
            float to_lo = xq[a] - sp->lo, to_hi = xq[a] - sp->hi;
            int right = to_lo + to_hi > 0.0f; /* nearer the right child's side of the gap */
            float cut = right ? to_lo : to_hi; /* to the far child's plane */
            float far_d2 = cell_d2 - off[a] * off[a] + cut * cut;
            /* The far child is written above the stack's top always and
             * kept only if it lies within the radius: whether it does goes
             * either way, and a branch on it was guessed wrong often
             * enough to cost 3–7 % of a search (docs/benchmarks.md). The
             * slot exists: the bound above KDTREE_STACK_SIZE keeps top
             * under KDTREE_STACK_SIZE − KDTREE_NEAREST_FIRST_ROOM + 31. */
            search_entry *far = &stack[top];
            far->cls = cls;
            far->node = 2 * h + !right;
            far->d2 = far_d2;
            far->off[0] = off[0];
            far->off[1] = off[1];
            far->off[2] = off[2];
            far->off[a] = cut;
            top += far_d2 < r2;
            h = 2 * h + right;
            if (--below == KDTREE_PREFETCH_LEVELS)
                prefetch_buckets(class_photons, t->count, t->depth, h, below);
        }
        uint32_t j = h - leaves, s = t->start + bucket_start(t->count, t->depth, j),
                 end = t->start + bucket_start(t->count, t->depth, j + 1);
        /* The bucket's distances first, and the photons inside the radius
         * as it stands listed without a branch; then those, in order, each
         * tested again against the radius, which shrinks as they are
         * added. The same photons are added in the same order as by one
         * test per photon, but a test that goes either way about half the
         * time (a k = 50 search keeps 104 of the 197 photons it scans)
         * is no longer a branch the processor must guess. */
        float d2s[KDTREE_BUCKET];
        uint32_t inside[KDTREE_BUCKET], n_inside = 0;
        for (uint32_t i = s; i < end; i++) {
            const photon *p = &m->photons[i];
            float d2 = disc ? kdtree_disc_dist2(p, x, normal, c2m1) : kdtree_dist2(p, x);
            d2s[i - s] = d2;
            inside[n_inside] = i;
            n_inside += d2 < r2;
        }
        for (uint32_t c = 0; c < n_inside; c++) {
            uint32_t i = inside[c];
            const photon *p = &m->photons[i];
            float d2 = d2s[i - s];
            if (d2 < r2 && (!f || kdtree_filter_accepts(f, p))) {
                if (visit) {
                    visit(ctx, p, d2);
                    visited++;
                } else {
                    r2 = knn_add(q, d2, i, r2);
                }
            }
        }
    }
    if (visit)
        return visited;
    q->radius2 = r2; /* still max_radius2 unless k were found */
    return q->found;
}

uint32_t photon_map_knn(const photon_map *m, vec3 x, float max_radius2, kdtree_query *q)
{
    return map_search(m, x, 0, v3s(0.0f), 0.0f, NULL, max_radius2, q, NULL, NULL);
}

uint32_t photon_map_knn_disc(const photon_map *m, vec3 x, vec3 normal, float flatten, float max_radius2,
                             kdtree_query *q)
{
    float c = flatten > 1.0f ? flatten : 1.0f;
    return map_search(m, x, 1, normal, c * c - 1.0f, NULL, max_radius2, q, NULL, NULL);
}

uint32_t photon_map_knn_surface(const photon_map *m, vec3 x, float flatten, const kdtree_filter *f,
                                float max_radius2, kdtree_query *q)
{
    float c = flatten > 1.0f ? flatten : 1.0f;
    return map_search(m, x, 1, f->normal, c * c - 1.0f, f, max_radius2, q, NULL, NULL);
}

uint32_t photon_map_range_surface(const photon_map *m, vec3 x, float flatten, const kdtree_filter *f,
                                  float radius2, kdtree_visit visit, void *ctx)
{
    float c = flatten > 1.0f ? flatten : 1.0f;
    return map_search(m, x, 1, f->normal, c * c - 1.0f, f, radius2, NULL, visit, ctx);
}
