/*
 * test_kdtree.c — the photon map's kd-tree against brute force
 * (docs/algorithms.md §2 and §9, check 3).
 *
 * Point sets of every size 1…300 and 10k/100k, in shapes that break naive
 * trees: duplicates, all points equal, coplanar, collinear, sorted input,
 * integer grids (many exactly equal distances) and box faces (photons on
 * walls), their photons of every class (facing and flags). For each map:
 * it holds the same photons, each class's photons in its own range and
 * bounding box, every split plane separates its two subtrees, lies along
 * the longest axis of its cell and leaves buckets of at most
 * KDTREE_BUCKET, a rebuild is byte-identical, every photon is found, and
 * the k-nearest results equal brute force for several k and radii, in the
 * Euclidean and the disc metric, with and without a surface filter.
 * Queries from several threads at once agree with single-threaded ones.
 */
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
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

/* The map holds the same photons. */
static int same_multiset(const photon *in, const photon *tree, uint32_t n)
{
    photon *a = malloc(sizeof(photon) * n), *b = malloc(sizeof(photon) * n);
    memcpy(a, in, sizeof(photon) * n);
    memcpy(b, tree, sizeof(photon) * n);
    qsort(a, n, sizeof(photon), compare_bytes);
    qsort(b, n, sizeof(photon), compare_bytes);
    int same = memcmp(a, b, sizeof(photon) * n) == 0;
    free(a);
    free(b);
    return same;
}

static uint32_t bucket_first(const photon_class_tree *t, uint32_t j)
{
    return t->start + (uint32_t)(((uint64_t)j * t->count) >> t->depth);
}

/* The photons of node h (buckets [j0, j1)) lie within [lo, hi] on every
 * axis of the cell; each split plane separates its children, with lo ≤ hi,
 * along the cell's longest axis (ties to the lower axis); the cell is
 * then narrowed to each child. */
static int node_ok(const photon_map *m, const photon_class_tree *t, uint32_t h, uint32_t j0, uint32_t j1,
                   float lo[3], float hi[3], int *bad_axes)
{
    for (uint32_t i = bucket_first(t, j0); i < bucket_first(t, j1); i++)
        for (int a = 0; a < 3; a++)
            if (m->photons[i].position[a] < lo[a] || m->photons[i].position[a] > hi[a])
                return 0;
    if (j1 - j0 == 1)
        return bucket_first(t, j1) - bucket_first(t, j0) <= KDTREE_BUCKET;
    const kdtree_split *sp = &m->splits[t->first_split + h - 1];
    float e[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    uint32_t want = (e[0] >= e[1] && e[0] >= e[2]) ? 0 : (e[1] >= e[2] ? 1 : 2);
    *bad_axes += sp->axis != want;
    if (sp->axis > 2 || !(sp->lo <= sp->hi))
        return 0;
    uint32_t a = sp->axis, jm = j0 + (j1 - j0) / 2;
    float keep = hi[a];
    hi[a] = sp->lo;
    int ok = node_ok(m, t, 2 * h, j0, jm, lo, hi, bad_axes);
    hi[a] = keep;
    keep = lo[a];
    lo[a] = sp->hi;
    ok = ok && node_ok(m, t, 2 * h + 1, jm, j1, lo, hi, bad_axes);
    lo[a] = keep;
    return ok;
}

/* Every class: its photons, contiguous and in order of class, inside its
 * bounding box, and its subtree well formed at the least depth. */
static int map_ordered(const photon_map *m, int *bad_axes)
{
    uint32_t next = 0;
    for (unsigned c = 0; c < PHOTON_CLASSES; c++) {
        const photon_class_tree *t = &m->classes[c];
        if (t->start != next || t->depth != kdtree_depth(t->count))
            return 0;
        next += t->count;
        if (t->count == 0)
            continue;
        for (uint32_t i = t->start; i < t->start + t->count; i++)
            if (photon_class(&m->photons[i]) != c)
                return 0;
        float lo[3], hi[3];
        memcpy(lo, t->lo, sizeof lo);
        memcpy(hi, t->hi, sizeof hi);
        if (!node_ok(m, t, 1, 0, 1u << t->depth, lo, hi, bad_axes))
            return 0;
    }
    return next == m->count;
}

/* ---- brute force --------------------------------------------------------- */

typedef struct metric {
    int disc;
    vec3 normal;
    float flatten;
    const kdtree_filter *filter; /* disc only: photon_map_knn_surface */
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

static uint32_t metric_knn(const metric *m, const photon_map *map, vec3 x, float r2, kdtree_query *q)
{
    if (m->filter)
        return photon_map_knn_surface(map, x, m->flatten, m->filter, r2, q);
    return m->disc ? photon_map_knn_disc(map, x, m->normal, m->flatten, r2, q) : photon_map_knn(map, x, r2, q);
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
    if (k > 0 && q->found == k && kdtree_result_dist2(q, 0) != want_r2) /* the k-th nearest comes first */
        return 0;
    memset(b->seen, 0, b->n);
    uint32_t nearer = 0;
    for (uint32_t j = 0; j < q->found; j++) {
        uint32_t i = kdtree_result_index(q, j);
        float d2 = kdtree_result_dist2(q, j);
        if (i >= b->n || b->seen[i] || d2 != b->d2[i] || !(d2 < r2) || d2 > want_r2)
            return 0;
        b->seen[i] = 1;
        nearer += d2 < want_r2;
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

/* A query at each photon's own position (k = 1, tiny radius) finds a
 * photon at distance 0: a bucket the traversal never visits fails.
 * `first` limits the check to the photons first…n − 1. */
static int slots_found(const photon_map *m, uint32_t first, kdtree_query *q1)
{
    for (uint32_t i = first; i < m->count; i++) {
        vec3 x = photon_position(&m->photons[i]);
        if (photon_map_knn(m, x, 1e-12f, q1) != 1 || kdtree_result_dist2(q1, 0) != 0.0f)
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
static void check_queries(const photon_map *map, int queries, uint32_t seed, kdtree_query qk[3], brute *b,
                          set_stats *st)
{
    const photon *tree = map->photons;
    uint32_t n = map->count, s = seed;
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
                metric_knn(&m, map, x, radii2[ri], &qk[ki]);
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

static int build_map(photon_map *m, const photon *in, uint32_t n)
{
    photon_map_init(m);
    return photon_map_append(m, in, n) && photon_map_build(m, NULL);
}

/* Builds one set and runs every check; `all_slots` looks for every
 * photon, otherwise for the last half. */
static void check_set(int kind, uint32_t n, int queries, int all_slots, kdtree_query qk[3], brute *b,
                      set_stats *st)
{
    uint32_t seed = hash_combine((uint32_t)kind, n);
    photon *in = make_set(kind, n, seed);
    photon_map m, again;
    st->builds++;
    if (!build_map(&m, in, n) || !build_map(&again, in, n)) {
        st->bad_multiset++;
        goto done;
    }
    st->bad_determinism += memcmp(m.photons, again.photons, sizeof(photon) * n) != 0 ||
                           m.split_count != again.split_count ||
                           (m.split_count && /* none: no array to compare */
                            memcmp(m.splits, again.splits, sizeof(kdtree_split) * m.split_count) != 0);
    st->bad_multiset += !same_multiset(in, m.photons, n);
    st->bad_order += !map_ordered(&m, &st->bad_axes);
    st->bad_slots += !slots_found(&m, all_slots ? 0 : n / 2, &qk[0]);
    check_queries(&m, queries, seed, qk, b, st);
done:
    photon_map_free(&m);
    photon_map_free(&again);
    free(in);
}

static void report(const char *what, const set_stats *st)
{
    CHECK_MSG(st->bad_multiset == 0, "%s: %d trees lost or duplicated photons", what, st->bad_multiset);
    CHECK_MSG(st->bad_order == 0, "%s: %d trees violate the kd ordering or the classes", what, st->bad_order);
    CHECK_MSG(st->bad_axes == 0, "%s: %d trees split off the cell's longest axis", what, st->bad_axes);
    CHECK_MSG(st->bad_determinism == 0, "%s: %d rebuilds differ", what, st->bad_determinism);
    CHECK_MSG(st->bad_slots == 0, "%s: %d trees have photons the search never reaches", what, st->bad_slots);
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

/* The least depth whose buckets hold at most KDTREE_BUCKET photons. */
static void test_depth(void)
{
    int bad = 0;
    for (uint32_t n = 0; n < 200000; n += n < 5000 ? 1 : 997) {
        uint32_t d = kdtree_depth(n);
        uint64_t leaves = (uint64_t)1 << d;
        bad += (n + leaves - 1) / leaves > KDTREE_BUCKET || (d > 0 && (n + leaves / 2 - 1) / (leaves / 2) <= KDTREE_BUCKET);
    }
    CHECK_MSG(bad == 0, "%d photon counts with a depth that is not the least", bad);
    CHECK(kdtree_depth(0) == 0 && kdtree_depth(KDTREE_BUCKET) == 0 && kdtree_depth(KDTREE_BUCKET + 1) == 1);
    /* ⌈(2^31 − 1)/2^d⌉ ≤ B = 2^b first at d = 31 − b (B is a power of two). */
    CHECK(kdtree_depth(0x7fffffffu) == 31u - (uint32_t)__builtin_ctz(KDTREE_BUCKET));
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

/* The searches must find what one search over all the photons finds, and
 * the surface search may skip only classes none of whose photons pass the
 * filter. Brute force over the map's photons, for every metric, random
 * query normals (axis-aligned ones too, whose 45° cones touch the class
 * boundaries), normal thresholds down to −1 and every excluded flag. */
static void test_map_classes(kdtree_query qk[3])
{
    const uint32_t n = 20000;
    photon *in = make_set(SET_UNIFORM, n, 11);
    photon_map m;
    CHECK(build_map(&m, in, n));
    int bad_axes = 0;
    CHECK_MSG(map_ordered(&m, &bad_axes) && bad_axes == 0, "classes: tree or class membership broken");
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
                metric_knn(&mt, &m, x, radii2[ri], &qk[ki]);
                queries++;
                bad += !knn_matches(&b, &qk[ki], ks[ki], radii2[ri]);
            }
    }
    CHECK_MSG(bad == 0, "map searches over facing classes: %u of %u differ from brute force", bad, queries);
    brute_free(&b);
    photon_map_free(&m);
    free(in);
}

/* k = 0, an empty or unbuilt map, and a zero radius find nothing. */
static void test_edge_cases(void)
{
    kdtree_query q0, q;
    CHECK(kdtree_query_init(&q0, 0) && kdtree_query_init(&q, 4));
    photon *p = make_set(SET_UNIFORM, 16, 5);
    photon_map m, empty, unbuilt;
    CHECK(build_map(&m, p, 16) && build_map(&empty, p, 0));
    photon_map_init(&unbuilt);
    CHECK(photon_map_append(&unbuilt, p, 16));
    CHECK(photon_map_knn(&m, v3s(0.5f), 1.0f, &q0) == 0 && q0.radius2 == 1.0f);
    CHECK(photon_map_knn(&empty, v3s(0.5f), 1.0f, &q) == 0 && q.radius2 == 1.0f);
    CHECK(photon_map_knn(&unbuilt, v3s(0.5f), 1.0f, &q) == 0);
    CHECK(photon_map_knn(&m, v3s(0.5f), 0.0f, &q) == 0);
    CHECK(empty.split_count == 0 && photon_map_memory(&empty) == sizeof(photon_map));
    /* A flatten below 1 is plain Euclidean. */
    photon_map_knn_disc(&m, v3s(0.5f), v3(0, 0, 1), 0.5f, 1.0f, &q);
    float disc_r2 = q.radius2;
    photon_map_knn(&m, v3s(0.5f), 1.0f, &q);
    CHECK(disc_r2 == q.radius2);
    photon_map_free(&m);
    photon_map_free(&empty);
    photon_map_free(&unbuilt);
    free(p);
    kdtree_query_free(&q0);
    kdtree_query_free(&q);
    kdtree_query_free(NULL);
}

/* Built on 1, 2 and 3 threads, several maps at once or one by one, large
 * classes (whose top levels are built first and their subtrees shared
 * out) and small ones: the same photons in the same order, the same
 * planes, byte for byte. */
static void test_parallel_build(void)
{
    const uint32_t n = 400000;
    photon *in = make_set(SET_BOX, n, 3);
    /* Most photons in one class, so that it is split between threads. */
    for (uint32_t i = 0; i < n; i += 4)
        in[i] = photon_make(photon_position(&in[i]), v3s(1.0f), v3(0, 0, -1), v3(0, 0, 1), 0);
    photon_map one, many[3][2];
    CHECK(build_map(&one, in, n));
    int differ = 0;
    for (uint32_t threads = 1; threads <= 3; threads++) {
        photon_map *maps[2] = {&many[threads - 1][0], &many[threads - 1][1]};
        for (int j = 0; j < 2; j++) {
            photon_map_init(maps[j]);
            CHECK(photon_map_append(maps[j], in, j ? n / 3 : n));
        }
        CHECK(photon_map_build_many(maps, 2, threads, NULL));
        differ += memcmp(one.photons, maps[0]->photons, sizeof(photon) * n) != 0 ||
                  one.split_count != maps[0]->split_count ||
                  memcmp(one.splits, maps[0]->splits, sizeof(kdtree_split) * one.split_count) != 0;
        photon_map third;
        CHECK(build_map(&third, in, n / 3));
        differ += memcmp(third.photons, maps[1]->photons, sizeof(photon) * (n / 3)) != 0 ||
                  memcmp(third.splits, maps[1]->splits, sizeof(kdtree_split) * third.split_count) != 0;
        photon_map_free(&third);
    }
    CHECK_MSG(differ == 0, "%d maps built on several threads differ from one built alone", differ);
    int bad_axes = 0;
    CHECK(map_ordered(&many[2][0], &bad_axes) && bad_axes == 0);
    for (int t = 0; t < 3; t++)
        for (int j = 0; j < 2; j++)
            photon_map_free(&many[t][j]);
    photon_map_free(&one);
    free(in);
}

/* ---- concurrent queries -------------------------------------------------- */

#define THREADS 4
#define THREAD_QUERIES 2000

typedef struct thread_job {
    const photon_map *map;
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
        job->found[i] = photon_map_knn(job->map, job->points[i], 0.01f, &q);
        job->radius2[i] = q.radius2;
    }
    kdtree_query_free(&q);
    return NULL;
}

/* Each thread's search lies on cache lines no other thread writes
 * (kdtree.h): the struct and its heap start on a line, and the heap's
 * block is whole lines; a per-thread array from parallel_scratch_calloc
 * puts each element on lines of its own. Two threads whose heaps shared a
 * line scaled 1.46x on 2 cores instead of 1.9x (docs/benchmarks.md,
 * "Thread scaling by stage"). */
static void test_query_on_own_lines(void)
{
    const uintptr_t line = PARALLEL_CACHE_LINE;
    CHECK(sizeof(kdtree_query) % line == 0);
    kdtree_query *qs = parallel_scratch_calloc(2, sizeof(kdtree_query));
    CHECK(qs != NULL);
    if (!qs)
        return;
    for (int t = 0; t < 2; t++) {
        CHECK((uintptr_t)&qs[t] % line == 0);
        CHECK(qs[t].k == 0 && qs[t].heap == NULL); /* zeroed */
        CHECK(kdtree_query_init(&qs[t], 50));
        CHECK((uintptr_t)qs[t].heap % line == 0);
    }
    /* The two heaps' blocks do not meet on a line: a block covers whole
     * lines, so the other's first line lies past this one's last. */
    for (int t = 0; t < 2; t++) {
        uintptr_t first = (uintptr_t)qs[t].heap / line, last = ((uintptr_t)(qs[t].heap + 51) - 1) / line;
        uintptr_t other = (uintptr_t)qs[1 - t].heap / line;
        uintptr_t other_last = ((uintptr_t)(qs[1 - t].heap + 51) - 1) / line;
        CHECK(other_last < first || other > last);
    }
    for (int t = 0; t < 2; t++)
        kdtree_query_free(&qs[t]);
    free(qs);
    /* Elements that would straddle lines are refused, not misaligned. */
    CHECK(parallel_scratch_calloc(2, 40) == NULL);
    CHECK(parallel_scratch_calloc(0, sizeof(kdtree_query)) == NULL);
}

/* Large k against brute force: a search that takes hundreds of photons
 * before the heap is full visits many cells nearest-first, which breaks
 * the stack's depth-first bound (kdtree.c); at k = 500 on 200 k photons it
 * once overran a 64-entry stack. Every metric, a wide and an unbounded
 * radius, on sets with room (uniform) and without (a box's faces). */
static void test_large_k(void)
{
    static const uint32_t big_ks[] = {500, 3000};
    static const float big_radii2[] = {0.3f * 0.3f, INFINITY};
    static const int kinds[] = {SET_UNIFORM, SET_BOX};
    const uint32_t n = 100000;
    brute b;
    brute_init(&b, n);
    for (size_t si = 0; si < sizeof(kinds) / sizeof(kinds[0]); si++) {
        photon *in = make_set(kinds[si], n, 4242);
        photon_map m;
        CHECK(build_map(&m, in, n));
        int queries = 0, bad = 0;
        uint32_t s = 17;
        for (uint32_t ki = 0; ki < 2; ki++) {
            kdtree_query q;
            CHECK(kdtree_query_init(&q, big_ks[ki]));
            for (uint32_t j = 0; j < 12; j++) {
                vec3 x = query_point(m.photons, n, j, &s);
                int mode = (int)(j % 3);
                metric mt = {mode > 0, v3_normalize(v3(rnd(&s) - 0.5f, rnd(&s) - 0.5f, 1.0f)), 6.0f, NULL};
                kdtree_filter f = {mt.normal, 0.2f, PHOTON_CAUSTIC, (uint16_t)(j & 1)};
                if (mode == 2)
                    mt.filter = &f;
                brute_compute(&b, &mt, m.photons, n, x);
                for (int ri = 0; ri < 2; ri++) {
                    metric_knn(&mt, &m, x, big_radii2[ri], &q);
                    queries++;
                    bad += !knn_matches(&b, &q, big_ks[ki], big_radii2[ri]);
                }
            }
            kdtree_query_free(&q);
        }
        CHECK_MSG(bad == 0, "%s, k = 500 and 3000: %d of %d queries differ from brute force", set_names[kinds[si]],
                  bad, queries);
        photon_map_free(&m);
        free(in);
    }
    brute_free(&b);
}

static void test_threads(void)
{
    const uint32_t n = 50000;
    photon *in = make_set(SET_BOX, n, 99);
    photon_map m;
    CHECK(build_map(&m, in, n));
    vec3 *points = malloc(sizeof(vec3) * THREAD_QUERIES);
    uint32_t s = 1;
    for (int i = 0; i < THREAD_QUERIES; i++)
        points[i] = query_point(m.photons, n, (uint32_t)i, &s);

    float want_r2[THREAD_QUERIES], r2[THREADS][THREAD_QUERIES];
    uint32_t want_found[THREAD_QUERIES], found[THREADS][THREAD_QUERIES];
    thread_job single = {&m, points, want_r2, want_found};
    thread_main(&single);

    pthread_t th[THREADS];
    thread_job jobs[THREADS];
    for (int t = 0; t < THREADS; t++) {
        jobs[t] = (thread_job){&m, points, r2[t], found[t]};
        CHECK(pthread_create(&th[t], NULL, thread_main, &jobs[t]) == 0);
    }
    int bad = 0;
    for (int t = 0; t < THREADS; t++) {
        pthread_join(th[t], NULL);
        bad += memcmp(r2[t], want_r2, sizeof want_r2) != 0 || memcmp(found[t], want_found, sizeof want_found) != 0;
    }
    CHECK_MSG(bad == 0, "%d threads got results different from a single thread", bad);
    free(points);
    photon_map_free(&m);
    free(in);
}

int main(void)
{
    kdtree_query qk[3];
    for (int i = 0; i < 3; i++)
        CHECK(kdtree_query_init(&qk[i], ks[i]));
    test_depth();
    test_small_sets(qk);
    test_large_sets(qk);
    test_map_classes(qk);
    test_large_k();
    test_edge_cases();
    test_parallel_build();
    test_threads();
    test_query_on_own_lines();
    for (int i = 0; i < 3; i++)
        kdtree_query_free(&qk[i]);
    return test_summary("test_kdtree");
}
