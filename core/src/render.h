/*
 * render.h — one render of a committed scene: the film, the tiles, the
 * worker threads and the state Python polls.
 */
#ifndef PHOS_RENDER_H
#define PHOS_RENDER_H

#include <pthread.h>
#include <stdatomic.h>

#include "film.h"
#include "integrator.h"
#include "scene.h"

struct phos_render {
    scene *scene;
    phos_render_settings settings;
    integrator_settings integrator;
    film film;
    pixel_filter filter;

    phos_tile *tiles;
    uint32_t tile_count;
    atomic_uint next_tile;        /* next tile index to hand to a worker */
    atomic_uint tiles_done;

    pthread_mutex_t lock;         /* guards everything below */
    pthread_cond_t finished_cond;
    uint32_t *finished;           /* finished tile indices, in finishing order */
    uint32_t finished_count, finished_read;
    uint32_t workers_running;
    int started, joined;
    uint32_t state;               /* enum phos_render_state */
    phos_status status;
    char error[512];

    atomic_int cancel;
    pthread_t *threads;
    uint32_t thread_count;
};

typedef struct phos_render render;

/* Fills render->tiles for the region, centre tiles first. */
int render_make_tiles(render *r);
phos_status render_start_threads(render *r);
void render_join(render *r);

#endif /* PHOS_RENDER_H */
