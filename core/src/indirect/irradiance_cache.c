/*
 * irradiance_cache.c — the records' octree, lookup and insertion
 * (irradiance_cache.h).
 */
#include "indirect/irradiance_cache.h"

#include <stdlib.h>
#include <string.h>

#define NO_RECORD UINT32_MAX
#define WEIGHT_MAX 1e4f      /* w at (almost) a record's own position */
#define MAX_DEPTH 24         /* octree levels below the root: 2⁻²⁴ of the scene's size */
#define LOOKUP_STACK (7 * MAX_DEPTH + 8) /* a depth-first walk holds at most 7 siblings per level */
/* A record lies in front of the point if the point is behind the record's
 * tangent plane, averaged with its own, by more than this share of the
 * record's reach: the two may see different light (Ward et al. 1988).
 * Relative, not absolute, so the test does not depend on the scene's
 * scale (docs/algorithms.md §10.2). The averaged normal makes the offset
 * vanish on a sphere, so curved surfaces need no larger tolerance. */
#define IN_FRONT_TOLERANCE 0.05f

/* Room for one more element in a growing array (doubling); 0 when memory
 * is exhausted. */
static int reserve_one(void **array, uint32_t count, uint32_t *capacity, size_t size, uint32_t first)
{
    if (count < *capacity)
        return 1;
    uint32_t cap = *capacity ? 2 * *capacity : first;
    void *a = realloc(*array, size * cap);
    if (!a)
        return 0;
    *array = a;
    *capacity = cap;
    return 1;
}

static uint32_t new_node(irradiance_cache *c, vec3 centre, float half)
{
    if (!reserve_one((void **)&c->nodes, c->node_count, &c->node_capacity, sizeof(*c->nodes), 64))
        return 0;
    irradiance_cache_node *n = &c->nodes[c->node_count];
    memset(n, 0, sizeof(*n));
    n->centre = centre;
    n->half = half;
    n->first = NO_RECORD;
    return c->node_count++;
}

uint64_t irradiance_cache_memory_estimate(uint32_t width, uint32_t height, float min_spacing)
{
    uint64_t pixels = (uint64_t)width * height;
    double per_record = min_spacing > 1.0f ? (double)min_spacing * (double)min_spacing : 1.0;
    uint64_t records = (uint64_t)((double)pixels / per_record) + 1;
    /* The record array grows by doubling; about two octree nodes a record. */
    uint64_t cache = 2 * records * sizeof(irradiance_record) + 2 * records * sizeof(irradiance_cache_node);
    /* The finest pass visits a quarter of the pixels: a flag and an index
     * each, and a record for each candidate left uncovered. */
    uint64_t candidates = pixels / 4 + 1;
    uint64_t pass = candidates * (2 + sizeof(uint32_t)) + records * sizeof(irradiance_record);
    return cache + pass;
}

int irradiance_cache_init(irradiance_cache *c, vec3 bmin, vec3 bmax, float accuracy)
{
    memset(c, 0, sizeof(*c));
    c->accuracy = accuracy;
    vec3 centre = v3_scale(v3_add(bmin, bmax), 0.5f);
    vec3 ext = v3_sub(bmax, bmin);
    float half = 0.5f * fmaxf(fmaxf(ext.x, ext.y), ext.z);
    half = half * 1.01f + 1e-6f;
    if (!(half < INFINITY))
        half = 1e30f;
    /* Node 0 is the root; it needs room before any child is made. */
    return new_node(c, centre, half) == 0 && c->nodes != NULL;
}

void irradiance_cache_free(irradiance_cache *c)
{
    free(c->records);
    free(c->nodes);
    memset(c, 0, sizeof(*c));
}

static float reach(const irradiance_cache *c, const irradiance_record *r) { return r->R / c->accuracy; }


static int octant(vec3 centre, vec3 p)
{
    return (p.x >= centre.x) | ((p.y >= centre.y) << 1) | ((p.z >= centre.z) << 2);
}

/* Whether p lies within the cube of node n grown by `grow` on every side. */
static int near_node(const irradiance_cache_node *n, vec3 p, float grow)
{
    float h = n->half + grow;
    return fabsf(p.x - n->centre.x) <= h && fabsf(p.y - n->centre.y) <= h && fabsf(p.z - n->centre.z) <= h;
}

/* Calls visit for every record whose node p may lie within the reach of,
 * plus `extra`: a record in a node of edge s reaches at most s beyond the
 * node's cube. Records are visited in a fixed order. */
typedef void (*record_visitor)(void *ctx, uint32_t record);
static void for_each_record_near(const irradiance_cache *c, vec3 p, float extra, record_visitor visit, void *ctx)
{
    uint32_t stack[LOOKUP_STACK];
    uint32_t top = 0;
    stack[top++] = 0;
    while (top) {
        const irradiance_cache_node *n = &c->nodes[stack[--top]];
        for (uint32_t r = n->first; r != NO_RECORD; r = c->records[r].next)
            visit(ctx, r);
        for (int k = 7; k >= 0; k--) {
            uint32_t ch = n->child[k];
            if (ch && top < LOOKUP_STACK && near_node(&c->nodes[ch], p, 2.0f * c->nodes[ch].half + extra))
                stack[top++] = ch;
        }
    }
}

/* ------------------------------------------------------------ insertion */

typedef struct clamp_ctx {
    irradiance_cache *c;
    uint32_t self;
} clamp_ctx;

static void clamp_record(irradiance_record *r, float bound)
{
    r->R_free = fminf(r->R_free, bound);
    r->R = clampf(r->R_free, r->R_lo, r->R_hi);
}

/* Neighbour clamping (Křivánek et al. 2006): two records whose reaches
 * overlap keep radii that differ by at most their distance, so a small
 * record near geometry detail lowers its neighbours' radii and they do
 * not reach across the detail. */
static void clamp_neighbour(void *ctx, uint32_t j)
{
    clamp_ctx *k = ctx;
    irradiance_cache *c = k->c;
    if (j == k->self)
        return;
    irradiance_record *ri = &c->records[k->self], *rj = &c->records[j];
    float d = v3_length(v3_sub(ri->p, rj->p));
    if (d >= reach(c, ri) + reach(c, rj))
        return;
    clamp_record(ri, rj->R + d);
    clamp_record(rj, ri->R + d);
}

/* Appends the record and returns its index, UINT32_MAX when memory is
 * exhausted. */
static uint32_t append(irradiance_cache *c, const irradiance_record *rec)
{
    if (!reserve_one((void **)&c->records, c->count, &c->capacity, sizeof(*c->records), 256))
        return UINT32_MAX;
    c->records[c->count] = *rec;
    c->records[c->count].next = NO_RECORD;
    return c->count++;
}

/* Puts record i in the largest node no larger than twice its reach. */
static int place(irradiance_cache *c, uint32_t i)
{
    vec3 p = c->records[i].p;
    float rho = reach(c, &c->records[i]);
    uint32_t node = 0;
    for (uint32_t depth = 0; depth < MAX_DEPTH && c->nodes[node].half > rho; depth++) {
        const irradiance_cache_node *n = &c->nodes[node];
        if (!near_node(n, p, 0.0f))
            break; /* outside the root: kept there */
        int o = octant(n->centre, p);
        uint32_t child = n->child[o];
        if (!child) {
            float h = 0.5f * n->half;
            vec3 cc = v3_add(n->centre, v3((o & 1) ? h : -h, (o & 2) ? h : -h, (o & 4) ? h : -h));
            child = new_node(c, cc, h); /* may move c->nodes */
            if (!child)
                return 0;
            c->nodes[node].child[o] = child;
        }
        node = child;
    }
    c->records[i].next = c->nodes[node].first;
    c->nodes[node].first = i;
    return 1;
}

/* A record that cannot reach anything (a point at the camera, a numerical
 * failure) would only deepen the tree. */
static int usable(const irradiance_record *rec)
{
    return rec->R > 0.0f && rec->R < INFINITY && v3_is_finite(rec->p);
}

int irradiance_cache_insert(irradiance_cache *c, const irradiance_record *rec)
{
    if (!usable(rec))
        return 1;
    uint32_t i = append(c, rec);
    if (i == UINT32_MAX)
        return 0;
    clamp_ctx k = {c, i};
    for_each_record_near(c, rec->p, reach(c, &c->records[i]), clamp_neighbour, &k);
    return place(c, i);
}

int irradiance_cache_rebuild(irradiance_cache *c)
{
    irradiance_cache_node root = c->nodes[0];
    memset(root.child, 0, sizeof(root.child));
    root.first = NO_RECORD;
    c->nodes[0] = root;
    c->node_count = 1;
    for (uint32_t i = 0; i < c->count; i++) {
        c->records[i].next = NO_RECORD;
        if (!place(c, i))
            return 0;
    }
    return 1;
}

int irradiance_cache_place(irradiance_cache *c, const irradiance_record *rec)
{
    if (!usable(rec))
        return 1;
    uint32_t i = append(c, rec);
    return i != UINT32_MAX && place(c, i);
}

/* --------------------------------------------------------------- lookup */

vec3 irradiance_record_extrapolate(const irradiance_record *r, vec3 p, vec3 n)
{
    vec3 rot = v3_cross(r->n, n), dp = v3_sub(p, r->p);
    vec3 E = r->E;
    E.x = fmaxf(E.x + v3_dot(rot, r->grad_r[0]) + v3_dot(dp, r->grad_t[0]), 0.0f);
    E.y = fmaxf(E.y + v3_dot(rot, r->grad_r[1]) + v3_dot(dp, r->grad_t[1]), 0.0f);
    E.z = fmaxf(E.z + v3_dot(rot, r->grad_r[2]) + v3_dot(dp, r->grad_t[2]), 0.0f);
    return E;
}

typedef struct lookup_ctx {
    const irradiance_cache *c;
    vec3 p, n;
    vec3 E, E_caustic, w_mean;
    float w_sum;
    uint32_t used;
} lookup_ctx;

static void weigh_record(void *ctx, uint32_t i)
{
    lookup_ctx *k = ctx;
    const irradiance_record *r = &k->c->records[i];
    float cos_n = v3_dot(k->n, r->n);
    if (!(cos_n > 0.0f))
        return;
    vec3 dp = v3_sub(k->p, r->p);
    float rho = reach(k->c, r);
    /* Beyond the reach, w ≤ q whatever the normals (the test below): most
     * records a lookup visits end here, before its square roots. */
    if (v3_length2(dp) >= rho * rho)
        return;
    /* In front: the point lies behind the record's surface. */
    if (0.5f * v3_dot(dp, v3_add(k->n, r->n)) < -IN_FRONT_TOLERANCE * rho)
        return;
    float e = v3_length(dp) / r->R + sqrtf(fmaxf(1.0f - cos_n, 0.0f));
    if (!(e * k->c->accuracy < 1.0f))
        return; /* w ≤ q */
    float w = e > 1.0f / WEIGHT_MAX ? 1.0f / e : WEIGHT_MAX;
    k->E = v3_madd(k->E, irradiance_record_extrapolate(r, k->p, k->n), w);
    k->E_caustic = v3_madd(k->E_caustic, r->E_caustic, w);
    k->w_mean = v3_madd(k->w_mean, r->w_mean, w);
    k->w_sum += w;
    k->used++;
}

int irradiance_cache_lookup(const irradiance_cache *c, vec3 p, vec3 n, irradiance_estimate *out)
{
    memset(out, 0, sizeof(*out));
    if (!c || c->count == 0)
        return 0;
    lookup_ctx k = {c, p, n, v3s(0.0f), v3s(0.0f), v3s(0.0f), 0.0f, 0};
    for_each_record_near(c, p, 0.0f, weigh_record, &k);
    if (!k.used)
        return 0;
    float inv = 1.0f / k.w_sum;
    out->E = v3_scale(k.E, inv);
    out->E_caustic = v3_scale(k.E_caustic, inv);
    float len = v3_length(k.w_mean);
    out->w_mean = len > 0.0f ? v3_scale(k.w_mean, 1.0f / len) : n;
    out->records = k.used;
    return 1;
}
