/*
 * irradiance_cache_file.h — the irradiance cache saved to a file and read
 * back, for animations (one cache for every frame of a walkthrough) and
 * render farms (every machine reads the same records): versioned,
 * little-endian whatever the machine, and refused when it was made for
 * another scene or other settings (docs/cache_files.md).
 */
#ifndef PHOS_IRRADIANCE_CACHE_FILE_H
#define PHOS_IRRADIANCE_CACHE_FILE_H

#include <stddef.h>

#include "indirect/irradiance_cache.h"
#include "phos.h"
#include "scene/scene.h"

/* Writes c's records with the scene's fingerprint and the settings that
 * shape them. PHOS_OK, or an error with a message in msg. */
phos_status irradiance_cache_save(const irradiance_cache *c, const scene *s, const phos_render_settings *rs,
                                  const char *path, char *msg, size_t msg_size);

/* Reads records into c (empty, initialised) from a file made for this
 * scene and these settings; otherwise an error whose message says what
 * differs (geometry, materials, lights, or the setting by name). */
phos_status irradiance_cache_load(irradiance_cache *c, const scene *s, const phos_render_settings *rs,
                                  const char *path, char *msg, size_t msg_size);

#endif /* PHOS_IRRADIANCE_CACHE_FILE_H */
