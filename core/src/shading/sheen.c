/*
 * sheen.c — the LTC microfiber sheen (see sheen.h).
 *
 * The LTC's inverse matrix in the frame (t, b, n), t the projection of wo
 * onto the surface, is M⁻¹ = [[A, 0, B], [0, A, 0], [0, 0, 1]]; with
 * v = M⁻¹ wi the lobe is D(wi) = max(v_z, 0)/π · A² / |v|⁴ (|M⁻¹| = A²,
 * Heitz et al. 2016 eq. 1), and it is sampled by transforming a cosine
 * sample by M. A, B and the albedo R come from a 32 × 32 table over
 * (μ, roughness), both on nodes j/31, read bilinearly as Cycles reads its
 * own table of the same fit, so the two interpolate alike.
 */
#include "shading/sheen.h"

#include "sampling/warp.h"
#include "shading/sheen_table.h"

#define SHEEN_MIN_ROUGHNESS 1e-3f

typedef struct ltc {
    float a, b, albedo;
} ltc;

static ltc sheen_ltc(float mu, float roughness)
{
    float x = clampf(mu, 0.0f, 1.0f) * (SHEEN_TABLE_SIZE - 1);
    float y = clampf(maxf(roughness, SHEEN_MIN_ROUGHNESS), 0.0f, 1.0f) * (SHEEN_TABLE_SIZE - 1);
    int i = (int)x, j = (int)y;
    if (i > SHEEN_TABLE_SIZE - 2)
        i = SHEEN_TABLE_SIZE - 2;
    if (j > SHEEN_TABLE_SIZE - 2)
        j = SHEEN_TABLE_SIZE - 2;
    float tx = x - (float)i, ty = y - (float)j;
    float v[3];
    for (int k = 0; k < 3; k++) {
        float r0 = sheen_ltc_table[j][i][k] + (sheen_ltc_table[j][i + 1][k] - sheen_ltc_table[j][i][k]) * tx;
        float r1 = sheen_ltc_table[j + 1][i][k] +
                   (sheen_ltc_table[j + 1][i + 1][k] - sheen_ltc_table[j + 1][i][k]) * tx;
        v[k] = r0 + (r1 - r0) * ty;
    }
    return (ltc){v[0], v[1], v[2]};
}

/* The lobe's tangent t: wo's direction in the surface plane (any at wo = n). */
static void sheen_frame(vec3 wo, vec3 *t, vec3 *b)
{
    float len = sqrtf(wo.x * wo.x + wo.y * wo.y);
    *t = len > 1e-7f ? v3(wo.x / len, wo.y / len, 0.0f) : v3(1.0f, 0.0f, 0.0f);
    *b = v3(-t->y, t->x, 0.0f);
}

float sheen_albedo(float mu, float roughness)
{
    ltc l = sheen_ltc(mu, roughness);
    return (fabsf(l.a) < 1e-5f || l.albedo < 1e-5f) ? 0.0f : l.albedo;
}

float sheen_eval(vec3 wo, vec3 wi, float roughness)
{
    ltc l = sheen_ltc(wo.z, roughness);
    if (fabsf(l.a) < 1e-5f || wi.z <= 0.0f)
        return 0.0f;
    vec3 t, b;
    sheen_frame(wo, &t, &b);
    float x = v3_dot(wi, t), y = v3_dot(wi, b), z = wi.z;
    float L = sqr(l.a * x + l.b * z) + sqr(l.a * y) + z * z;
    return PHOS_INV_PI * z * sqr(l.a / L);
}

vec3 sheen_sample(vec3 wo, float roughness, float2 u)
{
    ltc l = sheen_ltc(wo.z, roughness);
    vec3 d = warp_cosine_hemisphere(u);
    vec3 o = v3_normalize(v3(d.x - l.b * d.z, d.y, l.a * d.z));
    vec3 t, b;
    sheen_frame(wo, &t, &b);
    return v3_add(v3_add(v3_scale(t, o.x), v3_scale(b, o.y)), v3(0.0f, 0.0f, o.z));
}
