/*
 * specular_chain.h — following a ray through specular (delta) and
 * transparent surfaces, and glossy ones that carry caustics (bsdf.h),
 * to the first surface that a photon-map estimate can
 * be read at: what a final-gather ray does where it lands (Jensen 2001,
 * §9.3.2), and what the photon debug passes and the photon-importance
 * pilot do from the camera. In transport/, below photons/, the integrators
 * and the indirect-diffuse providers that call it (docs/architecture.md).
 */
#ifndef PHOS_SPECULAR_CHAIN_H
#define PHOS_SPECULAR_CHAIN_H

#include "sampling/sampler.h"
#include "lights/light.h"
#include "shading/material.h"

enum specular_chain_stop {
    STOP_AT_NON_CAUSTIC = 0, /* the first surface with a closure that does not carry caustics
                              (gather rays): a non-delta one, or a glossy one at least
                              caustic_roughness rough (bsdf.h); where it also has closures that
                              carry caustics, the ray goes on through them with their share of
                              the sampling weight, and stops with the rest */
    STOP_AT_DIFFUSE = 1    /* the first surface with a diffuse closure; glossy lobes are followed too */
};

typedef struct specular_chain {
    enum specular_chain_stop stop;
    uint32_t max_steps;    /* surfaces the ray may pass before it gives up */
    int coherent;          /* camera rays (a hint to the ray-tracing kernel) */
    const sampler *smp;    /* the lobe choice at step k: dimensions dim + 3k (1D pick) and dim + 3k + 1 (2D); */
    uint32_t dim;          /* smp NULL: always the lobe and direction at u = 0.5. The caller owns
                              dimensions dim ... dim + 3·max_steps − 1 of smp. */
    float first_pdf;       /* > 0: collect the emitters the first segment reaches (lamps, distant
                              lights, emissive surfaces), MIS-weighted as a sample of this pdf
                              against a light sample at the ray's origin; 0: none */
    const light_context *origin; /* first_pdf > 0: the receiver the ray leaves (light.h) */
    float caustic_roughness; /* STOP_AT_NON_CAUSTIC: glossy closures smoother than this are followed */
} specular_chain;

typedef struct specular_chain_end {
    surface sf;
    bsdf b;                /* the whole BSDF there */
    bsdf read;             /* the part to estimate there: STOP_AT_NON_CAUSTIC, its closures that
                              do not carry caustics (the others were followed or not, by chance:
                              beta holds the weight of the choice); STOP_AT_DIFFUSE, the whole BSDF */
    vec3 beta;             /* throughput of the surfaces passed */
    vec3 wo;               /* toward the previous surface */
    vec3 emission;         /* first_pdf > 0: the first segment's emitters, weighted (set also
                              when the ray escapes) */
    float first_distance;  /* how far the ray went to the first surface it hit, INFINITY if none
                              (set also when it escapes) */
} specular_chain_end;

/* Follows the ray (o, d) over t in (tmin, tmax); returns 1 with the surface
 * it stops at, 0 if it escapes, is absorbed or passes max_steps surfaces. */
int specular_chain_follow(const scene *s, const specular_chain *c, vec3 o, vec3 d, float tmin, float tmax,
                          specular_chain_end *out);

#endif /* PHOS_SPECULAR_CHAIN_H */
