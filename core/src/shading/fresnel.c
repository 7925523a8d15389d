/*
 * fresnel.c — interface reflectances (see fresnel.h).
 */
#include "shading/fresnel.h"

/* F = ½ ((g−c)/(g+c))² (1 + ((c(g+c)−1)/(c(g−c)+1))²) with g = √(η² − 1 + c²)
 * (Walter 2007 eq. 22; Cycles' fresnel_dielectric_cos). */
float fresnel_dielectric(float cos_theta_i, float eta)
{
    float c = fabsf(cos_theta_i);
    float g2 = eta * eta - 1.0f + c * c;
    if (!(g2 > 0.0f))
        return 1.0f; /* total internal reflection */
    float g = sqrtf(g2);
    float a = (g - c) / (g + c);
    float b = (c * (g + c) - 1.0f) / (c * (g - c) + 1.0f);
    return clampf(0.5f * a * a * (1.0f + b * b), 0.0f, 1.0f);
}

/* With g = η cos θt: T_s = 4cg / (c + g)², T_p = 4η²cg / (η²c + g)²
 * (Hecht, Optics §4.6.2), T = (T_s + T_p) / 2. */
float fresnel_dielectric_transmittance(float cos_theta_i, float eta)
{
    float c = fabsf(cos_theta_i);
    float g2 = eta * eta - 1.0f + c * c;
    if (!(g2 > 0.0f))
        return 0.0f;
    float g = sqrtf(g2), e2c = eta * eta * c;
    float ts = 4.0f * c * g / sqr(c + g);
    float tp = 4.0f * e2c * g / sqr(e2c + g);
    return clampf(0.5f * (ts + tp), 0.0f, 1.0f);
}

float fresnel_f0_from_ior(float eta)
{
    return sqr((eta - 1.0f) / (eta + 1.0f));
}

float fresnel_blend_factor(float eta, float cos_theta)
{
    float F0 = fresnel_dielectric(1.0f, eta);
    float F = fresnel_dielectric(cos_theta, eta);
    return F0 < 1.0f - 1e-6f ? clampf((F - F0) / (1.0f - F0), 0.0f, 1.0f) : 1.0f;
}

vec3 fresnel_blend_f0(vec3 f0, float eta, float cos_theta)
{
    float t = fresnel_blend_factor(eta, cos_theta);
    return v3_add(v3_scale(f0, 1.0f - t), v3s(t));
}

/* Schlick at μ = 1/7 is F_s = f0 + (1 − f0)(6/7)⁵; requiring
 * F_s − b (1/7)(6/7)⁶ = F_s·tint gives b = 7 F_s (1 − tint) / (6/7)⁶. */
vec3 fresnel_f82_b(vec3 f0, vec3 tint)
{
    const float m5 = 0.46266437f; /* (6/7)⁵ */
    const float m6 = 0.39656946f; /* (6/7)⁶ */
    vec3 schlick = v3_add(f0, v3_scale(v3_sub(v3s(1.0f), f0), m5));
    return v3_scale(v3_mul(schlick, v3_sub(v3s(1.0f), tint)), 7.0f / m6);
}

vec3 fresnel_f82(vec3 f0, vec3 b, float cos_theta)
{
    float mu = clampf(cos_theta, 0.0f, 1.0f), m = 1.0f - mu;
    float m5 = sqr(sqr(m)) * m;
    vec3 f = v3_add(f0, v3_scale(v3_sub(v3s(1.0f), f0), m5));
    f = v3_sub(f, v3_scale(b, mu * m5 * m));
    return v3_min(v3_max(f, v3s(0.0f)), v3s(1.0f));
}

/* ------------------------------------------------------------ thin film */

/* The s- and p-polarised reflectances of a dielectric interface with their
 * phase shifts (0 or π, the sign of the amplitude) and the cosine of the
 * refracted direction; 0 under total internal reflection. Amplitudes
 * r_s = (c − η c_t)/(c + η c_t), r_p = (η c − c_t)/(η c + c_t). */
typedef struct polarized {
    float R[2];     /* s, p */
    float phase[2]; /* radians */
    float cos_t;
} polarized;

static int fresnel_polarized(float c, float eta, polarized *out)
{
    float sin2_t = (1.0f - c * c) / (eta * eta);
    if (sin2_t >= 1.0f)
        return 0;
    float ct = sqrtf(1.0f - sin2_t);
    float rs = (c - eta * ct) / (c + eta * ct);
    float rp = (eta * c - ct) / (eta * c + ct);
    out->R[0] = rs * rs;
    out->R[1] = rp * rp;
    out->phase[0] = rs < 0.0f ? PHOS_PI : 0.0f;
    out->phase[1] = rp < 0.0f ? PHOS_PI : 0.0f;
    out->cos_t = ct;
    return 1;
}

/* Belcour & Barla's Gaussian fit of the CIE 1931 colour-matching functions'
 * Fourier transform (Belcour & Barla 2017, supplemental material): the XYZ
 * sensitivity to an interference term of optical path difference opd (nm)
 * and phase shift, normalised so that a flat spectrum gives 1. */
static vec3 thin_film_sensitivity(float opd, float shift)
{
    const float phase = 2.0f * PHOS_PI * opd * 1e-9f; /* rad/m·m */
    const vec3 val = v3(5.4856e-13f, 4.4201e-13f, 5.2481e-13f);
    const vec3 pos = v3(1.6810e+06f, 1.7953e+06f, 2.2084e+06f);
    const vec3 var = v3(4.3278e+09f, 9.3046e+09f, 6.6121e+09f);
    vec3 xyz;
    xyz.x = val.x * sqrtf(2.0f * PHOS_PI * var.x) * cosf(pos.x * phase + shift) * expf(-phase * phase * var.x);
    xyz.y = val.y * sqrtf(2.0f * PHOS_PI * var.y) * cosf(pos.y * phase + shift) * expf(-phase * phase * var.y);
    xyz.z = val.z * sqrtf(2.0f * PHOS_PI * var.z) * cosf(pos.z * phase + shift) * expf(-phase * phase * var.z);
    xyz.x += 1.64408e-8f * cosf(2.2399e+06f * phase + shift) * expf(-4.5282e+09f * phase * phase);
    return v3_scale(xyz, 1.0f / 1.0685e-7f);
}

vec3 fresnel_thin_film(float cos_theta, float film_ior, float substrate_eta, float thickness_nm)
{
    polarized top, bottom;
    float c = clampf(fabsf(cos_theta), 0.0f, 1.0f);
    if (!fresnel_polarized(c, film_ior, &top))
        return v3s(1.0f);
    if (!fresnel_polarized(top.cos_t, substrate_eta / film_ior, &bottom))
        return v3s(1.0f);
    float opd = 2.0f * film_ior * thickness_nm * top.cos_t;
    /* Airy summation per polarisation (Belcour & Barla 2017, eq. 10): the
     * film's light reflected m times inside adds with amplitude C_m and the
     * phase of m round trips; m > 3 is below the fit's resolution. */
    vec3 xyz = v3s(0.0f);
    for (int p = 0; p < 2; p++) {
        float R12 = top.R[p], R23 = bottom.R[p];
        float T121 = 1.0f - R12, R123 = R12 * R23, r123 = sqrtf(R123);
        float Rs = T121 * T121 * R23 / maxf(1.0f - R123, 1e-7f);
        float phi = PHOS_PI + top.phase[p] + bottom.phase[p];
        vec3 sum = v3s(R12 + Rs);
        float Cm = Rs - T121;
        for (int m = 1; m <= 3; m++) {
            Cm *= r123;
            sum = v3_add(sum, v3_scale(thin_film_sensitivity((float)m * opd, (float)m * phi), 2.0f * Cm));
        }
        xyz = v3_add(xyz, v3_scale(sum, 0.5f));
    }
    /* The fit is of the bare colour-matching functions (illuminant E): scale
     * by the white point of linear Rec. 709 (D65, Y = 1) so that a flat
     * reflectance stays grey, then XYZ → linear Rec. 709 (IEC 61966-2-1). */
    xyz = v3_mul(xyz, v3(0.95047f, 1.0f, 1.08883f));
    vec3 rgb = v3(3.2404542f * xyz.x - 1.5371385f * xyz.y - 0.4985314f * xyz.z,
                  -0.9692660f * xyz.x + 1.8760108f * xyz.y + 0.0415560f * xyz.z,
                  0.0556434f * xyz.x - 0.2040259f * xyz.y + 1.0572252f * xyz.z);
    return v3_min(v3_max(rgb, v3s(0.0f)), v3s(1.0f));
}

vec3 fresnel_thin_film_blend(vec3 f0, float eta, float cos_theta, float film_ior, float thickness_nm)
{
    vec3 F = fresnel_thin_film(cos_theta, film_ior, eta, thickness_nm);
    float F0 = fresnel_f0_from_ior(eta);
    if (!(F0 > 1e-5f))
        return F;
    /* Keep the artist's f0 (Specular Tint, IOR Level) near normal incidence:
     * each channel is scaled toward f0/F0 as far as it lies from 1 toward F0. */
    float Fc[3] = {F.x, F.y, F.z}, f[3] = {f0.x, f0.y, f0.z};
    for (int k = 0; k < 3; k++) {
        if (Fc[k] >= 1.0f)
            continue;
        float s = clampf((Fc[k] - 1.0f) / (F0 - 1.0f), 0.0f, 1.0f);
        Fc[k] *= 1.0f + (f[k] / F0 - 1.0f) * s;
    }
    return v3(Fc[0], Fc[1], Fc[2]);
}
