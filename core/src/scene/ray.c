/*
 * ray.c — the integer-ulp ray-origin offset of Wächter & Binder (2019):
 * far from the origin the position moves by a fixed number of float ulps
 * along the normal, near it (where ulps are tiny) by a fixed distance.
 */
#include <stdint.h>
#include <string.h>

#include "scene/ray.h"

static inline uint32_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof(u));
    return u;
}
static inline float bits_float(uint32_t u)
{
    float f;
    memcpy(&f, &u, sizeof(f));
    return f;
}

static float offset_component(float p, float n)
{
    const float origin = 1.0f / 32.0f;
    const float float_scale = 1.0f / 65536.0f;
    const float int_scale = 256.0f;
    if (fabsf(p) < origin)
        return p + float_scale * n;
    int32_t of = (int32_t)(int_scale * n);
    int32_t bits = (int32_t)float_bits(p);
    bits += (p < 0.0f) ? -of : of;
    return bits_float((uint32_t)bits);
}

vec3 offset_ray_origin(vec3 p, vec3 n)
{
    return v3(offset_component(p.x, n.x), offset_component(p.y, n.y), offset_component(p.z, n.z));
}
