/*
 * environment.h — a world whose radiance varies with direction (an HDR
 * environment map, a sky, any world node tree): its radiance, and a
 * piecewise-constant distribution over directions to sample it by.
 *
 * Sampling (docs/algorithms.md §11): the sphere is cut into a latitude-
 * longitude grid of cells, rows of equal Δθ by columns of equal Δφ, two
 * per pixel side of an equirectangular map, so cells fall on its pixels
 * (environment_resolution says why, with the measurements). A cell is drawn with probability ∝ its luminance × its solid angle (pbrt-
 * v4's luminance × sin θ), and a point uniform in θ and φ within it, of
 * density p_cell / (Δθ Δφ sin θ). A direction is drawn as
 * pbrt's 2-D distribution draws a point: a row by its share (the
 * marginal), then a cell of that row (the conditional), one number each,
 * so a stratified 2-D sample stays stratified over the sphere. The cells
 * fall into ENVIRONMENT_BINS × ENVIRONMENT_BINS bins of equal solid angle,
 * the bins of directions the photon projection map aims each through its
 * own plane (photons/projection_map.c); a direction can also be drawn
 * within one bin, by the same two steps restricted to its rows and columns.
 */
#ifndef PHOS_ENVIRONMENT_H
#define PHOS_ENVIRONMENT_H

#include "phos.h"
#include "sampling/distribution.h"
#include "sampling/sampler.h"
#include "scene/scene.h"

#define ENVIRONMENT_BINS 8            /* per side: 64 bins of π/8 in θ by π/4 in φ */
#define ENVIRONMENT_MAX_ROWS 1024     /* cells along θ: a 16K map is sampled at most this finely */
#define ENVIRONMENT_MAX_COLUMNS 2048  /* cells along φ */

typedef struct environment {
    const material *mat;        /* the world's material, whose program varies with direction */
    uint32_t rows, columns;     /* cells; multiples of ENVIRONMENT_BINS; row 0 at θ = 0 (+z) */
    float *weight;              /* per cell, row-major: luminance × solid angle, floored */
    float *row_cdf;             /* per row, columns + 1 cumulative shares of its cells, 0 .. 1 */
    distribution marginal;      /* the rows by their weight */
    distribution *bin_rows;     /* per bin: its rows by the weight of the bin's cells in them */
    double total;               /* the sum of the weights */
    double bin_total[ENVIRONMENT_BINS * ENVIRONMENT_BINS];
    float bin_integral[ENVIRONMENT_BINS * ENVIRONMENT_BINS]; /* ∫ over the bin of the channel mean of L dω, W/m² */
    double integral;            /* the same over the sphere: W/m² */
    uint32_t ray_flags;         /* added to every evaluation: SHADER_RAY_SKY_SUN_AS_LIGHT when the sky's
                                   sun is a light of its own (lights/sky_sun.c) */
} environment;

/* Cells for a world material: a quarter pixel of the largest image its
 * program reads, within the bounds above; 256 × 512 without one. */
void environment_resolution(const scene *s, const material *m, uint32_t *rows, uint32_t *columns);

/* Bytes environment_build allocates for that many cells (the memory
 * estimate). */
size_t environment_bytes(uint32_t rows, uint32_t columns);

/* Evaluates the world on the cells (with ray_flags added to every
 * evaluation, as e->ray_flags) and builds the distribution; *zero is set when the world sends no light at all.
 * Returns PHOS_ERROR_OUT_OF_MEMORY or PHOS_ERROR_CANCELLED (s->cancel).
 * A world of no power keeps no distribution (weight NULL). */
phos_status environment_build(environment *e, const scene *s, const material *m, uint32_t ray_flags,
                              uint32_t threads, int *zero);
void environment_free(environment *e);

/* Radiance W/(m²·sr) arriving along −d, i.e. seen by a ray of unit
 * direction d that left the scene; ray_flags: enum shader_ray_flags. */
vec3 environment_radiance(const scene *s, const environment *e, vec3 d, uint32_t ray_flags);

/* A direction by the distribution over the whole sphere, with its
 * solid-angle density (0 for a world of no power). */
vec3 environment_sample(const environment *e, float2 u, float *pdf);
float environment_pdf(const environment *e, vec3 d);

/* A direction within bin `bin` only, with its solid-angle density
 * conditional on the bin (integrating to 1 over the bin). */
vec3 environment_sample_in_bin(const environment *e, uint32_t bin, float2 u, float *pdf);

/* The bin a direction lies in; the direction at `at` ∈ [0,1]² within a bin
 * (θ then φ, linearly); and a bin's solid angle (sr). Bin b spans rows
 * b / ENVIRONMENT_BINS and columns b % ENVIRONMENT_BINS of the 8 × 8 grid. */
uint32_t environment_bin_of(vec3 d);
vec3 environment_bin_direction(uint32_t bin, float2 at);
float environment_bin_solid_angle(uint32_t bin);

#endif /* PHOS_ENVIRONMENT_H */
