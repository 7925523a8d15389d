/*
 * parallel.h — the core's thread pool for one stage of a render: runs
 * fn(ctx, item, thread) for every item on a fixed number of pthreads.
 * Items are handed out in increasing order; results that must not depend
 * on scheduling are written per item and combined in item order by the
 * caller.
 */
#ifndef PHOS_PARALLEL_H
#define PHOS_PARALLEL_H

#include <stdatomic.h>
#include <stdint.h>

typedef void (*parallel_fn)(void *ctx, uint32_t item, uint32_t thread);

/* Returns 1 when every item ran, 0 if *cancel was set (items already
 * started finish) or no thread could be started. */
int parallel_for(uint32_t count, uint32_t threads, parallel_fn fn, void *ctx, atomic_int *cancel);

/* Threads to use for a requested count (0: one per core). */
uint32_t parallel_thread_count(uint32_t requested);

#endif /* PHOS_PARALLEL_H */
