/*
 * valid_reflection.c — see valid_reflection.h and docs/algorithms.md §8.1.
 */
#include "shading/valid_reflection.h"

#include <math.h>

/* The normal x X + z Ng of z² = z2. */
static vec3 normal_of(vec3 x_axis, vec3 ng, float z2)
{
    return v3_add(v3_scale(x_axis, safe_sqrtf(1.0f - z2)), v3_scale(ng, safe_sqrtf(z2)));
}

/* Ng·R of the normal of z² = z2, in the X–Ng plane's coordinates. */
static float reflection_height(float ix, float iz, float z2)
{
    float nx = safe_sqrtf(1.0f - z2), nz = safe_sqrtf(z2);
    return 2.0f * (nx * ix + nz * iz) * nz - iz;
}

vec3 valid_reflection_normal(vec3 ng, vec3 i, vec3 n, uint32_t rule)
{
    if (rule == PHOS_NORMAL_CORRECTION_NONE)
        return n;
    if (rule == PHOS_NORMAL_CORRECTION_ONE_ROOT && n.x == ng.x && n.y == ng.y && n.z == ng.z)
        return n;
    vec3 r = v3_sub(v3_scale(n, 2.0f * v3_dot(n, i)), i);
    float iz = v3_dot(i, ng);
    float t = minf(0.9f * iz, 0.01f);
    if (v3_dot(ng, r) >= t)
        return n;
    vec3 across = v3_sub(n, v3_scale(ng, v3_dot(n, ng)));
    float across_len = v3_length(across);
    if (!(across_len > 0.0f))
        return ng; /* n along −ng: no plane to turn in */
    vec3 x_axis = v3_scale(across, 1.0f / across_len);
    float ix = v3_dot(i, x_axis);
    float a = ix * ix + iz * iz;
    if (!(a > 0.0f))
        return ng;
    float root = safe_sqrtf(ix * ix * (a - t * t));
    float mid = a + iz * t;
    float z2_plus = 0.5f * (mid + root) / a, z2_minus = 0.5f * (mid - root) / a;

    if (rule == PHOS_NORMAL_CORRECTION_ONE_ROOT) {
        /* Squaring admitted a root of 2 x Ix z = −(t + Iz(1 − 2z²)); the
         * true one makes Ix and the right-hand side agree in sign. */
        return normal_of(x_axis, ng, ix < 0.0f ? z2_plus : z2_minus);
    }
    int ok_plus = z2_plus > 1e-5f && z2_plus <= 1.0f + 1e-5f;
    int ok_minus = z2_minus > 1e-5f && z2_minus <= 1.0f + 1e-5f;
    float z2;
    if (ok_plus && ok_minus) {
        float h_plus = reflection_height(ix, iz, z2_plus), h_minus = reflection_height(ix, iz, z2_minus);
        int up_plus = h_plus >= 1e-5f, up_minus = h_minus >= 1e-5f;
        if (up_plus && up_minus)
            z2 = h_plus < h_minus ? z2_plus : z2_minus;
        else
            z2 = h_plus > h_minus ? z2_plus : z2_minus;
    } else if (ok_plus || ok_minus) {
        z2 = ok_plus ? z2_plus : z2_minus;
    } else {
        return ng;
    }
    return normal_of(x_axis, ng, z2);
}
