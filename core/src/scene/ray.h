/*
 * ray.h — leaving a surface: where a ray that starts on a surface begins so
 * that it does not hit that surface again. Used by every stage that traces
 * rays from surfaces (camera paths, photon paths, gather rays).
 */
#ifndef PHOS_RAY_H
#define PHOS_RAY_H

#include <math.h>

#include "util/vec.h"

/* Offsets a ray origin off a surface along n, scale-independently (Wächter
 * & Binder 2019, "A Fast and Robust Method for Avoiding Self-Intersection",
 * Ray Tracing Gems ch. 6). n must point to the side the ray leaves to. */
vec3 offset_ray_origin(vec3 p, vec3 n);

/* The origin for leaving a surface with geometric normal ng along d: offset
 * to the side d points to. */
static inline vec3 ray_leave_surface(vec3 p, vec3 ng, vec3 d)
{
    return offset_ray_origin(p, v3_dot(d, ng) >= 0.0f ? ng : v3_neg(ng));
}

/* Parametric start just beyond a surface hit at t, along the same ray
 * (transparent pass-through keeps the ray and moves its start). */
static inline float t_after_hit(float t) { return fmaxf(t * (1.0f + 4e-6f), t + 1e-7f); }

#endif /* PHOS_RAY_H */
