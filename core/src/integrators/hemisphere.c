/*
 * hemisphere.c — the stratified cosine hemisphere (hemisphere.h).
 */
#include "integrators/hemisphere.h"

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

gather_estimate hemisphere_gather(const indirect_query *q, uint32_t rays, hemisphere_incoming incoming)
{
    const surface *sf = q->sf;
    uint32_t M, N;
    hemisphere_strata(rays, &M, &N);
    sampler g = sampler_split(q->smp, 0x9a7e0000u + q->vertex);
    frame f = frame_from_normal(sf->ns);
    vec3 o_up = offset_ray_origin(sf->p, sf->ng);
    gather_estimate sum = {v3s(0.0f), v3s(0.0f)};
    uint32_t index = 0;
    for (uint32_t j = 0; j < M; j++) {
        for (uint32_t k = 0; k < N; k++, index++) {
            float2 u = sampler_2d(&g, 2u * index);
            float sin2 = ((float)j + u.x) / (float)M;
            float sin_t = sqrtf(sin2), cos_t = safe_sqrtf(1.0f - sin2);
            float phi = 2.0f * PHOS_PI * ((float)k + u.y) / (float)N;
            vec3 wi = frame_to_world(&f, v3(cosf(phi) * sin_t, sinf(phi) * sin_t, cos_t));
            if (v3_dot(wi, sf->ng) <= 0.0f || cos_t <= 0.0f)
                continue;
            vec3 fcos = bsdf_eval(q->diffuse, q->wo, wi, NULL);
            if (v3_is_zero(fcos))
                continue;
            gather_estimate Li = incoming(q, o_up, wi, &g, index, (float)(M * N) * cos_t * PHOS_INV_PI);
            /* f·cos / (cos/π) = π·f */
            vec3 weight = v3_scale(fcos, PHOS_PI / cos_t);
            sum.indirect = v3_add(sum.indirect, v3_mul(weight, Li.indirect));
            sum.direct = v3_add(sum.direct, v3_mul(weight, Li.direct));
        }
    }
    float inv = 1.0f / (float)(M * N);
    return (gather_estimate){v3_scale(sum.indirect, inv), v3_scale(sum.direct, inv)};
}
