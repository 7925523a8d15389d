/*
 * test_kdtree.c — the left-balanced kd-tree against brute force
 * (docs/algorithms.md §2 and §9, check 3).
 *
 * Point sets of every size 1…300 and 10k/100k, in shapes that break naive
 * trees: duplicates, all points equal, coplanar, collinear, sorted input,
 * integer grids (many exactly equal distances) and box faces (photons on
 * walls). For each: the heap holds the same photons, satisfies the kd
 * ordering on every node's axis, splits along the longest axis of each
 * node's cell, is byte-identical when rebuilt, finds every heap slot
 * (including the last ones, which Jensen's n/2 − 1 test never visits), and
 * its k-nearest results equal brute force for several k and radii, in the
 * Euclidean and the disc metric. Queries from several threads at once
 * agree with single-threaded ones.
 */
#include <pthread.h>
#include <string.h>

#include "photons/kdtree.h"
#include "photons/photon.h"
#include "sampling/sampler.h"
#include "test_util.h"

static float rnd(uint32_t *state)
{
    *state = hash_u32(*state + 0x9e3779b9U);
    return u32_to_unit_float(*state);
}

/* ---- point sets ---------------------------------------------------------- */

enum {
    SET_UNIFORM,
    SET_DUPLICATES, /* every point three times */
    SET_EQUAL,      /* all points at one place */
    SET_PLANE,      /* z = const: photons on a floor */
    SET_LINE,       /* collinear, along a diagonal */
    SET_SORTED,     /* sorted by x, then y: the quickselect's worst case with a bad pivot */
    SET_GRID,       /* integer coordinates: many equal keys and equal distances */
    SET_BOX,        /* on the six faces of a box, as photons land in a room */
    SET_COUNT
};
static const char *const set_names[SET_COUNT] = {"uniform", "duplicates", "equal", "plane",
                                                 "line",    "sorted",     "grid",  "box"};

static vec3 point_of(int kind, uint32_t i, uint32_t n, uint32_t *s)
{
    switch (kind) {
    case SET_DUPLICATES: {
        uint32_t t = 1000 + i / 3; /* the same point for i = 3j, 3j+1, 3j+2 */
        return v3(rnd(&t), rnd(&t), rnd(&t));
    }
    case SET_EQUAL:
        return v3(0.25f, -1.5f, 3.0f);
    case SET_PLANE:
        return v3(rnd(s), rnd(s), 0.5f);
    case SET_LINE: {
        float t = rnd(s);
        return v3(t, 2.0f * t, -t);
    }
    case SET_SORTED:
        return v3((float)i / (float)n, (float)(i % 7) / 7.0f, 0.0f);
    case SET_GRID:
        return v3((float)(int)(rnd(s) * 6), (float)(int)(rnd(s) * 6), (float)(int)(rnd(s) * 6));
    case SET_BOX: {
        int face = (int)(rnd(s) * 6);
        float u = rnd(s), v = rnd(s), w = (face & 1) ? 1.0f : 0.0f;
        return face < 2 ? v3(w, u, v) : face < 4 ? v3(u, w, v) : v3(u, v, w);
    }
    default:
        return v3(rnd(s), rnd(s), rnd(s));
    }
}

static photon *make_set(int kind, uint32_t n, uint32_t seed)
{
    photon *p = malloc(sizeof(photon) * (n ? n : 1));
    uint32_t s = seed;
    for (uint32_t i = 0; i < n; i++) {
        vec3 pos = point_of(kind, i, n, &s);
        /* Power, direction, normal and flags vary per photon so that the
         * multiset check below tells photons at the same place apart and
         * the filtered search has something to filter. */
        vec3 d = v3_normalize(v3(rnd(&s) - 0.5f, rnd(&s) - 0.5f, rnd(&s) - 0.5f));
        vec3 nrm = v3_normalize(v3(rnd(&s) - 0.5f, rnd(&s) - 0.5f, rnd(&s) - 0.5f));
        p[i] = photon_make(pos, v3(rnd(&s), 1.0f, 0.5f), d, nrm,
                           (i % 3 == 0 ? PHOTON_CAUSTIC : 0) | (i % 5 < 2 ? PHOTON_DIRECT : 0));
    }
    return p;
}

/* ---- structure checks ---------------------------------------------------- */

static int compare_bytes(const void *a, const void *b) { return memcmp(a, b, sizeof(photon)); }

/* The heap holds the same photons (the axis bits aside). */
static int same_multiset(const photon *in, const photon *tree, uint32_t n)
{
    photon *a = malloc(sizeof(photon) * n), *b = malloc(sizeof(photon) * n);
    for (uint32_t i = 0; i < n; i++) {
        a[i] = in[i];
        b[i] = tree[i];
        a[i].flags &= (uint16_t)~PHOTON_AXIS_MASK;
        b[i].flags &= (uint16_t)~PHOTON_AXIS_MASK;
    }
    qsort(a, n, sizeof(photon), compare_bytes);
    qsort(b, n, sizeof(photon), compare_bytes);
    int same = memcmp(a, b, sizeof(photon) * n) == 0;
    free(a);
    free(b);
    return same;
}

/* Every node of the subtree rooted at c lies on the `side` of split on axis
 * (≤ for the left subtree, ≥ for the right): walk the subtree level by
 * level, where its nodes are the ranges [c·2^d, c·2^d + 2^d − 1]. */
static int subtree_on_side(const photon *tree, uint32_t n, uint32_t c, int axis, float split, int right)
{
    for (uint64_t first = c, width = 1; first <= n; first *= 2, width *= 2)
        for (uint64_t j = first; j < first + width && j <= n; j++) {
            float v = tree[j - 1].position[axis];
            if (right ? v < split : v > split)
                return 0;
        }
    return 1;
}

static int heap_ordered(const photon *tree, uint32_t n)
{
    for (uint32_t i = 1; 2 * (uint64_t)i <= n; i++) {
        int axis = photon_axis(&tree[i - 1]);
        float split = tree[i - 1].position[axis];
        if (axis > 2 || !subtree_on_side(tree, n, 2 * i, axis, split, 0) ||
            (2 * i + 1 <= n && !subtree_on_side(tree, n, 2 * i + 1, axis, split, 1)))
            return 0;
    }
    return 1;
}

/* Each node splits on the longest axis of its cell: the bounding box of all
 * photons narrowed by the ancestors' planes (ties to the lower axis). */
static int cell_axes_ok(const photon *tree, uint32_t n, uint32_t i, float lo[3], float hi[3])
{
    if (i > n || 2 * i > n)
        return 1;
    const photon *p = &tree[i - 1];
    float e[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    int want = (e[0] >= e[1] && e[0] >= e[2]) ? 0 : (e[1] >= e[2] ? 1 : 2);
    int axis = photon_axis(p);
    if (axis != want)
        return 0;
    float split = p->position[axis], keep = hi[axis];
    hi[axis] = split;
    int ok = cell_axes_ok(tree, n, 2 * i, lo, hi);
    hi[axis] = keep;
    keep = lo[axis];
    lo[axis] = split;
    ok = ok && cell_axes_ok(tree, n, 2 * i + 1, lo, hi);
    lo[axis] = keep;
    return ok;
}

static int cell_axes_ok_root(const photon *tree, uint32_t n)
{
    float lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = hi[a] = tree[0].position[a];
        for (uint32_t i = 1; i < n; i++) {
            lo[a] = fminf(lo[a], tree[i].position[a]);
            hi[a] = fmaxf(hi[a], tree[i].position[a]);
        }
    }
    return cell_axes_ok(tree, n, 1, lo, hi);
}

/* ---- brute force --------------------------------------------------------- */

typedef struct metric {
    int disc;
    vec3 normal;
    float flatten;
    const kdtree_filter *filter; /* disc only: kdtree_knn_surface */
} metric;

/* The metric's distance, infinite for photons the filter rejects (they are
 * never found, whatever the radius). */
static float metric_dist2(const metric *m, const photon *p, vec3 x)
{
    if (!m->disc)
        return kdtree_dist2(p, x);
    if (m->filter && !kdtree_filter_accepts(m->filter, p))
        return INFINITY;
    float c = m->flatten > 1.0f ? m->flatten : 1.0f;
    return kdtree_disc_dist2(p, x, m->normal, c * c - 1.0f);
}

static uint32_t metric_knn(const metric *m, const photon *tree, uint32_t n, vec3 x, float r2, kdtree_query *q)
{
    if (m->filter)
        return kdtree_knn_surface(tree, n, x, m->flatten, m->filter, r2, q);
    return m->disc ? kdtree_knn_disc(tree, n, x, m->normal, m->flatten, r2, q) : kdtree_knn(tree, n, x, r2, q);
}

static int compare_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Brute-force distances for one query point: per photon and sorted. */
typedef struct brute {
    uint32_t n;
    float *d2;     /* per photon */
    float *sorted; /* ascending */
    uint8_t *seen; /* scratch for duplicate detection */
} brute;

static void brute_compute(brute *b, const metric *m, const photon *tree, uint32_t n, vec3 x)
{
    b->n = n;
    for (uint32_t i = 0; i < n; i++)
        b->d2[i] = b->sorted[i] = metric_dist2(m, &tree[i], x);
    qsort(b->sorted, n, sizeof(float), compare_float);
}

/* The search found a correct k-nearest set: the right count, the right
 * radius, its own distances, no photon twice, every photon strictly nearer
 * than the k-th distance present (ties at the k-th distance may be any). */
static int knn_matches(const brute *b, const kdtree_query *q, uint32_t k, float r2)
{
    uint32_t inside = 0;
    while (inside < b->n && b->sorted[inside] < r2)
        inside++;
    uint32_t want = inside < k ? inside : k;
    float want_r2 = (k > 0 && inside >= k) ? b->sorted[k - 1] : r2;
    if (q->found != want || q->radius2 != want_r2)
        return 0;
    memset(b->seen, 0, b->n);
    uint32_t nearer = 0;
    for (uint32_t j = 0; j < q->found; j++) {
        uint32_t i = q->index[j];
        if (i >= b->n || b->seen[i] || q->dist2[j] != b->d2[i] || !(q->dist2[j] < r2) ||
            q->dist2[j] > want_r2)
            return 0;
        b->seen[i] = 1;
        nearer += q->dist2[j] < want_r2;
    }
    uint32_t nearer_all = 0;
    while (nearer_all < b->n && b->sorted[nearer_all] < want_r2)
        nearer_all++;
    return k == 0 || nearer == nearer_all;
}

/* ---- one point set ------------------------------------------------------- */

typedef struct set_stats {
    int builds, queries, bad_multiset, bad_order, bad_axes, bad_determinism, bad_slots, bad_knn;
} set_stats;

/* A query at each heap slot's own position (k = 1, tiny radius) finds a
 * photon at distance 0: a slot the traversal never visits fails. Jensen's
 * `index < n/2 − 1` test skips the children of nodes n/2 − 1 and n/2, i.e.
 * some of the slots n−3 … n. `first` limits the check to the slots first…n. */
static int slots_found(const photon *tree, uint32_t n, uint32_t first, kdtree_query *q1)
{
    for (uint32_t i = first < 1 ? 1 : first; i <= n; i++) {
        vec3 x = photon_position(&tree[i - 1]);
        if (kdtree_knn(tree, n, x, 1e-12f, q1) != 1 || q1->dist2[0] != 0.0f)
            return 0;
    }
    return 1;
}

static vec3 query_point(const photon *tree, uint32_t n, uint32_t j, uint32_t *s)
{
    if (j % 3 == 0) /* exactly on a photon */
        return photon_position(&tree[(uint32_t)(rnd(s) * n) % n]);
    if (j % 7 == 1) /* well outside the points */
        return v3(-3.0f + rnd(s), 4.0f, 2.0f * rnd(s));
    vec3 p = photon_position(&tree[(uint32_t)(rnd(s) * n) % n]);
    return v3_add(p, v3(0.2f * rnd(s) - 0.1f, 0.2f * rnd(s) - 0.1f, 0.2f * rnd(s) - 0.1f));
}

static const uint32_t ks[] = {1, 5, 50};
static const float radii2[] = {0.003f * 0.003f, 0.05f * 0.05f, 0.3f * 0.3f, INFINITY};

/* k-NN against brute force at `queries` points, every metric (Euclidean,
 * disc, disc with a surface filter), all k and radii. */
static void check_queries(const photon *tree, uint32_t n, int queries, uint32_t seed, kdtree_query qk[3],
                          brute *b, set_stats *st)
{
    uint32_t s = seed;
    for (int j = 0; j < queries; j++) {
        vec3 x = query_point(tree, n, (uint32_t)j, &s);
        int mode = (j >> 1) % 3;
        metric m = {mode > 0, v3_normalize(v3(rnd(&s) - 0.5f, rnd(&s) - 0.5f, 1.0f)), 6.0f, NULL};
        kdtree_filter f = {m.normal, 0.2f, PHOTON_CAUSTIC, (uint16_t)(j & 1)};
        if (mode == 2)
            m.filter = &f;
        brute_compute(b, &m, tree, n, x);
        for (int ki = 0; ki < 3; ki++)
            for (int ri = 0; ri < 4; ri++) {
                metric_knn(&m, tree, n, x, radii2[ri], &qk[ki]);
                st->queries++;
                if (!knn_matches(b, &qk[ki], ks[ki], radii2[ri])) {
                    st->bad_knn++;
                    if (st->bad_knn <= 3)
                        fprintf(stderr, "  knn mismatch: n=%u k=%u r2=%g disc=%d found=%u\n", n, ks[ki],
                                (double)radii2[ri], m.disc, qk[ki].found);
                }
            }
    }
}

/* Builds one set and runs every check; `all_slots` checks every heap slot,
 * otherwise only the last half (n/2 … n), where Jensen's bug lives. */
static void check_set(int kind, uint32_t n, int queries, int all_slots, kdtree_query qk[3], brute *b,
                      set_stats *st)
{
    uint32_t seed = hash_combine((uint32_t)kind, n);
    photon *in = make_set(kind, n, seed);
    photon *tree = malloc(sizeof(photon) * n), *again = malloc(sizeof(photon) * n);
    memcpy(tree, in, sizeof(photon) * n);
    memcpy(again, in, sizeof(photon) * n);
    st->builds++;
    if (!kdtree_build(tree, n, NULL) || !kdtree_build(again, n, NULL)) {
        st->bad_multiset++;
        goto done;
    }
    st->bad_determinism += memcmp(tree, again, sizeof(photon) * n) != 0;
    st->bad_multiset += !same_multiset(in, tree, n);
    st->bad_order += !heap_ordered(tree, n);
    st->bad_axes += !cell_axes_ok_root(tree, n);
    st->bad_slots += !slots_found(tree, n, all_slots ? 1 : n / 2, &qk[0]);
    check_queries(tree, n, queries, seed, qk, b, st);
done:
    free(in);
    free(tree);
    free(again);
}

static void report(const char *what, const set_stats *st)
{
    CHECK_MSG(st->bad_multiset == 0, "%s: %d trees lost or duplicated photons", what, st->bad_multiset);
    CHECK_MSG(st->bad_order == 0, "%s: %d trees violate the kd ordering", what, st->bad_order);
    CHECK_MSG(st->bad_axes == 0, "%s: %d trees split off the cell's longest axis", what, st->bad_axes);
    CHECK_MSG(st->bad_determinism == 0, "%s: %d rebuilds differ", what, st->bad_determinism);
    CHECK_MSG(st->bad_slots == 0, "%s: %d trees have heap slots the search never reaches", what,
              st->bad_slots);
    CHECK_MSG(st->bad_knn == 0, "%s: %d of %d k-NN queries differ from brute force", what, st->bad_knn,
              st->queries);
}

static void brute_init(brute *b, uint32_t n)
{
    b->d2 = malloc(sizeof(float) * n);
    b->sorted = malloc(sizeof(float) * n);
    b->seen = malloc(n);
}

static void brute_free(brute *b)
{
    free(b->d2);
    free(b->sorted);
    free(b->seen);
}

/* ---- the tests ----------------------------------------------------------- */

static void test_left_size(void)
{
    CHECK(kdtree_left_size(1) == 0);
    CHECK(kdtree_left_size(2) == 1);
    CHECK(kdtree_left_size(3) == 1);
    CHECK(kdtree_left_size(7) == 3);
    CHECK(kdtree_left_size(10) == 6);
    CHECK(kdtree_left_size(14) == 7);
    /* Mitsuba's leftSubtreeSize, and the left subtree's size counted in a
     * heap of n nodes, for many n. */
    int bad = 0;
    for (uint32_t n = 2; n < 200000; n += n < 5000 ? 1 : 997) {
        uint32_t p = 1;
        while (2 * p <= n)
            p *= 2;
        uint32_t rem = n - p + 1;
        if (2 * rem < p)
            p = p / 2 + rem;
        uint32_t mts = p - 1, counted = 0;
        for (uint64_t first = 2, width = 1; first <= n; first *= 2, width *= 2)
            counted += (uint32_t)((first + width - 1 <= n ? first + width - 1 : n) - first + 1);
        bad += kdtree_left_size(n) != mts || kdtree_left_size(n) != counted;
    }
    CHECK_MSG(bad == 0, "%d sizes where L(n) is not the left subtree's size", bad);
    CHECK(kdtree_left_size(0x7fffffffu) == 0x3fffffffu);
}

static void test_small_sets(kdtree_query qk[3])
{
    brute b;
    brute_init(&b, 300);
    for (int kind = 0; kind < SET_COUNT; kind++) {
        set_stats st = {0};
        for (uint32_t n = 1; n <= 300; n++)
            check_set(kind, n, 12, 1, qk, &b, &st);
        report(set_names[kind], &st);
    }
    brute_free(&b);
}

static void test_large_sets(kdtree_query qk[3])
{
    static const int kinds[] = {SET_UNIFORM, SET_BOX, SET_DUPLICATES, SET_SORTED, SET_PLANE};
    brute b;
    brute_init(&b, 100000);
    for (size_t i = 0; i < sizeof(kinds) / sizeof(kinds[0]); i++) {
        set_stats st = {0};
        check_set(kinds[i], 10000, 40, 1, qk, &b, &st);
        check_set(kinds[i], 100000, 8, 0, qk, &b, &st);
        char name[64];
        snprintf(name, sizeof name, "%s 10k/100k", set_names[kinds[i]]);
        report(name, &st);
    }
    /* Degenerate at size: all equal, and points on a line (100k). */
    set_stats st = {0};
    check_set(SET_EQUAL, 100000, 2, 0, qk, &b, &st);
    check_set(SET_LINE, 100000, 4, 0, qk, &b, &st);
    report("equal/line 100k", &st);
    brute_free(&b);
}

/* A map keeps its photons in classes (facing, flags), each a tree of its own; its
 * searches must find what one search over all the photons finds, and the
 * surface search may skip only classes none of whose photons pass the
 * filter. Brute force over the map's photons, for every metric, random
 * query normals (axis-aligned ones too, whose 45° cones touch the class
 * boundaries) and normal thresholds down to −1. */
static void test_map_classes(kdtree_query qk[3])
{
    const uint32_t n = 20000;
    photon *in = make_set(SET_UNIFORM, n, 11);
    photon_map m;
    photon_map_init(&m);
    CHECK(photon_map_append(&m, in, n) && photon_map_build(&m, NULL));
    int ordered = 1, classed = 1;
    for (unsigned c = 0; c < PHOTON_CLASSES; c++) {
        uint32_t start = m.class_start[c], count = m.class_start[c + 1] - start;
        ordered &= heap_ordered(m.photons + start, count);
        for (uint32_t i = start; i < start + count; i++)
            classed &= photon_class(&m.photons[i]) == c;
    }
    CHECK_MSG(ordered && classed, "classes: kd order %d, class membership %d", ordered, classed);
    CHECK(m.class_start[PHOTON_CLASSES] == n);
    brute b;
    brute_init(&b, n);
    uint32_t s = 99, bad = 0, queries = 0;
    static const float min_cos[] = {0.7f, 0.5f, 0.0f, -1.0f, 0.99f};
    for (int j = 0; j < 300; j++) {
        vec3 x = v3(rnd(&s), rnd(&s), rnd(&s));
        vec3 nrm = j % 6 < 3 ? v3(j % 3 == 0 ? 1.0f : 0.0f, j % 3 == 1 ? -1.0f : 0.0f, j % 3 == 2 ? 1.0f : 0.0f)
                             : v3_normalize(v3(rnd(&s) - 0.5f, rnd(&s) - 0.5f, rnd(&s) - 0.5f));
        static const uint16_t excluded[] = {0, PHOTON_CAUSTIC, PHOTON_DIRECT, PHOTON_CAUSTIC | PHOTON_DIRECT};
        kdtree_filter f = {nrm, min_cos[j % 5], excluded[(j >> 3) & 3], (uint16_t)(j & 1)};
        int mode = j % 3;
        metric mt = {mode > 0, nrm, 4.0f, mode == 2 ? &f : NULL};
        brute_compute(&b, &mt, m.photons, n, x);
        for (int ki = 0; ki < 3; ki++)
            for (int ri = 0; ri < 4; ri++) {
                if (mode == 0)
                    photon_map_knn(&m, x, radii2[ri], &qk[ki]);
                else if (mode == 1)
                    photon_map_knn_disc(&m, x, nrm, 4.0f, radii2[ri], &qk[ki]);
                else
                    photon_map_knn_surface(&m, x, 4.0f, &f, radii2[ri], &qk[ki]);
                queries++;
                bad += !knn_matches(&b, &qk[ki], ks[ki], radii2[ri]);
            }
    }
    CHECK_MSG(bad == 0, "map searches over facing classes: %u of %u differ from brute force", bad, queries);
    brute_free(&b);
    photon_map_free(&m);
    free(in);
}

/* The map's photon order is irrelevant to the search results' distances,
 * and k = 0 or an empty tree find nothing. */
static void test_edge_cases(void)
{
    kdtree_query q0, q;
    CHECK(kdtree_query_init(&q0, 0) && kdtree_query_init(&q, 4));
    photon *p = make_set(SET_UNIFORM, 16, 5);
    CHECK(kdtree_build(p, 16, NULL));
    CHECK(kdtree_knn(p, 16, v3s(0.5f), 1.0f, &q0) == 0 && q0.radius2 == 1.0f);
    CHECK(kdtree_knn(p, 0, v3s(0.5f), 1.0f, &q) == 0 && q.radius2 == 1.0f);
    CHECK(kdtree_knn(p, 16, v3s(0.5f), 0.0f, &q) == 0);
    CHECK(kdtree_build(p, 0, NULL));
    /* A flatten below 1 is plain Euclidean. */
    kdtree_knn_disc(p, 16, v3s(0.5f), v3(0, 0, 1), 0.5f, 1.0f, &q);
    float disc_r2 = q.radius2;
    kdtree_knn(p, 16, v3s(0.5f), 1.0f, &q);
    CHECK(disc_r2 == q.radius2);
    free(p);
    kdtree_query_free(&q0);
    kdtree_query_free(&q);
    kdtree_query_free(NULL);
}

/* ---- concurrent queries -------------------------------------------------- */

#define THREADS 4
#define THREAD_QUERIES 2000

typedef struct thread_job {
    const photon *tree;
    uint32_t n;
    const vec3 *points;
    float *radius2; /* out: one per query */
    uint32_t *found;
} thread_job;

static void *thread_main(void *arg)
{
    thread_job *job = arg;
    kdtree_query q;
    if (!kdtree_query_init(&q, 50))
        return NULL;
    for (int i = 0; i < THREAD_QUERIES; i++) {
        job->found[i] = kdtree_knn(job->tree, job->n, job->points[i], 0.01f, &q);
        job->radius2[i] = q.radius2;
    }
    kdtree_query_free(&q);
    return NULL;
}

static void test_threads(void)
{
    const uint32_t n = 50000;
    photon *tree = make_set(SET_BOX, n, 99);
    CHECK(kdtree_build(tree, n, NULL));
    vec3 *points = malloc(sizeof(vec3) * THREAD_QUERIES);
    uint32_t s = 1;
    for (int i = 0; i < THREAD_QUERIES; i++)
        points[i] = query_point(tree, n, (uint32_t)i, &s);

    float want_r2[THREAD_QUERIES], r2[THREADS][THREAD_QUERIES];
    uint32_t want_found[THREAD_QUERIES], found[THREADS][THREAD_QUERIES];
    thread_job single = {tree, n, points, want_r2, want_found};
    thread_main(&single);

    pthread_t th[THREADS];
    thread_job jobs[THREADS];
    for (int t = 0; t < THREADS; t++) {
        jobs[t] = (thread_job){tree, n, points, r2[t], found[t]};
        CHECK(pthread_create(&th[t], NULL, thread_main, &jobs[t]) == 0);
    }
    int bad = 0;
    for (int t = 0; t < THREADS; t++) {
        pthread_join(th[t], NULL);
        bad += memcmp(r2[t], want_r2, sizeof want_r2) != 0 || memcmp(found[t], want_found, sizeof want_found) != 0;
    }
    CHECK_MSG(bad == 0, "%d threads got results different from a single thread", bad);
    free(points);
    free(tree);
}

int main(void)
{
    kdtree_query qk[3];
    for (int i = 0; i < 3; i++)
        CHECK(kdtree_query_init(&qk[i], ks[i]));
    test_left_size();
    test_small_sets(qk);
    test_large_sets(qk);
    test_map_classes(qk);
    test_edge_cases();
    test_threads();
    for (int i = 0; i < 3; i++)
        kdtree_query_free(&qk[i]);
    return test_summary("test_kdtree");
}
