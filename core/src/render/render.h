/*
 * render.h — one render of a committed scene: the stages it runs (photon
 * tracing, kd-tree builds, radiance precomputation, tiles), the film, and
 * the state Python polls.
 */
#ifndef PHOS_RENDER_H
#define PHOS_RENDER_H

#include <pthread.h>
#include <stdatomic.h>

#include "render/film.h"
#include "render/stages.h"
#include "integrators/integrator.h"
#include "indirect/irradiance_cache.h"
#include "indirect/irradiance_cache_fill.h"
#include "photons/photon_trace.h"
#include "photons/progressive_caustics.h"
#include "photons/shared_maps.h"
#include "scene/scene.h"

struct phos_render {
    scene *scene;
    phos_render_settings settings;
    integrator_settings integrator;
    film film;
    pixel_filter filter;
    uint32_t threads;

    /* The photon maps: traced by this render, or given to it complete
     * (phos_render_use_photon_maps, whose plan then leaves out the photon
     * stages); `maps` is &shared->maps. */
    shared_maps *shared;
    photon_maps *maps;
    int use_maps;                  /* the PHOTON integrator or a photon debug pass */
    int maps_given;
    atomic_int maps_complete;      /* built (and radiance precomputed): they may be kept */
    photon_trace_settings photon_settings;
    photon_trace_progress photon_progress;
    integrator_scratch *scratch;   /* one per thread */

    irradiance_cache cache;
    int use_cache;                 /* the irradiance cache is on (and the pre-pass in the plan) */
    irradiance_cache_fill_settings cache_fill;
    atomic_uint cache_passes_done;
    atomic_uint_fast64_t cache_lookups, cache_hits; /* by the tiles, summed per tile */
    atomic_uint_fast64_t cache_rays;                /* cast by the pre-pass */
    atomic_uint_fast64_t gather_rays;               /* hemisphere rays of tiles and pre-pass */
    char cache_path[PHOS_CACHE_KIND_COUNT][1024];   /* phos_render_set_cache_file, by enum phos_cache_kind */
    uint32_t cache_file_mode[PHOS_CACHE_KIND_COUNT]; /* enum phos_cache_file_mode */
    phos_camera_desc *views;       /* phos_render_add_view: more views the caches are made for */
    uint32_t view_count;

    phos_tile *tiles;
    uint32_t tile_count;
    atomic_uint tiles_done;        /* tiles finished over all sample passes */
    /* The rendering stage's passes over the frame (render_sample_passes):
     * their ends, the one running, and the samples every pixel has. */
    uint32_t pass_count, pass_ends[RENDER_MAX_SAMPLE_PASSES];
    uint32_t pass_first, pass_end;
    /* The sweep over the frame running now: samples [sweep_first,
     * sweep_end) of every tile, delivered at its end if sweep_delivers.
     * A pass is one sweep, or with progressive caustics one per sample,
     * delivered at the pass's last. */
    uint32_t sweep_first, sweep_end;
    int sweep_delivers;
    int use_progressive;           /* render_progressive_caustics */
    progressive_caustics progressive;
    atomic_uint samples_done;
    double time_limit_end;         /* monotonic seconds at which the time limit strikes */
    atomic_uint_fast64_t work_done; /* pixel samples of finished tiles, for the progress bar */
    atomic_uint_fast64_t rays_traced; /* by the tiles (render_tile) */
    stage_plan plan;               /* the stages it runs, fixed at create */
    atomic_uint stage_index;       /* the one running now, an index into plan */

    pthread_mutex_t lock;          /* guards everything below */
    pthread_cond_t finished_cond;
    uint32_t *finished;            /* finished tile indices, in finishing order (a tile once per pass) */
    uint32_t finished_count, finished_read;
    int started, running, joined, controller_started;
    uint32_t state;                /* enum phos_render_state */
    phos_status status;
    char error[512];
    double stage_seconds[PHOS_STAGE_COUNT]; /* wall time of each finished stage, s */
    double stage_started;          /* when the running stage began, s (monotonic clock); < 0 between stages */

    atomic_int cancel;
    pthread_t controller;
};

typedef struct phos_render render;

/* Sets up film, tiles, pixel filter, integrator and photon settings;
 * returns 0 when memory is exhausted. */
int render_prepare(render *r);
/* Starts the controller thread that runs the stages. */
phos_status render_start(render *r);
void render_join(render *r);
void render_free(render *r);
/* Seconds on the monotonic clock (stage timings). */
double monotonic_seconds(void);

#endif /* PHOS_RENDER_H */
