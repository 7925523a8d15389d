/*
 * irradiance_cache_fill.h — the pre-pass that fills the irradiance cache
 * before the image's tiles render, deterministically.
 */
#ifndef PHOS_IRRADIANCE_CACHE_FILL_H
#define PHOS_IRRADIANCE_CACHE_FILL_H

#include <stdatomic.h>

#include "indirect/indirect_diffuse.h"
#include "indirect/irradiance_cache.h"

typedef struct irradiance_cache_fill_settings {
    uint32_t width, height;     /* the full frame, pixels (not the border: see the .c) */
    uint32_t seed;
    uint32_t sampler;   /* enum sampler_kind */
    uint32_t rays;              /* gather rays per record */
    float min_spacing, max_spacing; /* a record's reach R/q, pixels of the image where it lies */
    uint32_t threads;
    /* More views to fill from after the scene's camera, in order (a render
     * farm's cache job over a camera path, phos_render_add_view); each
     * adds records only where the records before it leave a gap. */
    const phos_camera_desc *views;
    uint32_t view_count;
} irradiance_cache_fill_settings;

/* The passes the fill makes over the image, over every view: progress
 * counts them. */
uint32_t irradiance_cache_fill_passes(const irradiance_cache_fill_settings *fs);

/* Fills c from the camera of s, then from fs->views, with the gather rays of is->cache_inner;
 * scratch holds one entry per thread. *passes_done counts finished passes
 * and *rays_traced the rays cast. PHOS_ERROR_CANCELLED if *cancel was set,
 * PHOS_ERROR_OUT_OF_MEMORY. */
phos_status irradiance_cache_fill(irradiance_cache *c, const scene *s, const integrator_settings *is,
                                  const irradiance_cache_fill_settings *fs, integrator_scratch *scratch,
                                  atomic_int *cancel, atomic_uint *passes_done, atomic_uint_fast64_t *rays_traced);

#endif /* PHOS_IRRADIANCE_CACHE_FILL_H */
