/*
 * camera_path.h — the one place a camera path is walked. Both integrators
 * drive this walker; each is only the policy at a surface vertex (what is
 * estimated there and which part of the BSDF the path goes on through), as
 * pbrt-v4 separates a RayIntegrator's Li from the tile loop.
 *
 * The walker owns everything the integrators share:
 *  - intersection, emitters hit by the ray (lamps, the world, emissive
 *    triangles) with their MIS weight against the previous vertex's
 *    next-event estimate (Veach 1997, ch. 9, power heuristic);
 *  - transparent pass-through, which is not a bounce and keeps the ray's
 *    origin, so MIS pdfs stay those of the vertex the ray left;
 *  - leaving a surface, bounce counting as Cycles (with max_bounces = N at
 *    most N scattering events after the camera hit; the ray leaving the
 *    last vertex is still traced so that emission it finds completes the
 *    MIS pair of that vertex's next-event estimate);
 *  - Russian roulette (Arvo & Kirk 1990) from the third bounce;
 *  - alpha, and the light component each contribution belongs to.
 */
#ifndef PHOS_CAMERA_PATH_H
#define PHOS_CAMERA_PATH_H

#include "integrators/integrator.h"
#include "lights/light.h"
#include "shading/material.h"

#define CAMERA_PATH_MAX_TRANSPARENT_STEPS 64
#define CAMERA_PATH_ROULETTE_START_DEPTH 3

/* The walk so far, as a vertex policy sees it. */
typedef struct camera_path {
    const scene *s;
    const integrator_settings *is;
    const sampler *smp;
    integrator_scratch *scratch;
    sample_result *res;
    vec3 beta;              /* path throughput up to the current vertex */
    uint32_t depth;         /* scattering events before the current vertex */
    int first_diffuse;      /* the first scattering event took a diffuse lobe */
    int later_delta;        /* every later one took a delta lobe */
    /* Glossy receivers (docs/algorithms.md §12): per channel, the share of
     * beta whose light a caustic-map estimate at an earlier vertex already
     * counted, should it arrive through closures that carry caustics only
     * (0 on a camera ray, and always under PATH); and whether the policy
     * read the caustic map through the current vertex's receivers (bsdf.h). */
    vec3 caustic_counted;
    int reads_caustics;
} camera_path;

/* A surface vertex of the walk. */
typedef struct path_vertex {
    const surface *sf;
    const bsdf *b;          /* the whole BSDF there (at least one closure) */
    vec3 wo;                /* toward the previous vertex */
    uint32_t index;         /* surface interactions before this one: its sample dimensions */
    light_context *light;   /* the receiver for light samples here and for the MIS weights of what
                               the ray leaving it finds */
} path_vertex;

/* What an integrator does at a vertex: adds what it estimates there through
 * the camera_path_add_* calls below, and returns the part of the BSDF the
 * path continues through (written to *storage or v->b itself), or NULL to
 * end the path. */
typedef const bsdf *(*vertex_policy)(camera_path *p, const path_vertex *v, bsdf *storage);

/* PATH's policy (path.c): next-event estimation with the whole BSDF, and
 * on through the whole BSDF. */
const bsdf *path_vertex_policy(camera_path *p, const path_vertex *v, bsdf *storage);

/* PHOTON's policy, and PATH's with the irradiance cache (diffuse_split.c):
 * the diffuse part's indirect light and caustics by estimates (the
 * settings' indirect provider, the caustic map, which rough glossy
 * reflection reads too), its direct light by a light sample, and on
 * through the rest of the BSDF only. */
const bsdf *diffuse_split_vertex_policy(camera_path *p, const path_vertex *v, bsdf *rest);

/* Walks the camera ray; *res receives its light components and alpha. */
void camera_path_walk(const scene *s, const integrator_settings *is, camera_ray ray, const sampler *smp,
                      integrator_scratch *scratch, vertex_policy policy, sample_result *res);

/* Walks a gather ray that leaves a camera-path vertex after `depth`
 * scattering events (the one there included). Emission found on the first
 * segment is weighted for MIS as a sample of pdf first_pdf against the
 * vertex's light sample (first_pdf = 0: left out); emission found after
 * delta scatterings only is a caustic at the vertex the ray left
 * (indirect_diffuse.h): left out, or with caustics_apart filed as the
 * result's Caustics (which a walk from a vertex holds nothing else in).
 * The result's Emission holds what the first segment saw, its Specular and
 * Direct the rest of the radiance arriving along the ray. */
void camera_path_walk_indirect(const scene *s, const integrator_settings *is, const light_context *from, vec3 o, vec3 d,
                               uint32_t depth, float first_pdf, int caustics_apart, const sampler *smp,
                               integrator_scratch *scratch, vertex_policy policy, sample_result *res);

/* Light estimated at the vertex that arrived straight from an emitter and
 * scattered there once more (next-event estimation): f·L·T/pdf. */
void camera_path_add_direct(camera_path *p, vec3 L);

/* Light the diffuse part of the BSDF reflects at the vertex from light
 * that has scattered before: caustic (it came from an emitter through
 * specular surfaces only) or not. */
void camera_path_add_diffuse(camera_path *p, int caustic, vec3 L);

#endif /* PHOS_CAMERA_PATH_H */
