/*
 * parallel.c — a pthread fan-out per stage. A render has few stages, so
 * starting threads per stage costs microseconds against seconds of work,
 * and no pool outlives the render.
 */
#include "util/parallel.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct job {
    uint32_t count;
    parallel_fn fn;
    void *ctx;
    atomic_int *cancel;
    atomic_uint next;
} job;

typedef struct worker {
    job *j;
    uint32_t thread;
} worker;

static void *worker_main(void *arg)
{
    worker *w = arg;
    job *j = w->j;
    for (;;) {
        if (j->cancel && atomic_load_explicit(j->cancel, memory_order_relaxed))
            break;
        uint32_t i = atomic_fetch_add(&j->next, 1u);
        if (i >= j->count)
            break;
        j->fn(j->ctx, i, w->thread);
    }
    return NULL;
}

uint32_t parallel_thread_count(uint32_t requested)
{
    if (requested)
        return requested;
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    return cores > 0 ? (uint32_t)cores : 1u;
}

int parallel_for(uint32_t count, uint32_t threads, parallel_fn fn, void *ctx, atomic_int *cancel)
{
    job j = {count, fn, ctx, cancel, 0};
    if (threads > count)
        threads = count ? count : 1;
    if (threads <= 1) {
        worker w = {&j, 0};
        worker_main(&w);
    } else {
        pthread_t *tid = calloc(threads, sizeof(pthread_t));
        worker *ws = calloc(threads, sizeof(worker));
        if (!tid || !ws) {
            free(tid);
            free(ws);
            return 0;
        }
        uint32_t started = 0;
        for (uint32_t t = 0; t < threads; t++) {
            ws[t].j = &j;
            ws[t].thread = t;
            if (pthread_create(&tid[t], NULL, worker_main, &ws[t]) != 0)
                break;
            started++;
        }
        if (started == 0) {
            /* No thread: run on this one rather than fail. */
            worker w = {&j, 0};
            worker_main(&w);
        }
        for (uint32_t t = 0; t < started; t++)
            pthread_join(tid[t], NULL);
        free(tid);
        free(ws);
    }
    return !(cancel && atomic_load(cancel)) && atomic_load(&j.next) >= count;
}

void *parallel_scratch_calloc(size_t count, size_t size)
{
    if (count == 1)
        size = (size + PARALLEL_CACHE_LINE - 1) / PARALLEL_CACHE_LINE * PARALLEL_CACHE_LINE;
    if (count == 0 || size == 0 || size % PARALLEL_CACHE_LINE || count > SIZE_MAX / size)
        return NULL;
    void *p = aligned_alloc(PARALLEL_CACHE_LINE, count * size);
    if (p)
        memset(p, 0, count * size);
    return p;
}
