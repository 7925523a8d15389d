/*
 * environment.h — a world whose radiance varies with direction (an HDR
 * environment map, a sky, any world node tree): its radiance, and a
 * piecewise-constant distribution over directions to sample it by.
 *
 * Sampling (docs/algorithms.md §11): the sphere is cut into cells of equal
 * solid angle, rows of equal height in z = cos θ by columns of equal width
 * in φ (Archimedes' hat-box theorem: a band of height Δz has area 2πΔz), so
 * a cell's probability is its luminance over the total and the density in
 * solid angle is constant within it. On a latitude-longitude grid the same
 * distribution needs the Jacobian sin θ (pbrt-v4's luminance × sin θ);
 * equal-area cells carry it in their shape. The cells are grouped into
 * ENVIRONMENT_BINS × ENVIRONMENT_BINS bins of equal solid angle, the bins of
 * directions the photon projection map aims each through its own plane
 * (photons/projection_map.c); a bin is picked by its share, then a cell
 * within it, so a photon can also be drawn within a given bin.
 */
#ifndef PHOS_ENVIRONMENT_H
#define PHOS_ENVIRONMENT_H

#include "phos.h"
#include "sampling/distribution.h"
#include "sampling/sampler.h"
#include "scene/scene.h"

#define ENVIRONMENT_BINS 8            /* per side: 64 bins of π/16 sr */
#define ENVIRONMENT_MAX_ROWS 512      /* cells along z: a 16K map is sampled at most this finely */
#define ENVIRONMENT_MAX_COLUMNS 1024  /* cells along φ */

typedef struct environment {
    const material *mat;        /* the world's material, whose program varies with direction */
    uint32_t rows, columns;     /* cells; multiples of ENVIRONMENT_BINS */
    distribution bins;          /* the bins by the luminance they hold */
    distribution *cells;        /* per bin: its cells by luminance (bin-local order, row-major) */
    float bin_integral[ENVIRONMENT_BINS * ENVIRONMENT_BINS]; /* ∫ over the bin of the channel mean of L dω, W/m² */
    double integral;            /* the same over the sphere: W/m² */
} environment;

/* Cells for a world material: the finest image an Environment Texture of
 * its program reads sets them (about one cell per pixel at the horizon),
 * within the bounds above; 64 × 128 without one. */
void environment_resolution(const scene *s, const material *m, uint32_t *rows, uint32_t *columns);

/* Bytes environment_build allocates for that many cells (the memory
 * estimate). */
size_t environment_bytes(uint32_t rows, uint32_t columns);

/* Evaluates the world on the cells (2 × 2 points each) and builds the
 * distribution; *zero is set when the world sends no light at all.
 * Returns PHOS_ERROR_OUT_OF_MEMORY or PHOS_ERROR_CANCELLED (s->cancel). */
phos_status environment_build(environment *e, const scene *s, const material *m, uint32_t threads, int *zero);
void environment_free(environment *e);

/* Radiance W/(m²·sr) arriving along −d, i.e. seen by a ray of unit
 * direction d that left the scene; ray_flags: enum shader_ray_flags. */
vec3 environment_radiance(const scene *s, const environment *e, vec3 d, uint32_t ray_flags);

/* A direction by the distribution over the whole sphere, with its
 * solid-angle density. */
vec3 environment_sample(const environment *e, float2 u, float *pdf);
float environment_pdf(const environment *e, vec3 d);

/* A direction within bin `bin` only, with its solid-angle density
 * conditional on the bin (integrating to 1 over the bin). */
vec3 environment_sample_in_bin(const environment *e, uint32_t bin, float2 u, float *pdf);

/* The bin a direction lies in, and the unit square's point of a bin's
 * corner (u along z, v along φ, as warp_uniform_sphere reads them). */
uint32_t environment_bin_of(vec3 d);
float2 environment_bin_corner(uint32_t bin);

#endif /* PHOS_ENVIRONMENT_H */
