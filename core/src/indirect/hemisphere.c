/*
 * hemisphere.c — the stratified cosine hemisphere (hemisphere.h).
 */
#include "indirect/hemisphere.h"

#include "scene/ray.h"

void hemisphere_strata(uint32_t rays, uint32_t *M, uint32_t *N)
{
    *M = (uint32_t)(sqrtf((float)rays / PHOS_PI) + 0.5f);
    if (*M < 1)
        *M = 1;
    *N = rays / *M;
    if (*N < 1)
        *N = 1;
}

int hemisphere_walk(const indirect_query *q, uint32_t M, uint32_t N, hemisphere_visit visit, void *ctx)
{
    const surface *sf = q->sf;
    sampler g = sampler_split(q->smp, HEMISPHERE_GATHER_STREAM + q->vertex);
    frame f = frame_from_normal(sf->ns);
    hemisphere_ray ray = {0, v3s(0.0f), 0.0f, offset_ray_origin(sf->p, sf->ng)};
    for (uint32_t j = 0; j < M; j++) {
        /* A row is at most a few hundred rays. */
        if (q->scratch->cancel && atomic_load_explicit(q->scratch->cancel, memory_order_relaxed))
            return 0;
        for (uint32_t k = 0; k < N; k++) {
            ray.index = j * N + k;
            vec3 local = hemisphere_stratum_direction(j, k, M, N, sampler_2d(&g, 2u * ray.index));
            ray.cos_t = local.z;
            ray.wi = frame_to_world(&f, local);
            if (v3_dot(ray.wi, sf->ng) <= 0.0f || ray.cos_t <= 0.0f)
                continue;
            visit(ctx, q, &ray, &g);
        }
    }
    return 1;
}

typedef struct gather_walk {
    hemisphere_incoming incoming;
    float strata; /* M·N */
    int count_emitters;
    gather_estimate sum;
} gather_walk;

static void gather_visit(void *ctx, const indirect_query *q, const hemisphere_ray *ray, const sampler *g)
{
    gather_walk *w = ctx;
    vec3 fcos = bsdf_eval(q->diffuse, q->wo, ray->wi, NULL);
    if (v3_is_zero(fcos))
        return;
    float ray_pdf = w->count_emitters ? w->strata * ray->cos_t * PHOS_INV_PI : 0.0f;
    q->scratch->gather_rays++;
    gather_estimate Li = w->incoming(q, ray->origin, ray->wi, g, ray->index, ray_pdf);
    /* f·cos / (cos/π) = π·f */
    vec3 weight = v3_scale(fcos, PHOS_PI / ray->cos_t);
    w->sum.indirect = v3_add(w->sum.indirect, v3_mul(weight, Li.indirect));
    w->sum.direct = v3_add(w->sum.direct, v3_mul(weight, Li.direct));
    w->sum.caustic = v3_add(w->sum.caustic, v3_mul(weight, Li.caustic));
}

gather_estimate hemisphere_gather(const indirect_query *q, uint32_t rays, hemisphere_incoming incoming,
                                  int count_emitters)
{
    uint32_t M, N;
    hemisphere_strata(rays, &M, &N);
    gather_walk w = {incoming, (float)(M * N), count_emitters, GATHER_ESTIMATE_ZERO};
    /* A cancelled walk's partial sum is discarded by the caller with the
     * sample or the record. */
    hemisphere_walk(q, M, N, gather_visit, &w);
    float inv = 1.0f / (float)(M * N);
    w.sum.indirect = v3_scale(w.sum.indirect, inv);
    w.sum.direct = v3_scale(w.sum.direct, inv);
    w.sum.caustic = v3_scale(w.sum.caustic, inv);
    return w.sum;
}
