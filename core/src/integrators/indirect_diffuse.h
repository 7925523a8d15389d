/*
 * indirect_diffuse.h — the seam through which a camera-path vertex gets
 * the indirect light its diffuse part reflects,
 *
 *   L_indirect(x → wo) = ∫ f_d(x, wi, wo) L_i,indirect(x ← wi) cos θi dωi,
 *
 * where L_i,indirect leaves out light that reaches x from an emitter
 * through specular surfaces only (the caustic map counts it) or directly
 * (next-event estimation counts it; Jensen 1996, course notes 2002
 * "Rendering Equation Solution"; docs/algorithms.md §5). A provider whose
 * rays also see emitters returns their light separately, as its share of
 * the direct term under MIS (gather_estimate, gathers_emitters).
 *
 * Providers:
 *  - final gathering on the photon maps (PHOTON; final_gather.c);
 *  - the global photon map read at x itself (PHOTON's fast estimate);
 *  - the path-traced hemisphere (path_hemisphere.c): stratified rays, each
 *    continued as an unbiased path, the reference the others converge to.
 * An irradiance cache (Ward et al. 1988) wraps one of them: it calls it at
 * its record positions and interpolates between them.
 */
#ifndef PHOS_INDIRECT_DIFFUSE_H
#define PHOS_INDIRECT_DIFFUSE_H

#include "integrators/integrator.h"
#include "lights/light.h"
#include "shading/material.h"

/* Where and how an indirect estimate is asked for. */
typedef struct indirect_query {
    const scene *s;
    const integrator_settings *is;
    const surface *sf;
    const light_context *light; /* the surface as a receiver of light samples (light.h) */
    const bsdf *diffuse;        /* f_d: the diffuse closures of the surface's BSDF */
    vec3 wo;
    const sampler *smp;         /* the camera sample's */
    uint32_t vertex;            /* the camera-path vertex, for independent sample streams */
    uint32_t depth;             /* scattering events on the camera path before it */
    integrator_scratch *scratch;
} indirect_query;

/* Reflected radiance W/(m²·sr) toward q->wo from the diffuse part: from
 * light that scattered before (indirect), and, for providers whose rays
 * count emitters, from the emitters those rays reach directly, already
 * MIS-weighted (direct: it adds to the Direct component). */
typedef struct gather_estimate {
    vec3 indirect, direct;
} gather_estimate;

static inline gather_estimate gather_estimate_add(gather_estimate a, gather_estimate b)
{
    return (gather_estimate){v3_add(a.indirect, b.indirect), v3_add(a.direct, b.direct)};
}

typedef struct indirect_diffuse_provider {
    const char *name;
    /* 1: the provider sends is->final_gather_rays cosine-distributed rays
     * (stratified, pdf cos θ/π each) that also count the emitters they
     * reach on their first segment, MIS-weighted against the light sample
     * of the diffuse part (Veach 1997 §9.2, multi-sample power heuristic):
     * direct_light weights that sample with the same rule. 0: emitters
     * reach the diffuse part only through the light sample. */
    int gathers_emitters;
    gather_estimate (*estimate)(const indirect_query *q);
} indirect_diffuse_provider;

extern const indirect_diffuse_provider indirect_final_gather;   /* final_gather.c */
extern const indirect_diffuse_provider indirect_photon_map;     /* final_gather.c */
extern const indirect_diffuse_provider indirect_path_hemisphere; /* path_hemisphere.c */


/* The provider of a photon view (enum phos_photon_view); path_hemisphere.c. */
const indirect_diffuse_provider *indirect_provider_for(uint32_t photon_view);

#endif /* PHOS_INDIRECT_DIFFUSE_H */
