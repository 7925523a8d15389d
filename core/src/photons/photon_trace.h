/*
 * photon_trace.h — photon tracing (Jensen 2001, ch. 5; Jensen's course
 * notes 2002, "Photon tracing"): emission from the lights, scattering by
 * Russian roulette, storing at non-specular surfaces into the global and
 * caustic maps, and Christensen's precomputed radiance photons.
 */
#ifndef PHOS_PHOTON_TRACE_H
#define PHOS_PHOTON_TRACE_H

#include <stdatomic.h>

#include "photons/kdtree.h"
#include "photons/photon.h"
#include "photons/projection_map.h"
#include "scene/scene.h"

typedef struct photon_maps {
    photon_map global;         /* every non-specular hit: paths L {S|D}* D */
    photon_map caustic;        /* paths L S+ D */
    photon_map radiance;       /* Christensen 1999: power = outgoing radiance W/(m²·sr),
                                  direction and normal bits = the surface normal on the lit side */
    uint64_t global_emitted;   /* photon paths emitted to fill each map; 0 for a global map not
                                  traced (no light, or no gather would read it: gathers then path-trace
                                  instead, render.c) */
    uint64_t caustic_emitted;  /* by the caustic pass itself */
    uint32_t caustic_reused;   /* of the caustic map's photons, those the global pass traced */
    /* Where radiance photons will be computed (as many as a quarter of the
     * global photons, where photon paths of their own land): position,
     * normal on the lit side, diffuse reflectance; 9 floats each.
     * Freed by photon_maps_precompute_radiance. */
    float *radiance_sites;
    uint32_t radiance_site_count;
    /* The global map's photons from suns, the world or lamps reaching
     * several objects, or the caustic map's from suns or lamps reaching
     * several specular objects, were aimed at what the scene's camera
     * reads (photon_importance.h): unbiased maps for any view, but densest
     * where that camera looked. */
    int aimed_at_view;
    /* Bit (1 << enum phos_photon_map) of each map traced that ended short
     * of its count: the emission cap, or a yield too low ever to fill it
     * (its lights' photons mostly leave the scene or are absorbed). */
    uint32_t short_maps;
} photon_maps;

typedef struct photon_trace_settings {
    uint32_t global_photons;   /* photons to store in each map */
    uint32_t caustic_photons;
    uint64_t max_emitted;      /* give up on a map after this many paths */
    uint32_t max_bounces;      /* scattering events per photon path */
    uint32_t seed;
    uint32_t sampler;          /* enum sampler_kind */
    uint32_t threads;
    uint32_t radiance_k;       /* photons in the estimate behind each radiance photon */
    float max_radius;          /* search radius cap, scene units */
    float caustic_roughness;   /* glossy closures smoother than this carry caustic paths and store no
                                  photons (bsdf.h, closure_scatters_caustic) */
    uint32_t unaimed;          /* 1: the global map's lights emit over their whole distribution and the
                                  caustic map's cells and cones are not weighed by the view (the
                                  tests' reference for aimed maps); 0 in every render */
    uint32_t gathers_only;     /* 1: the render reads the global map only at the hits of gathers
                                  from surfaces (render_global_read_by_gathers), so a map that no
                                  gather from what the camera sees can reach is not traced */
    const phos_camera_desc *views; /* more views the global map is aimed at, besides the scene's
                                      camera (phos_render_add_view); not among the words below */
    uint32_t view_count;
} photon_trace_settings;

/* What the maps depend on besides the scene, as 32-bit words (floats by
 * their bits), for saved maps and maps kept between renders to be refused
 * when made otherwise. The camera is not among them: photons aimed at one
 * view are an unbiased map for any other, if a less dense one. */
#define PHOTON_TRACE_SETTING_WORDS 10u
void photon_trace_settings_words(const photon_trace_settings *ps, uint32_t w[PHOTON_TRACE_SETTING_WORDS]);
/* The user's name of the setting behind each word. */
extern const char *const photon_trace_setting_names[PHOTON_TRACE_SETTING_WORDS];

typedef struct photon_trace_progress {
    atomic_uint_fast64_t emitted;  /* paths emitted so far, both maps */
    atomic_uint stored;            /* photons kept so far, both maps */
    atomic_uint map;               /* the map being traced: enum phos_photon_map */
} photon_trace_progress;

void photon_maps_init(photon_maps *m);

/* Bytes photon tracing and the kd-tree builds need at their peak for maps
 * of `global` and `caustic` stored photons: the traced records (whose
 * batches grow by doubling), the stored photons and the build's copy, and
 * the radiance sites (render/memory.c checks it before a render starts). */
uint64_t photon_maps_memory_estimate(uint32_t global, uint32_t caustic);
void photon_maps_free(photon_maps *m);

/* Traces both maps. Photon path i of a map takes its random numbers from
 * (seed, map, i) and the maps are assembled in path order, so they are the
 * same for any thread count. Returns PHOS_ERROR_CANCELLED if *cancel was
 * set, PHOS_ERROR_OUT_OF_MEMORY, or PHOS_OK. */
phos_status photon_maps_trace(const scene *s, const photon_trace_settings *ps, photon_maps *out,
                              atomic_int *cancel, photon_trace_progress *progress);

/* The caustic map alone, traced with an aim built once by
 * photon_caustic_aim_build for the scene and settings: progressive
 * caustics trace a map every sample (progressive_caustics.h), and their
 * aim, with its pilot photons, is the same for all. ps->global_photons is
 * not read. Statuses as photon_maps_trace. */
phos_status photon_caustic_aim_build(const scene *s, const photon_trace_settings *ps, projection_map *aim,
                                     atomic_int *cancel);
phos_status photon_maps_trace_caustic(const scene *s, const photon_trace_settings *ps, const projection_map *aim,
                                      photon_maps *out, atomic_int *cancel);
/* Sets m->short_maps from its maps' counts against the settings (traced
 * or read from a file alike). */
void photon_maps_note_short(photon_maps *m, const scene *s, const photon_trace_settings *ps);

/* Balances the kd-trees of the global and caustic maps; PHOS_ERROR_CANCELLED
 * soon after *cancel is set (cancel may be NULL). */
phos_status photon_maps_build(photon_maps *m, uint32_t threads, atomic_int *cancel);

/* Christensen 1999: at each radiance site, the radiance the surface
 * reflects there, ρ/π·E, from the global map's photons that scattered at
 * least once (not the direct ones); stored as its own map so that final
 * gathering reads one photon instead of k. */
phos_status photon_maps_precompute_radiance(const scene *s, const photon_trace_settings *ps, photon_maps *m,
                                            atomic_int *cancel);

#endif /* PHOS_PHOTON_TRACE_H */
