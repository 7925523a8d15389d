/*
 * photon_trace.c — photon tracing (Jensen 2001, ch. 5; course notes 2002).
 *
 * Each photon path is a pure function of (seed, map, path index): a light
 * is picked by power and the photon leaves it carrying Φ_light/N_emitted
 * (light_sample_emission). At every surface with a non-specular component
 * the photon is stored before it scatters (global map: every such hit;
 * caustic map: those after one or more specular bounces only, L S+ D: the
 * global pass's caustic-flagged photons and a pass of its own for the
 * rest; fill_caustic_map).
 * Scattering samples the BSDF and continues by Russian roulette with
 * probability P = max(Φ·w)/max(Φ), w = f·cos/pdf the sample's weight
 * (Jensen's max form P = max(Φ·ρ)/max(Φ) for a Lambertian surface;
 * docs/algorithms.md §3.3), so a grey surface of albedo ρ keeps the
 * photon's power and ends a fraction 1 − ρ of the paths: powers stay similar.
 *
 * Determinism: paths are traced in batches on any number of threads, each
 * batch into its own buffer; buffers are merged in path order, and a map
 * takes whole paths until it holds the photons asked for. N_emitted is the
 * number of paths up to the last one taken, whatever the thread count.
 */
#include "photons/photon_trace.h"

#include <stdlib.h>
#include <string.h>

#include "lights/light.h"
#include "scene/embree.h"
#include "scene/ray.h"
#include "shading/material.h"
#include "util/parallel.h"
#include "photons/photon_importance.h"
#include "photons/projection_map.h"
#include "photons/radiance_estimate.h"

#define PATHS_PER_BATCH 2048u
#define RADIANCE_SITE_STRIDE 4u   /* Christensen: a quarter of the photons (RAD's default 0.25) */

/* The photon passes; each draws its paths from a sample domain of its own. */
enum { MAP_GLOBAL = 0, MAP_CAUSTIC = 1, MAP_RADIANCE_SITES = 2, MAP_PILOT = 3, MAP_CAUSTIC_PILOT = 4 };

#define PILOT_PHOTONS 8        /* pilot paths per cell of a sun's plane */
#define WORLD_PILOT_PHOTONS 4  /* per cell of the world's planes, which have 16 times as many */
#define PILOT_FLOOR 0.005f     /* weight of a cell no pilot path of which reached what the camera reads */
#define CONE_PILOT_PHOTONS 64  /* per cone of a lamp that has several (one per object it can reach) */

typedef struct traced_photon {
    vec3 position, power, direction; /* power: W for a single emitted photon */
    vec3 normal, albedo;             /* at the hit: the record's normal; radiance photons' sites */
    uint64_t path;
    uint16_t flags;
} traced_photon;

/* One batch's photons, in path order: what one work item traced. */
typedef struct batch {
    traced_photon *items;
    uint32_t count, capacity;
    uint32_t caustic; /* of count, those flagged PHOTON_CAUSTIC */
    int out_of_memory;
} batch;

static void batch_push(batch *b, const traced_photon *p)
{
    if (b->count == b->capacity) {
        uint32_t cap = b->capacity ? b->capacity * 2 : 1024;
        traced_photon *n = realloc(b->items, sizeof(traced_photon) * cap);
        if (!n) {
            b->out_of_memory = 1;
            return;
        }
        b->items = n;
        b->capacity = cap;
    }
    b->items[b->count++] = *p;
    b->caustic += (p->flags & PHOTON_CAUSTIC) != 0;
}

/* Keeps the first n of b's photons. */
static void batch_truncate(batch *b, uint32_t n)
{
    for (uint32_t i = n; i < b->count; i++)
        b->caustic -= (b->items[i].flags & PHOTON_CAUSTIC) != 0;
    b->count = n;
}

/* A map's photons in path order: the batches it kept, whole, each as its
 * tracer filled it. The batches are moved here, not copied: a copy of
 * every record (80 bytes) into one array was a serial pass between the
 * waves, a tenth of the tracing's time on two threads
 * (docs/benchmarks.md, "Where photon tracing's time goes"). */
typedef struct traced_list {
    batch *parts;
    uint32_t part_count, part_capacity;
    uint32_t count; /* photons over all parts */
} traced_list;

static void traced_list_free(traced_list *l)
{
    for (uint32_t i = 0; i < l->part_count; i++)
        free(l->parts[i].items);
    free(l->parts);
    memset(l, 0, sizeof(*l));
}

/* Moves the first n photons of *b to the end of l, leaving *b empty (its
 * buffer goes with them). Returns 0 when memory runs out (*b unchanged). */
static int traced_list_take(traced_list *l, batch *b, uint32_t n)
{
    if (n == 0)
        return 1;
    if (l->part_count == l->part_capacity) {
        uint32_t cap = l->part_capacity ? 2 * l->part_capacity : 64;
        batch *parts = realloc(l->parts, sizeof(batch) * cap);
        if (!parts)
            return 0;
        l->parts = parts;
        l->part_capacity = cap;
    }
    batch_truncate(b, n);
    l->parts[l->part_count++] = *b;
    l->count += n;
    memset(b, 0, sizeof(*b));
    return 1;
}

/* The photons of paths before `path`: l's first ones, as l is in path order. */
static uint32_t traced_list_count_before(const traced_list *l, uint64_t path)
{
    uint32_t n = l->count;
    for (uint32_t i = l->part_count; i-- > 0;) {
        const batch *b = &l->parts[i];
        uint32_t j = b->count;
        while (j > 0 && b->items[j - 1].path >= path)
            j--;
        n -= b->count - j;
        if (j > 0)
            break;
    }
    return n;
}

/* Keeps l's first n photons. */
static void traced_list_truncate(traced_list *l, uint32_t n)
{
    /* Whole parts past the n-th photon go; the last left keeps its photons
     * before it. */
    while (l->part_count > 0 && l->count - l->parts[l->part_count - 1].count >= n) {
        batch *b = &l->parts[--l->part_count];
        l->count -= b->count;
        free(b->items);
    }
    if (l->count > n) {
        batch *b = &l->parts[l->part_count - 1];
        batch_truncate(b, n - (l->count - b->count));
        l->count = n;
    }
}

static uint32_t traced_list_caustic(const traced_list *l)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < l->part_count; i++)
        n += l->parts[i].caustic;
    return n;
}

/* Diffuse reflectance of the BSDF, for radiance photons: its diffuse
 * closures' weights under their layers, seen along the normal (the
 * radiance photon is a Lambertian's, docs/algorithms.md §5.3). */
static vec3 diffuse_albedo(const bsdf *b)
{
    vec3 rho = v3s(0.0f);
    for (uint32_t i = 0; i < b->count; i++)
        if (closure_is_diffuse(&b->closures[i]))
            rho = v3_add(rho, v3_mul(b->closures[i].weight,
                                     bsdf_layer_scale(b, b->closures[i].under_layers,
                                                      b->frames[b->closures[i].frame].n)));
    return v3_min(rho, v3s(1.0f));
}

static float t_after(float t) { return fmaxf(t * (1.0f + 4e-6f), t + 1e-7f); }

enum { DIM_EMIT = 0, DIM_SCATTER_BASE = 5, DIM_SCATTER_STRIDE = 4 };

static void trace_from(const scene *s, const photon_trace_settings *ps, uint32_t map, const sampler *smp, vec3 o,
                       vec3 d, vec3 power, uint64_t path, batch *out);

static void trace_path(const scene *s, const photon_trace_settings *ps, uint32_t map, const projection_map *aim,
                       uint64_t path, batch *out)
{
    sampler smp = sampler_for_index(ps->sampler, ps->seed, map, path);
    float u[5];
    for (int k = 0; k < 5; k++)
        u[k] = sampler_1d(&smp, DIM_EMIT + (uint32_t)k);
    vec3 o, d, power;
    if (!(aim ? projection_map_emit(s, aim, u, &o, &d, &power) : light_sample_emission(s, u, &o, &d, &power)))
        return;
    trace_from(s, ps, map, &smp, o, d, power, path, out);
}

static void trace_from(const scene *s, const photon_trace_settings *ps, uint32_t map, const sampler *sp, vec3 o, vec3 d,
                       vec3 power, uint64_t path, batch *out)
{
    const sampler smp = *sp;
    const float r = ps->caustic_roughness;
    int specular_only = 1;   /* every scattering so far was by a closure that carries caustics */
    uint32_t depth = 0;      /* scattering events so far */
    float tmin = 0.0f;
    for (uint32_t step = 0; step < 4 * (ps->max_bounces + 16); step++) {
        ray_hit h;
        if (!embree_intersect(s->bvh, o, d, tmin, INFINITY, 0, &h))
            return;
        surface sf;
        surface_from_hit(s, h.instance, h.prim, h.b1, h.b2, d, &sf);
        bsdf b;
        material_bsdf(s, &sf, &b);
        if (b.count == 0)
            return; /* absorbed (black, or an emitter only) */
        bsdf_set_adjoint(&b);
        if (bsdf_has_non_caustic(&b, r)) {
            int caustic = specular_only && depth > 0;
            if (map != MAP_CAUSTIC || caustic) {
                traced_photon tp = {sf.p, power, d, sf.ns, diffuse_albedo(&b), path,
                                    (uint16_t)((depth == 0 ? PHOTON_DIRECT : 0) | (caustic ? PHOTON_CAUSTIC : 0))};
                batch_push(out, &tp);
            }
            /* A caustic path ends at the first surface that stores photons,
             * unless that surface also has closures that carry caustics (a
             * mirror mixed with a diffuse coat): the photon may leave by one
             * of them and stay caustic. */
            bsdf carry, rest;
            if (map == MAP_CAUSTIC && !(bsdf_split_caustic(&b, r, &carry, &rest) > 0.0f))
                return;
        }
        if (depth >= ps->max_bounces)
            return;
        uint32_t dim = DIM_SCATTER_BASE + step * DIM_SCATTER_STRIDE;
        bsdf_sample bs;
        if (!bsdf_sample_direction(&b, v3_neg(d), sampler_1d(&smp, dim), sampler_2d(&smp, dim + 1), &bs))
            return;
        /* Light flows from -d toward bs.wi: the adjoint BSDF (bsdf.h). */
        float eta_scale;
        vec3 weight = bsdf_photon_weight(&b, v3_neg(d), &bs, &eta_scale);
        vec3 scattered = v3_mul(power, weight);
        float p = fminf(1.0f, v3_max_component(scattered) / v3_max_component(power));
        if (!(p > 0.0f) || sampler_1d(&smp, dim + 3) >= p)
            return;
        power = v3_scale(scattered, eta_scale / p);
        if (!v3_is_finite(power))
            return;
        int carries = (bs.flags & BSDF_TRANSPARENT) || closure_scatters_caustic(&b.closures[bs.closure], r);
        if (map == MAP_CAUSTIC && !carries)
            return; /* left by a closure that stores photons: no longer a caustic path */
        if (bs.flags & BSDF_TRANSPARENT) {
            tmin = t_after(h.t); /* straight on along the same ray */
            continue;
        }
        specular_only &= carries;
        o = ray_leave_surface(sf.p, sf.ng, bs.wi);
        d = bs.wi;
        tmin = 0.0f;
        depth++;
    }
}

typedef struct wave {
    const scene *s;
    const photon_trace_settings *ps;
    uint32_t map;
    const projection_map *aim;  /* the caustic map's emission, or NULL */
    uint64_t first_path, end_path;
    uint32_t paths_per_batch;
    batch *batches;
    photon_trace_progress *progress;
    atomic_int *cancel;
} wave;

static void trace_batch(void *ctx, uint32_t item, uint32_t thread)
{
    wave *w = ctx;
    uint64_t begin = w->first_path + (uint64_t)item * w->paths_per_batch;
    uint64_t end = begin + w->paths_per_batch;
    if (end > w->end_path)
        end = w->end_path;
    /* Filled as a copy on this thread's stack, and stored back: the wave's
     * batches lie side by side, and two threads pushing into neighbours
     * wrote the same cache line at every photon (two threads took 10 %
     * more CPU time than one; docs/benchmarks.md, "Where photon tracing's
     * time goes"). */
    batch b = w->batches[item];
    for (uint64_t i = begin; i < end; i++) {
        if ((i & 255u) == 0 && atomic_load_explicit(w->cancel, memory_order_relaxed))
            break;
        trace_path(w->s, w->ps, w->map, w->aim, i, &b);
    }
    w->batches[item] = b;
    if (w->progress)
        atomic_fetch_add(&w->progress->emitted, end - begin);
}

/* A pass gives up once it has emitted CAUSTIC_PROBE_PATHS paths and its
 * yield so far would not store a tenth of its target even at its cap on
 * emitted paths (pass_path_cap): a small glass object far from the light,
 * a spot that lights nothing. The photons it has stay (they carry 1/emitted each, so
 * the map is as right as any, only sparse), and the tens of millions of
 * paths the cap would allow, which would store almost nothing, are not
 * traced. The map is then short (photon_maps.short_maps), which the host
 * tells the user. */
#define CAUSTIC_PROBE_PATHS 1000000u
#define CAUSTIC_HOPELESS_FRACTION 10u

/* A caustic pass traces at most this many paths per photon of its target.
 * Its photons each carry Φ/N_emitted, so the cap keeps them at least as
 * strong as those of a pass that stores one photon every
 * CAUSTIC_PATHS_PER_PHOTON paths (the aimed glass and metal objects of
 * docs/benchmarks.md store one in 2.7 to 8). Where far fewer paths end in
 * a caustic (a clear coat's few per cent of reflection over a diffuse
 * base), the caustic is faint in proportion, and so is the absolute error
 * of a map with fewer photons. Without the cap such a pass ran to the
 * emission cap: on the procedural-materials scene 50 M paths, 16.5 s of a
 * 19.5 s render, for 200 k photons of a light that the image's error did
 * not see (docs/algorithms.md §3.2). With it, and the hopeless-yield rule
 * judged against it, that pass stops at the 1 M-path probe. */
#define CAUSTIC_PATHS_PER_PHOTON 10u

/* The most paths a pass of `map` may trace for `target` photons: the
 * user's emission cap, and for a caustic pass CAUSTIC_PATHS_PER_PHOTON a
 * photon. */
static uint64_t pass_path_cap(const photon_trace_settings *ps, uint32_t map, uint32_t target)
{
    if (map != MAP_CAUSTIC)
        return ps->max_emitted;
    uint64_t budget = (uint64_t)target * CAUSTIC_PATHS_PER_PHOTON;
    return budget < ps->max_emitted ? budget : ps->max_emitted;
}

static int caustic_yield_hopeless(uint64_t emitted, uint32_t stored, uint32_t target, uint64_t cap)
{
    if (emitted < CAUSTIC_PROBE_PATHS)
        return 0;
    /* stored · cap / emitted < target / 10, in integers */
    return (long double)stored * (long double)cap * CAUSTIC_HOPELESS_FRACTION <
           (long double)target * (long double)emitted;
}

/* Paths the next wave traces: those that fill the map at the yield seen
 * so far (one photon a path before the first wave), a tenth more, and at
 * most a full wave; a full wave while nothing has been kept. Tracing a
 * full wave of 65 536 paths for a map of 500 photons, or a whole wave past
 * the path that fills a map, would be work whose photons are never
 * stored. The wave sizes do not change the map: paths are traced by
 * index and merged in path order up to the one that fills it. */
static uint64_t wave_paths(uint32_t target, uint32_t kept, uint64_t emitted, uint64_t full)
{
    if (emitted > 0 && kept == 0)
        return full;
    double per_path = emitted > 0 ? (double)kept / (double)emitted : 1.0;
    double want = 1.1 * (double)(target - kept) / per_path + 64.0;
    return want < (double)full ? (uint64_t)want : full;
}

/* Traces paths until `target` photons are kept; fills *kept (path order)
 * and *emitted. */
static phos_status trace_map(const scene *s, const photon_trace_settings *ps, uint32_t map, const projection_map *aim,
                             uint32_t target, traced_list *kept, uint64_t *emitted, atomic_int *cancel,
                             photon_trace_progress *progress, uint32_t stored_before)
{
    memset(kept, 0, sizeof(*kept));
    *emitted = 0;
    if (target == 0 || s->lights.count == 0)
        return PHOS_OK;
    uint32_t threads = parallel_thread_count(ps->threads);
    uint64_t cap = pass_path_cap(ps, map, target);
    /* 16 batches a thread: a wave ends when its last batch does, so the
     * other threads wait for half a batch on average, a smaller share of
     * the wave the more batches it has (8 a thread: 1.85 times one
     * thread's speed on two; 16: 1.91, docs/benchmarks.md). */
    uint32_t batches_per_wave = threads * 16;
    batch *batches = calloc(batches_per_wave, sizeof(batch));
    if (!batches)
        return PHOS_ERROR_OUT_OF_MEMORY;
    phos_status status = PHOS_OK;
    uint64_t next = 0, checkpoint = CAUSTIC_PROBE_PATHS;
    int done = 0;
    while (!done) {
        uint64_t paths = wave_paths(target, kept->count, next, (uint64_t)batches_per_wave * PATHS_PER_BATCH);
        uint32_t per_batch = (uint32_t)((paths + batches_per_wave - 1) / batches_per_wave);
        wave w = {s, ps, map, aim, next, next + paths, per_batch, batches, progress, cancel};
        if (w.end_path > cap)
            w.end_path = cap;
        uint32_t nb = (uint32_t)((w.end_path - next + per_batch - 1) / per_batch);
        for (uint32_t i = 0; i < nb; i++)
            batch_truncate(&batches[i], 0);
        if (!parallel_for(nb, threads, trace_batch, &w, cancel)) {
            status = PHOS_ERROR_CANCELLED;
            break;
        }
        /* Keep the batches in path order, up to the end of the path whose
         * photon fills the map. */
        for (uint32_t i = 0; i < nb && !done; i++) {
            batch *b = &batches[i];
            if (b->out_of_memory) {
                status = PHOS_ERROR_OUT_OF_MEMORY;
                break;
            }
            uint32_t take = b->count;
            if (take > 0 && kept->count + take >= target) {
                uint64_t cut = b->items[target - kept->count - 1].path;
                take = target - kept->count;
                while (take < b->count && b->items[take].path == cut)
                    take++;
                *emitted = cut + 1;
                done = 1;
            }
            if (!traced_list_take(kept, b, take))
                status = PHOS_ERROR_OUT_OF_MEMORY;
            if (status != PHOS_OK)
                break;
        }
        if (progress)
            atomic_store(&progress->stored, stored_before + kept->count);
        if (status != PHOS_OK || done)
            break;
        next = w.end_path;
        *emitted = next;
        if (next >= cap)
            done = 1; /* photons escape or are absorbed: keep what there is */
        /* The yield is judged at fixed path counts (1 M, 2 M, 4 M, ...),
         * not at wave ends, which depend on the thread count. */
        while (map != MAP_RADIANCE_SITES && !done && next >= checkpoint) {
            uint32_t before = traced_list_count_before(kept, checkpoint);
            if (caustic_yield_hopeless(checkpoint, before, target, cap)) {
                traced_list_truncate(kept, before);
                *emitted = checkpoint;
                done = 1;
            }
            checkpoint *= 2;
        }
    }
    for (uint32_t i = 0; i < batches_per_wave; i++)
        free(batches[i].items);
    free(batches);
    return status;
}

/* Packing traced photons into 20-byte records (photon_make: frexp, acos,
 * atan2 and the normal's octahedral search, some 100 ns each) runs on
 * every thread, a kept batch at a time, each into its own slots of the
 * map. */
typedef struct encode_job {
    const traced_list *kept;
    float scale;
    uint16_t flags;
    const uint32_t *first_out; /* per part: its first slot in out */
    photon *out;
    atomic_int not_finite;     /* a photon's position was not finite */
} encode_job;

static void encode_part(void *ctx, uint32_t item, uint32_t thread)
{
    (void)thread;
    encode_job *job = ctx; /* not const: it raises not_finite */
    const batch *b = &job->kept->parts[item];
    photon *out = job->out + job->first_out[item];
    for (uint32_t i = 0; i < b->count; i++) {
        const traced_photon *tp = &b->items[i];
        if ((tp->flags & job->flags) != job->flags)
            continue;
        /* A map never holds a position that is not finite (photon_map_append's rule). */
        if (!v3_is_finite(tp->position))
            atomic_store(&job->not_finite, 1);
        *out++ = photon_make(tp->position, v3_scale(tp->power, job->scale), tp->direction, tp->normal, tp->flags);
    }
}

/* Appends the kept photons (all, or those flagged PHOTON_CAUSTIC: `flags`)
 * scaled by `scale`, packed into 20-byte records on `threads` threads,
 * in their order. */
static phos_status append_photons(photon_map *m, const traced_list *kept, float scale, uint16_t flags,
                                  uint32_t threads)
{
    if (kept->part_count == 0)
        return PHOS_OK;
    uint32_t *first_out = malloc(sizeof(uint32_t) * kept->part_count);
    if (!first_out)
        return PHOS_ERROR_OUT_OF_MEMORY;
    uint32_t total = 0;
    for (uint32_t i = 0; i < kept->part_count; i++) {
        first_out[i] = total;
        total += flags == PHOTON_CAUSTIC ? kept->parts[i].caustic : kept->parts[i].count;
    }
    phos_status st = PHOS_OK;
    photon *out = total ? photon_map_extend(m, total) : NULL;
    if (total && !out) {
        st = PHOS_ERROR_OUT_OF_MEMORY;
    } else if (total) {
        encode_job job = {kept, scale, flags, first_out, out, 0};
        parallel_for(kept->part_count, threads, encode_part, &job, NULL);
        if (atomic_load(&job.not_finite))
            st = PHOS_ERROR_INTERNAL; /* a hit point off every finite scene */
    }
    free(first_out);
    return st;
}

/* Scales by 1/emitted and fills the map. */
static phos_status fill_map(photon_map *m, const traced_list *kept, uint64_t emitted, uint32_t threads)
{
    if (kept->count == 0)
        return PHOS_OK;
    return append_photons(m, kept, 1.0f / (float)emitted, 0, threads);
}

/* The caustic map from two independent estimates of the same caustic
 * flux: the global pass's caustic-flagged photons (n_g of them, from
 * N_g paths) and the caustic pass's own (n_c, from N_c aimed paths). Each
 * set alone is unbiased, so any α gives an unbiased map with the global
 * ones scaled by α/N_g and the caustic pass's by (1 − α)/N_c. α =
 * n_g/(n_g + n_c) weighs each set by its count, which is its inverse
 * variance where the two sets' photons carry similar power, and gives
 * every photon the same share of the map's power on average. */
static phos_status fill_caustic_map(photon_map *m, const traced_list *global, uint64_t global_emitted,
                                    uint32_t reused, const traced_list *own, uint64_t own_emitted, uint32_t threads)
{
    uint32_t n = reused + own->count;
    if (n == 0)
        return PHOS_OK;
    if (!photon_map_reserve(m, n))
        return PHOS_ERROR_OUT_OF_MEMORY;
    double alpha = (double)reused / n;
    phos_status st = reused ? append_photons(m, global, (float)(alpha / (double)global_emitted), PHOTON_CAUSTIC,
                                             threads)
                            : PHOS_OK;
    if (st == PHOS_OK && own->count)
        st = append_photons(m, own, (float)((1.0 - alpha) / (double)own_emitted), 0, threads);
    return st;
}

uint64_t photon_maps_memory_estimate(uint32_t global, uint32_t caustic)
{
    /* A map's traced records, at most twice their count in capacity while
     * batches double, live until the map is filled; the photons (20 bytes)
     * stay, sorting them into classes copies them once, and the kd-tree
     * adds fewer than 2n/KDTREE_BUCKET split planes (kdtree.h). */
    uint64_t largest = global > caustic ? global : caustic;
    uint64_t tracing = 2 * largest * sizeof(traced_photon);
    uint64_t stored = (uint64_t)global + caustic;
    uint64_t maps = 2 * stored * sizeof(photon) + 2 * stored / KDTREE_BUCKET * sizeof(kdtree_split);
    uint64_t sites = ((uint64_t)global + RADIANCE_SITE_STRIDE - 1) / RADIANCE_SITE_STRIDE;
    uint64_t site_bytes = sites * (9 * sizeof(float) + 2 * sizeof(photon) + 2 * sizeof(traced_photon));
    return tracing + maps + site_bytes;
}

void photon_maps_init(photon_maps *m)
{
    memset(m, 0, sizeof(*m));
    photon_map_init(&m->global);
    photon_map_init(&m->caustic);
    photon_map_init(&m->radiance);
}

static uint32_t float_bits(float x)
{
    uint32_t v;
    memcpy(&v, &x, 4);
    return v;
}

void photon_trace_settings_words(const photon_trace_settings *ps, uint32_t w[PHOTON_TRACE_SETTING_WORDS])
{
    uint32_t n = 0;
    w[n++] = ps->global_photons;
    w[n++] = ps->caustic_photons;
    w[n++] = (uint32_t)ps->max_emitted;
    w[n++] = (uint32_t)(ps->max_emitted >> 32);
    w[n++] = ps->max_bounces;
    w[n++] = ps->seed;
    w[n++] = ps->sampler;
    w[n++] = ps->radiance_k;
    w[n++] = float_bits(ps->max_radius);
    w[n++] = float_bits(ps->caustic_roughness);
}

const char *const photon_trace_setting_names[PHOTON_TRACE_SETTING_WORDS] = {
    "global_photons", "caustic_photons", "max_photons_emitted_millions", "max_photons_emitted_millions",
    "max_bounces", "seed", "sampler", "global_estimate_photons", "max_radius", "caustic_roughness"};

void photon_maps_free(photon_maps *m)
{
    photon_map_free(&m->global);
    photon_map_free(&m->caustic);
    photon_map_free(&m->radiance);
    free(m->radiance_sites);
    m->radiance_sites = NULL;
    m->radiance_site_count = 0;
}

/* Where radiance photons are computed: the landing points of photon paths
 * of their own, traced like the global map's, `n` of them. Sites taken
 * from the global map's own photons lie where its photons happen to
 * cluster, so their estimates (from the same photons) read high exactly
 * where their Voronoi cells are small and low where they are large, and a
 * lookup of the nearest site comes out dark on average: 3 % at 50 photons
 * an estimate, 27 % where sparse photons leave an estimate a handful
 * (measured in a sunlit room; docs/algorithms.md §5.3). Independent paths
 * make the sites independent of the photons they are estimated from. */
static phos_status trace_radiance_sites(const scene *s, const photon_trace_settings *ps, const projection_map *aim,
                                        photon_maps *out, uint32_t n, atomic_int *cancel,
                                        photon_trace_progress *progress)
{
    traced_list kept;
    uint64_t emitted;
    phos_status st = trace_map(s, ps, MAP_RADIANCE_SITES, aim, n, &kept, &emitted, cancel, progress, out->global.count);
    if (st == PHOS_OK && kept.count > 0) {
        out->radiance_sites = malloc(sizeof(float) * 9 * kept.count);
        if (!out->radiance_sites) {
            st = PHOS_ERROR_OUT_OF_MEMORY;
        } else {
            float *site = out->radiance_sites;
            for (uint32_t i = 0; i < kept.part_count; i++)
                for (uint32_t j = 0; j < kept.parts[i].count; j++, site += 9) {
                    const traced_photon *tp = &kept.parts[i].items[j];
                    memcpy(site, &tp->position, sizeof(vec3));
                    memcpy(site + 3, &tp->normal, sizeof(vec3));
                    memcpy(site + 6, &tp->albedo, sizeof(vec3));
                }
            out->radiance_site_count = kept.count;
        }
    }
    traced_list_free(&kept);
    return st;
}

/* Pilot photons through each distant light's cell and each lamp's cone
 * (docs/algorithms.md §3.1): the weight of a cell or cone is the share of
 * its pilot paths that store a photon where the camera reads photons
 * (photon_importance.h), never below PILOT_FLOOR, so that every one keeps
 * a chance and the map stays unbiased. Items are the cells, then the
 * cones, each list in its groups' order. */
typedef struct pilot {
    const scene *s;
    const photon_trace_settings *ps;
    const projection_map *pm;
    const photon_importance *imp;
    uint32_t map;                /* MAP_GLOBAL or MAP_CAUSTIC: the photons a pilot stores */
    uint32_t cells;              /* items below this are cells */
    const uint32_t *item_group;  /* the group of each item */
    const uint32_t *group_pilots;/* pilot paths through each group's cells or cones */
    float *weights;
} pilot;

/* Pilot path indices: the cells' from 0, the cones' from here. */
#define CONE_PILOT_BASE (1ull << 40)

static void pilot_item(void *ctx, uint32_t item, uint32_t thread)
{
    (void)thread;
    pilot *p = ctx;
    uint32_t g = p->item_group[item], is_cone = item >= p->cells;
    uint32_t k = (is_cone ? item - p->cells : item) - p->pm->groups[g].first;
    batch b;
    memset(&b, 0, sizeof(b));
    uint32_t useful = 0, pilots = p->group_pilots[g];
    for (uint32_t i = 0; i < pilots; i++) {
        uint64_t path = is_cone ? CONE_PILOT_BASE + (uint64_t)(item - p->cells) * CONE_PILOT_PHOTONS + i
                                : (uint64_t)item * PILOT_PHOTONS + i;
        sampler smp = sampler_for_index(p->ps->sampler, p->ps->seed,
                                        p->map == MAP_CAUSTIC ? MAP_CAUSTIC_PILOT : MAP_PILOT, path);
        vec3 o, d;
        if (is_cone) {
            if (!projection_map_cone_ray(p->s, p->pm, g, k, sampler_1d(&smp, DIM_EMIT), sampler_2d(&smp, DIM_EMIT + 1),
                                         sampler_2d(&smp, DIM_EMIT + 3), &o, &d))
                continue;
        } else {
            projection_map_cell_ray(p->s, p->pm, g, k, sampler_2d(&smp, DIM_EMIT + 1), sampler_2d(&smp, DIM_EMIT + 3),
                                    &o, &d);
        }
        b.count = 0;
        trace_from(p->s, p->ps, p->map, &smp, o, d, v3s(1.0f), path, &b);
        for (uint32_t j = 0; j < b.count; j++)
            if (photon_importance_marked(p->imp, b.items[j].position, b.items[j].normal)) {
                useful++;
                break;
            }
    }
    free(b.items);
    p->weights[item] = fmaxf((float)useful / (float)pilots, PILOT_FLOOR);
}

/* Weighs the map's cells and (where a lamp has more than one) cones by
 * pilots, each by the share of its paths that store a photon of `map`
 * where the camera reads; *weighed: any were. */
static phos_status weigh_by_pilots(const scene *s, const photon_trace_settings *ps, projection_map *aim,
                                   const photon_importance *imp, uint32_t map, atomic_int *cancel, int *weighed)
{
    uint32_t cells = 0, cones = 0;
    for (uint32_t g = 0; g < aim->group_count; g++) {
        const projection_group *pg = &aim->groups[g];
        cells += pg->distant ? pg->count : 0;
        cones += !pg->distant && !pg->all ? pg->count : 0;
    }
    uint32_t items = cells + cones;
    float *weights = malloc(sizeof(float) * items);
    uint32_t *item_group = malloc(sizeof(uint32_t) * items);
    uint32_t *group_pilots = calloc(aim->group_count, sizeof(uint32_t));
    phos_status st = weights && item_group && group_pilots ? PHOS_OK : PHOS_ERROR_OUT_OF_MEMORY;
    if (st == PHOS_OK) {
        for (uint32_t g = 0; g < aim->group_count; g++) {
            const projection_group *pg = &aim->groups[g];
            int world = light_is_world(&s->lights.lights[s->lights.groups[g].first]);
            group_pilots[g] = pg->distant ? (world ? WORLD_PILOT_PHOTONS : PILOT_PHOTONS) : CONE_PILOT_PHOTONS;
            uint32_t base = pg->distant ? 0 : cells;
            for (uint32_t k = 0; !pg->all && k < pg->count; k++)
                item_group[base + pg->first + k] = g;
        }
        pilot p = {s, ps, aim, imp, map, cells, item_group, group_pilots, weights};
        if (!parallel_for(items, parallel_thread_count(ps->threads), pilot_item, &p, cancel))
            st = PHOS_ERROR_CANCELLED;
        else if (!projection_map_set_weights(aim, s, weights) || !projection_map_set_cone_weights(aim, weights + cells))
            st = PHOS_ERROR_OUT_OF_MEMORY;
    }
    free(weights);
    free(item_group);
    free(group_pilots);
    *weighed = st == PHOS_OK;
    return st;
}

/* Where the camera reads global photons (photon_importance.h), built once
 * when the aim or the test for an unread map first asks for it. */
typedef struct view_pilot {
    photon_importance imp;
    int state; /* 0: not built, 1: built, -1: out of memory */
} view_pilot;

static const photon_importance *view_pilot_get(view_pilot *v, const scene *s, const photon_trace_settings *ps)
{
    if (v->state == 0)
        v->state = photon_importance_build(&v->imp, s, ps->views, ps->view_count) ? 1 : -1;
    return v->state == 1 ? &v->imp : NULL;
}

/* Global photons aimed (docs/algorithms.md §3.1): lamps and emissive
 * meshes at the objects their photons can land on, suns and the world at
 * what the camera reads; with a camera, pilot photons weigh the distant
 * lights' cells and the cones of lamps that have several, so that what
 * the camera reads gets the photons. *aimed: the map is to be used;
 * *at_view: the camera weighed it. Nothing is aimed (*aimed 0, the map
 * freed) where no light gains by it: every lamp among the objects, as in
 * a closed room, and no distant light with a camera. */
static phos_status aim_global(const scene *s, const photon_trace_settings *ps, projection_map *aim, int *aimed,
                              int *at_view, view_pilot *view, atomic_int *cancel)
{
    *aimed = *at_view = 0;
    if (!projection_map_build_global(aim, s))
        return PHOS_ERROR_OUT_OF_MEMORY;
    int has_distant = 0, has_cones = 0, several_cones = 0;
    for (uint32_t g = 0; g < aim->group_count; g++) {
        const projection_group *pg = &aim->groups[g];
        has_distant |= pg->distant;
        has_cones |= !pg->all && !pg->distant;
        several_cones |= !pg->all && !pg->distant && pg->count > 1;
    }
    if (!s->has_camera || !(has_distant || several_cones)) {
        if (has_cones)
            *aimed = 1;
        else
            projection_map_free(aim);
        return PHOS_OK;
    }
    const photon_importance *imp = view_pilot_get(view, s, ps);
    phos_status st = imp ? weigh_by_pilots(s, ps, aim, imp, MAP_GLOBAL, cancel, at_view) : PHOS_ERROR_OUT_OF_MEMORY;
    if (st != PHOS_OK)
        projection_map_free(aim);
    else
        *aimed = 1;
    return st;
}

/* The caustic pass's aim (docs/algorithms.md §3.1): every light's cells
 * or cones toward the objects that scatter caustics (projection_map.h);
 * with a camera, pilot photons weigh a sun's cells, and the cones of a
 * lamp that reaches several such objects, by the share of their paths
 * that store a caustic photon where the camera reads. Most of a sun's
 * paths through an object's bounding sphere miss the object, or pass it
 * and land unscattered (86 % through a metal ring's), and most caustic
 * photons of a close-up land out of view: neither is then traced much.
 * *at_view: the camera weighed it. */
static phos_status aim_caustic(const scene *s, const photon_trace_settings *ps, projection_map *aim, view_pilot *view,
                               atomic_int *cancel, int *at_view)
{
    *at_view = 0;
    if (!projection_map_build(aim, s, ps->caustic_roughness))
        return PHOS_ERROR_OUT_OF_MEMORY;
    int weighable = 0;
    for (uint32_t g = 0; g < aim->group_count; g++) {
        const projection_group *pg = &aim->groups[g];
        weighable |= !pg->all && pg->count > (pg->distant ? 0u : 1u);
    }
    if (ps->unaimed || !s->has_camera || !weighable)
        return PHOS_OK;
    const photon_importance *imp = view_pilot_get(view, s, ps);
    phos_status st = imp ? weigh_by_pilots(s, ps, aim, imp, MAP_CAUSTIC, cancel, at_view) : PHOS_ERROR_OUT_OF_MEMORY;
    if (st != PHOS_OK)
        projection_map_free(aim);
    return st;
}

phos_status photon_caustic_aim_build(const scene *s, const photon_trace_settings *ps, projection_map *aim,
                                     atomic_int *cancel)
{
    view_pilot view = {0};
    int at_view;
    phos_status st = aim_caustic(s, ps, aim, &view, cancel, &at_view);
    if (view.state == 1)
        photon_importance_free(&view.imp);
    return st;
}

/* The caustic pass's own photons (target of them, aimed by `aim`) into
 * out's caustic map, after `reused` caustic photons of the global pass. */
static phos_status trace_caustic_pass(const scene *s, const photon_trace_settings *ps, const projection_map *aim,
                                      uint32_t target, photon_maps *out, const traced_list *global, uint32_t reused,
                                      atomic_int *cancel, photon_trace_progress *progress)
{
    traced_list own;
    phos_status st = trace_map(s, ps, MAP_CAUSTIC, aim, target, &own, &out->caustic_emitted, cancel, progress,
                               out->global.count + reused);
    if (st == PHOS_OK) {
        st = fill_caustic_map(&out->caustic, global, out->global_emitted, reused, &own, out->caustic_emitted,
                              parallel_thread_count(ps->threads));
        out->caustic_reused = reused;
    }
    traced_list_free(&own);
    return st;
}

/* The caustic map, given the global pass's photons. A caustic photon
 * needs a delta scattering on its way (L S+ D): in a scene where no
 * surface has a delta lobe the map can never fill, and every path traced
 * for it would be wasted. The global pass's caustic-flagged photons
 * already hold part of the map; the caustic pass traces only the rest,
 * aimed at the objects that scatter delta (aim_caustic). */
static phos_status trace_caustic_map(const scene *s, const photon_trace_settings *ps, photon_maps *out,
                                     const traced_list *global, view_pilot *view, atomic_int *cancel,
                                     photon_trace_progress *progress)
{
    if (ps->caustic_photons == 0 || !scene_can_scatter_caustic(s, ps->caustic_roughness))
        return PHOS_OK;
    uint32_t reused = traced_list_caustic(global);
    uint32_t target = reused < ps->caustic_photons ? ps->caustic_photons - reused : 0;
    if (progress)
        atomic_store(&progress->map, PHOS_MAP_CAUSTIC);
    projection_map aim;
    int at_view = 0;
    phos_status st = target ? aim_caustic(s, ps, &aim, view, cancel, &at_view) : PHOS_OK;
    if (st != PHOS_OK)
        return st;
    st = trace_caustic_pass(s, ps, target ? &aim : NULL, target, out, global, reused, cancel, progress);
    out->aimed_at_view |= at_view;
    if (target)
        projection_map_free(&aim);
    return st;
}

phos_status photon_maps_trace_caustic(const scene *s, const photon_trace_settings *ps, const projection_map *aim,
                                      photon_maps *out, atomic_int *cancel)
{
    if (ps->caustic_photons == 0 || !scene_can_scatter_caustic(s, ps->caustic_roughness))
        return PHOS_OK;
    traced_list none;
    memset(&none, 0, sizeof(none));
    phos_status st = trace_caustic_pass(s, ps, aim, ps->caustic_photons, out, &none, 0, cancel, NULL);
    if (st == PHOS_OK)
        photon_maps_note_short(out, s, ps);
    return st;
}

/* The global map's photon count: none where the render would not read
 * the map (photon_trace_settings.gathers_only) because none of the
 * pilot's gathers from what the camera sees finds a surface, as around a
 * lone object in an empty world (Blender's default cube): every gather
 * leaves for the sky, and tracing the map would be time spent on photons
 * nothing reads. The render then path-traces its gathers (render.c), so a
 * gather the pilot missed still gets its light. */
static phos_status global_target(const scene *s, const photon_trace_settings *ps, view_pilot *view,
                                 uint32_t *target)
{
    *target = ps->global_photons;
    if (!*target || !ps->gathers_only || !s->has_camera)
        return PHOS_OK;
    const photon_importance *imp = view_pilot_get(view, s, ps);
    if (!imp)
        return PHOS_ERROR_OUT_OF_MEMORY;
    if (imp->gather_hits == 0)
        *target = 0;
    return PHOS_OK;
}

phos_status photon_maps_trace(const scene *s, const photon_trace_settings *ps, photon_maps *out, atomic_int *cancel,
                              photon_trace_progress *progress)
{
    traced_list kept;
    if (progress)
        atomic_store(&progress->map, PHOS_MAP_GLOBAL);
    projection_map global_aim;
    view_pilot view = {0};
    int aimed = 0, at_view = 0;
    uint32_t target;
    phos_status st = global_target(s, ps, &view, &target);
    if (st == PHOS_OK && target && !ps->unaimed)
        st = aim_global(s, ps, &global_aim, &aimed, &at_view, &view, cancel);
    if (st != PHOS_OK) {
        if (view.state == 1)
            photon_importance_free(&view.imp);
        return st;
    }
    const projection_map *ga = aimed ? &global_aim : NULL;
    st = trace_map(s, ps, MAP_GLOBAL, ga, target, &kept, &out->global_emitted, cancel, progress, 0);
    if (st == PHOS_OK)
        st = fill_map(&out->global, &kept, out->global_emitted, parallel_thread_count(ps->threads));
    uint32_t global_count = kept.count;
    if (st == PHOS_OK && global_count > 0)
        st = trace_radiance_sites(s, ps, ga, out, (global_count + RADIANCE_SITE_STRIDE - 1) / RADIANCE_SITE_STRIDE,
                                  cancel, progress);
    /* A map left out for this view is as much the view's as an aimed one:
     * a final render after a camera move traces it again. */
    out->aimed_at_view = at_view || (ps->global_photons && !target);
    if (aimed)
        projection_map_free(&global_aim);
    if (st == PHOS_OK)
        st = trace_caustic_map(s, ps, out, &kept, &view, cancel, progress);
    if (view.state == 1)
        photon_importance_free(&view.imp);
    traced_list_free(&kept);
    if (st == PHOS_OK)
        photon_maps_note_short(out, s, ps);
    return st;
}

void photon_maps_note_short(photon_maps *m, const scene *s, const photon_trace_settings *ps)
{
    int caustic_traced = ps->caustic_photons > 0 && scene_can_scatter_caustic(s, ps->caustic_roughness);
    /* A global map that emitted nothing was not traced, not cut short. */
    m->short_maps = (ps->global_photons && m->global_emitted && m->global.count < ps->global_photons
                         ? 1u << PHOS_MAP_GLOBAL
                         : 0u) |
                    (caustic_traced && m->caustic.count < ps->caustic_photons ? 1u << PHOS_MAP_CAUSTIC : 0u);
}

phos_status photon_maps_build(photon_maps *m, uint32_t threads, atomic_int *cancel)
{
    photon_map *const maps[2] = {&m->global, &m->caustic};
    if (!photon_map_build_many(maps, 2, threads, cancel))
        return cancel && atomic_load(cancel) ? PHOS_ERROR_CANCELLED : PHOS_ERROR_OUT_OF_MEMORY;
    return PHOS_OK;
}

typedef struct precompute {
    const scene *s;
    const photon_maps *maps;
    const photon_trace_settings *ps;
    kdtree_query *queries; /* one per thread */
    const uint32_t *order; /* the sites to estimate, in space order */
    photon *out;
} precompute;

#define SITES_PER_ITEM 256u

/* The sites are traced in path order, which scatters consecutive ones over
 * the whole scene: each search then finds the global map's buckets cold.
 * Estimated along a Morton curve instead, consecutive searches share their
 * buckets (docs/benchmarks.md, "Thread scaling by stage"). Each site's
 * radiance photon is written to its own slot, so the map is the same. */
typedef struct site_key {
    uint32_t code, index;
} site_key;

/* The low 10 bits of v, spread to every third bit. */
static uint32_t spread_bits_10(uint32_t v)
{
    v &= 1023u;
    v = (v | (v << 16)) & 0x030000ffu;
    v = (v | (v << 8)) & 0x0300f00fu;
    v = (v | (v << 4)) & 0x030c30c3u;
    v = (v | (v << 2)) & 0x09249249u;
    return v;
}

/* Sorts the n keys by code, keeping equal codes in the order given: a
 * least-significant-digit radix sort, three passes of 10 bits over the
 * 30-bit codes (Knuth, TAOCP vol. 3, §5.2.5). A comparison sort took 0.06 s
 * of the stage for 500 000 sites, on one thread; this takes a few ms.
 * `spare` holds n keys; returns whichever of the two holds the sorted keys. */
static const site_key *sort_site_keys(site_key *keys, site_key *spare, uint32_t n)
{
    for (int shift = 0; shift < 30; shift += 10) {
        uint32_t start[1024] = {0};
        for (uint32_t i = 0; i < n; i++)
            start[(keys[i].code >> shift) & 1023u]++;
        uint32_t sum = 0;
        for (uint32_t d = 0; d < 1024; d++) {
            uint32_t c = start[d];
            start[d] = sum;
            sum += c;
        }
        for (uint32_t i = 0; i < n; i++)
            spare[start[(keys[i].code >> shift) & 1023u]++] = keys[i];
        site_key *t = keys;
        keys = spare;
        spare = t;
    }
    return keys;
}

/* The n sites' indices along a Morton curve over their bounding box, 1024
 * cells an axis (ties by index, so the order is the same on every run);
 * NULL when memory runs out. */
static uint32_t *sites_in_space_order(const float *sites, uint32_t n)
{
    site_key *keys = malloc(sizeof(site_key) * 2 * (n ? n : 1));
    uint32_t *order = malloc(sizeof(uint32_t) * (n ? n : 1));
    if (!keys || !order) {
        free(keys);
        free(order);
        return NULL;
    }
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < n; i++)
        for (int a = 0; a < 3; a++) {
            lo[a] = fminf(lo[a], sites[9 * i + a]);
            hi[a] = fmaxf(hi[a], sites[9 * i + a]);
        }
    float scale[3];
    for (int a = 0; a < 3; a++)
        scale[a] = hi[a] > lo[a] ? 1023.0f / (hi[a] - lo[a]) : 0.0f;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t code = 0;
        for (int a = 0; a < 3; a++) {
            float cell = (sites[9 * i + a] - lo[a]) * scale[a];
            code |= spread_bits_10(cell > 0.0f ? (uint32_t)fminf(cell, 1023.0f) : 0u) << a; /* NaN: 0 */
        }
        keys[i] = (site_key){code, i};
    }
    const site_key *sorted = sort_site_keys(keys, keys + n, n);
    for (uint32_t i = 0; i < n; i++)
        order[i] = sorted[i].index;
    free(keys);
    return order;
}

static void precompute_sites(void *ctx, uint32_t item, uint32_t thread)
{
    precompute *pc = ctx;
    const photon_maps *m = pc->maps;
    /* Light that scattered at least once before: final gathering takes
     * direct light at its hits from a light sample (final_gather.c). */
    estimate_params ep = {pc->ps->radiance_k, pc->ps->max_radius, ESTIMATE_BOX, PHOTON_DIRECT, pc->s};
    uint32_t begin = item * SITES_PER_ITEM, end = begin + SITES_PER_ITEM;
    if (end > m->radiance_site_count)
        end = m->radiance_site_count;
    for (uint32_t k = begin; k < end; k++) {
        uint32_t i = pc->order[k];
        const float *site = m->radiance_sites + 9 * i;
        vec3 p = v3_load(site), n = v3_load(site + 3), rho = v3_load(site + 6);
        kdtree_query *q = &pc->queries[thread];
        q->radius2 = ep.max_radius * ep.max_radius; /* what it stays if there is no photon to search */
        vec3 E = photon_irradiance(&m->global, p, n, &ep, q);
        /* Lambertian exitance: L = ρ/π · E (W/(m²·sr)), and the radius
         * of the estimate (the disc metric's, so never below the
         * Euclidean distance of the photons it counted). */
        pc->out[i] = photon_make(p, v3_scale(v3_mul(rho, E), PHOS_INV_PI), n, n, 0);
        radiance_photon_set_radius(&pc->out[i], sqrtf(q->radius2));
    }
}

phos_status photon_maps_precompute_radiance(const scene *s, const photon_trace_settings *ps, photon_maps *m,
                                            atomic_int *cancel)
{
    uint32_t n = m->radiance_site_count;
    if (n == 0)
        return PHOS_OK;
    uint32_t threads = parallel_thread_count(ps->threads);
    uint32_t *order = sites_in_space_order(m->radiance_sites, n);
    precompute pc = {s, m, ps, parallel_scratch_calloc(threads, sizeof(kdtree_query)), order, malloc(sizeof(photon) * n)};
    phos_status st = PHOS_OK;
    if (!pc.queries || !pc.out || !order)
        st = PHOS_ERROR_OUT_OF_MEMORY;
    for (uint32_t t = 0; st == PHOS_OK && t < threads; t++)
        if (!kdtree_query_init(&pc.queries[t], ps->radiance_k))
            st = PHOS_ERROR_OUT_OF_MEMORY;
    if (st == PHOS_OK && !parallel_for((n + SITES_PER_ITEM - 1) / SITES_PER_ITEM, threads, precompute_sites, &pc, cancel))
        st = PHOS_ERROR_CANCELLED;
    if (st == PHOS_OK && (!photon_map_reserve(&m->radiance, n) || !photon_map_append(&m->radiance, pc.out, n) ||
                          !photon_map_build_many((photon_map *const[]){&m->radiance}, 1, threads, cancel)))
        st = cancel && atomic_load(cancel) ? PHOS_ERROR_CANCELLED : PHOS_ERROR_OUT_OF_MEMORY;
    for (uint32_t t = 0; pc.queries && t < threads; t++)
        kdtree_query_free(&pc.queries[t]);
    free(pc.queries);
    free(order);
    free(pc.out);
    free(m->radiance_sites);
    m->radiance_sites = NULL;
    return st;
}
