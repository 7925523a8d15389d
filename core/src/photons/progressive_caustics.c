/*
 * progressive_caustics.c — one caustic map per sample and the shrinking
 * fixed-radius estimate over it (progressive_caustics.h).
 */
#include "photons/progressive_caustics.h"

#include <math.h>
#include <string.h>

#include "photons/radiance_estimate.h"
#include "sampling/sampler.h"

void progressive_caustics_init(progressive_caustics *pc, const photon_trace_settings *ps, uint32_t photons,
                               float alpha, uint32_t k, float max_radius)
{
    memset(pc, 0, sizeof(*pc));
    photon_maps_init(&pc->maps[0]);
    photon_maps_init(&pc->maps[1]);
    pc->trace = *ps;
    pc->trace.global_photons = 0;
    pc->trace.caustic_photons = photons;
    pc->alpha = alpha;
    pc->k = k ? k : 1;
    pc->max_radius = max_radius;
    pc->sample = UINT32_MAX;
    pc->shrink = 1.0f;
}

void progressive_caustics_free(progressive_caustics *pc)
{
    photon_maps_free(&pc->maps[0]);
    photon_maps_free(&pc->maps[1]);
    if (pc->aim_built)
        projection_map_free(&pc->aim);
    pc->aim_built = 0;
    pc->current = pc->previous = NULL;
}

float progressive_caustics_shrink(uint32_t i, float alpha)
{
    double r2 = 1.0;
    for (uint32_t j = 1; j <= i; j++)
        r2 *= ((double)j + (double)alpha) / ((double)j + 1.0);
    return (float)sqrt(r2);
}

/* The map of sample i (i = UINT32_MAX: the pilot) into *m, built. Its
 * photon paths draw from a seed of their own per sample, so no two
 * samples' maps share a photon. */
static phos_status trace_sample_map(progressive_caustics *pc, const scene *s, uint32_t i, photon_maps *m,
                                    atomic_int *cancel)
{
    photon_maps_free(m);
    photon_maps_init(m);
    /* The aim and its pilots depend on the scene and the render's seed
     * alone: built with the first map, read by every one. */
    if (!pc->aim_built) {
        phos_status st = photon_caustic_aim_build(s, &pc->trace, &pc->aim, cancel);
        if (st != PHOS_OK)
            return st;
        pc->aim_built = 1;
    }
    photon_trace_settings ps = pc->trace;
    ps.seed = hash_combine(hash_combine(pc->trace.seed, 0x50504d31u /* "PPM1" */), i);
    phos_status st = photon_maps_trace_caustic(s, &ps, &pc->aim, m, cancel);
    if (st == PHOS_OK)
        st = photon_maps_build(m, ps.threads, cancel);
    if (st == PHOS_OK)
        pc->photons_traced += m->caustic.count;
    return st;
}

phos_status progressive_caustics_begin_sample(progressive_caustics *pc, const scene *s, uint32_t i,
                                              atomic_int *cancel)
{
    if (pc->sample == i && pc->current)
        return PHOS_OK;
    phos_status st;
    /* The map before: the last sample's, or traced afresh (the pilot
     * before sample 0; sample i − 1's map when the samples do not follow
     * on, so that each sample's estimate is the same whatever came before). */
    photon_maps *prev = &pc->maps[(i & 1u) ^ 1u], *cur = &pc->maps[i & 1u];
    if (!(pc->current && pc->sample != UINT32_MAX && pc->sample + 1u == i)) {
        st = trace_sample_map(pc, s, i ? i - 1u : UINT32_MAX, prev, cancel);
        if (st != PHOS_OK)
            return st;
    }
    st = trace_sample_map(pc, s, i, cur, cancel);
    if (st != PHOS_OK)
        return st;
    pc->clip = s;
    pc->previous = &prev->caustic;
    pc->current = &cur->caustic;
    pc->sample = i;
    pc->shrink = progressive_caustics_shrink(i, pc->alpha);
    return PHOS_OK;
}

vec3 progressive_caustic_radiance(const progressive_caustics *pc, const bsdf *b, vec3 wo, vec3 x, vec3 n,
                                  kdtree_query *q)
{
    if (!pc->current || pc->current->count == 0 || b->count == 0)
        return v3s(0.0f);
    /* R_0: the k-th nearest photon of the other map, by the same metric
     * and filter as the estimate (radiance_estimate.c). */
    kdtree_filter f = {n, ESTIMATE_NORMAL_MIN_COS, 0, 1};
    float max_r2 = pc->max_radius * pc->max_radius;
    uint32_t capacity = q->k;
    /* Where this sample's map holds no photon within the largest radius
     * the estimate can take, R_0 · shrink ≤ max_radius · shrink, the
     * estimate is zero whatever R_0 is: skip the search for R_0, which
     * explores the whole maximum radius where the other map is sparse.
     * The same filter and metric as the estimate's, so the answer is
     * exactly the one the estimate would give. */
    float reach = pc->max_radius * pc->shrink;
    q->k = 1;
    photon_map_knn_surface(pc->current, x, ESTIMATE_DISC_FLATTEN, &f, reach * reach, q);
    if (q->found == 0) {
        q->k = capacity;
        return v3s(0.0f);
    }
    q->k = pc->k < capacity ? pc->k : capacity;
    photon_map_knn_surface(pc->previous, x, ESTIMATE_DISC_FLATTEN, &f, max_r2, q);
    float r0 = q->found == q->k ? sqrtf(q->radius2) : pc->max_radius;
    q->k = capacity;
    return photon_radiance_within(pc->current, b, wo, x, n, r0 * pc->shrink, 0, pc->clip);
}
