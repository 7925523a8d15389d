/*
 * embree.c — every call into Embree (3.13 or 4.x).
 *
 * Following Embree's tutorials: one device with an error callback; per mesh
 * a scene holding one triangle geometry (new → fill buffers → commit →
 * attach → release); per placement an instance geometry pointing at the
 * mesh scene. Embree 4 changed the intersect/occluded argument structs; the
 * #if blocks below are the whole difference.
 */
#include "scene/embree.h"

#include <math.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if __has_include(<embree4/rtcore.h>)
#include <embree4/rtcore.h>
#define PHOS_EMBREE4 1
#else
#include <embree3/rtcore.h>
#define PHOS_EMBREE4 0
#endif

struct embree_bvh {
    RTCDevice device;
    RTCScene top;
    RTCScene *mesh_scenes;
    uint32_t mesh_count;
    uint32_t mesh_builds, top_builds; /* BVHs built so far (embree_bvh_build_counts) */
    atomic_int *cancel;
    char error[256];
};

/* Embree calls this while it builds, many times a second; false aborts the
 * commit with RTC_ERROR_CANCELLED. */
static bool build_progress(void *ptr, double fraction)
{
    (void)fraction;
    const struct embree_bvh *bvh = ptr;
    return !(bvh->cancel && atomic_load_explicit(bvh->cancel, memory_order_relaxed));
}

static int cancelled(const struct embree_bvh *bvh) { return !build_progress((void *)bvh, 0.0); }

static const char *device_config; /* embree_set_device_config */

void embree_set_device_config(const char *config) { device_config = config; }

static void error_callback(void *user, enum RTCError code, const char *str)
{
    struct embree_bvh *bvh = user;
    if (bvh && code != RTC_ERROR_NONE && bvh->error[0] == 0)
        snprintf(bvh->error, sizeof(bvh->error), "Embree error %d: %s", (int)code, str ? str : "");
}

static int build_mesh_scene(struct embree_bvh *bvh, const mesh *m, RTCScene *out)
{
    RTCScene sc = rtcNewScene(bvh->device);
    if (!sc)
        return 0;
    rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_HIGH);
    rtcSetSceneProgressMonitorFunction(sc, build_progress, bvh);
    RTCGeometry g = rtcNewGeometry(bvh->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!g) {
        rtcReleaseScene(sc);
        return 0;
    }
    /* Embree may read 16 bytes at the last vertex: allocate one float more. */
    float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                        (size_t)m->vertex_count + 1);
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                           m->triangle_count);
    if (!vb || !ib) {
        rtcReleaseGeometry(g);
        rtcReleaseScene(sc);
        return 0;
    }
    memcpy(vb, m->positions, sizeof(float) * 3 * m->vertex_count);
    memset(vb + 3 * (size_t)m->vertex_count, 0, 3 * sizeof(float));
    memcpy(ib, m->indices, sizeof(unsigned) * 3 * m->triangle_count);
    rtcCommitGeometry(g);
    rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(sc);
    *out = sc;
    return 1;
}

/* Embree wants a column-major 3x4 matrix. */
static void to_column_major(const float m[12], float out[12])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 3; r++)
            out[3 * c + r] = m[4 * r + c];
}

/* The BVHs of the meshes that have none yet or were replaced (`all`: of
 * every mesh); a mesh without triangles has none. */
static phos_status build_meshes(struct embree_bvh *bvh, const mesh *meshes, uint32_t mesh_count, int all,
                                char *error, size_t error_size)
{
    if (mesh_count > bvh->mesh_count) {
        RTCScene *grown = realloc(bvh->mesh_scenes, sizeof(RTCScene) * mesh_count);
        if (!grown)
            return PHOS_ERROR_OUT_OF_MEMORY;
        memset(grown + bvh->mesh_count, 0, sizeof(RTCScene) * (mesh_count - bvh->mesh_count));
        bvh->mesh_scenes = grown;
        bvh->mesh_count = mesh_count;
    }
    for (uint32_t i = 0; i < mesh_count; i++) {
        if (cancelled(bvh))
            return PHOS_ERROR_CANCELLED;
        if (!all && !meshes[i].changed && bvh->mesh_scenes[i])
            continue;
        if (bvh->mesh_scenes[i])
            rtcReleaseScene(bvh->mesh_scenes[i]);
        bvh->mesh_scenes[i] = NULL;
        if (meshes[i].triangle_count == 0)
            continue;
        bvh->mesh_builds++;
        if (!build_mesh_scene(bvh, &meshes[i], &bvh->mesh_scenes[i]) || cancelled(bvh)) {
            if (cancelled(bvh))
                return PHOS_ERROR_CANCELLED;
            snprintf(error, error_size, "could not build the BVH of mesh %u: %s", i,
                     bvh->error[0] ? bvh->error : "out of memory");
            return PHOS_ERROR_EMBREE;
        }
    }
    return PHOS_OK;
}

/* The top level, one Embree instance per instance, built anew. */
static phos_status build_top(struct embree_bvh *bvh, const instance *instances, uint32_t instance_count, char *error,
                             size_t error_size)
{
    if (bvh->top)
        rtcReleaseScene(bvh->top);
    bvh->top = rtcNewScene(bvh->device);
    if (!bvh->top)
        return PHOS_ERROR_EMBREE;
    bvh->top_builds++;
    rtcSetSceneProgressMonitorFunction(bvh->top, build_progress, bvh);
    for (uint32_t i = 0; i < instance_count; i++) {
        if ((i & 1023u) == 0 && cancelled(bvh))
            return PHOS_ERROR_CANCELLED;
        const instance *inst = &instances[i];
        RTCScene child = bvh->mesh_scenes[inst->mesh_id];
        if (!child || inst->hidden)
            continue;
        RTCGeometry g = rtcNewGeometry(bvh->device, RTC_GEOMETRY_TYPE_INSTANCE);
        if (!g)
            return PHOS_ERROR_EMBREE;
        rtcSetGeometryInstancedScene(g, child);
        float cm[12];
        to_column_major(inst->transform, cm);
        rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, cm);
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(bvh->top, g, i);
        rtcReleaseGeometry(g);
    }
    rtcCommitScene(bvh->top);
    if (cancelled(bvh))
        return PHOS_ERROR_CANCELLED;
    if (bvh->error[0]) {
        snprintf(error, error_size, "%s", bvh->error);
        return PHOS_ERROR_EMBREE;
    }
    return PHOS_OK;
}

phos_status embree_bvh_build(const mesh *meshes, uint32_t mesh_count, const instance *instances,
                             uint32_t instance_count, atomic_int *cancel, struct embree_bvh **out, char *error,
                             size_t error_size)
{
    struct embree_bvh *bvh = calloc(1, sizeof(*bvh));
    if (!bvh)
        return PHOS_ERROR_OUT_OF_MEMORY;
    *out = bvh;
    bvh->cancel = cancel;
    bvh->device = rtcNewDevice(device_config);
    if (!bvh->device) {
        snprintf(error, error_size, "could not create the Embree device (error %d)", (int)rtcGetDeviceError(NULL));
        return PHOS_ERROR_EMBREE;
    }
    rtcSetDeviceErrorFunction(bvh->device, error_callback, bvh);
    phos_status st = build_meshes(bvh, meshes, mesh_count, 1, error, error_size);
    return st == PHOS_OK ? build_top(bvh, instances, instance_count, error, error_size) : st;
}

phos_status embree_bvh_update(struct embree_bvh *bvh, const mesh *meshes, uint32_t mesh_count,
                              const instance *instances, uint32_t instance_count, char *error, size_t error_size)
{
    bvh->error[0] = 0;
    phos_status st = build_meshes(bvh, meshes, mesh_count, 0, error, error_size);
    return st == PHOS_OK ? build_top(bvh, instances, instance_count, error, error_size) : st;
}

void embree_bvh_build_counts(const struct embree_bvh *bvh, uint32_t *mesh_builds, uint32_t *top_builds)
{
    *mesh_builds = bvh ? bvh->mesh_builds : 0;
    *top_builds = bvh ? bvh->top_builds : 0;
}

void embree_bvh_destroy(struct embree_bvh *bvh)
{
    if (!bvh)
        return;
    if (bvh->top)
        rtcReleaseScene(bvh->top);
    for (uint32_t i = 0; bvh->mesh_scenes && i < bvh->mesh_count; i++)
        if (bvh->mesh_scenes[i])
            rtcReleaseScene(bvh->mesh_scenes[i]);
    free(bvh->mesh_scenes);
    if (bvh->device)
        rtcReleaseDevice(bvh->device);
    free(bvh);
}

/* Embree's own validity test of a ray (RayK::valid, asserted in Debian's
 * build, so a bad ray aborts the process): origin and direction within
 * ±FLT_LARGE ≈ 1.8e18 per component, no NaN bound. Scene coordinates are
 * only checked to be finite, so a ray from a vertex at 1e30 or a camera
 * there must be stopped here: it misses everything (intersect) or is
 * blocked (occluded, so it brings no light). NaN fails every comparison. */
#define EMBREE_FLT_LARGE 1.8e18f
static int ray_is_valid(vec3 o, vec3 d, float tmin, float tmax)
{
    return fabsf(o.x) <= EMBREE_FLT_LARGE && fabsf(o.y) <= EMBREE_FLT_LARGE && fabsf(o.z) <= EMBREE_FLT_LARGE &&
           fabsf(d.x) <= EMBREE_FLT_LARGE && fabsf(d.y) <= EMBREE_FLT_LARGE && fabsf(d.z) <= EMBREE_FLT_LARGE &&
           !isnan(tmin) && !isnan(tmax);
}

static void setup_ray(struct RTCRay *r, vec3 o, vec3 d, float tmin, float tmax)
{
    r->org_x = o.x;
    r->org_y = o.y;
    r->org_z = o.z;
    r->dir_x = d.x;
    r->dir_y = d.y;
    r->dir_z = d.z;
    r->tnear = tmin;
    r->tfar = tmax;
    r->time = 0.0f;
    r->mask = 0xFFFFFFFFu;
    r->id = 0;
    r->flags = 0;
}

static _Thread_local uint64_t thread_rays;
static _Atomic(embree_ray_recorder) recorder;
static void *recorder_ctx;

uint64_t embree_thread_rays(void) { return thread_rays; }

void embree_set_ray_recorder(embree_ray_recorder fn, void *ctx)
{
    recorder_ctx = ctx;
    atomic_store(&recorder, fn);
}

void *embree_bvh_scene(const struct embree_bvh *bvh) { return bvh->top; }

static void count_ray(vec3 o, vec3 d, float tmin, float tmax, int coherent, int occlusion)
{
    thread_rays++;
    embree_ray_recorder fn = atomic_load_explicit(&recorder, memory_order_relaxed);
    if (fn)
        fn(recorder_ctx, o, d, tmin, tmax, coherent, occlusion);
}

int embree_intersect(const struct embree_bvh *bvh, vec3 o, vec3 d, float tmin, float tmax, int coherent,
                     ray_hit *hit)
{
    if (!bvh->top)
        return 0;
    count_ray(o, d, tmin, tmax, coherent, 0);
    if (!ray_is_valid(o, d, tmin, tmax))
        return 0;
    struct RTCRayHit rh __attribute__((aligned(16)));
    setup_ray(&rh.ray, o, d, tmin, tmax);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
#if PHOS_EMBREE4
    struct RTCIntersectArguments args;
    rtcInitIntersectArguments(&args);
    args.flags = coherent ? RTC_RAY_QUERY_FLAG_COHERENT : RTC_RAY_QUERY_FLAG_INCOHERENT;
    rtcIntersect1(bvh->top, &rh, &args);
#else
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    ctx.flags = coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    rtcIntersect1(bvh->top, &ctx, &rh);
#endif
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
        return 0;
    hit->t = rh.ray.tfar;
    hit->instance = rh.hit.instID[0];
    hit->prim = rh.hit.primID;
    hit->b1 = rh.hit.u;
    hit->b2 = rh.hit.v;
    return 1;
}

int embree_occluded(const struct embree_bvh *bvh, vec3 o, vec3 d, float tmin, float tmax)
{
    if (!bvh->top)
        return 0;
    count_ray(o, d, tmin, tmax, 0, 1);
    if (!ray_is_valid(o, d, tmin, tmax))
        return 1;
    struct RTCRay r __attribute__((aligned(16)));
    setup_ray(&r, o, d, tmin, tmax);
#if PHOS_EMBREE4
    struct RTCOccludedArguments args;
    rtcInitOccludedArguments(&args);
    rtcOccluded1(bvh->top, &r, &args);
#else
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    rtcOccluded1(bvh->top, &ctx, &r);
#endif
    return r.tfar < 0.0f; /* Embree sets tfar to −inf on a hit */
}

const char *embree_version(void)
{
    return RTC_VERSION_STRING;
}
