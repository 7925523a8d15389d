/*
 * bench_core — the core's own costs, measured in one run on a Cornell box
 * built through the public API (docs/benchmarks.md, `make bench`):
 *
 *   rays      rays per second of PATH (camera, bounce and shadow rays, as
 *             counted by the core) against a minimal loop that only calls
 *             Embree on the same BVH with the same rays, recorded from a
 *             one-thread render of the same image and replayed on as many
 *             threads;
 *   threads   1 thread against all cores: every stage of a PHOTON and a
 *             PATH render sized so that their main stages take a second
 *             or more on one thread;
 *   photons   photon maps of 10⁵, 10⁶ and 10⁷ photons: trace, build and
 *             k-nearest query time, bytes per photon, against n·log n and
 *             the 20-byte record;
 *   dump      writes the Cornell box's global photons (raw 20-byte records)
 *             for bench_kdtree --input.
 *
 *   bench_core [rays|threads|photons|dump FILE N]... [--csv DIR]
 *
 * Times are the best of 3 where a stage is short; nothing is asserted.
 */
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#if __has_include(<embree4/rtcore.h>)
#include <embree4/rtcore.h>
#define BENCH_EMBREE4 1
#else
#include <embree3/rtcore.h>
#define BENCH_EMBREE4 0
#endif

#include "phos.h"
#include "photons/kdtree.h"
#include "photons/photon_trace.h"
#include "scene/embree.h"
#include "scene/scene.h"
#include "util/parallel.h"
#include "test_scenes.h"

static double now_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static FILE *csv_open(const char *dir, const char *name, const char *header)
{
    if (!dir)
        return NULL;
    char path[1024];
    snprintf(path, sizeof(path), "%s/%s", dir, name);
    FILE *f = fopen(path, "w");
    if (f)
        fprintf(f, "%s\n", header);
    else
        fprintf(stderr, "bench_core: cannot write %s\n", path);
    return f;
}

/* ------------------------------------------------------------ the scene */

static phos_scene *cornell_box(void)
{
    phos_scene *s = test_cornell_box(1);
    if (!s) {
        fprintf(stderr, "bench_core: the Cornell box does not commit\n");
        exit(1);
    }
    return s;
}

static phos_render_settings render_settings(uint32_t integrator, uint32_t size, uint32_t samples, uint32_t threads)
{
    phos_render_settings rs;
    phos_render_settings_init(&rs);
    rs.integrator = integrator;
    rs.width = rs.height = size;
    rs.samples = samples;
    rs.threads = threads;
    rs.max_bounces = 8;
    return rs;
}

typedef struct render_timing {
    double stage[PHOS_STAGE_COUNT]; /* s */
    uint64_t rays;
} render_timing;

static render_timing render_once(phos_scene *s, const phos_render_settings *rs)
{
    render_timing t;
    memset(&t, 0, sizeof(t));
    phos_render *r = NULL;
    if (phos_render_create(s, rs, &r) != PHOS_OK || phos_render_start(r) != PHOS_OK ||
        phos_render_wait(r, -1.0) != PHOS_OK) {
        fprintf(stderr, "bench_core: render failed: %s\n", r ? phos_render_error(r) : "create");
        exit(1);
    }
    phos_progress p;
    phos_render_progress(r, &p);
    memcpy(t.stage, p.stage_seconds, sizeof(t.stage));
    t.rays = p.rays_traced;
    phos_render_destroy(r);
    return t;
}

/* ---------------------------------------------------------------- rays */

typedef struct recorded_ray {
    float o[3], d[3], tmin, tmax;
    uint8_t coherent, occlusion;
} recorded_ray;

typedef struct ray_log {
    recorded_ray *rays;
    size_t count, capacity;
    pthread_mutex_t lock;
} ray_log;

static void record_ray(void *ctx, vec3 o, vec3 d, float tmin, float tmax, int coherent, int occlusion)
{
    ray_log *log = ctx;
    pthread_mutex_lock(&log->lock);
    if (log->count == log->capacity) {
        size_t cap = log->capacity ? 2 * log->capacity : 1u << 20;
        recorded_ray *n = realloc(log->rays, sizeof(recorded_ray) * cap);
        if (!n) {
            fprintf(stderr, "bench_core: out of memory recording rays\n");
            exit(1);
        }
        log->rays = n;
        log->capacity = cap;
    }
    recorded_ray *r = &log->rays[log->count++];
    r->o[0] = o.x, r->o[1] = o.y, r->o[2] = o.z;
    r->d[0] = d.x, r->d[1] = d.y, r->d[2] = d.z;
    r->tmin = tmin;
    r->tmax = tmax;
    r->coherent = (uint8_t)coherent;
    r->occlusion = (uint8_t)occlusion;
    pthread_mutex_unlock(&log->lock);
}

typedef struct replay {
    RTCScene scene;
    const recorded_ray *rays;
    size_t count;
    uint32_t threads;
    atomic_uint_fast64_t hits; /* so that the loop cannot be optimised away */
} replay;

typedef struct replay_part {
    replay *r;
    size_t begin, end;
} replay_part;

/* The minimal loop: one rtcIntersect1 or rtcOccluded1 per recorded ray,
 * nothing else. */
static void *replay_thread(void *arg)
{
    replay_part *part = arg;
    const replay *rp = part->r;
    uint64_t hits = 0;
    for (size_t i = part->begin; i < part->end; i++) {
        const recorded_ray *q = &rp->rays[i];
        if (q->occlusion) {
            struct RTCRay ray __attribute__((aligned(16)));
            ray.org_x = q->o[0], ray.org_y = q->o[1], ray.org_z = q->o[2];
            ray.dir_x = q->d[0], ray.dir_y = q->d[1], ray.dir_z = q->d[2];
            ray.tnear = q->tmin, ray.tfar = q->tmax, ray.time = 0.0f, ray.mask = 0xffffffffu, ray.id = 0,
            ray.flags = 0;
#if BENCH_EMBREE4
            rtcOccluded1(rp->scene, &ray, NULL);
#else
            struct RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            rtcOccluded1(rp->scene, &ctx, &ray);
#endif
            hits += ray.tfar < 0.0f;
        } else {
            struct RTCRayHit rh __attribute__((aligned(16)));
            rh.ray.org_x = q->o[0], rh.ray.org_y = q->o[1], rh.ray.org_z = q->o[2];
            rh.ray.dir_x = q->d[0], rh.ray.dir_y = q->d[1], rh.ray.dir_z = q->d[2];
            rh.ray.tnear = q->tmin, rh.ray.tfar = q->tmax, rh.ray.time = 0.0f, rh.ray.mask = 0xffffffffu,
            rh.ray.id = 0, rh.ray.flags = 0;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
#if BENCH_EMBREE4
            struct RTCIntersectArguments args;
            rtcInitIntersectArguments(&args);
            args.flags = q->coherent ? RTC_RAY_QUERY_FLAG_COHERENT : RTC_RAY_QUERY_FLAG_INCOHERENT;
            rtcIntersect1(rp->scene, &rh, &args);
#else
            struct RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            ctx.flags = q->coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
            rtcIntersect1(rp->scene, &ctx, &rh);
#endif
            hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
        }
    }
    atomic_fetch_add(&part->r->hits, hits);
    return NULL;
}

static double replay_seconds(replay *rp)
{
    pthread_t th[256];
    replay_part parts[256];
    uint32_t n = rp->threads < 256 ? rp->threads : 256;
    double t0 = now_seconds();
    for (uint32_t i = 0; i < n; i++) {
        parts[i] = (replay_part){rp, rp->count * i / n, rp->count * (i + 1) / n};
        pthread_create(&th[i], NULL, replay_thread, &parts[i]);
    }
    for (uint32_t i = 0; i < n; i++)
        pthread_join(th[i], NULL);
    return now_seconds() - t0;
}

static void bench_rays(const char *csv_dir)
{
    phos_scene *s = cornell_box();
    uint32_t threads = parallel_thread_count(0);
    phos_render_settings rs = render_settings(PHOS_INTEGRATOR_PATH, 128, 16, threads);
    double best = 1e30;
    uint64_t rays = 0;
    for (int k = 0; k < 3; k++) {
        render_timing t = render_once(s, &rs);
        if (t.stage[PHOS_STAGE_RENDERING] < best)
            best = t.stage[PHOS_STAGE_RENDERING];
        rays = t.rays;
    }
    /* The same image on one thread, every ray recorded in the order that
     * thread cast it; replayed in that order, split into one contiguous
     * run per thread. */
    ray_log log = {NULL, 0, 0, PTHREAD_MUTEX_INITIALIZER};
    rs.threads = 1;
    embree_set_ray_recorder(record_ray, &log);
    render_once(s, &rs);
    embree_set_ray_recorder(NULL, NULL);
    replay rp = {embree_bvh_scene(((const scene *)s)->bvh), log.rays, log.count, threads, 0};
    double raw = 1e30;
    for (int k = 0; k < 3; k++) {
        double t = replay_seconds(&rp);
        if (t < raw)
            raw = t;
    }
    size_t shadow = 0;
    for (size_t i = 0; i < log.count; i++)
        shadow += log.rays[i].occlusion;
    double phos_rate = (double)rays / best, raw_rate = (double)log.count / raw;
    printf("\nray throughput: PATH, Cornell box 128 x 128, 16 samples, %u threads (best of 3)\n", threads);
    printf("  rays per render          %12llu (recorded again on 1 thread: %zu, %.0f %% shadow rays)\n",
           (unsigned long long)rays, log.count, 100.0 * (double)shadow / (double)log.count);
    printf("  Phos PATH                %12.2f M rays/s (rendering stage %.3f s)\n", 1e-6 * phos_rate, best);
    printf("  raw Embree loop          %12.2f M rays/s (%.3f s)\n", 1e-6 * raw_rate, raw);
    printf("  Phos / raw               %12.2f  (target >= 0.70)\n", phos_rate / raw_rate);
    FILE *f = csv_open(csv_dir, "rays.csv", "threads,rays,phos_seconds,raw_rays,raw_seconds,phos_mrays_s,raw_mrays_s,ratio");
    if (f) {
        fprintf(f, "%u,%llu,%.6f,%zu,%.6f,%.4f,%.4f,%.4f\n", threads, (unsigned long long)rays, best, log.count, raw,
                1e-6 * phos_rate, 1e-6 * raw_rate, phos_rate / raw_rate);
        fclose(f);
    }
    free(log.rays);
    phos_scene_destroy(s);
}

/* ------------------------------------------------------------- threads */

static photon_trace_settings trace_settings(uint32_t global, uint32_t caustic, uint32_t threads)
{
    photon_trace_settings ps;
    memset(&ps, 0, sizeof(ps));
    ps.global_photons = global;
    ps.caustic_photons = caustic;
    ps.max_emitted = 500000000ull;
    ps.max_bounces = 8;
    ps.seed = 1;
    ps.threads = threads;
    ps.radiance_k = 50;
    ps.max_radius = 0.0f;
    return ps;
}

typedef struct map_timing {
    double trace, build; /* s */
    uint32_t stored;
    size_t bytes;
} map_timing;

static map_timing time_maps(phos_scene *s, uint32_t global, uint32_t threads, photon_maps *keep)
{
    map_timing t;
    photon_trace_settings ps = trace_settings(global, 0, threads);
    photon_maps m;
    photon_maps_init(&m);
    atomic_int cancel = 0;
    double t0 = now_seconds();
    if (photon_maps_trace((const scene *)s, &ps, &m, &cancel, NULL) != PHOS_OK) {
        fprintf(stderr, "bench_core: photon tracing failed\n");
        exit(1);
    }
    t.trace = now_seconds() - t0;
    t0 = now_seconds();
    if (photon_maps_build(&m, threads, NULL) != PHOS_OK) {
        fprintf(stderr, "bench_core: kd-tree build failed\n");
        exit(1);
    }
    t.build = now_seconds() - t0;
    t.stored = m.global.count;
    t.bytes = photon_map_memory(&m.global);
    if (keep)
        *keep = m;
    else
        photon_maps_free(&m);
    return t;
}

/* Thread scaling as issue 25 states its target: at least 1.9x on 2 cores
 * for every stage that takes a second or more. Whole renders, 1 thread
 * against all, each stage's time read from the render's own progress
 * (best of 3 per stage); the renders are sized so that their main stages
 * take a second or more on one thread here. Stages under a second are
 * listed too, marked: starting and joining the threads is a visible share
 * of them, and the target leaves them out. */
typedef struct scaling_render {
    const char *name;
    uint32_t integrator, size, samples, global_photons;
} scaling_render;

static const char *const stage_names[PHOS_STAGE_COUNT] = {
    [PHOS_STAGE_TRACING_PHOTONS] = "tracing photons",
    [PHOS_STAGE_BUILDING_KDTREES] = "building kd-trees",
    [PHOS_STAGE_PRECOMPUTING_RADIANCE] = "precomputing radiance",
    [PHOS_STAGE_FILLING_IRRADIANCE_CACHE] = "filling the irradiance cache",
    [PHOS_STAGE_RENDERING] = "rendering",
    [PHOS_STAGE_FILTERING] = "filtering",
};

static void bench_threads(const char *csv_dir)
{
    phos_scene *s = cornell_box();
    uint32_t all = parallel_thread_count(0);
    printf("\nthread scaling: Cornell box, whole renders' stages, 1 thread against %u (best of 3)\n", all);
    printf("  %-52s %10s %10s %8s\n", "", "1 thread", "all", "speed-up");
    FILE *f = csv_open(csv_dir, "threads.csv", "stage,threads,seconds_1,seconds_all,speedup,a_second_or_more");
    const scaling_render renders[2] = {
        {"PHOTON 192² at 16 spp with 2 M global photons", PHOS_INTEGRATOR_PHOTON, 192, 16, 2000000},
        {"PATH 160² at 32 spp", PHOS_INTEGRATOR_PATH, 160, 32, 0},
    };
    for (int i = 0; i < 2; i++) {
        double best[2][PHOS_STAGE_COUNT];
        for (int a = 0; a < 2; a++)
            for (int st = 0; st < PHOS_STAGE_COUNT; st++)
                best[a][st] = 1e30;
        for (int k = 0; k < 3; k++)
            for (int a = 0; a < 2; a++) {
                phos_render_settings rs =
                    render_settings(renders[i].integrator, renders[i].size, renders[i].samples, a ? all : 1);
                if (renders[i].global_photons)
                    rs.global_photons = renders[i].global_photons;
                render_timing t = render_once(s, &rs);
                for (int st = 0; st < PHOS_STAGE_COUNT; st++)
                    best[a][st] = t.stage[st] < best[a][st] ? t.stage[st] : best[a][st];
            }
        for (int st = 0; st < PHOS_STAGE_COUNT; st++) {
            if (!stage_names[st] || !(best[0][st] >= 0.01))
                continue; /* a stage this render does not have, or next to nothing */
            char name[160];
            snprintf(name, sizeof name, "%s: %s", renders[i].name, stage_names[st]);
            int counts = best[0][st] >= 1.0;
            printf("  %-52s %9.3fs %9.3fs %8.2f%s\n", name, best[0][st], best[1][st], best[0][st] / best[1][st],
                   counts ? "" : "  (under 1 s)");
            if (f)
                fprintf(f, "%s,%u,%.6f,%.6f,%.4f,%d\n", name, all, best[0][st], best[1][st],
                        best[0][st] / best[1][st], counts);
        }
    }
    printf("  (target >= 1.9x on 2 cores for every stage of a second or more)\n");
    if (f)
        fclose(f);
    phos_scene_destroy(s);
}

/* ------------------------------------------------------------- photons */

/* Photon maps up to max_photons (10⁷ in make bench, fewer for QUICK=1). */
static void bench_photons(const char *csv_dir, uint32_t max_photons)
{
    phos_scene *s = cornell_box();
    uint32_t threads = parallel_thread_count(0);
    const uint32_t counts[3] = {100000, 1000000, 10000000};
    const uint32_t k = 50, queries = 200000;
    printf("\nphoton maps: Cornell box, %u threads for tracing; build and %u k = %u queries on 1 thread\n", threads,
           queries, k);
    printf("  %10s %9s %9s %12s %10s %12s %11s\n", "photons", "trace s", "build s", "build/nlogn", "B/photon",
           "queries/s", "MB");
    FILE *f = csv_open(csv_dir, "photons.csv",
                       "photons,trace_seconds,build_seconds,build_ns_per_nlog2n,bytes_per_photon,queries_per_second");
    for (int c = 0; c < 3 && counts[c] <= max_photons; c++) {
        photon_maps m;
        map_timing t = time_maps(s, counts[c], threads, &m);
        /* Queries at stored photons' positions, as a gather's hits are. */
        kdtree_query q;
        kdtree_query_init(&q, k);
        float radius = 0.25f;
        double t0 = now_seconds();
        uint64_t found = 0;
        for (uint32_t i = 0; i < queries; i++) {
            const photon *ph = &m.global.photons[(uint64_t)i * 2654435761u % m.global.count];
            found += photon_map_knn(&m.global, photon_position(ph), radius * radius, &q);
        }
        double tq = now_seconds() - t0;
        kdtree_query_free(&q);
        double n = (double)t.stored, nlogn = n * log2(n);
        printf("  %10u %9.3f %9.3f %10.2f ns %10.2f %12.0f %11.1f\n", t.stored, t.trace, t.build, 1e9 * t.build / nlogn,
               (double)t.bytes / n, queries / tq, (double)t.bytes / 1e6);
        if (f)
            fprintf(f, "%u,%.6f,%.6f,%.4f,%.3f,%.1f\n", t.stored, t.trace, t.build, 1e9 * t.build / nlogn,
                    (double)t.bytes / n, queries / tq);
        (void)found;
        photon_maps_free(&m);
    }
    if (f)
        fclose(f);
    phos_scene_destroy(s);
}

/* Raw 20-byte photon records of the Cornell box's global map. */
static void dump_photons(const char *path, uint32_t n)
{
    phos_scene *s = cornell_box();
    photon_maps m;
    time_maps(s, n, parallel_thread_count(0), &m);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(m.global.photons, sizeof(photon), m.global.count, f) != m.global.count) {
        fprintf(stderr, "bench_core: cannot write %s\n", path);
        exit(1);
    }
    fclose(f);
    printf("wrote %u Cornell-box photons (%zu bytes each) to %s\n", m.global.count, sizeof(photon), path);
    photon_maps_free(&m);
    phos_scene_destroy(s);
}

int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0); /* lines as they come, also into a log */
    const char *csv_dir = NULL;
    uint32_t max_photons = 10000000;
    for (int i = 1; i + 1 < argc; i++) {
        if (strcmp(argv[i], "--csv") == 0)
            csv_dir = argv[i + 1];
        if (strcmp(argv[i], "--max-photons") == 0)
            max_photons = (uint32_t)strtoul(argv[i + 1], NULL, 10);
    }
    uint32_t v = phos_version();
    printf("bench_core: Phos %u.%u.%u, Embree %s, %u hardware threads\n", v >> 16, (v >> 8) & 0xffu, v & 0xffu,
           embree_version(), parallel_thread_count(0));
    int any = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--csv") == 0 || strcmp(argv[i], "--max-photons") == 0) {
            i++;
        } else if (strcmp(argv[i], "rays") == 0) {
            bench_rays(csv_dir), any = 1;
        } else if (strcmp(argv[i], "threads") == 0) {
            bench_threads(csv_dir), any = 1;
        } else if (strcmp(argv[i], "photons") == 0) {
            bench_photons(csv_dir, max_photons), any = 1;
        } else if (strcmp(argv[i], "dump") == 0 && i + 2 < argc) {
            dump_photons(argv[i + 1], (uint32_t)strtoul(argv[i + 2], NULL, 10)), any = 1;
            i += 2;
        } else {
            fprintf(stderr, "usage: bench_core [rays|threads|photons|dump FILE N]... [--csv DIR] [--max-photons N]\n");
            return 2;
        }
    }
    if (!any) {
        bench_rays(csv_dir);
        bench_threads(csv_dir);
        bench_photons(csv_dir, max_photons);
    }
    return 0;
}
