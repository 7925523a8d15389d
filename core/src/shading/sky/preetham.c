/*
 * preetham.c — Preetham, Shirley and Smits 1999, "A practical analytic
 * model for daylight": the Perez et al. (1993) luminance distribution with
 * coefficients linear in turbidity (the paper's Appendix A.2), and the
 * zenith's luminance and chromaticity (A.3); no sun disc
 * (docs/algorithms.md §11.1).
 */
#include "shading/color_space.h"
#include "shading/sky/sky.h"

/* The Perez function's A..E for Y, x and y, each a·T + b (Preetham et
 * al. 1999, A.2). */
static const float PEREZ[3][5][2] = {
    {{0.1787f, -1.4630f}, {-0.3554f, 0.4275f}, {-0.0227f, 5.3251f}, {0.1206f, -2.5771f}, {-0.0670f, 0.3703f}},
    {{-0.0193f, -0.2592f}, {-0.0665f, 0.0008f}, {-0.0004f, 0.2125f}, {-0.0641f, -0.8989f}, {-0.0033f, 0.0452f}},
    {{-0.0167f, -0.2608f}, {-0.0950f, 0.0092f}, {-0.0079f, 0.2102f}, {-0.0441f, -1.6537f}, {-0.0109f, 0.0529f}},
};

/* The zenith's chromaticity x and y: [T², T, 1] · M · [θ³, θ², θ, 1] (A.3). */
static const float ZENITH_CHROMA[2][3][4] = {
    {{0.00166f, -0.00375f, 0.00209f, 0.0f}, {-0.02903f, 0.06377f, -0.03202f, 0.00394f},
     {0.11693f, -0.21196f, 0.06052f, 0.25886f}},
    {{0.00275f, -0.00610f, 0.00317f, 0.0f}, {-0.04214f, 0.08970f, -0.04153f, 0.00516f},
     {0.15346f, -0.26756f, 0.06670f, 0.26688f}},
};

/* Perez et al.: (1 + A e^{B/cos θ})(1 + C e^{Dγ} + E cos²γ). */
static float perez(const float *c, float theta, float gamma)
{
    float cg = cosf(gamma);
    return (1.0f + c[0] * expf(c[1] / cosf(theta))) * (1.0f + c[2] * expf(c[3] * gamma) + c[4] * cg * cg);
}

phos_status sky_preetham_bake(const phos_sky_desc *d, float *data)
{
    vec3 sun = v3_normalize(v3_load(d->sun_direction));
    float theta = acosf(clampf(sun.z, -1.0f, 1.0f)), t = d->turbidity;
    data[SKY_ANALYTIC_THETA] = theta;
    data[SKY_ANALYTIC_PHI] = atan2f(sun.x, sun.y);
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < 5; i++)
            data[SKY_ANALYTIC_CONFIG + 5 * k + i] = PEREZ[k][i][0] * t + PEREZ[k][i][1];
    /* Zenith luminance in kcd/m² (A.3), scaled by 0.06 as Cycles scales
     * it (measured: Cycles' Preetham sky is 0.06 × the paper's value in
     * kcd/m² on 3.4, 4.5 and 5.3; tests/blender/test_sky.py). */
    float chi = (4.0f / 9.0f - t / 120.0f) * (PHOS_PI - 2.0f * theta);
    float zenith[3];
    zenith[0] = ((4.0453f * t - 4.9710f) * tanf(chi) - 0.2155f * t + 2.4192f) * 0.06f;
    float th[4] = {theta * theta * theta, theta * theta, theta, 1.0f}, tt[3] = {t * t, t, 1.0f};
    for (int k = 0; k < 2; k++) {
        float sum = 0.0f;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 4; j++)
                sum += tt[i] * ZENITH_CHROMA[k][i][j] * th[j];
        zenith[k + 1] = sum;
    }
    /* F(θ, γ) is normalised by its value at the zenith, where γ = θ_sun.
     * The paper's fit for Y makes that value 0 at turbidity 1.643 (its
     * first factor, 1 + A e^B, changes sign there): Cycles divides by it
     * all the same, and its sky blows up; Phos holds the divisor at 10⁻³
     * from 0, the same sky elsewhere. */
    for (int k = 0; k < 3; k++) {
        float f = perez(data + SKY_ANALYTIC_CONFIG + 5 * k, 0.0f, theta);
        if (fabsf(f) < 1e-3f)
            f = copysignf(1e-3f, f);
        data[SKY_ANALYTIC_ZENITH + k] = zenith[k] / f;
    }
    return PHOS_OK;
}

/* Y, x, y each the zenith's value times the Perez function of the view's
 * polar angle θ (held above the horizon) and its angle γ from the sun;
 * then CIE XYZ. */
vec3 sky_preetham_radiance(const float *data, vec3 d)
{
    float theta, gamma;
    sky_analytic_angles(data, d, &theta, &gamma);
    const float *c = data + SKY_ANALYTIC_CONFIG;
    float Y = data[SKY_ANALYTIC_ZENITH] * perez(c, theta, gamma);
    float x = data[SKY_ANALYTIC_ZENITH + 1] * perez(c + 5, theta, gamma);
    float y = data[SKY_ANALYTIC_ZENITH + 2] * perez(c + 10, theta, gamma);
    if (!(y != 0.0f))
        return v3s(0.0f);
    return xyz_to_rec709(v3(x * Y / y, Y, (1.0f - x - y) * Y / y));
}
