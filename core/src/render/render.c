/*
 * render.c — the stages of a render, the tile loop shared by the
 * integrators, progress and cancellation.
 *
 * A controller thread runs the stages in order; each stage fans out over
 * the render's threads (parallel.c). Tiles: each pixel is rendered with
 * all its samples before the next, so a finished tile is final and is
 * streamed to Blender at once. Every sample's random numbers depend only on
 * (seed, pixel, sample) and a pixel is the mean of its samples summed in
 * sample order; the photon maps are assembled in path order: the image is
 * the same for any thread count, tile order or region.
 */
#include "render/render.h"

#include "indirect/indirect_diffuse.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cache/irradiance_cache_file.h"
#include "cache/photon_maps_file.h"
#include "render/noise_filter.h"
#include "scene/embree.h"
#include "util/parallel.h"

/* ---------------------------------------------------------------- tiles */

typedef struct tile_key {
    float dist2;
    uint32_t index;
    phos_tile tile;
} tile_key;

static int compare_tile_keys(const void *a, const void *b)
{
    const tile_key *x = a, *y = b;
    if (x->dist2 != y->dist2)
        return x->dist2 < y->dist2 ? -1 : 1;
    return x->index < y->index ? -1 : (x->index > y->index);
}

/* Tiles a thread should have to choose from: a thread that takes the last
 * tile while the others have finished leaves them idle for that tile's
 * time, so a small image in few large tiles wastes much of the machine
 * (procedural_materials at 128², 2 threads: 4 tiles of 64 took 9.2 ms of
 * wall per sample, 64 tiles of 16 took 8.1; docs/benchmarks.md). */
#define TILES_PER_THREAD 16u

/* The tile edge: the setting's, halved (not below 8 pixels) until each
 * thread has TILES_PER_THREAD tiles. The image does not depend on it. */
static uint32_t tile_edge(const film *f, uint32_t setting, uint32_t threads)
{
    uint32_t ts = setting;
    while (ts >= 16) {
        uint64_t tiles = (uint64_t)((f->width + ts - 1) / ts) * ((f->height + ts - 1) / ts);
        if (tiles >= (uint64_t)TILES_PER_THREAD * threads)
            break;
        ts /= 2;
    }
    return ts;
}

/* Tiles sorted centre-first (stable: ties keep row-major order). */
static int make_tiles(render *r)
{
    const film *f = &r->film;
    uint32_t ts = tile_edge(f, r->settings.tile_size, r->threads);
    uint32_t nx = (f->width + ts - 1) / ts, ny = (f->height + ts - 1) / ts;
    r->tile_count = nx * ny;
    r->tiles = malloc(sizeof(phos_tile) * r->tile_count);
    /* A tile finishes once per pass, and once more after the noise filter. */
    r->finished = malloc(sizeof(uint32_t) * r->tile_count * (r->pass_count + 1));
    tile_key *keys = malloc(sizeof(tile_key) * r->tile_count);
    if (!r->tiles || !r->finished || !keys) {
        free(keys);
        return 0;
    }
    float cx = 0.5f * (float)f->width, cy = 0.5f * (float)f->height;
    for (uint32_t j = 0; j < ny; j++) {
        for (uint32_t i = 0; i < nx; i++) {
            tile_key *k = &keys[j * nx + i];
            k->index = j * nx + i;
            k->tile.x = f->x0 + i * ts;
            k->tile.y = f->y0 + j * ts;
            k->tile.width = (i + 1) * ts <= f->width ? ts : f->width - i * ts;
            k->tile.height = (j + 1) * ts <= f->height ? ts : f->height - j * ts;
            float dx = (float)(i * ts) + 0.5f * (float)k->tile.width - cx;
            float dy = (float)(j * ts) + 0.5f * (float)k->tile.height - cy;
            k->dist2 = dx * dx + dy * dy;
        }
    }
    qsort(keys, r->tile_count, sizeof(tile_key), compare_tile_keys);
    for (uint32_t i = 0; i < r->tile_count; i++)
        r->tiles[i] = keys[i].tile;
    free(keys);
    return 1;
}

static const uint32_t component_pass[COMPONENT_COUNT] = {PHOS_PASS_EMISSION, PHOS_PASS_DIRECT, PHOS_PASS_SPECULAR,
                                                          PHOS_PASS_CAUSTICS, PHOS_PASS_INDIRECT};

static int pass_on(const render *r, uint32_t pass) { return r->film.planes[pass] != NULL; }

/* The sums of one pixel's samples, per pass that is a mean over them. */
typedef struct pixel_sums {
    double combined[4];          /* RGB (each sample's components added first), alpha */
    double component[COMPONENT_COUNT][3];
    double debug[2][3];          /* the photon map's and the caustic map's estimates */
    double features[2][3];       /* denoising albedo and normal */
    double moments[2];           /* Σ Y and Σ Y² of the samples' luminance (film.moments) */
    double caustic_read[3];      /* Σ of the first samples' caustic-map estimates (film.caustic_reads) */
} pixel_sums;

/* Where each sum lives in pixel_sums, by pass (NULL: not a mean). */
static double *sums_of(pixel_sums *a, uint32_t pass)
{
    switch (pass) {
    case PHOS_PASS_COMBINED: return a->combined;
    case PHOS_PASS_PHOTON_MAP: return a->debug[0];
    case PHOS_PASS_CAUSTIC_MAP: return a->debug[1];
    case PHOS_PASS_DENOISING_ALBEDO: return a->features[0];
    case PHOS_PASS_DENOISING_NORMAL: return a->features[1];
    default:
        for (int c = 0; c < COMPONENT_COUNT; c++)
            if (component_pass[c] == pass)
                return a->component[c];
        return NULL;
    }
}

/* Progressive refinement: the sums kept on the film between passes
 * (film.sums), read before a pass and written after it. */
static void exchange_sums(const render *r, uint32_t x, uint32_t y, pixel_sums *a, int store)
{
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        double *kept = r->film.sums[p];
        double *mine = sums_of(a, p);
        if (!kept || !mine)
            continue;
        kept = film_sums(&r->film, p, x, y);
        size_t bytes = sizeof(double) * phos_pass_channels(p);
        memcpy(store ? kept : mine, store ? mine : kept, bytes);
    }
    if (r->film.caustic_reads) {
        double *kept = r->film.caustic_reads + 3 * film_index(&r->film, x, y);
        memcpy(store ? kept : a->caustic_read, store ? a->caustic_read : kept, sizeof(a->caustic_read));
    }
    if (r->film.moments) {
        double *kept = r->film.moments + 2 * film_index(&r->film, x, y);
        memcpy(store ? kept : a->moments, store ? a->moments : kept, sizeof(a->moments));
    }
}

/* The film's pixel of every enabled mean pass: its sum over `samples`.
 * The first samples' caustic-map estimates (caustic_reads) are the mean
 * over those samples, min(samples, caustic_reads), and join the Caustics
 * component and Combined (docs/algorithms.md §4.7). */
static void write_means(render *r, uint32_t x, uint32_t y, pixel_sums *a, uint32_t samples)
{
    double inv = 1.0 / (double)samples;
    uint32_t reads = r->integrator.caustic_reads;
    double inv_reads = reads ? 1.0 / (double)(samples < reads ? samples : reads) : 0.0;
    for (uint32_t p = 0; p < PHOS_PASS_COUNT; p++) {
        const double *sum = sums_of(a, p);
        if (!pass_on(r, p) || !sum)
            continue;
        float *px = film_pixel(&r->film, p, x, y);
        int caustics = reads && (p == PHOS_PASS_COMBINED || p == component_pass[COMPONENT_CAUSTICS]);
        for (uint32_t ch = 0; ch < phos_pass_channels(p); ch++)
            px[ch] = (float)(sum[ch] * inv + (caustics && ch < 3 ? a->caustic_read[ch] * inv_reads : 0.0));
    }
    if (pass_on(r, PHOS_PASS_SAMPLE_COUNT))
        film_pixel(&r->film, PHOS_PASS_SAMPLE_COUNT, x, y)[0] = (float)samples / (float)r->settings.samples;
    /* The image before the noise filter: Combined as rendered, which the
     * FILTERING stage then replaces (and Combined itself without a filter). */
    if (pass_on(r, PHOS_PASS_NOISY_IMAGE))
        memcpy(film_pixel(&r->film, PHOS_PASS_NOISY_IMAGE, x, y), film_pixel(&r->film, PHOS_PASS_COMBINED, x, y),
               4 * sizeof(float));
}

/* Luminance of linear Rec. 709 RGB (ITU-R BT.709). */
static double luminance(const double rgb[3]) { return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]; }

/* Adaptive sampling checks a pixel after its first adaptive_min_samples
 * samples and every ADAPTIVE_CHECK_STEP after: checking after every sample
 * would stop more pixels on a lucky run of low values. */
#define ADAPTIVE_CHECK_STEP 8u

/* Whether a pixel of n samples has converged: its mean's standard error,
 * from the samples' variance (Σ Y, Σ Y² in m), over the threshold times
 * √μ, or μ above 1. An error δ moves a pixel's displayed value, about
 * μ^(1/2.2), by δ/(2.2·μ^0.55), close to δ/√μ in the range most pixels
 * show; above 1 the view transform compresses, and the relative error
 * δ/μ is what shows (Cycles normalises its error the same way). With the
 * stratified samplers the sample variance overestimates the error of the
 * mean, so pixels stop later than they could, never earlier. */
static int pixel_converged(const phos_render_settings *rs, const double m[2], uint32_t n)
{
    if (n < rs->adaptive_min_samples || n < 2 || (n - rs->adaptive_min_samples) % ADAPTIVE_CHECK_STEP)
        return 0;
    double mean = m[0] / n;
    double variance = fmax((m[1] - m[0] * mean) / (n - 1), 0.0);
    double scale = mean < 1.0 ? sqrt(fmax(mean, 0.0)) : mean;
    return sqrt(variance / n) <= rs->adaptive_threshold * scale;
}

/* The time limit has struck: never in the first pass, so that every
 * pixel has a sample. */
static int out_of_time(const render *r)
{
    return r->settings.time_limit > 0.0f && r->pass_first > 0 && monotonic_seconds() >= r->time_limit_end;
}

static void add3(double sum[3], vec3 v)
{
    sum[0] += v.x;
    sum[1] += v.y;
    sum[2] += v.z;
}

/* What became of a pixel's samples. */
enum pixel_outcome {
    PIXEL_RENDERED,     /* its samples are in the film */
    PIXEL_CANCELLED,    /* cancelled part-way: it keeps what the passes before gave it */
    PIXEL_OUT_OF_TIME   /* the time limit struck part-way: likewise */
};

/* Renders samples [first, end) of one pixel, on top of the sums of those
 * before (progressive refinement), and writes the mean of all so far. A
 * cancel is checked before every sample, and inside its gathers, so even
 * pixels of millions of samples stop at once; so is the time limit.
 * Adaptive sampling may stop the pixel before `end`, for good. */
static enum pixel_outcome render_pixel(render *r, uint32_t x, uint32_t y, uint32_t first, uint32_t end,
                                       integrator_scratch *scratch)
{
    const phos_render_settings *rs = &r->settings;
    const scene *s = r->scene;
    uint32_t *count = &r->film.sample_counts[film_index(&r->film, x, y)];
    if (*count & PIXEL_CONVERGED)
        return PIXEL_RENDERED; /* stopped by adaptive sampling in an earlier pass */
    int debug = pass_on(r, PHOS_PASS_PHOTON_MAP) || pass_on(r, PHOS_PASS_CAUSTIC_MAP);
    pixel_sums a;
    memset(&a, 0, sizeof(a));
    if (first > 0)
        exchange_sums(r, x, y, &a, 0);
    uint32_t n = first, converged = 0;
    /* One footprint for all the pixel's samples: the angle between
     * neighbouring pixels' rays changes across a pixel by about one part in
     * the image's width, far below what texture filtering resolves. */
    camera_ray centre;
    camera_ray_set_footprint(&s->camera, ((float)x + 0.5f) / (float)rs->width, ((float)y + 0.5f) / (float)rs->height,
                             rs->width, rs->height, &centre);
    sampler smp = sampler_for_pixel(rs->sampler, rs->seed, x, y, first, rs->samples);
    float inv_width = 1.0f / (float)rs->width, inv_height = 1.0f / (float)rs->height;
    int features = r->integrator.denoising_features;
    for (uint32_t i = first; i < end && !converged; i++) {
        if (atomic_load_explicit(&r->cancel, memory_order_relaxed))
            return PIXEL_CANCELLED;
        if (out_of_time(r))
            return PIXEL_OUT_OF_TIME;
        smp.index = i;
        float2 uf = sampler_2d(&smp, DIM_FILM);
        float fx = ((float)x + 0.5f + pixel_filter_sample(&r->filter, uf.x)) * inv_width;
        float fy = ((float)y + 0.5f + pixel_filter_sample(&r->filter, uf.y)) * inv_height;
        float2 lens = camera_has_lens(&s->camera) ? sampler_2d(&smp, DIM_LENS) : (float2){0.5f, 0.5f};
        camera_ray ray = camera_generate_ray(&s->camera, fx, fy, lens);
        ray.spread_origin = centre.spread_origin;
        ray.spread_per_distance = centre.spread_per_distance;
        sample_result sr;
        if (rs->integrator == PHOS_INTEGRATOR_PHOTON)
            photon_render(s, &r->integrator, ray, &smp, scratch, &sr);
        else
            path_trace(s, &r->integrator, ray, &smp, scratch, &sr);
        if (debug)
            photon_debug_estimates(s, &r->integrator, ray, scratch, &sr);
        /* A non-finite sample (a numerical failure) is dropped rather than
         * allowed to poison the pixel: a NaN or an infinity in any component
         * makes their float sum non-finite too. */
        vec3 total = sr.caustic_read;
        for (int c = 0; c < COMPONENT_COUNT; c++)
            total = v3_add(total, sr.component[c]);
        if (!v3_is_finite(total)) {
            memset(sr.component, 0, sizeof(sr.component));
            sr.caustic_read = v3s(0.0f);
        }
        add3(a.caustic_read, sr.caustic_read);
        double sample_sum[3] = {0.0, 0.0, 0.0};
        for (int c = 0; c < COMPONENT_COUNT; c++) {
            add3(a.component[c], sr.component[c]);
            add3(sample_sum, sr.component[c]);
        }
        for (int ch = 0; ch < 3; ch++)
            a.combined[ch] += sample_sum[ch];
        a.combined[3] += sr.alpha;
        double y_lum = luminance(sample_sum);
        a.moments[0] += y_lum;
        a.moments[1] += y_lum * y_lum;
        if (debug && v3_is_finite(sr.photon_map) && v3_is_finite(sr.caustic_map)) {
            add3(a.debug[0], sr.photon_map);
            add3(a.debug[1], sr.caustic_map);
        }
        /* The features' means over the samples: the normal is not
         * renormalised, so a pixel straddling an edge holds the mean
         * direction (Cycles). */
        if (features && v3_is_finite(sr.denoising_albedo) && v3_is_finite(sr.denoising_normal)) {
            add3(a.features[0], sr.denoising_albedo);
            add3(a.features[1], sr.denoising_normal);
        }
        n = i + 1;
        converged = rs->adaptive_sampling && pixel_converged(rs, a.moments, n);
    }
    if (end < rs->samples || r->film.moments)
        exchange_sums(r, x, y, &a, 1);
    write_means(r, x, y, &a, n);
    *count = n | (converged ? PIXEL_CONVERGED : 0u);
    return PIXEL_RENDERED;
}

static void render_tile(void *ctx, uint32_t item, uint32_t thread)
{
    render *r = ctx;
    const phos_tile *t = &r->tiles[item];
    integrator_scratch *sc = &r->scratch[thread];
    uint64_t rays_before = embree_thread_rays(), lookups_before = sc->cache_lookups, hits_before = sc->cache_hits;
    uint64_t gathers_before = sc->gather_rays;
    /* A tile the time limit cut short is still delivered: each of its
     * pixels holds this pass's samples or the passes' before. */
    enum pixel_outcome outcome = PIXEL_RENDERED;
    for (uint32_t y = t->y; y < t->y + t->height && outcome == PIXEL_RENDERED; y++)
        for (uint32_t x = t->x; x < t->x + t->width && outcome == PIXEL_RENDERED; x++)
            outcome = atomic_load_explicit(&r->cancel, memory_order_relaxed)
                          ? PIXEL_CANCELLED
                          : render_pixel(r, x, y, r->sweep_first, r->sweep_end, sc);
    int whole = outcome != PIXEL_CANCELLED;
    atomic_fetch_add(&r->rays_traced, embree_thread_rays() - rays_before);
    atomic_fetch_add(&r->cache_lookups, sc->cache_lookups - lookups_before);
    atomic_fetch_add(&r->cache_hits, sc->cache_hits - hits_before);
    atomic_fetch_add(&r->gather_rays, sc->gather_rays - gathers_before);
    if (!whole)
        return;
    atomic_fetch_add(&r->work_done, (uint64_t)t->width * t->height * (r->sweep_end - r->sweep_first));
    if (!r->sweep_delivers && outcome == PIXEL_RENDERED)
        return;
    pthread_mutex_lock(&r->lock);
    r->finished[r->finished_count++] = item;
    pthread_mutex_unlock(&r->lock);
    atomic_fetch_add(&r->tiles_done, 1u);
}

/* -------------------------------------------------------- photon dots */

/* Film position (pixels) of a world point and whether the camera sees it. */
static int project_to_film(const render *r, vec3 p, float *px, float *py)
{
    const phos_camera_desc *c = &r->scene->camera;
    const float *m = c->transform;
    float fx, fy;
    vec3 pc;
    if (!camera_project(c, p, &fx, &fy, &pc))
        return 0;
    vec3 origin = c->type == PHOS_CAMERA_ORTHOGRAPHIC ? xform_point(m, v3(pc.x, pc.y, 0.0f)) : xform_point(m, v3s(0.0f));
    *px = fx * (float)r->settings.width;
    *py = fy * (float)r->settings.height;
    vec3 to = v3_sub(p, origin);
    float dist = v3_length(to);
    if (!(dist > 0.0f))
        return 0;
    /* Seen if nothing lies between the camera and just before the photon. */
    return !embree_occluded(r->scene->bvh, origin, v3_scale(to, 1.0f / dist), 0.0f, dist * (1.0f - 1e-3f));
}

/* A dot in a debug pass where the camera sees p, coloured by the hue of
 * `value` (its largest channel scaled to 1); nothing where value is 0. */
static void draw_dot(render *r, uint32_t pass, vec3 p, vec3 value)
{
    film *f = &r->film;
    float fx, fy;
    if (!project_to_film(r, p, &fx, &fy) || fx < (float)f->x0 || fy < (float)f->y0)
        return;
    uint32_t x = (uint32_t)fx, y = (uint32_t)fy;
    if (x >= f->x0 + f->width || y >= f->y0 + f->height)
        return;
    float mx = v3_max_component(value);
    if (!(mx > 0.0f))
        return;
    float *px = film_pixel(f, pass, x, y);
    px[0] = value.x / mx;
    px[1] = value.y / mx;
    px[2] = value.z / mx;
}

static void draw_photons(render *r, const photon_map *m)
{
    for (uint32_t i = 0; i < m->count; i++)
        draw_dot(r, PHOS_PASS_PHOTONS, photon_position(&m->photons[i]), photon_power(&m->photons[i]));
}

/* The records, as the course's "Cache Positions" pictures show them; a
 * record that gathered no light is drawn white. */
static void draw_records(render *r, const irradiance_cache *c)
{
    for (uint32_t i = 0; i < c->count; i++) {
        vec3 E = v3_add(c->records[i].E, c->records[i].E_caustic);
        draw_dot(r, PHOS_PASS_IRRADIANCE_CACHE, c->records[i].p, v3_max_component(E) > 0.0f ? E : v3s(1.0f));
    }
}

/* ---------------------------------------------------------- controller */

static void fail(render *r, phos_status st, const char *msg)
{
    pthread_mutex_lock(&r->lock);
    if (r->status == PHOS_OK) {
        r->status = st;
        snprintf(r->error, sizeof(r->error), "%s", msg);
    }
    pthread_mutex_unlock(&r->lock);
}

static uint64_t scratch_gather_rays(const render *r)
{
    uint64_t n = 0;
    for (uint32_t t = 0; t < r->threads; t++)
        n += r->scratch[t].gather_rays;
    return n;
}

/* The irradiance cache's pre-pass (its records' gathers read the maps),
 * or the cache read from its file; written to it after the pre-pass if
 * asked. */
static phos_status fill_cache(render *r)
{
    char msg[sizeof(r->error)];
    if (r->cache_file_mode[PHOS_CACHE_IRRADIANCE] == PHOS_CACHE_FILE_LOAD) {
        phos_status st = irradiance_cache_load(&r->cache, r->scene, &r->settings, r->cache_path[PHOS_CACHE_IRRADIANCE], msg, sizeof(msg));
        if (st != PHOS_OK)
            fail(r, st, msg);
        atomic_store(&r->cache_passes_done, irradiance_cache_fill_passes(&r->cache_fill));
        return st;
    }
    if (r->use_maps)
        r->integrator.maps = r->maps;
    uint64_t before = scratch_gather_rays(r);
    phos_status st = irradiance_cache_fill(&r->cache, r->scene, &r->integrator, &r->cache_fill, r->scratch, &r->cancel,
                                           &r->cache_passes_done, &r->cache_rays);
    atomic_fetch_add(&r->gather_rays, scratch_gather_rays(r) - before);
    if (st == PHOS_OK && r->cache_file_mode[PHOS_CACHE_IRRADIANCE] == PHOS_CACHE_FILE_SAVE) {
        st = irradiance_cache_save(&r->cache, r->scene, &r->settings, r->cache_path[PHOS_CACHE_IRRADIANCE], msg, sizeof(msg));
        if (st != PHOS_OK)
            fail(r, st, msg);
    }
    return st;
}

/* Photon tracing, or the maps read from their file instead; written to
 * it after tracing if asked. */
static phos_status trace_photons(render *r)
{
    char msg[sizeof(r->error)];
    const char *path = r->cache_path[PHOS_CACHE_PHOTON_MAPS];
    uint32_t mode = r->cache_file_mode[PHOS_CACHE_PHOTON_MAPS];
    phos_status st;
    if (mode == PHOS_CACHE_FILE_LOAD) {
        st = photon_maps_load(r->maps, r->scene, &r->photon_settings, path, msg, sizeof(msg));
        atomic_store(&r->photon_progress.stored, r->maps->global.count + r->maps->caustic.count);
        atomic_store(&r->photon_progress.emitted, r->maps->global_emitted + r->maps->caustic_emitted);
    } else {
        st = photon_maps_trace(r->scene, &r->photon_settings, r->maps, &r->cancel, &r->photon_progress);
        if (st == PHOS_OK && mode == PHOS_CACHE_FILE_SAVE)
            st = photon_maps_save(r->maps, r->scene, &r->photon_settings, path, msg, sizeof(msg));
        else if (st != PHOS_OK)
            return st;
    }
    if (st != PHOS_OK)
        fail(r, st, msg);
    return st;
}

/* Once the maps are complete (traced, loaded or given): a global map not
 * traced, because no gather the camera's pilot sent found a surface
 * (photon_trace.c) or no light emits, is not read. Gathers path-trace
 * onward instead, which is consistent, and costs nothing where they only
 * leave for the sky; maps loaded or kept from a render that did not trace
 * theirs read so for any view. */
static void settle_gathers(render *r)
{
    integrator_settings *is = &r->integrator;
    if (!r->use_maps || is->cache_inner != &indirect_final_gather || r->maps->global_emitted != 0)
        return;
    is->cache_inner = &indirect_path_hemisphere;
    if (!r->use_cache)
        is->indirect = is->cache_inner;
}

/* Samples [first, end) of every tile, delivered if `delivers`. */
static phos_status sweep(render *r, uint32_t first, uint32_t end, int delivers)
{
    r->sweep_first = first;
    r->sweep_end = end;
    r->sweep_delivers = delivers;
    if (!parallel_for(r->tile_count, r->threads, render_tile, r, &r->cancel))
        return atomic_load(&r->cancel) ? PHOS_ERROR_CANCELLED : PHOS_ERROR_INTERNAL;
    return PHOS_OK;
}

/* One pass of the rendering stage: one sweep, or with progressive
 * caustics one sweep per sample, each after its own caustic map (the end
 * of each sweep is the barrier that keeps the next map from replacing one
 * still read). A cancel or the time limit is seen between samples. */
static phos_status render_pass(render *r)
{
    if (!r->use_progressive)
        return sweep(r, r->pass_first, r->pass_end, 1);
    for (uint32_t i = r->pass_first; i < r->pass_end; i++) {
        if (atomic_load(&r->cancel))
            return PHOS_ERROR_CANCELLED;
        /* Out of time: a last sweep that renders nothing (every pixel
         * stops at once) delivers the tiles, without tracing a map. */
        int timed_out = out_of_time(r);
        if (!timed_out) {
            phos_status st = progressive_caustics_begin_sample(&r->progressive, r->scene, i, &r->cancel);
            if (st != PHOS_OK)
                return st;
            r->integrator.progressive = &r->progressive;
        }
        int last = i + 1 == r->pass_end || timed_out;
        phos_status st = sweep(r, i, i + 1, last);
        if (st != PHOS_OK || last)
            return st;
    }
    return PHOS_OK;
}

/* Runs one stage of the plan (stages.h). */
static phos_status run_stage(render *r, uint32_t stage)
{
    if (!stage_is_photon_stage(stage))
        settle_gathers(r);
    switch (stage) {
    case PHOS_STAGE_TRACING_PHOTONS:
        return trace_photons(r);
    case PHOS_STAGE_BUILDING_KDTREES:
        return photon_maps_build(r->maps, r->threads, &r->cancel);
    case PHOS_STAGE_PRECOMPUTING_RADIANCE:
        return photon_maps_precompute_radiance(r->scene, &r->photon_settings, r->maps, &r->cancel);
    case PHOS_STAGE_FILLING_IRRADIANCE_CACHE:
        return fill_cache(r);
    case PHOS_STAGE_RENDERING:
        /* The maps and the cache are complete: draw them, hand them to the
         * integrators. */
        if (r->use_maps) {
            if (pass_on(r, PHOS_PASS_PHOTONS)) {
                draw_photons(r, &r->maps->global);
                draw_photons(r, &r->maps->caustic);
            }
            r->integrator.maps = r->maps;
        }
        if (r->use_cache) {
            if (pass_on(r, PHOS_PASS_IRRADIANCE_CACHE))
                draw_records(r, &r->cache);
            r->integrator.cache = &r->cache;
        }
        /* Pass after pass over the whole frame (progressive refinement);
         * the end of each parallel_for is the barrier that keeps a tile's
         * next pass from starting before its last one ended. */
        r->time_limit_end = monotonic_seconds() + (double)r->settings.time_limit;
        for (uint32_t p = 0; p < r->pass_count; p++) {
            r->pass_first = p ? r->pass_ends[p - 1] : 0;
            r->pass_end = r->pass_ends[p];
            phos_status st = render_pass(r);
            if (st != PHOS_OK)
                return st;
            if (out_of_time(r))
                break; /* pixels hold different sample counts: the Sample Count pass shows them */
            atomic_store(&r->samples_done, r->pass_end);
        }
        return PHOS_OK;
    case PHOS_STAGE_FILTERING:
        return render_filter(r);
    default: /* WAITING and FINISHED only mark the ends of the plan */
        return PHOS_OK;
    }
}

double monotonic_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void *controller_main(void *arg)
{
    render *r = arg;
    phos_status st = PHOS_OK;
    /* The stages between WAITING and FINISHED, in plan order; a cancel is
     * seen before each (and inside the long ones). */
    for (uint32_t i = 1; i + 1 < r->plan.count && st == PHOS_OK; i++) {
        if (atomic_load(&r->cancel)) {
            st = PHOS_ERROR_CANCELLED;
            break;
        }
        pthread_mutex_lock(&r->lock);
        r->stage_started = monotonic_seconds();
        atomic_store(&r->stage_index, i);
        pthread_mutex_unlock(&r->lock);
        st = run_stage(r, r->plan.stages[i]);
        if (st == PHOS_OK && r->use_maps && !atomic_load(&r->maps_complete) &&
            !stage_is_photon_stage(r->plan.stages[i + 1])) {
            /* The last photon stage is done: the maps may now be kept. */
            shared_maps_seal(r->shared, r->scene, &r->photon_settings,
                             stage_plan_has(&r->plan, PHOS_STAGE_PRECOMPUTING_RADIANCE));
            atomic_store(&r->maps_complete, 1);
        }
        pthread_mutex_lock(&r->lock);
        r->stage_seconds[r->plan.stages[i]] += monotonic_seconds() - r->stage_started;
        r->stage_started = -1.0;
        pthread_mutex_unlock(&r->lock);
    }
    if (st == PHOS_ERROR_OUT_OF_MEMORY)
        fail(r, st, "out of memory while rendering (try fewer photons or a smaller image)");
    else if (st == PHOS_ERROR_INTERNAL)
        fail(r, st, "the render threads could not be started");
    atomic_store(&r->stage_index, r->plan.count - 1);
    pthread_mutex_lock(&r->lock);
    if (st == PHOS_OK)
        r->state = PHOS_STATE_DONE;
    else if (st == PHOS_ERROR_CANCELLED) {
        r->state = PHOS_STATE_CANCELLED;
        r->status = PHOS_ERROR_CANCELLED;
    } else
        r->state = PHOS_STATE_FAILED;
    r->running = 0;
    pthread_cond_broadcast(&r->finished_cond);
    pthread_mutex_unlock(&r->lock);
    return NULL;
}

/* -------------------------------------------------------------- set-up */

static float scene_size(const scene *s) { return v3_length(v3_sub(s->bounds_max, s->bounds_min)); }

int render_prepare(render *r)
{
    const phos_render_settings *rs = &r->settings;
    r->threads = parallel_thread_count(rs->threads);
    pixel_filter_init(&r->filter, rs->filter_width);
    r->pass_count = render_sample_passes(rs, r->pass_ends);
    if (!film_create(&r->film, rs->region_x, rs->region_y, rs->region_width, rs->region_height,
                     render_film_passes(rs), render_film_extras(rs)) ||
        !make_tiles(r))
        return 0;
    stage_plan_make(rs, &r->plan);
    r->use_maps = stage_plan_has(&r->plan, PHOS_STAGE_TRACING_PHOTONS);
    r->shared = shared_maps_create();
    if (!r->shared)
        return 0;
    r->maps = &r->shared->maps;
    float radius = rs->max_radius > 0.0f ? rs->max_radius : scene_size(r->scene) / 40.0f;
    integrator_settings *is = &r->integrator;
    is->max_bounces = rs->max_bounces;
    is->transparent_background = rs->transparent_background != 0;
    is->maps = NULL;
    is->global_estimate = (estimate_params){rs->global_estimate_photons, radius, ESTIMATE_BOX, 0, r->scene};
    is->caustic_estimate = (estimate_params){rs->caustic_estimate_photons, radius, ESTIMATE_CONE, 0, r->scene};
    is->final_gather_rays = rs->final_gather_rays;
    is->radiance_lookup_radius = radius;
    /* Where the diffuse part's indirect light comes from: PATH follows the
     * whole BSDF unless the irradiance cache wraps its path-traced
     * hemisphere; PHOTON reads its photon view's provider, or the cache
     * wrapping it. */
    r->use_cache = stage_plan_has(&r->plan, PHOS_STAGE_FILLING_IRRADIANCE_CACHE);
    int photon = rs->integrator == PHOS_INTEGRATOR_PHOTON;
    is->cache_inner = photon ? indirect_provider_for(rs->photon_view) : &indirect_path_hemisphere;
    is->indirect = r->use_cache ? &indirect_irradiance_cache : (photon ? is->cache_inner : NULL);
    is->cache = NULL;
    is->gathers_find_caustics = !photon;
    is->caustic_roughness = photon ? rs->caustic_roughness : 0.0f;
    is->caustic_reads = render_caustic_reads(rs);
    is->denoising_features = (r->film.pass_mask & ((1u << PHOS_PASS_DENOISING_ALBEDO) |
                                               (1u << PHOS_PASS_DENOISING_NORMAL))) != 0;
    is->camera = &r->scene->camera;
    irradiance_cache_fill_settings *fs = &r->cache_fill;
    fs->width = rs->width;
    fs->height = rs->height;
    fs->seed = rs->seed;
    fs->sampler = rs->sampler;
    fs->rays = rs->ic_rays;
    fs->min_spacing = rs->ic_min_spacing;
    fs->max_spacing = rs->ic_max_spacing;
    fs->threads = r->threads;
    if (r->use_cache && !irradiance_cache_init(&r->cache, r->scene->bounds_min, r->scene->bounds_max, rs->ic_accuracy))
        return 0;
    photon_trace_settings *ps = &r->photon_settings;
    ps->global_photons = render_global_photons(rs);
    ps->gathers_only = render_global_read_by_gathers(rs) != 0;
    ps->caustic_photons = rs->caustic_photons;
    ps->max_emitted = (uint64_t)rs->max_photons_emitted_millions * 1000000u;
    ps->max_bounces = rs->max_bounces;
    ps->seed = rs->seed;
    ps->sampler = rs->sampler;
    ps->threads = r->threads;
    ps->radiance_k = rs->global_estimate_photons;
    ps->max_radius = radius;
    ps->caustic_roughness = rs->caustic_roughness;
    /* Progressive caustics: the camera reads each sample's own map; the
     * caustic map above serves only the final gather's near hits
     * (final_gather.c). */
    r->use_progressive = r->use_maps && render_progressive_caustics(rs);
    progressive_caustics_init(&r->progressive, ps, rs->progressive_caustic_photons, rs->progressive_alpha,
                              rs->progressive_first_photons, radius);
    r->scratch = parallel_scratch_calloc(r->threads, sizeof(integrator_scratch));
    if (!r->scratch)
        return 0;
    uint32_t k_radiance = 1; /* radiance_photon_lookup: the nearest facing record */
    /* The caustic query serves the fixed estimate and the progressive
     * first radius alike. */
    uint32_t caustic_k = rs->caustic_estimate_photons > rs->progressive_first_photons ? rs->caustic_estimate_photons
                                                                                        : rs->progressive_first_photons;
    caustic_k = caustic_k ? caustic_k : 1;
    for (uint32_t t = 0; t < r->threads; t++) {
        integrator_scratch *sc = &r->scratch[t];
        sc->cancel = &r->cancel;
        if (!kdtree_query_init(&sc->global, rs->global_estimate_photons ? rs->global_estimate_photons : 1) ||
            !kdtree_query_init(&sc->caustic, caustic_k) ||
            !kdtree_query_init(&sc->radiance, k_radiance))
            return 0;
    }
    return 1;
}

phos_status render_start(render *r)
{
    pthread_mutex_lock(&r->lock);
    r->started = 1;
    r->running = 1;
    r->state = PHOS_STATE_RUNNING;
    if (pthread_create(&r->controller, NULL, controller_main, r) != 0) {
        r->running = 0;
        r->state = PHOS_STATE_FAILED;
        r->status = PHOS_ERROR_INTERNAL;
        snprintf(r->error, sizeof(r->error), "could not start the render thread");
        pthread_mutex_unlock(&r->lock);
        return PHOS_ERROR_INTERNAL;
    }
    r->controller_started = 1;
    pthread_mutex_unlock(&r->lock);
    return PHOS_OK;
}

void render_join(render *r)
{
    if (!r->controller_started || r->joined)
        return;
    pthread_join(r->controller, NULL);
    r->joined = 1;
}

void render_free(render *r)
{
    film_free(&r->film);
    free(r->tiles);
    free(r->finished);
    if (r->scratch) {
        for (uint32_t t = 0; t < r->threads; t++) {
            kdtree_query_free(&r->scratch[t].global);
            kdtree_query_free(&r->scratch[t].caustic);
            kdtree_query_free(&r->scratch[t].radiance);
        }
        free(r->scratch);
    }
    progressive_caustics_free(&r->progressive);
    shared_maps_release(r->shared);
    irradiance_cache_free(&r->cache);
    free(r->views);
}
