/*
 * fingerprint.h — what a saved cache was computed from, so that a file
 * made for another scene or other settings is refused, never used
 * (docs/cache_files.md). Three 64-bit FNV-1a hashes of the scene, taken
 * over its values in a fixed byte order (little-endian 32-bit words), so
 * the same scene hashes the same on any machine; the camera is left out,
 * since a cache holds world-space records that any view may read.
 */
#ifndef PHOS_FINGERPRINT_H
#define PHOS_FINGERPRINT_H

#include <stdint.h>

#include "scene/scene.h"

typedef struct scene_fingerprint {
    uint64_t geometry;   /* meshes (positions, triangles, normals to 1/1024, UVs, slots) and instances */
    uint64_t materials;  /* materials' closures and the images they read */
    uint64_t lights;     /* lamps and the world */
} scene_fingerprint;

scene_fingerprint scene_fingerprint_of(const scene *s);

#endif /* PHOS_FINGERPRINT_H */
