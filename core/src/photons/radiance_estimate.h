/*
 * radiance_estimate.h — density estimation on a photon map (Jensen 1996,
 * "Global Illumination using Photon Maps"; Jensen's course notes 2002,
 * "Radiance Estimate"):
 *
 *     L_r(x, ω) ≈ Σ_p f_r(x, ω_p, ω) ΔΦ_p / (π r²)
 *
 * over the k nearest photons within a maximum radius.
 */
#ifndef PHOS_RADIANCE_ESTIMATE_H
#define PHOS_RADIANCE_ESTIMATE_H

#include "shading/bsdf.h"
#include "photons/kdtree.h"

enum estimate_filter {
    ESTIMATE_BOX = 0,
    ESTIMATE_CONE = 1 /* Jensen's cone filter, w = 1 − d/r, normalised by 1 − 2/3 */
};

struct phos_scene;

typedef struct estimate_params {
    uint32_t k;              /* photons in the estimate */
    float max_radius;        /* scene units */
    uint32_t filter;         /* enum estimate_filter */
    uint16_t exclude_flags;  /* skip photons with any of these flags (PHOTON_DIRECT, PHOTON_CAUSTIC) */
    /* Non-NULL: the disc's area is clipped where walls of this scene cut
     * it (estimate_disc_coverage); NULL: the whole disc, πr². */
    const struct phos_scene *clip;
} estimate_params;

/* Probes in the surface's plane that measure how much of a search disc
 * the surface covers (docs/algorithms.md §4.6). */
#define ESTIMATE_CLIP_PROBES 16

/* The share of the disc of radius r about x, in the plane of unit normal
 * n, that the surface covers before a wall: probes from just above x along
 * the plane, each as long as the radius, and the polar area of what they
 * reach, ½∮ min(t(φ), r)² dφ / (πr²) for the box kernel (the kernel's
 * integral over that area, over its integral over the disc, for the
 * cone). 1 where nothing is within r; 1/4 at the corner of a box-shaped
 * room. The probes turn by an angle hashed from
 * x, so neighbouring estimates do not share one set of directions. */
float estimate_disc_coverage(const struct phos_scene *s, vec3 x, vec3 n, float r, uint32_t filter);

/* Flattening of the search sphere along the normal (docs/algorithms.md
 * §4.3): keeps photons of an adjacent wall or the far side of a thin wall
 * out. */
#define ESTIMATE_DISC_FLATTEN 4.0f

/* A photon counts in an estimate only if the normal of the surface it
 * landed on is within 44.8° of the normal where the estimate is read
 * (photon_normal): a corner's other wall (90°) and the far side of a thin
 * wall (180°) are left out, while the facets of a smoothly curved mesh,
 * which the flattened disc already limits to a few tens of degrees across
 * a search, still count. Just above cos 45° = 0.7071, so that an
 * axis-aligned wall's search enters its own facing class only: at 0.7 the
 * four classes beside it (whose normals reach 45° from it) were searched
 * too, for photons they almost never hold. */
#define ESTIMATE_NORMAL_MIN_COS 0.71f

/* Irradiance E (W/m²) at x on the side of unit normal n, from the photons
 * that arrived on that side onto a surface facing about the same way
 * (kdtree_filter). q must hold k. */
vec3 photon_irradiance(const photon_map *m, vec3 x, vec3 n, const estimate_params *ep, kdtree_query *q);

/* Reflected radiance W/(m²·sr) toward wo through the BSDF b at x, n on the
 * side of wo. */
vec3 photon_radiance(const photon_map *m, const bsdf *b, vec3 wo, vec3 x, vec3 n, const estimate_params *ep,
                     kdtree_query *q);

/* Reflected radiance W/(m²·sr) from every photon within `radius` (disc
 * metric, the same filter as photon_radiance), with a box kernel:
 * Σ f ΔΦ / (π r²). Given a radius that does not depend on the map's
 * photons, the estimate's mean is the disc's average of the reflected
 * radiance: progressive photon mapping's per-pass estimate (Knaus &
 * Zwicker 2011; photons/progressive_caustics.c). clip: as in estimate_params
 * (NULL: the whole disc). */
vec3 photon_radiance_within(const photon_map *m, const bsdf *b, vec3 wo, vec3 x, vec3 n, float radius,
                            uint16_t exclude_flags, const struct phos_scene *clip);

/* A radiance photon answers a lookup whose normal is within 41° of its
 * own. Christensen (1999) allows 60°; 41° keeps the lookup inside the
 * facing class of an axis-aligned wall (photon.h), where a 60° cone also
 * searched the four classes beside it: final gathering in the Cornell box
 * took 37 % less time. */
#define RADIANCE_LOOKUP_MIN_COS 0.75f

/* The precomputed radiance photon nearest to x (disc metric, §4.3) whose
 * normal agrees with n (RADIANCE_LOOKUP_MIN_COS), within max_radius: returns 1 and its radiance
 * (W/(m²·sr)) in *L, or 0 if there is none (the caller then estimates on
 * the fly from the global map). docs/algorithms.md §5.3. */
int radiance_photon_lookup(const photon_map *m, vec3 x, vec3 n, float max_radius, kdtree_query *q, vec3 *L);

/* The same, also returning the radius (scene units) of the estimate the
 * radiance photon was computed from (radiance_photon_set_radius). */
int radiance_photon_lookup_radius(const photon_map *m, vec3 x, vec3 n, float max_radius, kdtree_query *q, vec3 *L,
                                  float *radius);

/* A radiance photon has no direction of travel, so its two direction
 * bytes keep the radius of the estimate behind it: 16 bits, in steps of
 * 1/256 of an octave, r = 2^((code − 32768)/256), rounded up (the decoded
 * radius is never below r, by at most 0.3 %). Final gathering reads it to
 * tell whether a gather ray landed inside that estimate's disc. */
void radiance_photon_set_radius(photon *p, float radius);
float radiance_photon_radius(const photon *p);

#endif /* PHOS_RADIANCE_ESTIMATE_H */
