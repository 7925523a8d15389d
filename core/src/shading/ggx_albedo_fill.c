/*
 * ggx_albedo_fill.c — computes the GGX albedo tables (ggx_albedo_tables.h)
 * by quadrature of the lobes themselves. The build runs it once, through
 * gen_ggx_albedo, and compiles its output into the library, so no render
 * pays for it (about a second for all tables).
 *
 * Each entry is a deterministic quadrature over the microfacets visible
 * from wo (Heitz 2018 sampling): for a sampled normal h the reflected (or
 * refracted) direction wi carries f·cos/pdf = G2/G1(wo) with the
 * height-correlated G2 = 1/(1 + Λ(wo) + Λ(wi)) (Heitz 2014 eq. 99), the
 * weight Cycles 4's lobes have, times the Fresnel share of the lobe.
 * Directions that leave on the wrong side of the surface carry nothing.
 */
#include "shading/ggx_albedo_tables.h"

#include "shading/fresnel.h"
#include "shading/microfacet.h"

#define N_MU_AVG 256     /* μ points of the hemispherical averages */
#define QUAD 24          /* QUAD × QUAD visible-normal samples per entry */
#define QUAD_WARP 3      /* u₁ = 1 − (1 − t)³: more samples in the lobe's tail */

static float grid(int i, int n) { return (float)i / (float)(n - 1); }
static float grid_mu(int i, int n) { return fmaxf(grid(i, n), 1e-4f); }
static float eta_of_z(float z) { return (1.0f + z * z) / (1.0f - z * z); }

enum lobe { LOBE_REFLECTION, LOBE_GLASS, LOBE_BLEND };

/* f·cos/pdf of one visible-normal sample h for wo (wo.z > 0), per lobe. */
static float sample_weight(enum lobe lobe, vec3 wo, vec3 h, float alpha, float eta)
{
    float cos_oh = v3_dot(wo, h);
    if (!(cos_oh > 0.0f))
        return 0.0f;
    float lambda_o = ggx_lambda(wo, alpha);
    vec3 wr = v3_sub(v3_scale(h, 2.0f * cos_oh), wo);
    float reflected = 0.0f;
    if (wr.z > 0.0f)
        reflected = (1.0f + lambda_o) / (1.0f + lambda_o + ggx_lambda(wr, alpha));
    if (lobe == LOBE_REFLECTION)
        return reflected;
    if (lobe == LOBE_BLEND)
        return wr.z > 0.0f ? fresnel_blend_factor(eta, cos_oh) : 0.0f;
    float F = fresnel_dielectric(cos_oh, eta);
    float value = F * reflected;
    /* Refraction through h (Snell with η = η_t/η_o): only if it goes below. */
    float sin2_t = (1.0f - cos_oh * cos_oh) / (eta * eta);
    if (sin2_t < 1.0f) {
        float cos_t = sqrtf(1.0f - sin2_t);
        vec3 wt = v3_add(v3_scale(wo, -1.0f / eta), v3_scale(h, cos_oh / eta - cos_t));
        if (wt.z < 0.0f)
            value += (1.0f - F) * (1.0f + lambda_o) / (1.0f + lambda_o + ggx_lambda(wt, alpha));
    }
    return value;
}

/* The midpoint rule on a QUAD × QUAD grid of the sampler's unit square,
 * with u₁ warped toward 1, where the visible normals of GGX's long tail
 * lie (on a plain grid their loss of energy was missed by up to 2 % at
 * roughness 0.37). */
static float integrate(enum lobe lobe, float mu, float roughness, float eta)
{
    float alpha = fmaxf(roughness * roughness, 1e-4f);
    vec3 wo = v3(safe_sqrtf(1.0f - mu * mu), 0.0f, mu);
    double sum = 0.0;
    for (int i = 0; i < QUAD; i++) {
        double t = ((double)i + 0.5) / QUAD, rest = 1.0 - t;
        double u1 = 1.0 - rest * rest * rest, jacobian = QUAD_WARP * rest * rest;
        for (int j = 0; j < QUAD; j++) {
            float2 u = {(float)u1, ((float)j + 0.5f) / QUAD};
            sum += jacobian * sample_weight(lobe, wo, ggx_sample_visible_normal(wo, alpha, u), alpha, eta);
        }
    }
    return (float)(sum / (QUAD * QUAD));
}

/* ∫ E(μ) 2μ dμ over one row of a table (N points over μ ∈ [0, 1]), E
 * interpolated linearly as the lookups do. */
static float row_average(const float *row, int n)
{
    double sum = 0.0;
    for (int k = 0; k < N_MU_AVG; k++) {
        double mu = ((double)k + 0.5) / N_MU_AVG, p = mu * (n - 1);
        int i = (int)p < n - 1 ? (int)p : n - 2;
        double e = row[i] + (row[i + 1] - row[i]) * (p - i);
        sum += 2.0 * mu * e;
    }
    return (float)(sum / N_MU_AVG);
}

void ggx_albedo_fill(ggx_albedo_tables *t)
{
    for (int r = 0; r < GGX_N_ROUGH; r++) {
        for (int m = 0; m < GGX_N_MU; m++)
            t->E[r][m] = integrate(LOBE_REFLECTION, grid_mu(m, GGX_N_MU), grid(r, GGX_N_ROUGH), 1.0f);
        t->E_avg[r] = row_average(t->E[r], GGX_N_MU);
    }
    for (int z = 0; z < GGX_N3; z++)
        for (int r = 0; r < GGX_N3; r++)
            for (int m = 0; m < GGX_N3; m++)
                t->blend[z][r][m] = integrate(LOBE_BLEND, grid_mu(m, GGX_N3), grid(r, GGX_N3),
                                              eta_of_z(grid(z, GGX_N3) * GGX_Z_MAX));
    for (int side = 0; side < 2; side++)
        for (int z = 0; z < GGX_N3; z++) {
            float eta = eta_of_z(grid(z, GGX_N3) * GGX_Z_MAX);
            if (side)
                eta = 1.0f / eta;
            for (int r = 0; r < GGX_N3; r++) {
                for (int m = 0; m < GGX_N3; m++)
                    t->glass[side][z][r][m] = integrate(LOBE_GLASS, grid_mu(m, GGX_N3), grid(r, GGX_N3), eta);
                t->glass_avg[side][z][r] = row_average(t->glass[side][z][r], GGX_N3);
            }
        }
}

