/*
 * photon_importance.c — the voxel grid of where the camera reads photons
 * (photon_importance.h).
 */
#include "photons/photon_importance.h"

#include <stdlib.h>
#include <string.h>

#include "sampling/sampler.h"
#include "sampling/warp.h"
#include "scene/camera.h"
#include "scene/embree.h"
#include "scene/ray.h"
#include "transport/specular_chain.h"

#define GRID 64            /* voxels per axis */
#define PILOT 64           /* camera rays per image axis */
#define PILOT_GATHER 4     /* gather rays per axis from each camera hit (4 × 4, stratified) */
#define CHAIN_STEPS 16

static int facing(vec3 n)
{
    vec3 a = v3(fabsf(n.x), fabsf(n.y), fabsf(n.z));
    int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    float c = axis == 0 ? n.x : (axis == 1 ? n.y : n.z);
    return 2 * axis + (c < 0.0f);
}

static int voxel_of(const photon_importance *imp, vec3 p, int v[3])
{
    float q[3] = {(p.x - imp->lo.x) * imp->inv_voxel, (p.y - imp->lo.y) * imp->inv_voxel,
                  (p.z - imp->lo.z) * imp->inv_voxel};
    for (int k = 0; k < 3; k++) {
        if (!(q[k] >= 0.0f) || q[k] >= (float)imp->n)
            return 0;
        v[k] = (int)q[k];
    }
    return 1;
}

static size_t bit_index(const photon_importance *imp, int x, int y, int z, int f)
{
    return (((size_t)z * imp->n + (size_t)y) * imp->n + (size_t)x) * 6u + (size_t)f;
}

/* Marks the voxel of p and its 26 neighbours, for the facing of n. */
static void mark(photon_importance *imp, vec3 p, vec3 n)
{
    int v[3];
    if (!voxel_of(imp, p, v))
        return;
    int f = facing(n);
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                int x = v[0] + dx, y = v[1] + dy, z = v[2] + dz;
                if (x < 0 || y < 0 || z < 0 || x >= (int)imp->n || y >= (int)imp->n || z >= (int)imp->n)
                    continue;
                size_t b = bit_index(imp, x, y, z, f);
                imp->bits[b >> 3] |= (uint8_t)(1u << (b & 7u));
            }
}

int photon_importance_marked(const photon_importance *imp, vec3 p, vec3 n)
{
    int v[3];
    if (!imp->bits || !voxel_of(imp, p, v))
        return 0;
    size_t b = bit_index(imp, v[0], v[1], v[2], facing(n));
    return (imp->bits[b >> 3] >> (b & 7u)) & 1u;
}

void photon_importance_free(photon_importance *imp)
{
    free(imp->bits);
    memset(imp, 0, sizeof(*imp));
}

/* From a surface the camera sees (pilot ray `pixel`), the first surfaces
 * of a stratified cosine hemisphere of rays: where a final gather there
 * reads. Each stratum is jittered by a hash of the pilot ray and the
 * stratum, so that the pilot's gathers together cover the whole
 * hemisphere: at the strata's centres none would leave below 21° of
 * elevation, and an object near a surface's horizon (a cube seen from the
 * floor it stands on) would never be found. */
static void mark_gather(photon_importance *imp, const scene *s, const surface *sf, uint32_t pixel)
{
    frame f = frame_from_normal(sf->ns);
    for (int i = 0; i < PILOT_GATHER; i++)
        for (int j = 0; j < PILOT_GATHER; j++) {
            uint32_t jitter = hash_u32(pixel * (PILOT_GATHER * PILOT_GATHER) + (uint32_t)(i * PILOT_GATHER + j));
            float2 u = {((float)i + (float)(jitter & 0xffffu) * (1.0f / 65536.0f)) / PILOT_GATHER,
                        ((float)j + (float)(jitter >> 16) * (1.0f / 65536.0f)) / PILOT_GATHER};
            vec3 d = frame_to_world(&f, warp_cosine_hemisphere(u));
            if (v3_dot(d, sf->ng) <= 0.0f)
                continue;
            ray_hit h;
            if (!embree_intersect(s->bvh, ray_leave_surface(sf->p, sf->ng, d), d, 0.0f, INFINITY, 0, &h))
                continue;
            surface hit;
            surface_from_hit(s, h.instance, h.prim, h.b1, h.b2, d, &hit);
            mark(imp, hit.p, hit.ns);
            imp->gather_hits++;
        }
}

/* The pilot of one view: PILOT × PILOT camera rays through pixel centres,
 * each followed to its first diffuse surface and that surface's gathers.
 * The gathers' jitter hashes view · PILOT² + ray: distinct for every view
 * up to PHOS_MAX_VIEWS (16384 · 4096 · 16 strata < 2³²). */
static void mark_view(photon_importance *imp, const scene *s, const phos_camera_desc *camera, uint32_t view)
{
    specular_chain c = {STOP_AT_DIFFUSE, CHAIN_STEPS, 1, NULL, 0, 0.0f, NULL, 0.0f};
    for (int j = 0; j < PILOT; j++)
        for (int i = 0; i < PILOT; i++) {
            float2 lens = {0.5f, 0.5f};
            camera_ray ray = camera_generate_ray(camera, ((float)i + 0.5f) / PILOT, ((float)j + 0.5f) / PILOT, lens);
            specular_chain_end end;
            if (!specular_chain_follow(s, &c, ray.o, ray.d, ray.tmin, ray.tmax, &end))
                continue;
            mark(imp, end.sf.p, end.sf.ns);
            mark_gather(imp, s, &end.sf, view * (PILOT * PILOT) + (uint32_t)(j * PILOT + i));
        }
}

int photon_importance_build(photon_importance *imp, const scene *s, const phos_camera_desc *views,
                            uint32_t view_count)
{
    memset(imp, 0, sizeof(*imp));
    if (!s->has_camera)
        return 0;
    vec3 size = v3_sub(s->bounds_max, s->bounds_min);
    float extent = fmaxf(fmaxf(size.x, size.y), fmaxf(size.z, 1e-3f));
    imp->n = GRID;
    imp->inv_voxel = (float)GRID / (extent * 1.0001f);
    imp->lo = s->bounds_min;
    imp->bits = calloc(((size_t)GRID * GRID * GRID * 6u + 7u) / 8u, 1);
    if (!imp->bits)
        return 0;
    mark_view(imp, s, &s->camera, 0);
    for (uint32_t v = 0; v < view_count; v++)
        mark_view(imp, s, &views[v], v + 1);
    return 1;
}
