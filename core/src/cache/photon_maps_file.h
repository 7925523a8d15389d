/*
 * photon_maps_file.h — the photon maps kept in a file between renders
 * (docs/cache_files.md): written as they leave photon tracing, read back
 * in its place, refused when made for another scene or other settings.
 */
#ifndef PHOS_PHOTON_MAPS_FILE_H
#define PHOS_PHOTON_MAPS_FILE_H

#include <stddef.h>

#include "photons/photon_trace.h"

/* Writes the traced (not yet built) maps. PHOS_OK, or an error with a
 * message in msg. */
phos_status photon_maps_save(const photon_maps *maps, const scene *s, const photon_trace_settings *ps,
                             const char *path, char *msg, size_t msg_size);

/* Reads maps (initialised, empty) as tracing would have left them, from a
 * file made for this scene and these settings; otherwise an error whose
 * message says what differs. */
phos_status photon_maps_load(photon_maps *maps, const scene *s, const photon_trace_settings *ps, const char *path,
                             char *msg, size_t msg_size);

#endif /* PHOS_PHOTON_MAPS_FILE_H */
