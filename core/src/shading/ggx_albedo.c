/*
 * ggx_albedo.c — lookups in the GGX albedo tables (ggx_albedo_tables.h),
 * computed when the library is built, and the Multiscatter GGX factor.
 */
#include "shading/ggx_albedo.h"

#include "shading/ggx_albedo_tables.h"

/* Cell index i0 and fraction t of x on a grid of n points over [0, hi]. */
static void locate(float x, float hi, int n, int *i0, float *t)
{
    float p = clampf(x / hi, 0.0f, 1.0f) * (float)(n - 1);
    int i = (int)p;
    if (i > n - 2)
        i = n - 2;
    *i0 = i;
    *t = p - (float)i;
}

/* Bilinear lookup in rows × n_inner values, x along a row over [0, x_hi],
 * y across rows over [0, y_hi]. */
static float lerp2(const float *t, int rows, int n_inner, float x, float y, float x_hi, float y_hi)
{
    int i, j;
    float ti, tj;
    locate(x, x_hi, n_inner, &i, &ti);
    locate(y, y_hi, rows, &j, &tj);
    const float *r0 = t + j * n_inner, *r1 = r0 + n_inner;
    float a = r0[i] + (r0[i + 1] - r0[i]) * ti;
    float b = r1[i] + (r1[i + 1] - r1[i]) * ti;
    return a + (b - a) * tj;
}

/* Trilinear lookup in a [z][roughness][μ] table. */
static float lerp3(const float (*t)[GGX_N3][GGX_N3], float mu, float roughness, float z)
{
    int k;
    float tk;
    locate(z, GGX_Z_MAX, GGX_N3, &k, &tk);
    float a = lerp2(&t[k][0][0], GGX_N3, GGX_N3, mu, roughness, 1.0f, 1.0f);
    float b = lerp2(&t[k + 1][0][0], GGX_N3, GGX_N3, mu, roughness, 1.0f, 1.0f);
    return a + (b - a) * tk;
}

static float z_of_eta(float eta)
{
    return safe_sqrtf((eta - 1.0f) / (eta + 1.0f));
}

float ggx_albedo(float mu, float roughness)
{
    return lerp2(&ggx_albedo_data.E[0][0], GGX_N_ROUGH, GGX_N_MU, mu, roughness, 1.0f, 1.0f);
}

float ggx_albedo_average(float roughness)
{
    int i;
    float t;
    locate(roughness, 1.0f, GGX_N_ROUGH, &i, &t);
    return ggx_albedo_data.E_avg[i] + (ggx_albedo_data.E_avg[i + 1] - ggx_albedo_data.E_avg[i]) * t;
}

float ggx_glass_albedo(float mu, float roughness, float eta)
{
    int inside = eta < 1.0f;
    return lerp3(ggx_albedo_data.glass[inside], mu, roughness, z_of_eta(inside ? 1.0f / eta : eta));
}

float ggx_glass_albedo_average(float roughness, float eta)
{
    int inside = eta < 1.0f;
    float z = z_of_eta(inside ? 1.0f / eta : eta);
    return lerp2(&ggx_albedo_data.glass_avg[inside][0][0], GGX_N3, GGX_N3, roughness, z, 1.0f, GGX_Z_MAX);
}

float ggx_fresnel_blend_average(float mu, float roughness, float eta)
{
    return lerp3(ggx_albedo_data.blend, mu, roughness, z_of_eta(maxf(eta, 1.0f)));
}

vec3 ggx_multiscatter_scale(float E, float E_avg, vec3 F_ss)
{
    if (!(E > 0.0f))
        return v3s(1.0f);
    float missing = (1.0f - E) / E;
    vec3 F_ms = v3_div(v3_scale(F_ss, E_avg), v3_sub(v3s(1.0f), v3_scale(F_ss, 1.0f - E_avg)));
    return v3_add(v3s(1.0f), v3_scale(F_ms, missing));
}
