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
#include <stddef.h>
#include <stdint.h>

typedef void (*parallel_fn)(void *ctx, uint32_t item, uint32_t thread);

/* Returns 1 when every item ran, 0 if *cancel was set (items already
 * started finish) or no thread could be started. */
int parallel_for(uint32_t count, uint32_t threads, parallel_fn fn, void *ctx, atomic_int *cancel);

/* Threads to use for a requested count (0: one per core). */
uint32_t parallel_thread_count(uint32_t requested);

/* Bytes in a cache line on the CPUs Phos runs on. Two threads that write
 * the same line, even to different bytes of it, pass it back and forth
 * between their cores on every write ("false sharing"); a search's heap is
 * written on every replacement, so what one thread writes that often is
 * kept on lines of its own. */
#define PARALLEL_CACHE_LINE 64u

/* Puts a member (and so its struct) at the start of a cache line; C11's
 * _Alignas, spelled as C++ spells it for the C++ benchmarks. */
#ifdef __cplusplus
#define PARALLEL_LINE_ALIGNED alignas(PARALLEL_CACHE_LINE)
#else
#define PARALLEL_LINE_ALIGNED _Alignas(PARALLEL_CACHE_LINE)
#endif

/* count zeroed elements of size bytes, starting on a cache line; size is
 * rounded up to whole lines when count is 1, and must be a multiple of
 * PARALLEL_CACHE_LINE otherwise (a per-thread type with a
 * PARALLEL_LINE_ALIGNED member is). free() releases it; NULL when memory
 * runs out. */
void *parallel_scratch_calloc(size_t count, size_t size);

#endif /* PHOS_PARALLEL_H */
