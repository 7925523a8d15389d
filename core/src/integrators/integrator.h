/*
 * integrator.h — what every integrator supplies to the shared tile loop in
 * render.c: the radiance carried by one camera ray (pbrt-v4's split between
 * ImageTileIntegrator and the per-sample step), split into the components
 * of Jensen's rendering-equation solution (course notes 2002):
 *
 *   EMISSION   emitters seen by the camera (no scattering)
 *   DIRECT     light that reached the eye after exactly one scattering
 *   SPECULAR   everything after a specular or glossy first bounce
 *   CAUSTICS   diffuse first bounce, then only specular bounces: L S+ D E
 *   INDIRECT   diffuse first bounce, then at least one more non-specular one
 *
 * Both integrators classify their contributions this way (camera_path.c),
 * so Combined is the sum of the five and each pass of PHOTON can be checked
 * against PATH (README, "What the passes mean").
 */
#ifndef PHOS_INTEGRATOR_H
#define PHOS_INTEGRATOR_H

#include "scene/camera.h"
#include "photons/photon_trace.h"
#include "photons/radiance_estimate.h"
#include "sampling/sampler.h"
#include "scene/ray.h"
#include "scene/scene.h"

enum light_component {
    COMPONENT_EMISSION = 0,
    COMPONENT_DIRECT,
    COMPONENT_SPECULAR,
    COMPONENT_CAUSTICS,
    COMPONENT_INDIRECT,
    COMPONENT_COUNT
};

struct indirect_diffuse_provider;
struct progressive_caustics;

typedef struct integrator_settings {
    uint32_t max_bounces;          /* scattering events after the camera hit */
    int transparent_background;    /* camera rays do not see the world */
    /* Photon mapping (NULL maps: none were built). */
    const photon_maps *maps;
    estimate_params global_estimate, caustic_estimate;
    uint32_t final_gather_rays;
    float radiance_lookup_radius;  /* scene units */
    /* PHOTON, and PATH with the irradiance cache: where the diffuse part's
     * indirect light comes from (indirect_diffuse.h; indirect_provider_for
     * chooses it); NULL: PATH follows the whole BSDF. */
    const struct indirect_diffuse_provider *indirect;
    /* The irradiance cache's provider: the read-only cache (NULL while the
     * pre-pass fills it: every lookup misses) and the provider whose gather
     * rays it sends (irradiance_cache.h). */
    const struct irradiance_cache *cache;
    const struct indirect_diffuse_provider *cache_inner;
    /* 1: no caustic map counts the light reaching a diffuse point from
     * emitters through specular surfaces only (PATH with the irradiance
     * cache): the gathers' rays count it, apart (indirect_diffuse.h). */
    int gathers_find_caustics;
    /* Glossy closures smoother than this carry caustics (bsdf.h): camera
     * and gather rays follow them as mirrors, and photons pass them; those
     * at least this rough receive the caustic map's estimate at camera
     * vertices (diffuse_split.c). 0 under PATH: only deltas. */
    float caustic_roughness;
    /* Progressive caustics (progressive_caustics.h): the current sample's
     * map and radius replace the caustic map's k nearest; NULL: off. */
    const struct progressive_caustics *progressive;
    /* Nonzero: only a pixel's first `caustic_reads` samples read the
     * caustic map at their first vertex, into sample_result.caustic_read,
     * which the film averages over those samples alone (render.c; 0: every
     * sample reads it, into COMPONENT_CAUSTICS). */
    uint32_t caustic_reads;
    /* 1: camera paths also record the denoising features (a Denoising pass is on). */
    int denoising_features;
    const phos_camera_desc *camera; /* for the features' camera-space normal */
} integrator_settings;

/* Per-thread scratch: photon-map queries, and counts render.c sums per
 * tile: the irradiance cache's lookups and interpolations, and the gather
 * rays the hemispheres sent (hemisphere.c, irradiance_record.c). */
typedef struct integrator_scratch {
    kdtree_query global, caustic, radiance;
    uint64_t cache_lookups, cache_hits, gather_rays;
    /* The render's cancel flag (NULL: none). A hemisphere of thousands of
     * path-traced rays takes seconds, so the gathers look at it too and
     * stop early; what they return then is discarded (render.c). */
    const atomic_int *cancel;
} integrator_scratch;

typedef struct sample_result {
    vec3 component[COMPONENT_COUNT]; /* W/(m²·sr) along the camera ray */
    vec3 photon_map;               /* debug: global-map estimate at the first diffuse hit */
    vec3 caustic_map;              /* debug: caustic-map estimate there */
    vec3 caustic_read;             /* the first vertex's caustic-map estimate, kept apart when
                                    * integrator_settings.caustic_reads is set (0 otherwise) */
    vec3 denoising_albedo;         /* the denoising features (integrator_settings.denoising_features) */
    vec3 denoising_normal;         /* camera space, unit (0 if the ray hit nothing) */
    float alpha;                   /* 1 where the ray hit something opaque */
    float first_distance;          /* how far the ray went to the first surface it hit (INFINITY: none) */
} sample_result;

/* The integrators: each is a vertex policy of the camera-path walker
 * (camera_path.h). Unbiased path tracing with next-event estimation and
 * MIS (Veach 1997); path.c. */
void path_trace(const scene *s, const integrator_settings *is, camera_ray ray, const sampler *smp,
                integrator_scratch *scratch, sample_result *res);

/* Photon mapping (Jensen 1996, 2001): direct light by next-event
 * estimation, specular and glossy by ray tracing, caustics from the
 * caustic map, indirect diffuse from the settings' indirect provider;
 * photon.c. */
void photon_render(const scene *s, const integrator_settings *is, camera_ray ray, const sampler *smp,
                   integrator_scratch *scratch, sample_result *res);

/* The caustics reflected toward wo through b at x (n on wo's side),
 * W/(m²·sr): the caustic map's k nearest photons, or with progressive
 * caustics the current sample's map within its radius. */
vec3 photon_caustic_radiance(const integrator_settings *is, const bsdf *b, vec3 wo, vec3 x, vec3 n,
                             integrator_scratch *scratch);

/* The maps' estimates at the first diffuse surface the camera sees (the
 * debug passes), for either integrator. */
void photon_debug_estimates(const scene *s, const integrator_settings *is, camera_ray ray,
                            integrator_scratch *scratch, sample_result *res);

#endif /* PHOS_INTEGRATOR_H */
