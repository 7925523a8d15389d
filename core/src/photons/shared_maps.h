/*
 * shared_maps.h — photon maps that outlive the render that built them
 * (phos_photon_maps): the viewport keeps them while only the view moves,
 * and a second render of an unchanged scene (Blender's Persistent Data)
 * reads them instead of tracing again. Built maps are only read by the
 * tiles, so renders may share them; a reference count frees them with
 * the last holder.
 */
#ifndef PHOS_SHARED_MAPS_H
#define PHOS_SHARED_MAPS_H

#include <stdatomic.h>
#include <stddef.h>

#include "photons/photon_trace.h"
#include "scene/scene.h"

struct phos_photon_maps {
    atomic_int refcount;
    photon_maps maps;
    /* What they were made from, set when they are complete. */
    uint64_t scene_id, scene_version;  /* the scene and its version without the camera (scene.h) */
    uint32_t settings[PHOTON_TRACE_SETTING_WORDS];
    int has_radiance;                  /* radiance photons precomputed (final gathering) */
    phos_camera_desc camera;           /* the view the maps were aimed at, if maps.aimed_at_view */
};

typedef struct phos_photon_maps shared_maps;

/* Empty maps with one reference; NULL when memory is exhausted. */
shared_maps *shared_maps_create(void);
void shared_maps_retain(shared_maps *m);
void shared_maps_release(shared_maps *m);

/* Records what the complete maps were made from. */
void shared_maps_seal(shared_maps *m, const scene *s, const photon_trace_settings *ps, int has_radiance);

/* NULL if a render of scene s with settings ps may read the maps (needing
 * radiance photons if needs_radiance; from any view if any_view, else only
 * from the camera the maps were aimed at); else why not, written to
 * detail or a constant. */
const char *shared_maps_mismatch(const shared_maps *m, const scene *s, const photon_trace_settings *ps,
                                 int needs_radiance, int any_view, char *detail, size_t detail_size);

#endif /* PHOS_SHARED_MAPS_H */
