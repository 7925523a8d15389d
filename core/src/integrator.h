/*
 * integrator.h — what every integrator supplies to the shared tile loop in
 * render.c: the radiance carried by one camera ray (pbrt-v4's split between
 * ImageTileIntegrator and the per-sample step).
 */
#ifndef PHOS_INTEGRATOR_H
#define PHOS_INTEGRATOR_H

#include "camera.h"
#include "sampler.h"
#include "scene.h"

typedef struct integrator_settings {
    uint32_t max_bounces;          /* scattering events after the camera hit */
    int transparent_background;    /* camera rays do not see the world */
} integrator_settings;

typedef struct sample_result {
    vec3 radiance;                 /* W/(m²·sr) along the camera ray */
    float alpha;                   /* 1 where the ray hit something opaque */
} sample_result;

/* Unbiased path tracing with next-event estimation and MIS (Veach 1997). */
sample_result path_trace(const scene *s, const integrator_settings *is, camera_ray ray, const sampler *smp);

/* Offsets a ray origin off a surface along n, scale-independently (Wächter
 * & Binder 2019, "A Fast and Robust Method for Avoiding Self-Intersection",
 * Ray Tracing Gems ch. 6). n must point to the side the ray leaves to. */
vec3 offset_ray_origin(vec3 p, vec3 n);

#endif /* PHOS_INTEGRATOR_H */
