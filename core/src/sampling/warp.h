/*
 * warp.h — maps from the unit square to disks, spheres, cones and the
 * cosine-weighted hemisphere, shared by the camera, lights and BSDFs
 * (Shirley & Chiu 1997; pbrt-v4 sampling.h). Each notes its pdf.
 */
#ifndef PHOS_WARP_H
#define PHOS_WARP_H

#include "sampling/sampler.h"
#include "util/vec.h"

/* Concentric map to the unit disk (Shirley & Chiu 1997): area-preserving
 * and low-distortion; pdf 1/π per unit area. */
static inline float2 warp_disk_concentric(float2 u)
{
    float ox = 2.0f * u.x - 1.0f, oy = 2.0f * u.y - 1.0f;
    float2 r = {0.0f, 0.0f};
    if (ox == 0.0f && oy == 0.0f)
        return r;
    float rad, theta;
    if (fabsf(ox) > fabsf(oy)) {
        rad = ox;
        theta = (PHOS_PI / 4.0f) * (oy / ox);
    } else {
        rad = oy;
        theta = (PHOS_PI / 2.0f) - (PHOS_PI / 4.0f) * (ox / oy);
    }
    r.x = rad * cosf(theta);
    r.y = rad * sinf(theta);
    return r;
}

/* Cosine-weighted hemisphere about +z by Malley's method; pdf cos θ / π. */
static inline vec3 warp_cosine_hemisphere(float2 u)
{
    float2 d = warp_disk_concentric(u);
    return v3(d.x, d.y, safe_sqrtf(1.0f - d.x * d.x - d.y * d.y));
}

/* Cosine-weighted hemisphere about the unit normal n (Malley's method);
 * pdf max(cos θ, 0) / π about n. */
static inline vec3 warp_cosine_about(vec3 n, float2 u)
{
    frame f = frame_from_normal(n);
    return frame_to_world(&f, warp_cosine_hemisphere(u));
}

/* Uniform over the unit sphere; pdf 1/(4π). */
static inline vec3 warp_uniform_sphere(float2 u)
{
    float z = 1.0f - 2.0f * u.x;
    float r = safe_sqrtf(1.0f - z * z);
    float phi = 2.0f * PHOS_PI * u.y;
    return v3(r * cosf(phi), r * sinf(phi), z);
}

/* Solid angle (sr) of the cone of directions within acos(cos_half) of an
 * axis: 2π (1 − cos_half). */
static inline float cone_solid_angle(float cos_half)
{
    return 2.0f * PHOS_PI * (1.0f - cos_half);
}

/* Uniform in the cone of directions within acos(cos_max) of the unit axis;
 * pdf 1 / cone_solid_angle(cos_max). */
static inline vec3 warp_cone(vec3 axis, float cos_max, float2 u)
{
    float cos_t = 1.0f - u.x * (1.0f - cos_max);
    float sin_t = safe_sqrtf(1.0f - cos_t * cos_t);
    float phi = 2.0f * PHOS_PI * u.y;
    frame f = frame_from_normal(axis);
    return frame_to_world(&f, v3(cosf(phi) * sin_t, sinf(phi) * sin_t, cos_t));
}

#endif /* PHOS_WARP_H */
