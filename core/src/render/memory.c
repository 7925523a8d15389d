/*
 * memory.c — a render's memory, estimated from its settings before
 * anything is allocated (memory.h). Linux overcommits: a calloc of 500 GB
 * for a 65536² film "succeeds" and the process is killed when the pages
 * are touched, so a failed malloc cannot be relied on to say no.
 */
#include "render/memory.h"

#include <inttypes.h>
#include <stdio.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "indirect/irradiance_cache.h"
#include "photons/photon_trace.h"
#include "render/film.h"
#include "render/stages.h"

void render_memory_estimate(const phos_render_settings *rs, memory_estimate *out)
{
    memset(out, 0, sizeof(*out));
    uint32_t w = rs->region_width ? rs->region_width : rs->width;
    uint32_t h = rs->region_height ? rs->region_height : rs->height;
    out->film = film_memory_bytes(w, h, render_film_passes(rs), render_film_extras(rs));
    stage_plan plan;
    stage_plan_make(rs, &plan);
    if (stage_plan_has(&plan, PHOS_STAGE_TRACING_PHOTONS))
        out->photon_maps = photon_maps_memory_estimate(render_global_photons(rs), rs->caustic_photons);
    /* Progressive caustics hold two maps of a sample's photons at a time:
     * the sample's own and the one before (progressive_caustics.h). */
    if (render_progressive_caustics(rs))
        out->photon_maps += 2u * photon_maps_memory_estimate(0, rs->progressive_caustic_photons);
    /* The pre-pass covers the full frame, whatever the region. */
    if (stage_plan_has(&plan, PHOS_STAGE_FILLING_IRRADIANCE_CACHE))
        out->irradiance_cache = irradiance_cache_memory_estimate(rs->width, rs->height, rs->ic_min_spacing);
    out->total = out->film + out->photon_maps + out->irradiance_cache;
}

/* A "Name:   123 kB" line of /proc/meminfo, in bytes; 0 if absent. */
static uint64_t meminfo_bytes(const char *text, const char *name)
{
    const char *p = strstr(text, name);
    unsigned long long kb = 0;
    if (p && sscanf(p + strlen(name), " %llu", &kb) == 1)
        return (uint64_t)kb * 1024u;
    return 0;
}

/* The whole of a small file into buf (NUL-terminated); 0 if unreadable. */
static int read_small_file(const char *path, char *buf, size_t size)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    size_t n = fread(buf, 1, size - 1, f);
    fclose(f);
    buf[n] = 0;
    return n > 0;
}

/* A number in a file ("max" or a huge value: no limit, UINT64_MAX). */
static uint64_t file_number(const char *path)
{
    char buf[64];
    unsigned long long v;
    if (!read_small_file(path, buf, sizeof(buf)) || sscanf(buf, "%llu", &v) != 1)
        return UINT64_MAX;
    return (uint64_t)v;
}

/* What the process's memory cgroup still allows: limit − usage, in the
 * v2 layout (memory.max, memory.current under the "0::" path) or the v1
 * one (memory.limit_in_bytes, memory.usage_in_bytes under "memory:"). */
static uint64_t cgroup_headroom(void)
{
    char groups[4096], path[4200];
    if (!read_small_file("/proc/self/cgroup", groups, sizeof(groups)))
        return UINT64_MAX;
    uint64_t headroom = UINT64_MAX;
    for (char *line = strtok(groups, "\n"); line; line = strtok(NULL, "\n")) {
        uint64_t limit = UINT64_MAX, used = 0;
        if (strncmp(line, "0::", 3) == 0) {
            snprintf(path, sizeof(path), "/sys/fs/cgroup%s/memory.max", line + 3);
            limit = file_number(path);
            snprintf(path, sizeof(path), "/sys/fs/cgroup%s/memory.current", line + 3);
            used = file_number(path);
        } else {
            const char *m = strstr(line, ":memory:");
            if (!m)
                continue;
            snprintf(path, sizeof(path), "/sys/fs/cgroup/memory%s/memory.limit_in_bytes", m + 8);
            limit = file_number(path);
            snprintf(path, sizeof(path), "/sys/fs/cgroup/memory%s/memory.usage_in_bytes", m + 8);
            used = file_number(path);
        }
        /* v1 reports "no limit" as a page-rounded 2^63. */
        if (limit >= (UINT64_C(1) << 62) || used == UINT64_MAX)
            continue;
        uint64_t room = limit > used ? limit - used : 0;
        if (room < headroom)
            headroom = room;
    }
    return headroom;
}

uint64_t memory_available(void)
{
    uint64_t available = UINT64_MAX;
    char info[8192];
    if (read_small_file("/proc/meminfo", info, sizeof(info))) {
        uint64_t mem = meminfo_bytes(info, "MemAvailable:");
        if (mem)
            available = mem + meminfo_bytes(info, "SwapFree:");
    } else {
        long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
        if (pages > 0 && page > 0)
            available = (uint64_t)pages * (uint64_t)page;
    }
    uint64_t room = cgroup_headroom();
    if (room < available)
        available = room;
    struct rlimit rl;
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY && (uint64_t)rl.rlim_cur < available)
        available = (uint64_t)rl.rlim_cur;
    return available;
}

static double gib(uint64_t bytes) { return (double)bytes / (1024.0 * 1024.0 * 1024.0); }

int render_memory_fits(const memory_estimate *e, uint64_t available, char *msg, size_t msg_size)
{
    if (e->total <= available)
        return 1;
    snprintf(msg, msg_size,
             "render: needs about %.1f GiB of memory (film %.1f GiB, photon maps %.1f GiB, irradiance cache "
             "%.1f GiB) but %.1f GiB is available: lower the photon counts, the resolution, the passes or "
             "raise the cache's Min Spacing",
             gib(e->total), gib(e->film), gib(e->photon_maps), gib(e->irradiance_cache), gib(available));
    return 0;
}
