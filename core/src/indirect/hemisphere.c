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

gather_estimate hemisphere_gather(const indirect_query *q, uint32_t rays, hemisphere_incoming incoming,
                                  int count_emitters)
{
    const surface *sf = q->sf;
    uint32_t M, N;
    hemisphere_strata(rays, &M, &N);
    sampler g = sampler_split(q->smp, HEMISPHERE_GATHER_STREAM + q->vertex);
    frame f = frame_from_normal(sf->ns);
    vec3 o_up = offset_ray_origin(sf->p, sf->ng);
    gather_estimate sum = GATHER_ESTIMATE_ZERO;
    uint32_t index = 0;
    for (uint32_t j = 0; j < M; j++) {
        /* A row is at most a few hundred rays: a cancel stops the gather
         * within one (its caller discards the sample or the record). */
        if (q->scratch->cancel && atomic_load_explicit(q->scratch->cancel, memory_order_relaxed))
            break;
        for (uint32_t k = 0; k < N; k++, index++) {
            vec3 local = hemisphere_stratum_direction(j, k, M, N, sampler_2d(&g, 2u * index));
            float cos_t = local.z;
            vec3 wi = frame_to_world(&f, local);
            if (v3_dot(wi, sf->ng) <= 0.0f || cos_t <= 0.0f)
                continue;
            vec3 fcos = bsdf_eval(q->diffuse, q->wo, wi, NULL);
            if (v3_is_zero(fcos))
                continue;
            float ray_pdf = count_emitters ? (float)(M * N) * cos_t * PHOS_INV_PI : 0.0f;
            q->scratch->gather_rays++;
            gather_estimate Li = incoming(q, o_up, wi, &g, index, ray_pdf);
            /* f·cos / (cos/π) = π·f */
            vec3 weight = v3_scale(fcos, PHOS_PI / cos_t);
            sum.indirect = v3_add(sum.indirect, v3_mul(weight, Li.indirect));
            sum.direct = v3_add(sum.direct, v3_mul(weight, Li.direct));
            sum.caustic = v3_add(sum.caustic, v3_mul(weight, Li.caustic));
        }
    }
    float inv = 1.0f / (float)(M * N);
    sum.indirect = v3_scale(sum.indirect, inv);
    sum.direct = v3_scale(sum.direct, inv);
    sum.caustic = v3_scale(sum.caustic, inv);
    return sum;
}
