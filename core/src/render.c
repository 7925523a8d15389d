/*
 * render.c — the tile loop shared by the integrators, the worker threads,
 * progress and cancellation.
 *
 * Workers take tiles from an atomic counter and render each pixel with all
 * its samples before moving on, so a finished tile is final and can be
 * streamed to Blender at once. Every sample's random numbers depend only on
 * (seed, pixel, sample), and a pixel is the mean of its samples summed in
 * sample order: the image is the same for any thread count, tile order or
 * region. Cancellation is checked per pixel.
 */
#include "render.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Tiles sorted centre-first (stable: ties keep row-major order). */
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

int render_make_tiles(render *r)
{
    const film *f = &r->film;
    uint32_t ts = r->settings.tile_size;
    uint32_t nx = (f->width + ts - 1) / ts, ny = (f->height + ts - 1) / ts;
    r->tile_count = nx * ny;
    r->tiles = malloc(sizeof(phos_tile) * r->tile_count);
    r->finished = malloc(sizeof(uint32_t) * r->tile_count);
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

/* Renders one pixel; returns 0 if cancelled part-way (checked every 64
 * samples, so even pixels of millions of samples stop at once). */
static int render_pixel(render *r, uint32_t x, uint32_t y)
{
    const phos_render_settings *rs = &r->settings;
    const scene *s = r->scene;
    double sum[4] = {0.0, 0.0, 0.0, 0.0};
    for (uint32_t i = 0; i < rs->samples; i++) {
        if ((i & 63u) == 63u && atomic_load_explicit(&r->cancel, memory_order_relaxed))
            return 0;
        sampler smp = sampler_for_pixel(rs->seed, x, y, i);
        float2 uf = sampler_2d(&smp, DIM_FILM);
        float fx = ((float)x + 0.5f + pixel_filter_sample(&r->filter, uf.x)) / (float)rs->width;
        float fy = ((float)y + 0.5f + pixel_filter_sample(&r->filter, uf.y)) / (float)rs->height;
        camera_ray ray = camera_generate_ray(&s->camera, fx, fy, sampler_2d(&smp, DIM_LENS));
        sample_result sr = path_trace(s, &r->integrator, ray, &smp);
        /* A non-finite sample (a numerical failure) is dropped rather than
         * allowed to poison the pixel. */
        if (!v3_is_finite(sr.radiance))
            sr.radiance = v3s(0.0f);
        sum[0] += sr.radiance.x;
        sum[1] += sr.radiance.y;
        sum[2] += sr.radiance.z;
        sum[3] += sr.alpha;
    }
    float *px = film_pixel(&r->film, PHOS_PASS_COMBINED, x, y);
    double inv = 1.0 / (double)rs->samples;
    for (int c = 0; c < 4; c++)
        px[c] = (float)(sum[c] * inv);
    return 1;
}

/* Renders one tile; returns 0 if cancelled before it was complete. */
static int render_tile(render *r, const phos_tile *t)
{
    for (uint32_t y = t->y; y < t->y + t->height; y++) {
        for (uint32_t x = t->x; x < t->x + t->width; x++) {
            if (atomic_load_explicit(&r->cancel, memory_order_relaxed) || !render_pixel(r, x, y))
                return 0;
        }
    }
    return 1;
}

static void *worker_main(void *arg)
{
    render *r = arg;
    for (;;) {
        if (atomic_load(&r->cancel))
            break;
        uint32_t i = atomic_fetch_add(&r->next_tile, 1u);
        if (i >= r->tile_count)
            break;
        if (!render_tile(r, &r->tiles[i]))
            break;
        pthread_mutex_lock(&r->lock);
        r->finished[r->finished_count++] = i;
        pthread_mutex_unlock(&r->lock);
        atomic_fetch_add(&r->tiles_done, 1u);
    }
    pthread_mutex_lock(&r->lock);
    if (--r->workers_running == 0) {
        r->state = atomic_load(&r->cancel) ? PHOS_STATE_CANCELLED : PHOS_STATE_DONE;
        if (r->state == PHOS_STATE_CANCELLED)
            r->status = PHOS_ERROR_CANCELLED;
        pthread_cond_broadcast(&r->finished_cond);
    }
    pthread_mutex_unlock(&r->lock);
    return NULL;
}

phos_status render_start_threads(render *r)
{
    uint32_t n = r->settings.threads;
    if (n == 0) {
        long cores = sysconf(_SC_NPROCESSORS_ONLN);
        n = cores > 0 ? (uint32_t)cores : 1u;
    }
    if (n > r->tile_count)
        n = r->tile_count ? r->tile_count : 1;
    r->threads = calloc(n, sizeof(pthread_t));
    if (!r->threads)
        return PHOS_ERROR_OUT_OF_MEMORY;
    pthread_mutex_lock(&r->lock);
    r->state = PHOS_STATE_RUNNING;
    r->started = 1;
    for (uint32_t i = 0; i < n; i++) {
        if (pthread_create(&r->threads[i], NULL, worker_main, r) != 0) {
            /* Run with the threads we have; none at all is a failure. */
            if (i == 0) {
                r->state = PHOS_STATE_FAILED;
                r->status = PHOS_ERROR_INTERNAL;
                snprintf(r->error, sizeof(r->error), "could not start a render thread");
                pthread_mutex_unlock(&r->lock);
                return PHOS_ERROR_INTERNAL;
            }
            break;
        }
        r->thread_count++;
        r->workers_running++;
    }
    pthread_mutex_unlock(&r->lock);
    return PHOS_OK;
}

void render_join(render *r)
{
    if (!r->started || r->joined)
        return;
    for (uint32_t i = 0; i < r->thread_count; i++)
        pthread_join(r->threads[i], NULL);
    r->joined = 1;
}
