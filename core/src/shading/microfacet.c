/*
 * microfacet.c — GGX, isotropic and anisotropic, and Beckmann: D, Smith Λ/G1/G,
 * visible-normal sampling and the half-vector Jacobians. See microfacet.h
 * for the references. The anisotropic forms (roughness αx along the
 * frame's x axis, αy along y) reduce to the isotropic ones at αx = αy; the
 * isotropic functions call them so.
 *
 * All directions are unit vectors in the local shading frame (z = normal).
 * Angles never appear explicitly: tan²θ = (x² + y²) / z² on unit vectors.
 */
#include "shading/microfacet.h"

/* D(h) = 1 / (π αx αy (hx²/αx² + hy²/αy² + hz²)²) (Heitz 2014 eq. 85 on
 * unit vectors), written as αx³αy³ / (π (αy² hx² + αx² hy² + αx²αy² hz²)²)
 * so that it stays finite for tiny α; at αx = αy = α it is Walter 2007
 * eq. 33, α² / (π (sin²θh + α² cos²θh)²). Units 1/sr. */
float ggx_D_aniso(vec3 h, float ax, float ay)
{
    if (h.z <= 0.0f)
        return 0.0f;
    float axy = ax * ay;
    float denom = ay * ay * h.x * h.x + ax * ax * h.y * h.y + axy * axy * h.z * h.z;
    if (denom <= 0.0f)
        return 0.0f;
    return axy * axy * axy / (PHOS_PI * denom * denom);
}

float ggx_D(vec3 h, float alpha)
{
    return ggx_D_aniso(h, alpha, alpha);
}

/* Λ(w) = (√(1 + a²) − 1) / 2 with a² = (αx² wx² + αy² wy²) / wz², the
 * roughness projected on w's azimuth times tan²θ (Heitz 2014 eq. 72, 86),
 * written as a² / (2 (√(1 + a²) + 1)) to avoid cancellation near θ = 0. */
float ggx_lambda_aniso(vec3 w, float ax, float ay)
{
    float z2 = maxf(w.z * w.z, 1e-20f);
    float a2_tan2 = (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / z2;
    return 0.5f * a2_tan2 / (sqrtf(1.0f + a2_tan2) + 1.0f);
}

float ggx_lambda(vec3 w, float alpha)
{
    return ggx_lambda_aniso(w, alpha, alpha);
}

/* G1 = 1 / (1 + Λ) = 2 / (1 + √(1 + α² tan²θ)) (Walter 2007 eq. 34). */
float ggx_G1(vec3 w, float alpha)
{
    return 1.0f / (1.0f + ggx_lambda(w, alpha));
}

/* G = G1(wo) G1(wi), masking and shadowing treated as uncorrelated
 * (Heitz 2014 eq. 98; Walter 2007 eq. 23). */
float ggx_G_separable_aniso(vec3 wo, vec3 wi, float ax, float ay)
{
    return 1.0f / ((1.0f + ggx_lambda_aniso(wo, ax, ay)) * (1.0f + ggx_lambda_aniso(wi, ax, ay)));
}

float ggx_G_separable(vec3 wo, vec3 wi, float alpha)
{
    return ggx_G_separable_aniso(wo, wi, alpha, alpha);
}

/* G = 1 / (1 + Λ(wo) + Λ(wi)), height-correlated (Heitz 2014 eq. 99). */
float ggx_G_correlated_aniso(vec3 wo, vec3 wi, float ax, float ay)
{
    return 1.0f / (1.0f + ggx_lambda_aniso(wo, ax, ay) + ggx_lambda_aniso(wi, ax, ay));
}

float ggx_G_correlated(vec3 wo, vec3 wi, float alpha)
{
    return ggx_G_correlated_aniso(wo, wi, alpha, alpha);
}

/* Heitz 2018, listing 1: stretch the view to the α = 1 configuration,
 * sample the projected area of the visible hemisphere (a disk whose lower
 * half is squashed by (1 + cosθ)/2), lift onto the hemisphere and unstretch
 * the resulting normal. Exact for GGX with the Smith G1 above; the
 * stretch by (αx, αy) makes it exact for anisotropic GGX too. */
vec3 ggx_sample_visible_normal_aniso(vec3 wo, float ax, float ay, float2 u)
{
    /* Section 3.2: the view in the hemisphere configuration. */
    vec3 vh = v3_normalize(v3(ax * wo.x, ay * wo.y, wo.z));

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
    return v3_normalize(v3(ax * nh.x, ay * nh.y, maxf(0.0f, nh.z)));
}

vec3 ggx_sample_visible_normal(vec3 wo, float alpha, float2 u)
{
    return ggx_sample_visible_normal_aniso(wo, alpha, alpha, u);
}

/* D_wo(h) = G1(wo) max(0, wo·h) D(h) / cos θo (Heitz 2014 eq. 16). */
float ggx_visible_normal_pdf_aniso(vec3 wo, vec3 h, float ax, float ay)
{
    float cos_oh = v3_dot(wo, h);
    if (wo.z <= 0.0f || cos_oh <= 0.0f)
        return 0.0f;
    return cos_oh * ggx_D_aniso(h, ax, ay) / ((1.0f + ggx_lambda_aniso(wo, ax, ay)) * wo.z);
}

float ggx_visible_normal_pdf(vec3 wo, vec3 h, float alpha)
{
    return ggx_visible_normal_pdf_aniso(wo, h, alpha, alpha);
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

/* ------------------------------------------------------------ Beckmann */

#define INV_SQRT_PI 0.56418958354775628695f /* 1/√π */

/* D(h) = exp(−(hx²/αx² + hy²/αy²)/hz²) / (π αx αy hz⁴) (Walter 2007 eq. 25,
 * anisotropic as Heitz 2014 eq. 85). Units 1/sr. */
float beckmann_D_aniso(vec3 h, float ax, float ay)
{
    if (h.z <= 0.0f)
        return 0.0f;
    float z2 = h.z * h.z;
    float e = (h.x * h.x / (ax * ax) + h.y * h.y / (ay * ay)) / z2;
    if (!(e < 80.0f)) /* exp(−80) is below any float that matters */
        return 0.0f;
    return expf(-e) / (PHOS_PI * ax * ay * z2 * z2);
}

/* Λ(w) by Walter 2007's rational approximation (eq. 27, as Cycles 3.x and
 * 4.x use it): with a = 1/(α tanθ), α projected on w's azimuth,
 * Λ = (1 − 1.259a + 0.396a²)/(3.535a + 2.181a²) for a < 1.6, else 0. */
float beckmann_lambda_aniso(vec3 w, float ax, float ay)
{
    float z2 = maxf(w.z * w.z, 1e-20f);
    float a2_tan2 = (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / z2;
    if (a2_tan2 < 0.39f) /* a ≥ 1.6 */
        return 0.0f;
    float a = 1.0f / sqrtf(a2_tan2);
    return (1.0f - 1.259f * a + 0.396f * a * a) / (3.535f * a + 2.181f * a * a);
}

/* Λ(w) exact for Beckmann (Heitz 2014; anisotropic as GGX's): with
 * a = 1/(α tanθ), α projected on w's azimuth,
 * Λ = (erf(a) − 1)/2 + exp(−a²)/(2a√π). It is what the visible-normal
 * sampler below draws from; the BSDF's value keeps Walter's approximation
 * above, as Cycles. Below 10⁻¹⁵ from a = 6 on, where it is taken as 0. */
float beckmann_lambda_exact_aniso(vec3 w, float ax, float ay)
{
    float z2 = maxf(w.z * w.z, 1e-20f);
    float a2_tan2 = (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / z2;
    if (!(a2_tan2 > 1.0f / 36.0f)) /* a > 6 */
        return 0.0f;
    float a = 1.0f / sqrtf(a2_tan2);
    return 0.5f * (INV_SQRT_PI * expf(-a * a) / a - erfcf(a));
}

/* erf⁻¹ in single precision: Giles 2010, "Approximating the erfinv
 * function" (GPU Computing Gems, Jade Edition), his single-precision
 * polynomials in w = −ln(1 − x²), central (w < 5) and tail. Relative
 * error below 10⁻⁶ (erff(erf⁻¹(y)) within 1.2·10⁻⁷ of y); x is clamped to
 * ±(1 − 2⁻²⁴), where the result is ±3.83. */
float erfinvf_approx(float x)
{
    x = clampf(x, -0.99999994f, 0.99999994f);
    float w = -logf((1.0f - x) * (1.0f + x)), p;
    if (w < 5.0f) {
        w -= 2.5f;
        p = 2.81022636e-08f;
        p = 3.43273939e-07f + p * w;
        p = -3.5233877e-06f + p * w;
        p = -4.39150654e-06f + p * w;
        p = 0.00021858087f + p * w;
        p = -0.00125372503f + p * w;
        p = -0.00417768164f + p * w;
        p = 0.246640727f + p * w;
        p = 1.50140941f + p * w;
    } else {
        w = sqrtf(w) - 3.0f;
        p = -0.000200214257f;
        p = 0.000100950558f + p * w;
        p = 0.00134934322f + p * w;
        p = -0.00367342844f + p * w;
        p = 0.00573950773f + p * w;
        p = -0.0076224613f + p * w;
        p = 0.00943887047f + p * w;
        p = 1.00167406f + p * w;
        p = 2.83297682f + p * w;
    }
    return p * x;
}

/* The slope x along the view's azimuth of a visible microfacet of an
 * α = 1 Beckmann surface seen at θ (cos_t > 0, sin_t ≥ 0), from u in
 * [0, 1). The visible slopes have the density
 * G1 (1 − x tanθ) exp(−x² − y²)/π for x < a = cotθ (D_wo in slope space,
 * Heitz & d'Eon 2014), so x has the cumulative distribution
 * C(x) = G1 [erfc(−x)/2 + tanθ exp(−x²)/(2√π)], with C(a) = G1 (1 + Λ) = 1:
 * a Gaussian part of mass erfc(−a)/2 and a tilt part of mass
 * tanθ exp(−a²)/(2√π).
 * C(x) = u is solved by Newton steps kept inside a shrinking bracket
 * (bisection when a step leaves it), as Jakob 2014 does, until a step is
 * below 10⁻⁴ or C is met to float's rounding: |C(x) − u| < 6·10⁻⁷, 2
 * evaluations of C on average. The start blends the two parts' own
 * quantiles by their masses — the Gaussian's below a, erf⁻¹(u erfc(−a) − 1),
 * and the tilt's at a → 0, −√(−ln u) — shifted so that its mean is the
 * distribution's, E[x] = −tanθ erfc(−a) / (4 (1 + Λ)) (for small θ the
 * tilt 1 − x tanθ ≈ exp(−x tanθ) moves the Gaussian by −tanθ/2). Near
 * normal incidence (cos θ > 0.9999) the tilt's mass is 0 in float and the
 * start is the Gaussian slope, erf⁻¹(2u − 1) − tanθ/2; the steps still
 * correct it, so that the density is D_wo's at every θ. Slopes below −6
 * (u within 10⁻¹⁵ of 0) are clamped. */
static float beckmann_visible_slope_x(float cos_t, float sin_t, float u)
{
    float tan_t = sin_t / cos_t, lo = -6.0f, hi = 6.0f, total = 1.0f, x;
    if (cos_t > 0.9999f) {
        x = erfinvf_approx(2.0f * u - 1.0f) - 0.5f * tan_t;
    } else {
        float a = cos_t / sin_t;
        float gauss = 0.5f * erfcf(-a), tilt = 0.5f * INV_SQRT_PI * tan_t * expf(-a * a);
        float x_gauss = erfinvf_approx(2.0f * u * gauss - 1.0f); /* mean −tilt a/gauss */
        float x_tilt = -sqrtf(-logf(maxf(u, 1e-30f)));            /* mean −√π/2 */
        total = gauss + tilt;                                      /* 1 + Λ */
        hi = minf(a, hi);
        float shift = tilt * (a + 0.5f / INV_SQRT_PI) - 0.5f * tan_t * gauss; /* to E[x] */
        x = (gauss * x_gauss + tilt * x_tilt + shift) / total;
    }
    float target = u * total;
    x = clampf(x, lo, hi);
    for (int i = 0; i < 16; i++) {
        float e = INV_SQRT_PI * expf(-x * x);
        float f = 0.5f * erfcf(-x) + 0.5f * tan_t * e - target; /* C(x)/G1 − u/G1 */
        if (fabsf(f) <= 4e-7f * target) /* float's rounding of C */
            break;
        if (f > 0.0f)
            hi = x;
        else
            lo = x;
        float step = f / ((1.0f - x * tan_t) * e); /* C'(x)/G1 = (1 − x tanθ) e^(−x²)/√π */
        float next = x - step;
        if (!(next >= lo && next <= hi)) {
            next = 0.5f * (lo + hi);
        } else if (fabsf(step) <= 1e-4f) {
            return next; /* converging quadratically: off by ~1e-8 |C''/C'| */
        }
        if (next == x)
            break;
        x = next;
    }
    return x;
}

/* Heitz & d'Eon 2014, with Jakob 2014's inversion for Beckmann:
 * stretch wo by (αx, αy) to the α = 1 configuration, sample a slope of the
 * microfacets visible from it — x along its azimuth by inverting the
 * cumulative distribution above, y across it Gaussian, erf⁻¹(2u − 1), as
 * masking does not depend on it — turn the slope to wo's azimuth, scale it
 * by (αx, αy) and return the normal (−x, −y, 1) normalised. The result is
 * distributed as D_wo(h) with the exact Λ. */
vec3 beckmann_sample_visible_normal_aniso(vec3 wo, float ax, float ay, float2 u)
{
    vec3 v = v3_normalize(v3(ax * wo.x, ay * wo.y, maxf(wo.z, 1e-7f)));
    float sin_t = sqrtf(v.x * v.x + v.y * v.y);
    float sx = beckmann_visible_slope_x(v.z, sin_t, u.x);
    float sy = erfinvf_approx(2.0f * u.y - 1.0f);
    float c = 1.0f, s = 0.0f; /* the azimuth of v; any at normal incidence */
    if (sin_t > 1e-7f) {
        c = v.x / sin_t;
        s = v.y / sin_t;
    }
    float mx = ax * (c * sx - s * sy), my = ay * (s * sx + c * sy);
    return v3_normalize(v3(-mx, -my, 1.0f));
}

/* D_wo(h) = G1(wo) max(0, wo·h) D(h) / cos θo (Heitz 2014 eq. 16;
 * Heitz & d'Eon 2014) with the exact G1 = 1/(1 + Λ): the density of
 * beckmann_sample_visible_normal_aniso (1/sr of h). */
float beckmann_visible_normal_pdf_aniso(vec3 wo, vec3 h, float ax, float ay)
{
    float cos_oh = v3_dot(wo, h);
    if (wo.z <= 0.0f || cos_oh <= 0.0f)
        return 0.0f;
    return cos_oh * beckmann_D_aniso(h, ax, ay) / ((1.0f + beckmann_lambda_exact_aniso(wo, ax, ay)) * wo.z);
}

/* ------------------------------------------------- Ashikhmin-Shirley */

float ashikhmin_shirley_exponent(float alpha)
{
    float a = clampf(alpha, 1e-4f, 1.0f); /* Cycles' range for this closure */
    return 2.0f / (a * a) - 2.0f;
}

/* p(h) = √((nx + 1)(ny + 1)) / (2π) · cos θh^((nx hx² + ny hy²)/(hx² + hy²))
 * (Ashikhmin & Shirley 2000 eq. 6, 2): a normalised density of h. */
float ashikhmin_shirley_h_pdf(vec3 h, float nx, float ny)
{
    if (h.z <= 0.0f)
        return 0.0f;
    float s2 = h.x * h.x + h.y * h.y;
    float lobe = s2 > 0.0f ? powf(minf(h.z, 1.0f), (nx * h.x * h.x + ny * h.y * h.y) / s2) : 1.0f;
    return sqrtf((nx + 1.0f) * (ny + 1.0f)) * lobe / (2.0f * PHOS_PI);
}

/* Ashikhmin & Shirley 2000 eq. 9: in the first quadrant
 * φ = atan(√((nx + 1)/(ny + 1)) tan(π u/2)), cos θ = v^(1/(nx cos²φ + ny sin²φ + 1));
 * u chooses the quadrant, which mirrors φ. */
vec3 ashikhmin_shirley_sample_h(float nx, float ny, float2 u)
{
    float scaled = 4.0f * u.x;
    int quadrant = (int)minf(scaled, 3.0f);
    float uq = scaled - (float)quadrant;
    float phi = atanf(sqrtf((nx + 1.0f) / (ny + 1.0f)) * tanf(0.5f * PHOS_PI * minf(uq, 0.99999994f)));
    float c = cosf(phi), sn = sinf(phi);
    float cos_t = powf(u.y, 1.0f / (nx * c * c + ny * sn * sn + 1.0f));
    float sin_t = safe_sqrtf(1.0f - cos_t * cos_t);
    float sx = quadrant == 1 || quadrant == 2 ? -c : c;
    float sy = quadrant >= 2 ? -sn : sn;
    return v3(sin_t * sx, sin_t * sy, cos_t);
}
