/*
 * microfacet.c — isotropic GGX: D, Smith Λ/G1/G, visible-normal sampling
 * and the half-vector Jacobians. See microfacet.h for the references.
 *
 * All directions are unit vectors in the local shading frame (z = normal).
 * Angles never appear explicitly: tan²θ = (x² + y²) / z² on unit vectors.
 */
#include "shading/microfacet.h"

/* D(h) = α² / (π (α² cos²θh + sin²θh)²) — Walter 2007 eq. 33 rewritten
 * without tan so that it stays finite at θh = 0 for tiny α. Units 1/sr. */
float ggx_D(vec3 h, float alpha)
{
    if (h.z <= 0.0f)
        return 0.0f;
    float a2 = alpha * alpha;
    float sin2 = h.x * h.x + h.y * h.y;
    float denom = sin2 + a2 * h.z * h.z;
    if (denom <= 0.0f)
        return 0.0f;
    return a2 / (PHOS_PI * denom * denom);
}

/* Λ(w) = (√(1 + α² tan²θ) − 1) / 2 (Heitz 2014 eq. 72), written as
 * α²tan²θ / (2 (√(1 + α² tan²θ) + 1)) to avoid cancellation near θ = 0. */
float ggx_lambda(vec3 w, float alpha)
{
    float z2 = fmaxf(w.z * w.z, 1e-20f);
    float a2_tan2 = alpha * alpha * (w.x * w.x + w.y * w.y) / z2;
    return 0.5f * a2_tan2 / (sqrtf(1.0f + a2_tan2) + 1.0f);
}

/* G1 = 1 / (1 + Λ) = 2 / (1 + √(1 + α² tan²θ)) (Walter 2007 eq. 34). */
float ggx_G1(vec3 w, float alpha)
{
    return 1.0f / (1.0f + ggx_lambda(w, alpha));
}

/* G = G1(wo) G1(wi), masking and shadowing treated as uncorrelated
 * (Heitz 2014 eq. 98; Walter 2007 eq. 23). */
float ggx_G_separable(vec3 wo, vec3 wi, float alpha)
{
    return ggx_G1(wo, alpha) * ggx_G1(wi, alpha);
}

/* G = 1 / (1 + Λ(wo) + Λ(wi)), height-correlated (Heitz 2014 eq. 99). */
float ggx_G_correlated(vec3 wo, vec3 wi, float alpha)
{
    return 1.0f / (1.0f + ggx_lambda(wo, alpha) + ggx_lambda(wi, alpha));
}

/* Heitz 2018, listing 1: stretch the view to the α = 1 configuration,
 * sample the projected area of the visible hemisphere (a disk whose lower
 * half is squashed by (1 + cosθ)/2), lift onto the hemisphere and unstretch
 * the resulting normal. Exact for GGX with the Smith G1 above. */
vec3 ggx_sample_visible_normal(vec3 wo, float alpha, float2 u)
{
    /* Section 3.2: the view in the hemisphere configuration. */
    vec3 vh = v3_normalize(v3(alpha * wo.x, alpha * wo.y, wo.z));

    /* Section 4.1: orthonormal basis around vh (any basis at normal incidence). */
    float len2 = vh.x * vh.x + vh.y * vh.y;
    vec3 t1 = len2 > 1e-14f ? v3_scale(v3(-vh.y, vh.x, 0.0f), 1.0f / sqrtf(len2))
                            : v3(1.0f, 0.0f, 0.0f);
    vec3 t2 = v3_cross(vh, t1);

    /* Section 4.2: uniform point on the unit disk, lower half squashed. */
    float r = sqrtf(u.x);
    float phi = 2.0f * PHOS_PI * u.y;
    float p1 = r * cosf(phi);
    float p2 = r * sinf(phi);
    float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * safe_sqrtf(1.0f - p1 * p1) + s * p2;

    /* Section 4.3: reproject onto the hemisphere. */
    float pz = safe_sqrtf(1.0f - p1 * p1 - p2 * p2);
    vec3 nh = v3_add(v3_add(v3_scale(t1, p1), v3_scale(t2, p2)), v3_scale(vh, pz));

    /* Section 3.4: back to the ellipsoid configuration. */
    return v3_normalize(v3(alpha * nh.x, alpha * nh.y, fmaxf(0.0f, nh.z)));
}

/* D_wo(h) = G1(wo) max(0, wo·h) D(h) / cos θo (Heitz 2014 eq. 16). */
float ggx_visible_normal_pdf(vec3 wo, vec3 h, float alpha)
{
    float cos_oh = v3_dot(wo, h);
    if (wo.z <= 0.0f || cos_oh <= 0.0f)
        return 0.0f;
    return ggx_G1(wo, alpha) * cos_oh * ggx_D(h, alpha) / wo.z;
}

int microfacet_reflect_half_vector(vec3 wo, vec3 wi, vec3 *h)
{
    vec3 s = v3_add(wo, wi);
    float len2 = v3_length2(s);
    if (!(len2 > 1e-12f))
        return 0;
    *h = v3_scale(s, 1.0f / sqrtf(len2));
    return 1;
}

/* Walter 2007 eq. 16: h ∝ −(η_o wo + η_i wi); only its line matters, so
 * take wo + η wi and orient it to the macro normal's side. The pair is a
 * refraction through h only if wo and wi lie on opposite sides of h. */
int microfacet_refract_half_vector(vec3 wo, vec3 wi, float eta, vec3 *h)
{
    vec3 s = v3_madd(wo, wi, eta);
    float len2 = v3_length2(s);
    if (!(len2 > 1e-12f))
        return 0;
    vec3 n = v3_scale(s, 1.0f / sqrtf(len2));
    if (n.z < 0.0f)
        n = v3_neg(n);
    if (!(n.z > 0.0f) || v3_dot(wo, n) <= 0.0f || v3_dot(wi, n) >= 0.0f)
        return 0;
    *h = n;
    return 1;
}

/* Walter 2007 eq. 14: ∂ω_h/∂ω_i = 1 / (4 |wi·h|), and wi·h = wo·h. */
float microfacet_reflect_jacobian(vec3 wo, vec3 h)
{
    float c = fabsf(v3_dot(wo, h));
    return c > 0.0f ? 0.25f / c : 0.0f;
}

/* Walter 2007 eq. 17: ∂ω_h/∂ω_i = η_i² |wi·h| / (η_o wo·h + η_i wi·h)²,
 * divided through by η_o² so that only the ratio η appears. */
float microfacet_refract_jacobian(vec3 wo, vec3 wi, vec3 h, float eta)
{
    float cos_ih = v3_dot(wi, h);
    float denom = v3_dot(wo, h) + eta * cos_ih;
    denom *= denom;
    if (!(denom > 0.0f))
        return 0.0f;
    return eta * eta * fabsf(cos_ih) / denom;
}
