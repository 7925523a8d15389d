/*
 * irradiance_cache.h — Ward's irradiance cache (Ward, Rubinstein & Clear
 * 1988, "A Ray Tracing Solution for Diffuse Interreflection"), with the
 * gradients of Ward & Heckbert 1992 and the neighbour clamping of Křivánek
 * et al. 2006 (course notes 2002, "Irradiance Caching"; docs/algorithms.md
 * §10).
 *
 * Indirect irradiance changes slowly over a diffuse surface, so it is
 * computed accurately at a few points (records) and interpolated between
 * them. A record holds the irradiance E from a stratified hemisphere of
 * rays, the harmonic mean distance R of the surfaces those rays hit, and
 * E's gradients. At a point x with normal n, record i weighs
 *
 *   w_i(x, n) = 1 / (‖x − x_i‖/R_i + √(1 − n·n_i))
 *
 * and is used where w_i > q (the accuracy, "w > 10" on the course's
 * slides), i.e. within R_i/q of x_i on a surface of the same orientation
 * (its reach). E(x) = Σ w_i E_i(x) / Σ w_i over those records, with each
 * E_i extrapolated to x and n by its gradients.
 *
 * The cache holds irradiance, not reflected radiance: the surface's
 * diffuse BSDF multiplies it where it is read, so textures stay sharp.
 *
 * A cache is filled in fixed order by the pre-pass (irradiance_cache_fill.c)
 * and only read while the image's tiles render, from any thread.
 */
#ifndef PHOS_IRRADIANCE_CACHE_H
#define PHOS_IRRADIANCE_CACHE_H

#include <stdint.h>

#include "util/vec.h"

typedef struct irradiance_record {
    vec3 p;                /* position, scene units */
    vec3 n;                /* shading normal, on the side the record gathered */
    vec3 E;                /* irradiance W/m² from light that scattered before */
    vec3 E_caustic;        /* irradiance W/m² from emitters through specular surfaces only; only
                              where no caustic map counts it (integrator_settings.gathers_find_caustics) */
    vec3 w_mean;           /* mean incident direction of E, weighted by luminance (unit) */
    vec3 grad_r[3];        /* per RGB channel: rotational gradient, W/m² per radian (Ward & Heckbert) */
    vec3 grad_t[3];        /* per RGB channel: translational gradient, W/m³ */
    float R;               /* radius R_i in the weight, scene units (the reach is R/q) */
    float R_free;          /* R before the spacing clamps: what neighbour clamping lowers */
    float R_lo, R_hi;      /* the spacing clamps at this record, scene units */
    uint32_t next;         /* the next record of its octree node, UINT32_MAX: none */
} irradiance_record;

typedef struct irradiance_cache_node {
    vec3 centre;
    float half;            /* half the cube's edge, scene units */
    uint32_t child[8];     /* node indices, 0: none (the root is never a child) */
    uint32_t first;        /* the node's first record, UINT32_MAX: none */
} irradiance_cache_node;

typedef struct irradiance_cache {
    float accuracy;        /* q: records are used where w > q */
    irradiance_record *records;
    uint32_t count, capacity;
    /* Octree over the records (Ward et al. 1988, as Radiance): a record is
     * kept in the largest node no larger than twice its reach, so a lookup
     * visits a node only if the point lies within the node's cube grown
     * by the node's edge on every side. */
    irradiance_cache_node *nodes;
    uint32_t node_count, node_capacity;
} irradiance_cache;

/* What a lookup interpolated. */
typedef struct irradiance_estimate {
    vec3 E, E_caustic;     /* W/m² */
    vec3 w_mean;           /* unit */
    uint32_t records;      /* records used */
} irradiance_estimate;

/* Bytes a cache filled over a width × height frame may take: a record
 * keeps at least min_spacing pixels from the next, so at most one per
 * min_spacing² pixels (one per pixel below 1), with the octree's nodes
 * and the pre-pass's per-candidate arrays. An upper estimate for the
 * memory check of a render (render/memory.c). */
uint64_t irradiance_cache_memory_estimate(uint32_t width, uint32_t height, float min_spacing);

/* An empty cache over the box [bmin, bmax]; 0 when memory is exhausted. */
int irradiance_cache_init(irradiance_cache *c, vec3 bmin, vec3 bmax, float accuracy);
void irradiance_cache_free(irradiance_cache *c);

/* Adds a record (its R clamped to [R_lo, R_hi] already) and clamps the
 * radii of it and its neighbours: R_i ≤ R_j + ‖x_i − x_j‖ both ways
 * (Křivánek et al. 2006, "Making Radiance and Irradiance Caching
 * Practical"), then each to its spacing clamps again. 0 when memory is
 * exhausted. */
int irradiance_cache_insert(irradiance_cache *c, const irradiance_record *r);

/* Adds a record as it is, its radius already clamped against its
 * neighbours (a cache read from a file, irradiance_cache_file.h): the
 * cache holds exactly the records it was saved with. 0 when memory is
 * exhausted. */
int irradiance_cache_place(irradiance_cache *c, const irradiance_record *r);

/* Places every record again, in index order, by its final radius: the
 * tree a cache read from a file gets, so that a lookup sums the same
 * records in the same order whether the cache was computed or read. */
int irradiance_cache_rebuild(irradiance_cache *c);

/* Interpolates at p with shading normal n; 1 if some record has w > q. */
int irradiance_cache_lookup(const irradiance_cache *c, vec3 p, vec3 n, irradiance_estimate *out);

/* E_i extrapolated to (p, n) by its gradients, each channel at least 0:
 * E_i + (n_i × n)·∇_r E_i + (p − p_i)·∇_t E_i (Ward & Heckbert 1992). */
vec3 irradiance_record_extrapolate(const irradiance_record *r, vec3 p, vec3 n);

#endif /* PHOS_IRRADIANCE_CACHE_H */
