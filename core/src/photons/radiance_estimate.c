/*
 * radiance_estimate.c — photon density estimates.
 *
 * Radius: with k photons found, r is the distance of the k-th and only the
 * k − 1 inside it are summed; counting the k-th as well would overestimate
 * by k/(k − 1) (García et al. 2012, "Description and Solution of an
 * Unreported Intrinsic Bias in Photon Mapping Density Estimation with
 * Constant Kernel"; docs/algorithms.md §4.2). With fewer than k inside
 * the maximum radius, r is the maximum radius: a fixed-radius estimate,
 * unbiased for smooth illumination.
 *
 * Photons of other surfaces: the search is a disc (the sphere flattened
 * along the normal), and it ranks only photons that arrived from the side
 * of n and landed on a surface facing about the same way (their normal
 * within ESTIMATE_NORMAL_MIN_COS of n; kdtree_filter). Without the normal
 * test, photons on the adjacent wall of a corner count on the floor, and
 * so do photons on the outside of a thin wall: a room lit through a window
 * read its floor 9 % too bright, whatever the photon count. Filtering after
 * the search let the outside's photons set the radius, and radiance
 * photons inside read 30 % dark (docs/algorithms.md §4.3).
 */
#include "photons/radiance_estimate.h"

#include <string.h>

#include "sampling/sampler.h"
#include "scene/embree.h"
#include "scene/scene.h"

/* Whether the probe from o along d meets, within r, a surface whose
 * photons the estimate would not take: one facing away from n by more
 * than the estimate's normal test allows (a wall). A surface facing about
 * the way n does (the same surface curving up, inside a bowl or a lamp
 * shade) holds photons the estimate counts, so the disc goes on there. */
static int probe_reaches_wall(const scene *s, vec3 o, vec3 d, vec3 n, float r, ray_hit *h)
{
    if (!embree_intersect(s->bvh, o, d, 0.0f, r, 0, h))
        return 0;
    vec3 v[3];
    scene_triangle_vertices(s, &s->instances[h->instance], h->prim, v);
    vec3 ng = v3_normalize(v3_cross(v3_sub(v[1], v[0]), v3_sub(v[2], v[0])));
    if (v3_dot(ng, d) > 0.0f)
        ng = v3_neg(ng); /* the side the probe arrives on */
    return !(v3_dot(ng, n) >= ESTIMATE_NORMAL_MIN_COS);
}

float estimate_disc_coverage(const scene *s, vec3 x, vec3 n, float r, uint32_t filter)
{
    if (!s || !(r > 0.0f))
        return 1.0f;
    frame f = frame_from_normal(n);
    /* Just above the surface: a wall meeting it is hit at its distance,
     * the surface itself never. */
    vec3 o = v3_madd(x, n, 0.01f * r);
    uint32_t bits[3];
    memcpy(bits, &x, sizeof(bits));
    float turn = u32_to_unit_float(hash_combine(hash_combine(hash_u32(bits[0]), bits[1]), bits[2]));
    /* Each probe stands for its 1/N of the directions (a Riemann sum of
     * the polar integral; with the turn uniform over one step its mean is
     * the integral itself, so neighbouring estimates' errors average out
     * over the image instead of adding up). */
    float sum = 0.0f;
    for (int i = 0; i < ESTIMATE_CLIP_PROBES; i++) {
        float phi = 2.0f * PHOS_PI * ((float)i + turn) / (float)ESTIMATE_CLIP_PROBES;
        vec3 d = frame_to_world(&f, v3(cosf(phi), sinf(phi), 0.0f));
        ray_hit h;
        float t = probe_reaches_wall(s, o, d, n, r, &h) ? h.t / r : 1.0f;
        /* The kernel's integral along the probe, ∫_0^t w(ρ) ρ dρ, over
         * its value at t = 1: box t², cone (t²/2 − t³/3)·6. */
        sum += filter == ESTIMATE_CONE ? t * t * (3.0f - 2.0f * t) : t * t;
    }
    float coverage = sum / (float)ESTIMATE_CLIP_PROBES;
    return coverage > 1.0f / ESTIMATE_CLIP_PROBES ? coverage : 1.0f / ESTIMATE_CLIP_PROBES;
}

typedef struct weighted_photon_sum {
    float r2;        /* squared radius of the estimate */
    float norm;      /* the kernel's integral over the disc, in units of πr² */
} weighted_photon_sum;

/* Searches; returns the index in q of the k-th photon found, which only
 * sets the radius (the k−1 rule), or UINT32_MAX when fewer than k were
 * found within the maximum radius. */
static uint32_t gather(const photon_map *m, vec3 x, vec3 n, const estimate_params *ep, kdtree_query *q,
                       weighted_photon_sum *w)
{
    float max_r2 = ep->max_radius * ep->max_radius;
    kdtree_filter f = {n, ESTIMATE_NORMAL_MIN_COS, ep->exclude_flags, 1};
    /* k from the estimate, not the query, which may be made for more
     * (render.c's caustic one also serves progressive caustics' first
     * radius). */
    uint32_t capacity = q->k;
    q->k = ep->k < capacity ? ep->k : capacity;
    photon_map_knn_surface(m, x, ESTIMATE_DISC_FLATTEN, &f, max_r2, q);
    uint32_t far_index = UINT32_MAX;
    w->r2 = max_r2;
    if (q->found == q->k && q->k > 1) {
        w->r2 = q->radius2;
        far_index = 0; /* the k-th nearest (kdtree_query) */
    }
    q->k = capacity;
    w->norm = ep->filter == ESTIMATE_CONE ? 1.0f / 3.0f : 1.0f;
    return far_index;
}

static float kernel_weight(const estimate_params *ep, float d2, float r2)
{
    if (ep->filter == ESTIMATE_CONE)
        return fmaxf(1.0f - sqrtf(d2 / r2), 0.0f); /* Jensen 1996 cone filter with k = 1 */
    return 1.0f;
}

/* A photon's power times the BSDF toward wo, f ΔΦ (b NULL: f = 1); with
 * `lambertian` (bsdf_lambertian_about) the power alone, or none below the
 * geometric surface, and the caller multiplies the sum by ρ/π. */
static inline vec3 reflected_power(const photon *p, int lambertian, const bsdf *b, vec3 wo, vec3 n)
{
    vec3 power = photon_power(p);
    if (lambertian)
        return v3_dot(photon_direction(p), b->ng) < 0.0f ? power : v3s(0.0f);
    if (!b)
        return power;
    vec3 wi = v3_neg(photon_direction(p)); /* toward where the photon came from */
    /* bsdf_eval includes |cos θi|; the estimate wants f alone. The search
     * kept only photons with cos θi = wi·n > 0. */
    return v3_mul(v3_scale(bsdf_eval(b, wo, wi, NULL), 1.0f / v3_dot(wi, n)), power);
}

/* Σ w_j f_j ΔΦ_j / (π r² · norm) over the photons found, with f_j the BSDF
 * toward wo (b NULL: f = 1, the irradiance). One loop for both estimates.
 * A Lambertian b (bsdf_lambertian_about) has the same f = ρ/π for every
 * photon the search keeps, except those below the geometric surface
 * (wi·ng ≤ 0, where a smooth shading normal leans past it), which it
 * reflects none of: the powers are summed and multiplied by ρ/π once. */
static vec3 estimate(const photon_map *m, const bsdf *b, vec3 wo, vec3 x, vec3 n, const estimate_params *ep,
                     kdtree_query *q)
{
    vec3 sum = v3s(0.0f);
    if (m->count == 0 || !(ep->max_radius > 0.0f) || (b && b->count == 0))
        return sum;
    vec3 rho;
    int lambertian = b && bsdf_lambertian_about(b, n, &rho);
    weighted_photon_sum w;
    uint32_t far_index = gather(m, x, n, ep, q, &w);
    for (uint32_t j = 0; j < q->found; j++) {
        if (j == far_index)
            continue;
        const photon *p = kdtree_result(m->photons, q, j);
        float weight = kernel_weight(ep, kdtree_result_dist2(q, j), w.r2);
        sum = v3_madd(sum, reflected_power(p, lambertian, b, wo, n), weight);
    }
    if (lambertian)
        sum = v3_mul(sum, v3_scale(rho, PHOS_INV_PI));
    float area = PHOS_PI * w.r2 * w.norm;
    if (ep->clip && !v3_is_zero(sum))
        area *= estimate_disc_coverage(ep->clip, x, n, sqrtf(w.r2), ep->filter);
    return v3_scale(sum, 1.0f / area);
}

/* The range search's running sum (photon_radiance_within). */
typedef struct range_sum {
    const bsdf *b;
    vec3 wo, n, sum;
    int lambertian;
} range_sum;

static void add_in_range(void *ctx, const photon *p, float d2)
{
    (void)d2; /* a box kernel */
    range_sum *rs = ctx;
    rs->sum = v3_add(rs->sum, reflected_power(p, rs->lambertian, rs->b, rs->wo, rs->n));
}

vec3 photon_radiance_within(const photon_map *m, const bsdf *b, vec3 wo, vec3 x, vec3 n, float radius,
                            uint16_t exclude_flags, const scene *clip)
{
    range_sum rs = {b, wo, n, v3s(0.0f), 0};
    if (m->count == 0 || !(radius > 0.0f) || b->count == 0)
        return rs.sum;
    vec3 rho;
    rs.lambertian = bsdf_lambertian_about(b, n, &rho);
    kdtree_filter f = {n, ESTIMATE_NORMAL_MIN_COS, exclude_flags, 1};
    float r2 = radius * radius;
    photon_map_range_surface(m, x, ESTIMATE_DISC_FLATTEN, &f, r2, add_in_range, &rs);
    if (rs.lambertian)
        rs.sum = v3_mul(rs.sum, v3_scale(rho, PHOS_INV_PI));
    float area = PHOS_PI * r2;
    if (clip && !v3_is_zero(rs.sum))
        area *= estimate_disc_coverage(clip, x, n, radius, ESTIMATE_BOX);
    return v3_scale(rs.sum, 1.0f / area);
}

vec3 photon_irradiance(const photon_map *m, vec3 x, vec3 n, const estimate_params *ep, kdtree_query *q)
{
    return estimate(m, NULL, v3s(0.0f), x, n, ep, q);
}

vec3 photon_radiance(const photon_map *m, const bsdf *b, vec3 wo, vec3 x, vec3 n, const estimate_params *ep,
                     kdtree_query *q)
{
    return estimate(m, b, wo, x, n, ep, q);
}

int radiance_photon_lookup_radius(const photon_map *m, vec3 x, vec3 n, float max_radius, kdtree_query *q, vec3 *L,
                                  float *radius)
{
    *L = v3s(0.0f);
    /* The nearest record facing about the way n does: the search ranks
     * only those, so the many records of a corner's other wall or of a thin
     * wall's far side cannot hide it. */
    kdtree_filter f = {n, RADIANCE_LOOKUP_MIN_COS, 0, 0};
    uint32_t capacity = q->k;
    q->k = 1;
    photon_map_knn_surface(m, x, ESTIMATE_DISC_FLATTEN, &f, max_radius * max_radius, q);
    q->k = capacity;
    if (q->found == 0)
        return 0;
    const photon *p = kdtree_result(m->photons, q, 0);
    *L = photon_power(p);
    if (radius)
        *radius = radiance_photon_radius(p);
    return 1;
}

int radiance_photon_lookup(const photon_map *m, vec3 x, vec3 n, float max_radius, kdtree_query *q, vec3 *L)
{
    return radiance_photon_lookup_radius(m, x, n, max_radius, q, L, NULL);
}

void radiance_photon_set_radius(photon *p, float radius)
{
    float code = radius > 0.0f ? ceilf(256.0f * log2f(radius)) + 32768.0f : 0.0f;
    uint32_t c = code <= 0.0f ? 0u : code >= 65535.0f ? 65535u : (uint32_t)code; /* NaN: 0 */
    p->theta = (uint8_t)(c & 0xffu);
    p->phi = (uint8_t)(c >> 8);
}

float radiance_photon_radius(const photon *p)
{
    uint32_t c = (uint32_t)p->theta | (uint32_t)p->phi << 8;
    return exp2f(((float)c - 32768.0f) / 256.0f);
}
