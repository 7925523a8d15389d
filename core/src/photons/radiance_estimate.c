/*
 * radiance_estimate.c — photon density estimates.
 *
 * Radius: with k photons found, r is the distance of the k-th and only the
 * k − 1 inside it are summed; counting the k-th as well would overestimate
 * by k/(k − 1) (García et al. 2012, "Description and Solution of an
 * Unreported Intrinsic Bias in Photon Mapping Density Estimation with
 * Constant Kernel"; docs/algorithms.md §4.2). With fewer than k inside
 * the maximum radius, r is the maximum radius: a fixed-radius estimate,
 * unbiased for smooth illumination. The search is a disc (the sphere flattened along
 * the normal) so light from an adjacent wall does not leak into corners.
 */
#include "photons/radiance_estimate.h"

typedef struct weighted_photon_sum {
    float r2;        /* squared radius of the estimate */
    float norm;      /* the kernel's integral over the disc, in units of πr² */
} weighted_photon_sum;

/* Searches, and marks in skip[] the photons (indices in q) to leave out:
 * the k-th, which only sets the radius (k−1 rule), and with at_photon the
 * photon lying at x itself. Then k−1 photons in all are left out of the k
 * found: with the one at x excluded, the others are k−1 samples of the
 * density and their k−1-th sets the radius, so k−2 are summed, as the
 * k−1 rule asks for k−1 found (docs/algorithms.md §5.3). */
typedef struct skipped {
    uint32_t far, self;
} skipped;

static skipped gather(const photon_map *m, vec3 x, vec3 n, const estimate_params *ep, kdtree_query *q,
                      weighted_photon_sum *w)
{
    float max_r2 = ep->max_radius * ep->max_radius;
    photon_map_knn_disc(m, x, n, ESTIMATE_DISC_FLATTEN, max_r2, q);
    skipped skip = {UINT32_MAX, UINT32_MAX};
    w->r2 = max_r2;
    if (ep->at_photon)
        for (uint32_t j = 0; j < q->found; j++)
            if (q->dist2[j] == 0.0f) {
                skip.self = j;
                break;
            }
    if (q->found == q->k && q->k > 1) {
        w->r2 = q->radius2;
        float far = -1.0f;
        for (uint32_t j = 0; j < q->found; j++)
            if (j != skip.self && q->dist2[j] > far) {
                far = q->dist2[j];
                skip.far = j;
            }
    }
    w->norm = ep->filter == ESTIMATE_CONE ? 1.0f / 3.0f : 1.0f;
    return skip;
}

static float kernel_weight(const estimate_params *ep, float d2, float r2)
{
    if (ep->filter == ESTIMATE_CONE)
        return fmaxf(1.0f - sqrtf(d2 / r2), 0.0f); /* Jensen 1996 cone filter with k = 1 */
    return 1.0f;
}

vec3 photon_irradiance(const photon_map *m, vec3 x, vec3 n, const estimate_params *ep, kdtree_query *q)
{
    vec3 sum = v3s(0.0f);
    if (m->count == 0 || !(ep->max_radius > 0.0f))
        return sum;
    weighted_photon_sum w;
    skipped skip = gather(m, x, n, ep, q, &w);
    for (uint32_t j = 0; j < q->found; j++) {
        if (j == skip.far || j == skip.self)
            continue;
        const photon *p = kdtree_result(m->photons, q, j);
        if (p->flags & ep->exclude_flags)
            continue;
        if (v3_dot(photon_direction(p), n) >= 0.0f) /* arrived from behind */
            continue;
        sum = v3_madd(sum, photon_power(p), kernel_weight(ep, q->dist2[j], w.r2));
    }
    return v3_scale(sum, 1.0f / (PHOS_PI * w.r2 * w.norm));
}

vec3 photon_radiance(const photon_map *m, const bsdf *b, vec3 wo, vec3 x, vec3 n, const estimate_params *ep,
                     kdtree_query *q)
{
    vec3 sum = v3s(0.0f);
    if (m->count == 0 || !(ep->max_radius > 0.0f) || b->count == 0)
        return sum;
    weighted_photon_sum w;
    skipped skip = gather(m, x, n, ep, q, &w);
    for (uint32_t j = 0; j < q->found; j++) {
        if (j == skip.far || j == skip.self)
            continue;
        const photon *p = kdtree_result(m->photons, q, j);
        if (p->flags & ep->exclude_flags)
            continue;
        vec3 wi = v3_neg(photon_direction(p)); /* toward where the photon came from */
        float cos_i = v3_dot(wi, n);
        if (cos_i <= 0.0f)
            continue;
        /* bsdf_eval includes |cos θi|; the estimate wants f alone. */
        vec3 f = v3_scale(bsdf_eval(b, wo, wi, NULL), 1.0f / cos_i);
        sum = v3_add(sum, v3_scale(v3_mul(f, photon_power(p)), kernel_weight(ep, q->dist2[j], w.r2)));
    }
    return v3_scale(sum, 1.0f / (PHOS_PI * w.r2 * w.norm));
}

/* The nearest of the k nearest records whose normal agrees with n. */
static int nearest_facing(const photon_map *m, vec3 x, vec3 n, float max_r2, uint32_t k, kdtree_query *q, vec3 *L)
{
    uint32_t capacity = q->k;
    q->k = k < capacity ? k : capacity;
    photon_map_knn_disc(m, x, n, ESTIMATE_DISC_FLATTEN, max_r2, q);
    q->k = capacity;
    float best = INFINITY;
    for (uint32_t j = 0; j < q->found; j++) {
        const photon *p = kdtree_result(m->photons, q, j);
        if (v3_dot(photon_direction(p), n) <= 0.5f) /* the record's normal is in the direction bytes */
            continue;
        if (q->dist2[j] < best) {
            best = q->dist2[j];
            *L = photon_power(p);
        }
    }
    return best < INFINITY;
}

int radiance_photon_lookup(const photon_map *m, vec3 x, vec3 n, float max_radius, kdtree_query *q, vec3 *L)
{
    *L = v3s(0.0f);
    if (m->count == 0)
        return 0;
    float max_r2 = max_radius * max_radius;
    return nearest_facing(m, x, n, max_r2, RADIANCE_LOOKUP_FIRST, q, L) ||
           nearest_facing(m, x, n, max_r2, RADIANCE_LOOKUP_WIDE, q, L);
}
