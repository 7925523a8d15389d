/*
 * memory.h — what a render will allocate, checked against what the
 * machine can give before anything is allocated: a render that would
 * exhaust memory is refused with a message saying how much it needs,
 * instead of being killed by the kernel half-way (and taking Blender, and
 * the user's unsaved work, with it). docs/reliability.md.
 */
#ifndef PHOS_MEMORY_H
#define PHOS_MEMORY_H

#include <stddef.h>
#include <stdint.h>

#include "phos.h"

typedef struct memory_estimate {
    uint64_t film;              /* the enabled passes of the region, bytes */
    uint64_t photon_maps;       /* tracing and kd-tree builds at their peak, 0 without maps */
    uint64_t irradiance_cache;  /* records, octree and pre-pass, 0 without the cache */
    uint64_t total;
} memory_estimate;

/* The estimate for these (validated) settings. */
void render_memory_estimate(const phos_render_settings *rs, memory_estimate *out);

/* Bytes this process can still allocate without swapping itself to death
 * or being killed: the kernel's MemAvailable plus free swap, capped by the
 * memory limit of the process's cgroup (a render farm's job limit, v1 or
 * v2) and by RLIMIT_AS; UINT64_MAX if none of them can be read. */
uint64_t memory_available(void);

/* 1 if the estimate fits in `available` bytes; else 0 with a message for
 * the user in msg ("needs about 12.4 GiB (photon maps 12.3 GiB, …) but
 * 9.8 GiB is available: …"). */
int render_memory_fits(const memory_estimate *e, uint64_t available, char *msg, size_t msg_size);

#endif /* PHOS_MEMORY_H */
