/*
 * bsdf.c — the closures of a surface and their weighted mixture, with the
 * semantics of Cycles 3.4 (kernel/closure/bsdf_*.h, kernel/svm/closure.h)
 * so that Phos and Cycles agree on brightness:
 *
 *   DIFFUSE             Lambert, f = 1/π, cosine sampling.
 *   PRINCIPLED_DIFFUSE  Burley 2012 diffuse with the retro-reflection of
 *                       Burley 2015 §2.3 ("full" component), cosine sampling.
 *   REFLECTION          GGX reflection, F = 1; mirror when α is tiny.
 *   REFLECTION_FRESNEL  GGX reflection with the Principled (v1) Fresnel:
 *                       f0 blended to white by the normalised dielectric
 *                       Fresnel of eta.
 *   REFRACTION          GGX refraction without Fresnel; sharp when α tiny.
 *   GLASS               MACRO: Fresnel at the shading normal splits a GGX
 *                       reflection and a GGX refraction lobe (Cycles < 4).
 *                       MICROFACET: Walter et al. 2007 dielectric with the
 *                       Fresnel of each sampled microfacet (Cycles 4).
 *   TRANSPARENT         straight pass-through.
 *   METAL               GGX reflection with the F82-tint Fresnel (Cycles 4).
 *   OREN_NAYAR          energy-preserving Oren-Nayar (Fujii 2012 with the
 *                       OpenPBR multiple-scattering term), cosine sampling.
 *   SHEEN               microfiber sheen, an LTC lobe (sheen.c).
 *   TRANSLUCENT         Lambertian transmission, f = 1/π on the far side,
 *                       cosine sampling about −n (Cycles' Translucent BSDF).
 *
 * Cycles up to 3.4 uses the separable Smith G1(wo)·G1(wi) for GGX; Cycles 4
 * uses the height-correlated G (Heitz 2014 eq. 99) for every GGX lobe
 * (microfacet GGX and GGX_MULTISCATTER here, and the MICROFACET glass), and
 * its Multiscatter GGX scales a lobe by 1 + F_ms (1 − E(μo))/E(μo)
 * (ggx_albedo.h). Microfacet lobes sample the visible normals (Heitz 2018),
 * see microfacet.c. The microfacet closures may instead be Beckmann
 * (Walter 2007; its visible normals sampled as Heitz & d'Eon 2014) and
 * the reflection ones anisotropic (αx along the closure frame's tangent,
 * αy across) or, for Cycles' Glossy, Ashikhmin-Shirley (2000): enum
 * phos_microfacet, mf_lobe below.
 *
 * Mixture: a closure is picked with probability sample_weight / sum; a
 * non-delta pick is weighted by the whole non-delta mixture (one-sample
 * MIS, balance heuristic over closures, as Cycles does), a delta pick by
 * its own value over the probability of having picked it.
 *
 * Frames: each closure is evaluated and sampled in its own shading frame
 * (bsdf.frames[closure.frame]), as each Cycles closure carries its own N,
 * so a Mix of BSDFs with different Bump normals, or a coat over a bumped
 * base, shades each part about its own normal; the mixture's pdf sums the
 * closures' densities, each taken in its frame.
 *
 * Robustness: a reflected wi must lie above both the shading and the
 * geometric normal, a transmitted wi below both; otherwise the closure has
 * no value and no density there, so eval and sample stay consistent.
 */
#include "shading/bsdf.h"

#include <string.h>

#include "shading/ggx_albedo.h"
#include "shading/microfacet.h"
#include "shading/sheen.h"
#include "sampling/warp.h"

/* One evaluation query in the shading frame. */
typedef struct query {
    vec3 wo, wi;  /* unit, local shading frame */
    float ng_wi;  /* dot(ng, wi): which side of the real surface wi is on */
} query;

/* What a closure's sampler produces. */
typedef struct lobe_sample {
    vec3 wi;        /* local shading frame */
    uint32_t flags; /* enum bsdf_flags */
    vec3 value;     /* delta lobes: the lobe's total f·|cos|/δ, weight applied */
    float prob;     /* delta lobes: probability of this lobe within the closure */
} lobe_sample;

/* ------------------------------------------------------------ helpers */

/* Schlick's weight (1 − cos)⁵ with cos clamped to [0,1] (Burley 2012). */
static float schlick_weight(float cos_theta)
{
    float m = clampf(1.0f - cos_theta, 0.0f, 1.0f);
    float m2 = m * m;
    return m2 * m2 * m;
}

/* Mirror of wo about the unit normal m. */
static vec3 reflect_about(vec3 wo, vec3 m)
{
    return v3_sub(v3_scale(m, 2.0f * v3_dot(wo, m)), wo);
}

/* Snell refraction of wo (on m's side) through the unit normal m, eta =
 * η_other / η_wo-side. Returns 0 under total internal reflection. */
static int refract_about(vec3 wo, vec3 m, float eta, vec3 *wi)
{
    float cos_o = v3_dot(wo, m);
    float sin2_t = (1.0f - cos_o * cos_o) / (eta * eta);
    if (!(cos_o > 0.0f) || sin2_t >= 1.0f)
        return 0;
    float cos_t = sqrtf(1.0f - sin2_t);
    *wi = v3_normalize(v3_add(v3_scale(wo, -1.0f / eta), v3_scale(m, cos_o / eta - cos_t)));
    return 1;
}

static int reflection_side(const query *q) { return q->wi.z > 0.0f && q->ng_wi > 0.0f; }
static int transmission_side(const query *q) { return q->wi.z < 0.0f && q->ng_wi < 0.0f; }

static int closure_is_sharp(const closure *c) { return c->alpha * c->alpha_y < BSDF_SHARP_ALPHA * BSDF_SHARP_ALPHA; }
/* Cycles 4's GGX (height-correlated G) rather than 3.x's (separable). */
static int closure_correlated(const closure *c)
{
    return c->microfacet != PHOS_MICROFACET_GGX_SEPARABLE && c->microfacet != PHOS_MICROFACET_BECKMANN_SEPARABLE;
}
static int closure_beckmann(const closure *c)
{
    return c->microfacet == PHOS_MICROFACET_BECKMANN || c->microfacet == PHOS_MICROFACET_BECKMANN_SEPARABLE;
}
static int closure_has_thin_film(const closure *c) { return c->film_thickness > THIN_FILM_MIN_THICKNESS; }
static int is_white(vec3 v) { return v.x == 1.0f && v.y == 1.0f && v.z == 1.0f; }
/* The refraction lobe of a MACRO glass has its own roughness (Cycles 3.4
 * Principled: 1 − (1 − roughness)(1 − transmission roughness)). */
static int refraction_is_sharp(const closure *c) { return c->alpha_t < BSDF_SHARP_ALPHA; }
static int closure_index_matched(const closure *c) { return fabsf(c->eta - 1.0f) < BSDF_INDEX_MATCHED; }

/* GLASS splits by Fresnel at the shading normal (MACRO) or per microfacet.
 * An index-matched glass always uses MACRO: its refraction is a delta. */
static int glass_per_microfacet(const closure *c)
{
    return c->glass_fresnel == PHOS_GLASS_FRESNEL_MICROFACET && !closure_index_matched(c);
}

/* ---------------------------------------------------- microfacet lobes */

/* Cycles has anisotropic GGX for its reflection closures only. */
static int closure_may_be_anisotropic(const closure *c)
{
    return c->type == PHOS_CLOSURE_REFLECTION || c->type == PHOS_CLOSURE_REFLECTION_FRESNEL ||
           c->type == PHOS_CLOSURE_METAL;
}

/* One microfacet lobe: its distribution (GGX or Beckmann), roughness ax
 * along the frame's x axis and ay along y, and its Smith G. */
typedef struct mf_lobe {
    float ax, ay;
    int beckmann;   /* Beckmann, else GGX */
    int correlated; /* height-correlated G (Cycles 4), else separable (3.x) */
    int ashikhmin;  /* Ashikhmin-Shirley (reflection only), exponents nx, ny */
    float nx, ny;
} mf_lobe;

static mf_lobe lobe_of(const closure *c, float ax, float ay, int correlated)
{
    /* Ashikhmin-Shirley is a reflection model; elsewhere it stands for GGX. */
    int ashikhmin = c->microfacet == PHOS_MICROFACET_ASHIKHMIN_SHIRLEY && closure_may_be_anisotropic(c);
    mf_lobe m = {ax, ay, closure_beckmann(c), correlated, ashikhmin, 0.0f, 0.0f};
    if (m.ashikhmin) {
        m.nx = ashikhmin_shirley_exponent(ax);
        m.ny = ashikhmin_shirley_exponent(ay);
    }
    return m;
}

static float lobe_D(const mf_lobe *m, vec3 h)
{
    return m->beckmann ? beckmann_D_aniso(h, m->ax, m->ay) : ggx_D_aniso(h, m->ax, m->ay);
}

static float lobe_lambda(const mf_lobe *m, vec3 w)
{
    return m->beckmann ? beckmann_lambda_aniso(w, m->ax, m->ay) : ggx_lambda_aniso(w, m->ax, m->ay);
}

/* Smith G (Heitz 2014 eq. 98 or 99). */
static float lobe_G(const mf_lobe *m, vec3 wo, vec3 wi)
{
    float lo = lobe_lambda(m, wo), li = lobe_lambda(m, wi);
    return m->correlated ? 1.0f / (1.0f + lo + li) : 1.0f / ((1.0f + lo) * (1.0f + li));
}

/* A half vector for wo from the normals visible from it: GGX's by Heitz
 * 2018, Beckmann's by Heitz & d'Eon 2014 (slopes as Jakob 2014). */
static vec3 lobe_sample_h(const mf_lobe *m, vec3 wo, float2 u)
{
    if (m->ashikhmin)
        return ashikhmin_shirley_sample_h(m->nx, m->ny, u);
    return m->beckmann ? beckmann_sample_visible_normal_aniso(wo, m->ax, m->ay, u)
                       : ggx_sample_visible_normal_aniso(wo, m->ax, m->ay, u);
}

/* The density of lobe_sample_h (1/sr of h): D_wo(h), for Beckmann with
 * the exact Λ that its sampler follows rather than the approximation
 * lobe_G uses, so that the pdf is the sampler's own; a sample's weight
 * f·cos/pdf is then G(approximate Λ) / G1(wo, exact Λ). */
static float lobe_h_pdf(const mf_lobe *m, vec3 wo, vec3 h)
{
    if (m->ashikhmin)
        return ashikhmin_shirley_h_pdf(h, m->nx, m->ny);
    return m->beckmann ? beckmann_visible_normal_pdf_aniso(wo, h, m->ax, m->ay)
                       : ggx_visible_normal_pdf_aniso(wo, h, m->ax, m->ay);
}

/* Microfacet reflection without Fresnel: returns f·cos θi = D G / (4 cos θo)
 * (Walter 2007 eq. 20 times cos θi) and the solid-angle pdf of sampling wi
 * through lobe_sample_h, p(h) / (4 wo·h) (Walter 2007 eq. 14; for
 * visible normals Heitz 2018 eq. 17). */
static float microfacet_reflection(const query *q, const mf_lobe *m, vec3 *h, float *pdf)
{
    *pdf = 0.0f;
    if (q->wo.z <= 0.0f || !reflection_side(q) || !microfacet_reflect_half_vector(q->wo, q->wi, h))
        return 0.0f;
    if (m->ashikhmin) {
        /* Ashikhmin & Shirley 2000 eq. 4 without Fresnel (Cycles' Glossy):
         * f·cos θi = cos θi · p(h) / (4 (h·wo) max(cos θo, cos θi)). */
        float ph = ashikhmin_shirley_h_pdf(*h, m->nx, m->ny), cos_oh = maxf(v3_dot(q->wo, *h), 1e-6f);
        if (!(ph > 0.0f))
            return 0.0f;
        *pdf = ph * microfacet_reflect_jacobian(q->wo, *h);
        return q->wi.z * ph / (4.0f * cos_oh * maxf(maxf(q->wo.z, q->wi.z), 1e-6f));
    }
    float D = lobe_D(m, *h);
    if (!(D > 0.0f))
        return 0.0f;
    if (!m->beckmann) {
        /* GGX: the visible-normal pdf D·(wo·h)/((1 + Λ(wo)) cos θo) times
         * the Jacobian 1/(4 wo·h) shares D and Λ(wo) with f, and wo·h > 0
         * for a reflection's half vector: pdf = D / (4 cos θo (1 + Λ(wo))). */
        float lo = ggx_lambda_aniso(q->wo, m->ax, m->ay), li = ggx_lambda_aniso(q->wi, m->ax, m->ay);
        float G = m->correlated ? 1.0f / (1.0f + lo + li) : 1.0f / ((1.0f + lo) * (1.0f + li));
        float D_over = D / (4.0f * q->wo.z);
        *pdf = D_over / (1.0f + lo);
        return D_over * G;
    }
    *pdf = lobe_h_pdf(m, q->wo, *h) * microfacet_reflect_jacobian(q->wo, *h);
    return D * lobe_G(m, q->wo, q->wi) / (4.0f * q->wo.z);
}

/* Microfacet refraction without Fresnel: f·|cos θi| =
 * |wo·h| |wi·h| η² D G / (cos θo (wo·h + η wi·h)²) (Walter 2007 eq. 21 times
 * |cos θi|, without the 1/η² radiance scaling, as Cycles), and the pdf
 * p(h) |dω_h/dω_i| of sampling wi through lobe_sample_h. */
static float microfacet_refraction(const query *q, const mf_lobe *m, float eta, vec3 *h, float *pdf)
{
    *pdf = 0.0f;
    if (q->wo.z <= 0.0f || !transmission_side(q) ||
        !microfacet_refract_half_vector(q->wo, q->wi, eta, h))
        return 0.0f;
    float D = lobe_D(m, *h);
    if (!(D > 0.0f))
        return 0.0f;
    float jacobian = microfacet_refract_jacobian(q->wo, q->wi, *h, eta);
    *pdf = lobe_h_pdf(m, q->wo, *h) * jacobian;
    return v3_dot(q->wo, *h) * D * lobe_G(m, q->wo, q->wi) / q->wo.z * jacobian;
}

/* -------------------------------------------------------- Fresnel */

/* Reflectance of a reflection closure at a microfacet seen at cos θ = wo·h. */
static vec3 reflection_fresnel(const closure *c, float cos_theta)
{
    switch (c->type) {
    case PHOS_CLOSURE_REFLECTION_FRESNEL:
        if (closure_has_thin_film(c))
            return fresnel_thin_film_blend(c->f0, c->eta, cos_theta, c->film_ior, c->film_thickness);
        return fresnel_blend_f0(c->f0, c->eta, cos_theta);
    case PHOS_CLOSURE_METAL:
        return fresnel_f82(c->f0, fresnel_f82_b(c->f0, c->specular_tint), cos_theta);
    default:
        return v3s(1.0f);
    }
}

/* Reflectance of a MICROFACET glass at wo·h (its transmittance is 1 − it):
 * the dielectric Fresnel, or, tinted or with a thin film, the Principled
 * form with f0 = F0(η)·tint (Cycles 4's transmission lobe). */
static vec3 glass_reflectance(const closure *c, float cos_oh)
{
    if (!closure_has_thin_film(c) && is_white(c->specular_tint))
        return v3s(fresnel_dielectric(cos_oh, c->eta));
    vec3 f0 = v3_scale(c->specular_tint, fresnel_f0_from_ior(c->eta));
    if (closure_has_thin_film(c))
        return fresnel_thin_film_blend(f0, c->eta, cos_oh, c->film_ior, c->film_thickness);
    return fresnel_blend_f0(f0, c->eta, cos_oh);
}

static vec3 glass_transmittance(const closure *c, float cos_oh, vec3 R)
{
    if (!closure_has_thin_film(c) && is_white(c->specular_tint))
        return v3s(fresnel_dielectric_transmittance(cos_oh, c->eta)); /* without cancellation */
    return v3_sub(v3s(1.0f), R);
}

/* Multiscatter GGX: the factor 1 + F_ms (1 − E(μo))/E(μo) by which the lobe
 * is scaled (ggx_albedo.h); 1 for other models and for sharp lobes. */
static vec3 multiscatter_scale(const closure *c, float mu)
{
    if (c->microfacet != PHOS_MICROFACET_GGX_MULTISCATTER || closure_is_sharp(c))
        return v3s(1.0f);
    if (c->type == PHOS_CLOSURE_GLASS)
        return ggx_multiscatter_scale(ggx_glass_albedo(mu, c->roughness, c->eta),
                                      ggx_glass_albedo_average(c->roughness, c->eta), c->fss);
    return ggx_multiscatter_scale(ggx_albedo(mu, c->roughness), ggx_albedo_average(c->roughness), c->fss);
}

/* ------------------------------------------------------------ layers */

/* The share of light at μ = cos θo that a layer returns toward the viewer
 * relative to its weight, as Cycles 4 estimates it for layering
 * (bsdf_albedo): a dielectric f0 + (1 − f0)·s(μ) with s the mean Fresnel
 * interpolation over the visible microfacets (the Fresnel at μ itself when
 * a thin film makes it coloured), times the Multiscatter darkening
 * E + F_ms (1 − E), which is 1 when F_ss = 1; the sheen's albedo R(μ). */
static vec3 layer_albedo(const bsdf_layer *l, float mu)
{
    if (l->type == PHOS_CLOSURE_SHEEN)
        return v3s(sheen_albedo(mu, l->roughness));
    vec3 F;
    if (l->film_thickness > THIN_FILM_MIN_THICKNESS)
        F = fresnel_thin_film_blend(l->f0, l->eta, mu, l->film_ior, l->film_thickness);
    else
        F = v3_add(l->f0, v3_scale(v3_sub(v3s(1.0f), l->f0), ggx_fresnel_blend_average(mu, l->roughness, l->eta)));
    if (l->microfacet == PHOS_MICROFACET_GGX_MULTISCATTER && l->roughness * l->roughness >= BSDF_SHARP_ALPHA) {
        float E = ggx_albedo(mu, l->roughness);
        F = v3_mul(F, v3_scale(ggx_multiscatter_scale(E, ggx_albedo_average(l->roughness), l->fss), E));
    }
    return F;
}

/* Cycles' closure_layering_weight: 1 − max over channels of the layer's
 * albedo; then a coat's absorption, tint^(1/cos θt) through a unit
 * thickness along the refracted view direction, mixed in by tint_weight. */
static vec3 layer_scale(const bsdf_layer *l, float mu)
{
    float over = v3_max_component(v3_mul(l->weight, layer_albedo(l, mu)));
    vec3 scale = v3s(clampf(1.0f - over, 0.0f, 1.0f));
    if (l->type != PHOS_CLOSURE_SHEEN && !(l->tint.x == 1.0f && l->tint.y == 1.0f && l->tint.z == 1.0f)) {
        float cos_t = safe_sqrtf(1.0f - (1.0f - mu * mu) / (l->eta * l->eta));
        float depth = 1.0f / maxf(cos_t, 1e-4f);
        vec3 absorbed = v3(powf(l->tint.x, depth), powf(l->tint.y, depth), powf(l->tint.z, depth));
        scale = v3_mul(scale, v3_add(v3s(1.0f - l->tint_weight), v3_scale(absorbed, l->tint_weight)));
    }
    return scale;
}

/* Scales of every layer, so a mixture evaluates each once; mu[f] is
 * cos θo in the bsdf's frame f, and a layer sees wo from its own closure's
 * frame (Cycles' bsdf_albedo reads the layer closure's N). */
static void layer_scales(const bsdf *b, const float *mu, vec3 *out)
{
    for (uint32_t j = 0; j < b->layer_count; j++)
        out[j] = layer_scale(&b->layers[j], clampf(mu[b->layers[j].frame], 0.0f, 1.0f));
}

/* cos θo of wo (world) in each of the bsdf's frames. */
static void frame_cosines(const bsdf *b, vec3 wo, float *mu)
{
    for (uint32_t f = 0; f < b->frame_count; f++)
        mu[f] = v3_dot(wo, b->frames[f].n);
}

static vec3 scale_under(const vec3 *scales, uint32_t under_layers)
{
    vec3 s = v3s(1.0f);
    for (uint32_t j = 0; under_layers; j++, under_layers >>= 1)
        if (under_layers & 1u)
            s = v3_mul(s, scales[j]);
    return s;
}

vec3 bsdf_layer_scale(const bsdf *b, uint32_t under_layers, vec3 wo)
{
    if (!under_layers)
        return v3s(1.0f);
    vec3 scales[BSDF_MAX_LAYERS];
    float mu[BSDF_MAX_FRAMES];
    frame_cosines(b, wo, mu);
    layer_scales(b, mu, scales);
    return scale_under(scales, under_layers);
}

/* The share of light a closure returns toward μ = cos θo, relative to its
 * weight (its directional albedo, estimated as Cycles does for its passes:
 * a smooth surface's Fresnel, the Principled layers' tables). */
static vec3 closure_albedo_estimate(const closure *c, float mu)
{
    switch (c->type) {
    case PHOS_CLOSURE_SHEEN:
        return v3s(sheen_albedo(mu, c->roughness));
    case PHOS_CLOSURE_REFLECTION:
    case PHOS_CLOSURE_REFLECTION_FRESNEL: {
        bsdf_layer l = {c->type, c->roughness, c->eta, c->microfacet, c->f0, c->fss, c->film_thickness,
                        c->film_ior, v3s(1.0f), v3s(1.0f), 0.0f, 0};
        return c->type == PHOS_CLOSURE_REFLECTION ? v3s(1.0f) : layer_albedo(&l, mu);
    }
    case PHOS_CLOSURE_METAL:
        return reflection_fresnel(c, mu);
    case PHOS_CLOSURE_GLASS: {
        float F = fresnel_dielectric(mu, c->eta);
        return v3_add(v3s(F), v3_scale(c->transmission_tint, 1.0f - F));
    }
    default:
        return v3s(1.0f);
    }
}

/* Cycles' cut between the closures a denoiser's features stop at and
 * those it looks through: α above 0.075 for a microfacet lobe. */
static int closure_diffuse_like(const closure *c)
{
    switch (c->type) {
    case PHOS_CLOSURE_TRANSPARENT:
        return 0;
    case PHOS_CLOSURE_REFLECTION:
    case PHOS_CLOSURE_REFLECTION_FRESNEL:
    case PHOS_CLOSURE_METAL:
    case PHOS_CLOSURE_REFRACTION:
    case PHOS_CLOSURE_GLASS:
        return c->alpha * c->alpha_y > 0.075f * 0.075f; /* √(αx αy) > 0.075 */
    default:
        return 1;
    }
}

/* What each closure returns toward wo, per channel: its weight times its
 * albedo estimate at the cosine of wo with its normal, times what the
 * layers over it let through (out[k] for closure k). */
static void returned_light(const bsdf *b, vec3 wo, vec3 *out)
{
    float mus[BSDF_MAX_FRAMES];
    frame_cosines(b, wo, mus);
    vec3 scales[BSDF_MAX_LAYERS];
    if (b->layer_count)
        layer_scales(b, mus, scales);
    for (uint32_t k = 0; k < b->count; k++) {
        const closure *c = &b->closures[k];
        out[k] = v3_mul(c->weight, closure_albedo_estimate(c, clampf(mus[c->frame], 0.0f, 1.0f)));
        if (c->under_layers)
            out[k] = v3_mul(out[k], scale_under(scales, c->under_layers));
    }
}

/* The pick weights as Cycles sets them: a closure is picked in proportion
 * to the light it returns toward wo, not to its weight alone, so a
 * Principled BSDF's dielectric specular, which returns a few per cent,
 * stops taking half the samples from the diffuse base under it. Cycles
 * multiplies a Fresnel closure's sample weight by its Fresnel colour
 * (3.x) or its directional albedo (4.x), and a layered closure's weight
 * by what the layers over it let through. The mixture's pdf (bsdf_eval)
 * uses the same weights, so only the variance changes. A floor of 1 % of
 * the weight keeps every closure drawable. A lone closure is always
 * picked: nothing to weigh. */
void bsdf_weight_picks(bsdf *b, vec3 wo)
{
    if (b->count < 2)
        return;
    vec3 returned[PHOS_MAX_CLOSURES];
    returned_light(b, wo, returned);
    b->sample_weight_sum = 0.0f;
    for (uint32_t k = 0; k < b->count; k++) {
        closure *c = &b->closures[k];
        vec3 r = returned[k];
        float w = (fabsf(r.x) + fabsf(r.y) + fabsf(r.z)) * (1.0f / 3.0f);
        float by_weight = (fabsf(c->weight.x) + fabsf(c->weight.y) + fabsf(c->weight.z)) * (1.0f / 3.0f);
        c->sample_weight = isfinite(w) ? maxf(w, 0.01f * by_weight) : by_weight;
        b->sample_weight_sum += c->sample_weight;
    }
}

void bsdf_denoising_features(const bsdf *b, vec3 wo, bsdf_features *out)
{
    memset(out, 0, sizeof(*out));
    vec3 returned[PHOS_MAX_CLOSURES];
    returned_light(b, wo, returned);
    for (uint32_t k = 0; k < b->count; k++) {
        const closure *c = &b->closures[k];
        float w = c->sample_weight; /* the light it returns toward wo (bsdf_weight_picks) */
        out->weight_total += w;
        if (closure_diffuse_like(c)) {
            out->albedo_diffuse = v3_add(out->albedo_diffuse, returned[k]);
            out->weight_diffuse += w;
        } else {
            out->albedo_specular = v3_add(out->albedo_specular, returned[k]);
        }
    }
}

int bsdf_add_layer(bsdf *b, const bsdf_layer *layer)
{
    if (b->layer_count >= BSDF_MAX_LAYERS)
        return -1;
    b->layers[b->layer_count] = *layer;
    if (layer->frame >= b->frame_count)
        b->layers[b->layer_count].frame = 0;
    return (int)b->layer_count++;
}

/* -------------------------------------------------------- evaluation */

static vec3 eval_diffuse(const closure *c, const query *q, float *pdf)
{
    if (!reflection_side(q))
        return v3s(0.0f);
    *pdf = q->wi.z * PHOS_INV_PI;
    return v3_scale(c->weight, q->wi.z * PHOS_INV_PI);
}

/* Lambertian transmission: f = 1/π for wi below both normals, so that a
 * white closure transmits all the light it receives (albedo 1 into the far
 * hemisphere, ∫ |cos θi|/π dωi = 1); pdf |cos θi|/π, cosine sampling. */
static vec3 eval_translucent(const closure *c, const query *q, float *pdf)
{
    if (!transmission_side(q))
        return v3s(0.0f);
    float cos_i = -q->wi.z;
    *pdf = cos_i * PHOS_INV_PI;
    return v3_scale(c->weight, cos_i * PHOS_INV_PI);
}

/* Burley 2012 diffuse, f = (1/π)[(1 − ½F_L)(1 − ½F_V) + R_R (F_L + F_V + F_L F_V (R_R − 1))]
 * with F = (1 − cos)⁵ and R_R = roughness·(1 + wo·wi) = 2 roughness cos²θd
 * (Burley 2015 §2.3, as Cycles 3.4's PRINCIPLED_DIFFUSE_FULL). */
static vec3 eval_principled_diffuse(const closure *c, const query *q, float *pdf)
{
    if (!reflection_side(q))
        return v3s(0.0f);
    float fl = schlick_weight(q->wi.z);
    float fv = schlick_weight(q->wo.z);
    float f = (1.0f - 0.5f * fl) * (1.0f - 0.5f * fv);
    float rr = c->roughness * (1.0f + v3_dot(q->wo, q->wi));
    f += rr * (fl + fv + fl * fv * (rr - 1.0f));
    *pdf = q->wi.z * PHOS_INV_PI;
    return v3_scale(c->weight, f * q->wi.z * PHOS_INV_PI);
}

/* Energy-preserving Oren-Nayar (Fujii 2012, "A tiny improvement of
 * Oren-Nayar reflectance model", with the multiple-scattering term of the
 * OpenPBR "EON" diffuse; Cycles 4.3's Diffuse Roughness):
 * f = A + B·s + E_ms (1 − E(μi))(1 − E(μo)), s = wo·wi − μo μi (divided by
 * max(μo, μi) where positive), A = 1/(π + σ(π/2 − 2/3)), B = σA,
 * E(μ) = Aπ + B·G(μ) its directional albedo, E_ms the albedo's missing
 * energy, τρ(E_avg/(1 − E_avg))/(π(1 − ρ(1 − E_avg))) for the colour ρ
 * (f0), which the closure's weight carries once more: with τ = 1 (the
 * specular_tint) the term is ρ² as in OpenPBR's EON and Cycles 5.1+;
 * Cycles 4.3-5.0 tint it by ρ again (τ = ρ, docs/algorithms.md §8.6). */
static float oren_nayar_G(float mu)
{
    if (mu < 1e-6f)
        return (0.5f * PHOS_PI - 2.0f / 3.0f) - mu;
    float sin_t = safe_sqrtf(1.0f - mu * mu), theta = acosf(mu);
    return sin_t * (theta - 2.0f / 3.0f - sin_t * mu) + (2.0f / 3.0f) * (sin_t / mu) * (1.0f - sin_t * sin_t * sin_t);
}

static vec3 eval_oren_nayar(const closure *c, const query *q, float *pdf)
{
    if (!reflection_side(q))
        return v3s(0.0f);
    float sigma = c->roughness;
    float A = 1.0f / (PHOS_PI + sigma * (0.5f * PHOS_PI - 2.0f / 3.0f)), B = sigma * A;
    float mo = q->wo.z, mi = q->wi.z;
    float t = v3_dot(q->wo, q->wi) - mo * mi;
    if (t > 0.0f)
        t /= maxf(mo, mi);
    float E_o = A * PHOS_PI + B * oren_nayar_G(maxf(mo, 0.0f)), E_i = A * PHOS_PI + B * oren_nayar_G(mi);
    vec3 f = v3s(A + B * t);
    if (sigma > 0.0f) { /* roughness 0 is Lambert: nothing is missing */
        float E_avg = A * PHOS_PI + B * (2.0f * PHOS_PI - 5.6f) / 3.0f;
        vec3 rho = v3_min(v3_max(c->f0, v3s(0.0f)), v3s(1.0f));
        vec3 E_ms = v3_scale(v3_div(v3_scale(v3_mul(c->specular_tint, rho), E_avg / (1.0f - E_avg)),
                                    v3_sub(v3s(1.0f), v3_scale(rho, 1.0f - E_avg))),
                             PHOS_INV_PI);
        f = v3_add(f, v3_scale(E_ms, (1.0f - E_i) * (1.0f - E_o)));
    }
    *pdf = mi * PHOS_INV_PI;
    return v3_scale(v3_mul(c->weight, f), mi);
}

/* The sheen lobe times its albedo R(μo); it samples the lobe itself. */
static vec3 eval_sheen(const closure *c, const query *q, float *pdf)
{
    if (!reflection_side(q) || q->wo.z <= 0.0f)
        return v3s(0.0f);
    float lobe = sheen_eval(q->wo, q->wi, c->roughness);
    *pdf = lobe;
    return v3_scale(c->weight, lobe * sheen_albedo(q->wo.z, c->roughness));
}

static vec3 eval_glossy(const closure *c, const query *q, float *pdf)
{
    if (closure_is_sharp(c))
        return v3s(0.0f);
    vec3 h;
    mf_lobe m = lobe_of(c, c->alpha, c->alpha_y, closure_correlated(c));
    float v = microfacet_reflection(q, &m, &h, pdf);
    if (v == 0.0f)
        return v3s(0.0f);
    vec3 colour = v3_mul(c->weight, reflection_fresnel(c, v3_dot(q->wi, h)));
    return v3_scale(v3_mul(colour, multiscatter_scale(c, q->wo.z)), v);
}

static vec3 eval_refraction(const closure *c, const query *q, float *pdf)
{
    if (closure_is_sharp(c) || closure_index_matched(c))
        return v3s(0.0f);
    vec3 h;
    mf_lobe m = lobe_of(c, c->alpha, c->alpha, closure_correlated(c));
    return v3_scale(c->weight, microfacet_refraction(q, &m, c->eta, &h, pdf));
}

/* The probability with which a MACRO glass picks its reflection lobe: F at
 * the shading normal, capped for photons (bsdf_set_adjoint) where a rough
 * refraction lobe exists. A sharp glass keeps F: its lobes are deltas,
 * whose adjoint is the lobe itself. */
static float macro_reflect_pick(const closure *c, float F)
{
    if (c->adjoint && !closure_is_sharp(c) && !refraction_is_sharp(c) && !closure_index_matched(c))
        return minf(F, BSDF_ADJOINT_MAX_REFLECT);
    return F;
}

static vec3 eval_glass(const closure *c, const query *q, float *pdf)
{
    vec3 h;
    float v, lobe;
    if (glass_per_microfacet(c)) {
        if (closure_is_sharp(c))
            return v3s(0.0f);
        /* Walter 2007 eq. 20/21 with F(wo·h); sampling picks the lobe with
         * the mean over the channels of F(wo·h). */
        int reflect = q->wi.z > 0.0f;
        mf_lobe m = lobe_of(c, c->alpha, c->alpha, 1);
        if (reflect)
            v = microfacet_reflection(q, &m, &h, pdf);
        else
            v = microfacet_refraction(q, &m, c->eta, &h, pdf);
        if (v == 0.0f)
            return v3s(0.0f);
        float cos_oh = v3_dot(q->wo, h);
        vec3 R = glass_reflectance(c, cos_oh);
        vec3 T = glass_transmittance(c, cos_oh, R);
        float pick_r = v3_average(R) / maxf(v3_average(R) + v3_average(T), 1e-12f);
        *pdf *= reflect ? pick_r : 1.0f - pick_r;
        vec3 colour = reflect ? v3_mul(c->weight, R) : v3_mul(v3_mul(c->weight, c->transmission_tint), T);
        return v3_scale(v3_mul(colour, multiscatter_scale(c, q->wo.z)), v);
    } else {
        /* Cycles 3.4: two closures weighted F and 1 − F, F at the shading
         * normal; sampling picks them with macro_reflect_pick. */
        float F = fresnel_dielectric(q->wo.z, c->eta), pick = macro_reflect_pick(c, F);
        if (q->wi.z > 0.0f) {
            mf_lobe m = lobe_of(c, c->alpha, c->alpha, 0);
            v = closure_is_sharp(c) ? 0.0f : microfacet_reflection(q, &m, &h, pdf);
            lobe = F;
            *pdf *= pick;
        } else {
            v = (closure_index_matched(c) || refraction_is_sharp(c))
                    ? 0.0f
                    : microfacet_refraction(q, &(mf_lobe){c->alpha_t, c->alpha_t, closure_beckmann(c), 0, 0, 0.0f, 0.0f}, c->eta,
                                            &h, pdf);
            lobe = fresnel_dielectric_transmittance(q->wo.z, c->eta);
            *pdf *= pick < F ? 1.0f - pick : lobe; /* lobe: 1 − F without cancellation */
        }
        if (v == 0.0f) {
            *pdf = 0.0f;
            return v3s(0.0f);
        }
        vec3 colour = q->wi.z > 0.0f ? c->weight : v3_mul(c->weight, c->transmission_tint);
        return v3_scale(v3_mul(colour, multiscatter_scale(c, q->wo.z)), v * lobe);
    }
}

/* f·|cos θi| of one closure (weight applied) and its own sampling density;
 * zero for delta closures, which only exist through sampling. */
static vec3 closure_eval(const closure *c, const query *q, float *pdf)
{
    *pdf = 0.0f;
    switch (c->type) {
    case PHOS_CLOSURE_DIFFUSE: return eval_diffuse(c, q, pdf);
    case PHOS_CLOSURE_PRINCIPLED_DIFFUSE: return eval_principled_diffuse(c, q, pdf);
    case PHOS_CLOSURE_OREN_NAYAR: return eval_oren_nayar(c, q, pdf);
    case PHOS_CLOSURE_SHEEN: return eval_sheen(c, q, pdf);
    case PHOS_CLOSURE_TRANSLUCENT: return eval_translucent(c, q, pdf);
    case PHOS_CLOSURE_REFLECTION:
    case PHOS_CLOSURE_REFLECTION_FRESNEL:
    case PHOS_CLOSURE_METAL: return eval_glossy(c, q, pdf);
    case PHOS_CLOSURE_REFRACTION: return eval_refraction(c, q, pdf);
    case PHOS_CLOSURE_GLASS: return eval_glass(c, q, pdf);
    default: return v3s(0.0f);
    }
}

/* ---------------------------------------------------------- sampling */

static int sample_delta(lobe_sample *s, vec3 wi, uint32_t flags, vec3 value, float prob)
{
    s->wi = wi;
    s->flags = BSDF_DELTA | flags;
    s->value = value;
    s->prob = prob;
    return prob > 0.0f;
}

static int sample_glossy(const closure *c, vec3 wo, float2 u, lobe_sample *s)
{
    if (closure_is_sharp(c))
        return sample_delta(s, v3(-wo.x, -wo.y, wo.z), 0, v3_mul(c->weight, reflection_fresnel(c, wo.z)), 1.0f);
    mf_lobe m = lobe_of(c, c->alpha, c->alpha_y, closure_correlated(c));
    vec3 h = lobe_sample_h(&m, wo, u);
    if (v3_dot(wo, h) <= 0.0f)
        return 0;
    s->wi = reflect_about(wo, h);
    s->flags = BSDF_GLOSSY;
    return 1;
}

static int sample_refraction(const closure *c, vec3 wo, float2 u, lobe_sample *s)
{
    vec3 wi;
    if (closure_is_sharp(c) || closure_index_matched(c)) {
        if (!refract_about(wo, v3(0.0f, 0.0f, 1.0f), c->eta, &wi))
            return 0;
        return sample_delta(s, wi, BSDF_TRANSMISSION, c->weight, 1.0f);
    }
    mf_lobe m = lobe_of(c, c->alpha, c->alpha, closure_correlated(c));
    vec3 h = lobe_sample_h(&m, wo, u);
    if (!refract_about(wo, h, c->eta, &wi))
        return 0; /* total internal reflection at this microfacet: no light */
    s->wi = wi;
    s->flags = BSDF_GLOSSY | BSDF_TRANSMISSION;
    return 1;
}

static int sample_glass(const closure *c, vec3 wo, float u_lobe, float2 u, lobe_sample *s)
{
    const vec3 n = v3(0.0f, 0.0f, 1.0f);
    vec3 wi;
    if (glass_per_microfacet(c)) {
        /* Walter 2007 §5.3 with visible normals: pick h, then reflect with
         * probability F(wo·h) (the channels' mean), otherwise refract
         * through h; a sharp glass has h = n. */
        mf_lobe m = lobe_of(c, c->alpha, c->alpha, 1);
        vec3 h = closure_is_sharp(c) ? n : lobe_sample_h(&m, wo, u);
        float cos_oh = v3_dot(wo, h);
        if (cos_oh <= 0.0f)
            return 0;
        vec3 R = glass_reflectance(c, cos_oh), T = glass_transmittance(c, cos_oh, R);
        float pick_r = v3_average(R) / maxf(v3_average(R) + v3_average(T), 1e-12f);
        if (closure_is_sharp(c)) {
            if (u_lobe < pick_r)
                return sample_delta(s, v3(-wo.x, -wo.y, wo.z), 0, v3_mul(c->weight, R), pick_r);
            if (!refract_about(wo, n, c->eta, &wi))
                return 0;
            return sample_delta(s, wi, BSDF_TRANSMISSION, v3_mul(v3_mul(c->weight, c->transmission_tint), T),
                                1.0f - pick_r);
        }
        if (u_lobe < pick_r) {
            s->wi = reflect_about(wo, h);
            s->flags = BSDF_GLOSSY;
            return 1;
        }
        if (!refract_about(wo, h, c->eta, &wi))
            return 0;
        s->wi = wi;
        s->flags = BSDF_GLOSSY | BSDF_TRANSMISSION;
        return 1;
    }

    /* Fresnel at the shading normal (MACRO, or an index-matched glass). */
    float F = fresnel_dielectric(wo.z, c->eta);
    if (u_lobe < macro_reflect_pick(c, F)) {
        if (closure_is_sharp(c))
            return sample_delta(s, v3(-wo.x, -wo.y, wo.z), 0, v3_scale(c->weight, F), F);
        mf_lobe m = lobe_of(c, c->alpha, c->alpha, 0);
        vec3 h = lobe_sample_h(&m, wo, u);
        if (v3_dot(wo, h) <= 0.0f)
            return 0;
        s->wi = reflect_about(wo, h);
        s->flags = BSDF_GLOSSY;
        return 1;
    }
    vec3 tinted = v3_mul(c->weight, c->transmission_tint);
    if (refraction_is_sharp(c) || closure_index_matched(c)) {
        if (!refract_about(wo, n, c->eta, &wi))
            return 0;
        float T = fresnel_dielectric_transmittance(wo.z, c->eta);
        return sample_delta(s, wi, BSDF_TRANSMISSION, v3_scale(tinted, T), T);
    }
    mf_lobe mt = lobe_of(c, c->alpha_t, c->alpha_t, 0);
    vec3 h = lobe_sample_h(&mt, wo, u);
    if (!refract_about(wo, h, c->eta, &wi))
        return 0;
    s->wi = wi;
    s->flags = BSDF_GLOSSY | BSDF_TRANSMISSION;
    return 1;
}

/* Samples wi from one closure; u_lobe in [0,1) chooses a lobe inside it. */
static int closure_sample(const closure *c, vec3 wo, float u_lobe, float2 u, lobe_sample *s)
{
    switch (c->type) {
    case PHOS_CLOSURE_DIFFUSE:
    case PHOS_CLOSURE_PRINCIPLED_DIFFUSE:
    case PHOS_CLOSURE_OREN_NAYAR:
        s->wi = warp_cosine_hemisphere(u);
        s->flags = BSDF_DIFFUSE;
        return s->wi.z > 0.0f;
    case PHOS_CLOSURE_SHEEN:
        s->wi = sheen_sample(wo, c->roughness, u);
        s->flags = BSDF_DIFFUSE;
        return s->wi.z > 0.0f;
    case PHOS_CLOSURE_TRANSLUCENT: {
        vec3 w = warp_cosine_hemisphere(u);
        s->wi = v3(w.x, w.y, -w.z);
        s->flags = BSDF_DIFFUSE | BSDF_TRANSMISSION;
        return s->wi.z < 0.0f;
    }
    case PHOS_CLOSURE_TRANSPARENT:
        return sample_delta(s, v3_neg(wo), BSDF_TRANSPARENT | BSDF_TRANSMISSION, c->weight, 1.0f);
    default:
        break;
    }
    /* Microfacet closures see only the front of the shading normal (as Cycles). */
    if (wo.z <= 0.0f)
        return 0;
    switch (c->type) {
    case PHOS_CLOSURE_REFLECTION:
    case PHOS_CLOSURE_REFLECTION_FRESNEL:
    case PHOS_CLOSURE_METAL: return sample_glossy(c, wo, u, s);
    case PHOS_CLOSURE_REFRACTION: return sample_refraction(c, wo, u, s);
    case PHOS_CLOSURE_GLASS: return sample_glass(c, wo, u_lobe, u, s);
    default: return 0;
    }
}

/* ----------------------------------------------------------- mixture */

/* The pair (wo, wi) in the bsdf's frame f. */
static query make_query(const bsdf *b, uint32_t f, vec3 wo, vec3 wi)
{
    query q;
    q.wo = frame_to_local(&b->frames[f], wo);
    q.wi = frame_to_local(&b->frames[f], wi);
    q.ng_wi = v3_dot(b->ng, wi);
    return q;
}

/* Whether a closure is one of those a bumped normal darkens toward the
 * terminator: the diffuse-like ones (Cycles' CLOSURE_IS_BSDF_DIFFUSE,
 * which includes translucency). */
static int closure_bump_shadowed(const closure *c)
{
    return closure_is_diffuse(c) || c->type == PHOS_CLOSURE_TRANSLUCENT;
}

/* The bump shadowing term of a diffuse closure whose normal n was bent
 * away from the surface's smooth normal n0 (Chiang, Li & Burley 2019,
 * "Taming the Shadow Terminator", as Cycles applies it): with
 * g = (n0·wi) / ((n·wi)(n0·n)), light with g ≥ 1 is unshadowed, g < 0 is
 * black, and between the masking −g³ + g² + g rounds off the terminator
 * the bent normal would otherwise push past the geometry. The sign of g
 * does not depend on which side wi is (a translucent closure's). */
static float bump_shadowing(vec3 n0, vec3 n, vec3 wi)
{
    float denom = v3_dot(n, wi) * v3_dot(n0, n);
    float g = denom != 0.0f ? v3_dot(n0, wi) / denom : 0.0f;
    if (g >= 1.0f)
        return 1.0f;
    if (!(g >= 0.0f))
        return 0.0f;
    float g2 = g * g;
    return -g2 * g + g2 + g;
}

/* A closure's part on caustic paths (closure_scatters_caustic,
 * closure_receives_caustic). */
enum caustic_role { CAUSTIC_CARRIER, CAUSTIC_RECEIVER, CAUSTIC_NEITHER, CAUSTIC_ROLE_COUNT };

static int closure_caustic_role(const closure *c, float max_roughness);

/* Σ f·|cos θi| over the closures, each in its own frame and scaled by the
 * layers over it (and, bumped diffuse ones, by their bump shadowing), and
 * Σ (sample_weight_k / sum) pdf_k: the densities are the lobes' own. With
 * `parts` (not NULL) also the sums over each caustic role's closures. */
static vec3 eval_mixture_parts(const bsdf *b, vec3 wo, vec3 wi, float *pdf, float max_roughness,
                               vec3 parts[CAUSTIC_ROLE_COUNT])
{
    vec3 value = v3s(0.0f);
    float p = 0.0f;
    query q[BSDF_MAX_FRAMES];
    float mu[BSDF_MAX_FRAMES];
    for (uint32_t f = 0; f < b->frame_count; f++) {
        q[f] = make_query(b, f, wo, wi);
        mu[f] = q[f].wo.z;
    }
    vec3 scales[BSDF_MAX_LAYERS];
    if (b->layer_count)
        layer_scales(b, mu, scales);
    for (uint32_t k = 0; k < b->count; k++) {
        float pk;
        const closure *c = &b->closures[k];
        vec3 v = closure_eval(c, &q[c->frame], &pk);
        if (c->frame != 0 && closure_bump_shadowed(c))
            v = v3_scale(v, bump_shadowing(b->frames[0].n, b->frames[c->frame].n, wi));
        if (b->closures[k].under_layers)
            v = v3_mul(v, scale_under(scales, b->closures[k].under_layers));
        value = v3_add(value, v);
        if (parts) {
            int role = closure_caustic_role(c, max_roughness);
            parts[role] = v3_add(parts[role], v);
        }
        p += b->closures[k].sample_weight * pk;
    }
    *pdf = b->sample_weight_sum > 0.0f ? p / b->sample_weight_sum : 0.0f;
    if (!v3_is_finite(value) || !isfinite(*pdf)) {
        *pdf = 0.0f;
        if (parts)
            for (int r = 0; r < CAUSTIC_ROLE_COUNT; r++)
                parts[r] = v3s(0.0f);
        return v3s(0.0f);
    }
    return value;
}

static vec3 eval_mixture(const bsdf *b, vec3 wo, vec3 wi, float *pdf)
{
    return eval_mixture_parts(b, wo, wi, pdf, 0.0f, NULL);
}

int bsdf_lambertian_about(const bsdf *b, vec3 n, vec3 *rho)
{
    vec3 sum = v3s(0.0f);
    if (b->count == 0 || b->frames[0].n.x != n.x || b->frames[0].n.y != n.y || b->frames[0].n.z != n.z)
        return 0;
    for (uint32_t k = 0; k < b->count; k++) {
        const closure *c = &b->closures[k];
        if (c->type != PHOS_CLOSURE_DIFFUSE || c->frame != 0 || c->under_layers)
            return 0;
        sum = v3_add(sum, c->weight);
    }
    *rho = sum;
    return 1;
}

void bsdf_init(bsdf *b, vec3 n_shading, vec3 n_geometric)
{
    b->frames[0] = frame_from_normal(n_shading);
    b->frame_count = 1;
    b->ng = n_geometric;
    b->count = 0;
    b->sample_weight_sum = 0.0f;
    b->layer_count = 0;
}

uint32_t bsdf_add_frame(bsdf *b, vec3 n, vec3 t)
{
    frame f = frame_from_normal(n);
    vec3 x = v3_sub(t, v3_scale(n, v3_dot(t, n)));
    if (v3_is_finite(x) && v3_length2(x) > 1e-12f) {
        f.t = v3_normalize(x);
        f.b = v3_cross(n, f.t);
    }
    for (uint32_t k = 0; k < b->frame_count; k++)
        if (memcmp(&b->frames[k], &f, sizeof(f)) == 0)
            return k;
    if (b->frame_count >= BSDF_MAX_FRAMES)
        return 0;
    b->frames[b->frame_count] = f;
    return b->frame_count++;
}

vec3 bsdf_normal(const bsdf *b)
{
    uint32_t first = b->count ? b->closures[0].frame : 0;
    vec3 sum = v3s(0.0f);
    int shared = 1;
    for (uint32_t k = 0; k < b->count; k++) {
        sum = v3_add(sum, v3_scale(b->frames[b->closures[k].frame].n, b->closures[k].sample_weight));
        shared &= b->closures[k].frame == first;
    }
    if (shared || !(v3_length2(sum) > 0.0f))
        return b->frames[first].n;
    return v3_normalize(sum);
}

/* Splits b's closures into those `in_first` accepts and the others. */
/* Closures for which in_first(c, threshold) holds go to `first`. */
/* The closures of b into `first` (those in_first accepts) and `second`
 * (the rest; NULL: not wanted), each with b's frames and layers. */
static void split_closures(const bsdf *b, int (*in_first)(const closure *, float), float threshold, bsdf *first,
                          bsdf *second)
{
    bsdf *parts[2] = {first, second};
    for (int k = 0; k < 2; k++) {
        bsdf *part = parts[k];
        if (!part)
            continue;
        part->frame_count = b->frame_count;
        for (uint32_t f = 0; f < b->frame_count; f++)
            part->frames[f] = b->frames[f];
        part->ng = b->ng;
        part->count = 0;
        part->sample_weight_sum = 0.0f;
        part->layer_count = b->layer_count;
        for (uint32_t j = 0; j < b->layer_count; j++)
            part->layers[j] = b->layers[j];
    }
    for (uint32_t i = 0; i < b->count; i++) {
        const closure *c = &b->closures[i];
        bsdf *dst = in_first(c, threshold) ? first : second;
        if (!dst)
            continue;
        dst->closures[dst->count++] = *c;
        dst->sample_weight_sum += c->sample_weight;
    }
}

int closure_is_diffuse(const closure *c)
{
    return c->type == PHOS_CLOSURE_DIFFUSE || c->type == PHOS_CLOSURE_PRINCIPLED_DIFFUSE ||
           c->type == PHOS_CLOSURE_OREN_NAYAR || c->type == PHOS_CLOSURE_SHEEN;
}

static int closure_is_diffuse_at(const closure *c, float unused) { return (void)unused, closure_is_diffuse(c); }

void bsdf_split(const bsdf *b, bsdf *diffuse, bsdf *other)
{
    split_closures(b, closure_is_diffuse_at, 0.0f, diffuse, other);
}

/* Whether closure c has a lobe that is not a Dirac delta (transparent
 * pass-through counts as delta). */
static int closure_has_non_delta(const closure *c)
{
    switch (c->type) {
    case PHOS_CLOSURE_DIFFUSE:
    case PHOS_CLOSURE_PRINCIPLED_DIFFUSE:
    case PHOS_CLOSURE_OREN_NAYAR:
    case PHOS_CLOSURE_SHEEN:
    case PHOS_CLOSURE_TRANSLUCENT:
        return 1;
    case PHOS_CLOSURE_TRANSPARENT:
        return 0;
    case PHOS_CLOSURE_GLASS:
        return !closure_is_sharp(c) || (!glass_per_microfacet(c) && !refraction_is_sharp(c));
    default:
        return !closure_is_sharp(c);
    }
}

int bsdf_has_non_delta(const bsdf *b)
{
    for (uint32_t i = 0; i < b->count; i++)
        if (closure_has_non_delta(&b->closures[i]))
            return 1;
    return 0;
}

int closure_transmits(const closure *c)
{
    return c->type == PHOS_CLOSURE_REFRACTION || c->type == PHOS_CLOSURE_GLASS || c->type == PHOS_CLOSURE_TRANSLUCENT;
}

int bsdf_transmits(const bsdf *b)
{
    for (uint32_t i = 0; i < b->count; i++)
        if (closure_transmits(&b->closures[i]))
            return 1;
    return 0;
}

static int closure_is_delta(const closure *c) { return !closure_has_non_delta(c); }
static int closure_is_delta_at(const closure *c, float unused) { return (void)unused, closure_is_delta(c); }

float bsdf_split_delta(const bsdf *b, bsdf *delta, bsdf *rest)
{
    split_closures(b, closure_is_delta_at, 0.0f, delta, rest);
    return b->sample_weight_sum > 0.0f ? delta->sample_weight_sum / b->sample_weight_sum : 0.0f;
}

/* The microfacet closures' roughest lobe (Blender roughness, √α): a
 * glass's refraction lobe may be rougher than its reflection. */
static float closure_roughest(const closure *c)
{
    float a = fmaxf(c->alpha, c->alpha_y);
    if (c->type == PHOS_CLOSURE_GLASS && !glass_per_microfacet(c))
        a = fmaxf(a, c->alpha_t);
    return sqrtf(a);
}

int closure_scatters_caustic(const closure *c, float max_roughness)
{
    if (closure_is_delta(c))
        return 1;
    switch (c->type) {
    case PHOS_CLOSURE_REFLECTION:
    case PHOS_CLOSURE_METAL:
    case PHOS_CLOSURE_GLASS:
    case PHOS_CLOSURE_REFRACTION:
        return closure_roughest(c) < max_roughness;
    default:
        /* A glossy dielectric layer (REFLECTION_FRESNEL: the Principled
         * specular and coat) reflects a few per cent: its caustics are
         * faint, and tracing them cost 100 times the photon pass on a
         * product shot (docs/algorithms.md §12). Sharp, it is a mirror. */
        return 0;
    }
}

float bsdf_split_caustic(const bsdf *b, float max_roughness, bsdf *caustic, bsdf *rest)
{
    split_closures(b, closure_scatters_caustic, max_roughness, caustic, rest);
    return b->sample_weight_sum > 0.0f ? caustic->sample_weight_sum / b->sample_weight_sum : 0.0f;
}

int closure_receives_caustic(const closure *c, float max_roughness)
{
    if (closure_scatters_caustic(c, max_roughness) || closure_transmits(c))
        return 0;
    return closure_is_diffuse(c) || !(closure_roughest(c) < max_roughness);
}

static int closure_caustic_role(const closure *c, float max_roughness)
{
    if (closure_scatters_caustic(c, max_roughness))
        return CAUSTIC_CARRIER;
    return closure_receives_caustic(c, max_roughness) ? CAUSTIC_RECEIVER : CAUSTIC_NEITHER;
}

void bsdf_caustic_receivers(const bsdf *b, float max_roughness, bsdf *receivers)
{
    split_closures(b, closure_receives_caustic, max_roughness, receivers, NULL);
}

/* f_part / f per channel; 0 where f is 0 (the sample then carries nothing). */
static vec3 share_of(vec3 part, vec3 f)
{
    vec3 r;
    r.x = f.x > 0.0f ? clampf(part.x / f.x, 0.0f, 1.0f) : 0.0f;
    r.y = f.y > 0.0f ? clampf(part.y / f.y, 0.0f, 1.0f) : 0.0f;
    r.z = f.z > 0.0f ? clampf(part.z / f.z, 0.0f, 1.0f) : 0.0f;
    return r;
}

void bsdf_caustic_shares(const bsdf *b, vec3 wo, const bsdf_sample *bs, float max_roughness, vec3 *carry,
                         vec3 *receive)
{
    /* A delta lobe's direction has no density under the other closures:
     * the whole sample is the delta's, and deltas carry caustics. */
    if (bs->flags & BSDF_DELTA) {
        *carry = v3s(1.0f);
        *receive = v3s(0.0f);
        return;
    }
    /* Where the non-delta closures all have one role, the shares are 0
     * and 1 without evaluating them (a rough metal or a plain diffuse
     * surface: most vertices). */
    int roles = 0;
    for (uint32_t k = 0; k < b->count; k++)
        if (closure_has_non_delta(&b->closures[k]))
            roles |= 1 << closure_caustic_role(&b->closures[k], max_roughness);
    if (roles == 0 || (roles & (roles - 1)) == 0) {
        *carry = v3s(roles == 1 << CAUSTIC_CARRIER ? 1.0f : 0.0f);
        *receive = v3s(roles == 1 << CAUSTIC_RECEIVER ? 1.0f : 0.0f);
        return;
    }
    float pdf;
    vec3 parts[CAUSTIC_ROLE_COUNT] = {{0}};
    vec3 f = eval_mixture_parts(b, wo, bs->wi, &pdf, max_roughness, parts);
    *carry = share_of(parts[CAUSTIC_CARRIER], f);
    *receive = share_of(parts[CAUSTIC_RECEIVER], f);
}

void bsdf_scale_caustic_carriers(bsdf *b, float max_roughness, vec3 scale)
{
    /* The weights only: sample_weight, and so the mixture's pdf, stay
     * those of the BSDF a path samples. */
    for (uint32_t i = 0; i < b->count; i++)
        if (closure_scatters_caustic(&b->closures[i], max_roughness))
            b->closures[i].weight = v3_mul(b->closures[i].weight, scale);
}

int bsdf_has_non_caustic(const bsdf *b, float max_roughness)
{
    for (uint32_t i = 0; i < b->count; i++)
        if (!closure_scatters_caustic(&b->closures[i], max_roughness))
            return 1;
    return 0;
}

int bsdf_add_closure(bsdf *b, const closure *c)
{
    /* Emission and holdout are not scattering (material.h reads them apart). */
    if (c->type == PHOS_CLOSURE_EMISSION || c->type == PHOS_CLOSURE_HOLDOUT || c->type >= PHOS_CLOSURE_TYPE_COUNT)
        return 1;
    closure k = *c;
    k.adjoint = 0;
    if (k.frame >= b->frame_count)
        k.frame = 0;
    if (!v3_is_finite(k.weight))
        return 1;
    /* Clamp parameters into their domains as Cycles' setup functions do. */
    k.alpha = k.alpha > 0.0f ? minf(k.alpha, 1.0f) : 0.0f;
    k.alpha_y = closure_may_be_anisotropic(&k) && k.alpha_y > 0.0f ? minf(k.alpha_y, 1.0f) : k.alpha;
    /* Cycles reads the albedo tables of an anisotropic lobe (Multiscatter
     * GGX, layering) at the roughness (αx αy)^¼ (bsdf_microfacet.h). */
    if (k.alpha_y != k.alpha)
        k.roughness = sqrtf(sqrtf(k.alpha * k.alpha_y));
    k.alpha_t = k.alpha_t > 0.0f ? minf(k.alpha_t, 1.0f) : 0.0f;
    k.transmission_tint = v3_max(k.transmission_tint, v3s(0.0f));
    k.roughness = k.roughness > 0.0f ? minf(k.roughness, 1.0f) : 0.0f;
    k.eta = (k.eta > 0.0f && isfinite(k.eta)) ? maxf(k.eta, 1e-5f) : 1.0f;
    k.f0 = v3_min(v3_max(k.f0, v3s(0.0f)), v3s(1.0f));
    k.specular_tint = v3_min(v3_max(k.specular_tint, v3s(0.0f)), v3s(1.0f));
    k.fss = v3_min(v3_max(k.fss, v3s(0.0f)), v3s(1.0f));
    /* Cycles: sample weight = average |weight| over the channels. */
    k.sample_weight = (fabsf(k.weight.x) + fabsf(k.weight.y) + fabsf(k.weight.z)) * (1.0f / 3.0f);
    if (!(k.sample_weight > 0.0f))
        return 1;
    if (b->count >= PHOS_MAX_CLOSURES)
        return 0;
    b->closures[b->count++] = k;
    b->sample_weight_sum += k.sample_weight;
    return 1;
}

vec3 bsdf_eval(const bsdf *b, vec3 wo, vec3 wi, float *pdf)
{
    float p = 0.0f;
    vec3 value = v3s(0.0f);
    if (b->count > 0)
        value = eval_mixture(b, wo, wi, &p);
    if (pdf)
        *pdf = p;
    return value;
}

vec3 bsdf_photon_weight(const bsdf *b, vec3 w_from, const bsdf_sample *bs, float *eta_scale)
{
    *eta_scale = 1.0f;
    if (bs->flags & BSDF_TRANSPARENT)
        return bs->weight;
    if (!(bs->flags & BSDF_DELTA)) {
        vec3 w = bsdf_adjoint_weight(b, w_from, bs->wi, bs->pdf);
        if (!(bs->flags & BSDF_TRANSMISSION))
            return w;
        /* The adjoint's η² split off for the roulette, as for a delta. */
        *eta_scale = 1.0f / (bs->eta * bs->eta);
        return v3_scale(w, bs->eta * bs->eta);
    }
    vec3 ns = bs->ns;
    float ng_from = fabsf(v3_dot(b->ng, w_from)), ns_to = fabsf(v3_dot(ns, bs->wi));
    if (!(ng_from > 0.0f) || !(ns_to > 0.0f))
        return v3s(0.0f);
    float correction = fabsf(v3_dot(ns, w_from)) * fabsf(v3_dot(b->ng, bs->wi)) / (ng_from * ns_to);
    if (bs->flags & BSDF_TRANSMISSION)
        *eta_scale = 1.0f / (bs->eta * bs->eta);
    return v3_scale(bs->weight, correction);
}

void bsdf_set_adjoint(bsdf *b)
{
    for (uint32_t i = 0; i < b->count; i++)
        b->closures[i].adjoint = 1;
}

/* The surface as material_bsdf builds it for a ray from the other side. */
static void bsdf_other_side(const bsdf *b, bsdf *out)
{
    *out = *b;
    for (uint32_t f = 0; f < b->frame_count; f++) /* (t, −b, −n): still right-handed */
        out->frames[f] = (frame){b->frames[f].t, v3_neg(b->frames[f].b), v3_neg(b->frames[f].n)};
    out->ng = v3_neg(b->ng);
    for (uint32_t i = 0; i < out->count; i++) /* a coating's IOR is seen from outside only */
        if (out->closures[i].type == PHOS_CLOSURE_GLASS || out->closures[i].type == PHOS_CLOSURE_REFRACTION)
            out->closures[i].eta = 1.0f / out->closures[i].eta;
}

vec3 bsdf_adjoint_weight(const bsdf *b, vec3 w_from, vec3 w_to, float pdf)
{
    float ng_from = fabsf(v3_dot(b->ng, w_from)), ng_to = fabsf(v3_dot(b->ng, w_to));
    if (!(pdf > 0.0f) || !(ng_from > 0.0f))
        return v3s(0.0f);
    bsdf other;
    const bsdf *seen = b;
    if (v3_dot(b->ng, w_to) < 0.0f) { /* transmitted: query from w_to's side */
        bsdf_other_side(b, &other);
        seen = &other;
    }
    vec3 fcos = bsdf_eval(seen, w_to, w_from, NULL); /* f(w_to, w_from)·|ns·w_from| */
    return v3_scale(fcos, ng_to / (ng_from * pdf));
}

/* Chooses closure k with probability sample_weight_k / sum and rescales
 * u_pick to a fresh uniform number for the choice inside the closure. */
static int pick_closure(const bsdf *b, float u_pick, float *u_lobe)
{
    float target = u_pick * b->sample_weight_sum;
    float start = 0.0f;
    int last = -1;
    for (uint32_t k = 0; k < b->count; k++) {
        float w = b->closures[k].sample_weight;
        if (!(w > 0.0f))
            continue;
        last = (int)k;
        if (target < start + w || k + 1 == b->count) {
            *u_lobe = clampf((target - start) / w, 0.0f, 0x1.fffffep-1f);
            return (int)k;
        }
        start += w;
    }
    *u_lobe = 0.5f;
    return last;
}

int bsdf_sample_direction(const bsdf *b, vec3 wo, float u_pick, float2 u, bsdf_sample *out)
{
    if (b->count == 0 || !(b->sample_weight_sum > 0.0f))
        return 0;
    float u_lobe;
    int k = pick_closure(b, u_pick, &u_lobe);
    if (k < 0)
        return 0;
    const closure *c = &b->closures[k];
    float pick = c->sample_weight / b->sample_weight_sum;

    lobe_sample s;
    s.value = v3s(0.0f);
    s.prob = 0.0f;
    const frame *fr = &b->frames[c->frame];
    vec3 wo_local = frame_to_local(fr, wo);
    if (!closure_sample(c, wo_local, u_lobe, u, &s))
        return 0;
    vec3 wi = v3_normalize(frame_to_world(fr, s.wi));
    if (!v3_is_finite(wi) || v3_length2(wi) == 0.0f)
        return 0;

    if (s.flags & BSDF_DELTA) {
        /* Light-leak test against the geometric normal (pass-through is exempt). */
        float ng_wi = v3_dot(b->ng, wi);
        if (!(s.flags & BSDF_TRANSPARENT) &&
            ((s.flags & BSDF_TRANSMISSION) ? ng_wi >= 0.0f : ng_wi <= 0.0f))
            return 0;
        float p = pick * s.prob;
        vec3 value = c->under_layers ? v3_mul(s.value, bsdf_layer_scale(b, c->under_layers, wo)) : s.value;
        vec3 weight = v3_scale(value, 1.0f / p);
        if (!(p > 0.0f) || !v3_is_finite(weight))
            return 0;
        out->wi = wi;
        out->weight = weight;
        out->pdf = p;
        out->flags = s.flags;
        out->eta = (s.flags & BSDF_TRANSMISSION) && !(s.flags & BSDF_TRANSPARENT) ? c->eta : 1.0f;
        out->ns = fr->n;
        out->closure = (uint32_t)k;
        return 1;
    }

    /* Non-delta: the direction only counts where the lobe that produced it
     * has density — on that lobe's side of both normals (a reflection that
     * dips below the horizon is lost, not mistaken for a transmission) and
     * where its closure's eval is nonzero — then the mixture weights it. */
    query q = make_query(b, c->frame, wo, wi);
    if (!((s.flags & BSDF_TRANSMISSION) ? transmission_side(&q) : reflection_side(&q)))
        return 0;
    float pdf_own, pdf;
    closure_eval(c, &q, &pdf_own);
    if (!(pdf_own > 0.0f))
        return 0;
    vec3 value = eval_mixture(b, wo, wi, &pdf);
    if (!(pdf > 0.0f))
        return 0;
    vec3 weight = v3_scale(value, 1.0f / pdf);
    if (!v3_is_finite(weight))
        return 0;
    out->wi = wi;
    out->weight = weight;
    out->pdf = pdf;
    out->flags = s.flags;
    /* Diffuse transmission does not refract: no η (no η² for photons). */
    out->eta = (s.flags & BSDF_TRANSMISSION) && !(s.flags & BSDF_DIFFUSE) ? c->eta : 1.0f;
    out->ns = fr->n;
    out->closure = (uint32_t)k;
    return 1;
}

vec3 bsdf_transparency(const bsdf *b)
{
    vec3 t = v3s(0.0f);
    for (uint32_t k = 0; k < b->count; k++)
        if (b->closures[k].type == PHOS_CLOSURE_TRANSPARENT)
            t = v3_add(t, b->closures[k].weight);
    return t;
}
