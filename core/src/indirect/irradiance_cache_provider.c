/*
 * irradiance_cache_provider.c — the indirect-diffuse provider that reads
 * the irradiance cache (irradiance_cache.h) and, where no record is close
 * enough, sends the wrapped provider's gather at that sample alone, without
 * inserting a record: the tiles only read the cache, so the image does not
 * depend on the order they run in (irradiance_cache_fill.c fills it).
 *
 * PATH with the cache is Ward's method (Ward et al. 1988), PHOTON with it
 * Jensen's (course notes 2002, "Photon Mapping": the irradiance cache over
 * final gathering).
 */
#include "indirect/hemisphere.h"
#include "indirect/irradiance_cache.h"

/* f_d toward wo (1/sr) for light arriving along w, or along the normal
 * where w grazes the surface. The cache holds irradiance E, and
 * L = f_d·E is exact for Lambertian closures whatever w is; for the
 * others (Principled's retro-reflection, a diffuse base under a coat) f_d
 * is read along the mean direction the light came from (as pbrt-v2's
 * irradiance cache does). */
static vec3 diffuse_brdf_along(const bsdf *diffuse, const surface *sf, vec3 wo, vec3 w)
{
    float cos_w = v3_dot(w, sf->ns);
    if (!(cos_w > 0.05f) || v3_dot(w, sf->ng) <= 0.0f) {
        w = sf->ns;
        cos_w = 1.0f;
    }
    return v3_scale(bsdf_eval(diffuse, wo, w, NULL), 1.0f / cos_w);
}

static gather_estimate cached_estimate(const indirect_query *q)
{
    const integrator_settings *is = q->is;
    irradiance_estimate e;
    q->scratch->cache_lookups++;
    if (irradiance_cache_lookup(is->cache, q->sf->p, q->sf->ns, &e)) {
        q->scratch->cache_hits++;
        vec3 f = diffuse_brdf_along(q->diffuse, q->sf, q->wo, e.w_mean);
        gather_estimate out = GATHER_ESTIMATE_ZERO;
        out.indirect = v3_mul(f, e.E);
        out.caustic = v3_mul(f, e.E_caustic);
        return out;
    }
    /* A miss: this sample's own gather, its rays leaving the emitters to
     * the light sample, as the records' rays do. */
    return hemisphere_gather(q, is->final_gather_rays, is->cache_inner->incoming, 0);
}

/* Its rays never count emitters: the light sample at the point does,
 * unweighted, whether the cache interpolates or the sample gathers. */
const indirect_diffuse_provider indirect_irradiance_cache = {"irradiance cache", 0, cached_estimate, NULL};
