/*
 * bsdf.h — the scattering function at a surface point: a weighted sum of
 * closures, as Cycles builds from a shader node tree.
 *
 * Conventions (pbrt's): wo points toward the viewer (−ray direction), wi
 * toward where light comes from; both unit length, in world space. The
 * shading normal is flipped to the side of wo when the ray hits a back face,
 * and eta is then 1/ior (Cycles' convention), so a closure never needs to
 * know which side it was hit from.
 *
 * Values include the cosine: eval returns f(wo, wi)·|cos θi| (1/sr), and a
 * sample's weight is f·|cos θi| / pdf. No 1/η² radiance scaling is applied
 * across refraction (as Cycles): radiance re-enters the medium it left.
 */
#ifndef PHOS_BSDF_H
#define PHOS_BSDF_H

#include "phos.h"
#include "sampling/sampler.h"
#include "shading/fresnel.h"
#include "util/vec.h"

enum bsdf_flags {
    BSDF_DELTA = 1 << 0,        /* a Dirac lobe: pdf is not a density, MIS does not apply */
    BSDF_TRANSMISSION = 1 << 1, /* wi is on the other side of the surface */
    BSDF_TRANSPARENT = 1 << 2,  /* straight pass-through (does not count as a bounce) */
    BSDF_DIFFUSE = 1 << 3,
    BSDF_GLOSSY = 1 << 4
};

/* Below this GGX alpha (anisotropic: √(αx αy), as Cycles compares αx αy)
 * a microfacet lobe is treated as perfectly sharp. */
#define BSDF_SHARP_ALPHA 1e-4f
/* |η − 1| below this: the interface does not bend light, refraction is a
 * straight pass-through whatever the roughness (as Cycles 3.4). */
#define BSDF_INDEX_MATCHED 1e-4f

typedef struct closure {
    uint32_t type;          /* enum phos_closure_type */
    vec3 weight;            /* linear RGB, textures already applied */
    float roughness;        /* Blender roughness in [0,1]; anisotropic: (αx αy)^¼, set by bsdf_add_closure */
    float alpha;            /* GGX alpha = roughness²; anisotropic: αx, along the frame's tangent */
    float alpha_y;          /* REFLECTION, REFLECTION_FRESNEL, METAL: αy, across the tangent
                               (anisotropic GGX); 0 or other types: alpha */
    float alpha_t;          /* GLASS (MACRO): GGX alpha of the refraction lobe */
    vec3 transmission_tint; /* GLASS: colour applied to refracted light only */
    float eta;              /* relative IOR across the surface as seen from wo's side */
    vec3 f0;                /* REFLECTION_FRESNEL, METAL: reflectance at normal incidence;
                               OREN_NAYAR: the albedo of its multiple-scattering term */
    vec3 specular_tint;     /* METAL: F82 tint; GLASS (MICROFACET): f0 = F0(η)·tint */
    uint32_t glass_fresnel; /* enum phos_glass_fresnel */
    uint32_t microfacet;    /* enum phos_microfacet */
    vec3 fss;               /* GGX_MULTISCATTER: mean single-scattering Fresnel */
    float film_thickness;   /* nm, thin film when > THIN_FILM_MIN_THICKNESS */
    float film_ior;         /* the film's IOR (relative to the outside) */
    uint32_t under_layers;  /* bit j: lies under the bsdf's layers[j] */
    float sample_weight;    /* probability mass for picking this closure when sampling */
    uint32_t adjoint;       /* 1: sampled for photons (bsdf_set_adjoint); set by bsdf_add_closure to 0 */
    uint32_t frame;         /* its shading frame: the bsdf's frames[frame] (0: the surface's) */
} closure;

/* A layer over other closures of the BSDF (Cycles 4's Principled BSDF):
 * those under it are scaled by 1 − max over channels of weight × its
 * directional albedo toward the viewer, and by a coat's tint raised to the
 * optical depth 1/cos θt (bsdf_layer_scale). A copy of the layer closure's
 * parameters, kept apart so that bsdf_split's parts keep their layers. */
typedef struct bsdf_layer {
    uint32_t type;          /* REFLECTION_FRESNEL (a dielectric: specular or coat) or SHEEN */
    float roughness, eta;
    uint32_t microfacet;    /* enum phos_microfacet */
    vec3 f0, fss;
    float film_thickness, film_ior;
    vec3 weight;            /* the layer's weight relative to those under it */
    vec3 tint;              /* a coat's colour at normal incidence; white: none */
    float tint_weight;
    uint32_t frame;         /* the layer closure's shading frame (bsdf frames[frame]) */
} bsdf_layer;
#define BSDF_MAX_LAYERS 6

/* Each closure has its own shading frame, as each Cycles closure has its
 * own N (and T when anisotropic): the surface's, and one per distinct
 * Normal (Bump, Normal Map, Coat Normal) or Tangent bound to a closure. */
#define BSDF_MAX_FRAMES (PHOS_MAX_CLOSURES + 1)

typedef struct bsdf {
    frame frames[BSDF_MAX_FRAMES]; /* shading frames, normals on the side of wo; 0: the surface's */
    uint32_t frame_count;
    vec3 ng;                /* geometric normal, on the side of wo */
    uint32_t count;
    closure closures[PHOS_MAX_CLOSURES];
    float sample_weight_sum;
    uint32_t layer_count;
    bsdf_layer layers[BSDF_MAX_LAYERS];
} bsdf;

typedef struct bsdf_sample {
    vec3 wi;                /* sampled direction (world) */
    vec3 weight;            /* f·|cos θi| / pdf, the throughput factor */
    float pdf;              /* solid-angle pdf of the whole mixture; for a delta lobe the
                               probability of having picked it */
    uint32_t flags;         /* enum bsdf_flags of the sampled lobe */
    float eta;              /* a refraction: the sampled closure's relative IOR (from wo's side); else 1 */
    vec3 ns;                /* the sampled closure's shading normal */
    uint32_t closure;       /* index of the sampled closure in the bsdf */
} bsdf_sample;

/* n_shading and n_geometric must be unit length and already face wo;
 * n_shading is frame 0, the one of closures that have none of their own. */
void bsdf_init(bsdf *b, vec3 n_shading, vec3 n_geometric);

/* The index of the shading frame with unit normal n (facing wo) and, for
 * anisotropic closures, its x axis along the tangent t projected onto the
 * plane ⊥ n (Cycles' make_orthonormals_tangent); t = 0: any x axis. An
 * identical frame already present is shared; 0 (the surface's) when full.
 * A t parallel to n counts as none. */
uint32_t bsdf_add_frame(bsdf *b, vec3 n, vec3 t);

/* The normal a denoiser is given, as Cycles' denoising features: the
 * closures' shading normals weighted by their sampling weights (frame 0's
 * when there is no closure). */
vec3 bsdf_normal(const bsdf *b);

/* Adds a closure (weight and parameters set; sample_weight is computed
 * here). Closures with zero weight are dropped; returns 0 when full. */
int bsdf_add_closure(bsdf *b, const closure *c);

/* Adds a layer; returns its index, or -1 when full (BSDF_MAX_LAYERS). */
int bsdf_add_layer(bsdf *b, const bsdf_layer *layer);

/* How much of a closure under the layers `under_layers` (bit j: layers[j])
 * reaches the viewer at wo (world): the product of the layers' scales. */
vec3 bsdf_layer_scale(const bsdf *b, uint32_t under_layers, vec3 wo);

/* Σ over non-delta closures of f·|cos θi| (1/sr), and the mixture pdf of
 * sampling wi (solid angle), where pdf may be NULL. */
vec3 bsdf_eval(const bsdf *b, vec3 wo, vec3 wi, float *pdf);

/* Samples a direction: u_pick chooses the closure, u the direction within
 * it. Returns 0 when no direction could be sampled (absorbed). */
int bsdf_sample_direction(const bsdf *b, vec3 wo, float u_pick, float2 u, bsdf_sample *out);

/* The throughput factor of light (a photon) that arrived along -w_from,
 * i.e. from direction w_from, and leaves toward w_to: the adjoint BSDF
 * f*(w_from -> w_to) = f(w_to, w_from) with Veach's shading-normal
 * correction (Veach 1997 §5.3.2, eq. 5.17), times |cos θ| / pdf:
 *   f(w_to, w_from)·|ns·w_from| · |ng·w_to| / (|ng·w_from| · pdf).
 * b is built for a ray arriving from w_from's side, as photon tracing
 * builds it; where w_to lies on the other side the reciprocal query is made
 * on the surface as seen from there (normals reversed, each interface's
 * relative IOR inverted). The BSDFs here are not symmetric — a refraction
 * lobe's Fresnel split at the shading normal depends on which side it is
 * entered from — so photons weighted by f(w_from, w_to) would not converge
 * to what camera paths compute with f (docs/algorithms.md §3). pdf is the
 * density with which w_to was sampled (bsdf_sample.pdf); non-delta lobes
 * only. */
vec3 bsdf_adjoint_weight(const bsdf *b, vec3 w_from, vec3 w_to, float pdf);

/* The weight of a photon that arrived from w_from and was scattered by the
 * sample bs of b (b prepared with bsdf_set_adjoint), times *eta_scale:
 * bsdf_adjoint_weight for a non-delta lobe; a delta lobe's own weight with
 * the same shading-normal correction; a pass-through's own weight. Across
 * a refraction the adjoint carries 1/η² (f(ωo→ωi; η) = η² f(ωi→ωo; 1/η)
 * when radiance carries no 1/η², as here and in Cycles: light entering
 * water from air carries T/η²), which is returned in *eta_scale (1
 * otherwise) and left out of the weight. It is
 * returned apart so that Russian roulette does not end half the photons
 * entering glass only for their power to grow back by η² as they leave. */
vec3 bsdf_photon_weight(const bsdf *b, vec3 w_from, const bsdf_sample *bs, float *eta_scale);

/* Prepares b to be sampled for photons, whose weights are the adjoint's
 * (bsdf_adjoint_weight): the sampling density must cover every direction
 * the adjoint can send light to. A MACRO glass picks its reflection lobe
 * with F at the shading normal, which is 1 beyond the critical angle from
 * inside; but seen from outside, a rough refraction lobe can carry light
 * into those directions, so for photons the pick of reflection is capped
 * at BSDF_ADJOINT_MAX_REFLECT. Values are unchanged, only densities. */
#define BSDF_ADJOINT_MAX_REFLECT 0.75f
void bsdf_set_adjoint(bsdf *b);

/* Splits b into its diffuse closures (Lambert, Principled diffuse,
 * Oren-Nayar, sheen) and all others (glossy, specular, glass,
 * transparent, translucent): the split of Jensen's rendering equation into
 * f_r,d and f_r,s (course notes 2002). The layering between the closures
 * is kept (each part still sees the layers over it). The diffuse part is
 * what the indirect-diffuse providers estimate, and they gather over the
 * hemisphere in front of the surface only (the irradiance cache's records
 * hold irradiance from that side, Ward et al. 1988): a translucent closure,
 * whose light comes from behind, goes with the rest, which camera paths
 * trace on and whose photon estimate reads both sides (final_gather.c). */
void bsdf_split(const bsdf *b, bsdf *diffuse, bsdf *other);

/* Whether a closure is one of bsdf_split's diffuse ones. */
int closure_is_diffuse(const closure *c);

/* Whether b is Lambertian reflection about the unit normal n alone: only
 * PHOS_CLOSURE_DIFFUSE closures, in the surface's own shading frame,
 * whose normal is n, under no layer. Then, for every wi with wi·n > 0,
 *     bsdf_eval(b, wo, wi) = (wi·ng > 0 ? ρ/π : 0) · (wi·n),
 * with ρ = the closures' summed weight, written to *rho. A density
 * estimate then sums photon powers and multiplies by ρ/π once (as
 * Mitsuba's photon mapper reads irradiance × diffuse reflectance / π),
 * instead of evaluating the BSDF per photon. */
int bsdf_lambertian_about(const bsdf *b, vec3 n, vec3 *rho);

/* What a denoiser is told about a surface (Cycles' denoising features,
 * Blender 4.5 and 5.0): each closure's albedo toward wo — its weight times
 * the share of light it returns, under its layers — summed apart for the
 * diffuse-like closures (Lambert, Oren-Nayar, sheen, and microfacet lobes
 * rougher than α = 0.075) and the specular rest, and the closures'
 * sampling weights (each times its albedo estimate, as Cycles weighs
 * closures), all and diffuse-like. */
typedef struct bsdf_features {
    vec3 albedo_diffuse, albedo_specular;
    float weight_total, weight_diffuse;
} bsdf_features;
void bsdf_denoising_features(const bsdf *b, vec3 wo, bsdf_features *out);

/* Sets the closures' pick weights to the light each returns toward wo
 * (their weight × albedo estimate), as Cycles does; material_bsdf calls it
 * once the BSDF is whole. */
void bsdf_weight_picks(bsdf *b, vec3 wo);

/* Whether some closure has a non-delta lobe (next-event estimation helps). */
int bsdf_has_non_delta(const bsdf *b);

/* Splits b into the closures that are entirely delta (sharp mirrors and
 * glass, transparent pass-through) and the others, and returns the share
 * of the delta ones in b's sampling weights: the probability that a
 * sample of b picks one (0 if b cannot be sampled). */
float bsdf_split_delta(const bsdf *b, bsdf *delta, bsdf *rest);

/* Whether some closure refracts or transmits diffusely (REFRACTION, GLASS,
 * TRANSLUCENT): light can reach wo from the far side of the surface. */
int bsdf_transmits(const bsdf *b);

/* Glossy caustics (docs/algorithms.md §12): a closure scatters like a
 * specular surface on a caustic path (L S+ D) when it is a delta, or a
 * microfacet reflection or refraction whose roughest lobe has Blender
 * roughness below max_roughness. Photons pass such closures without being
 * stored, and the camera and gather rays follow them as they follow
 * mirrors; at max_roughness 0 only deltas do, as before. Glossy dielectric
 * layers (REFLECTION_FRESNEL) carry caustics only when sharp. */
int closure_scatters_caustic(const closure *c, float max_roughness);
float bsdf_split_caustic(const bsdf *b, float max_roughness, bsdf *caustic, bsdf *rest);
int bsdf_has_non_caustic(const bsdf *b, float max_roughness);

/* Glossy receivers (docs/algorithms.md §12; course notes 2002, "Caustics
 * on glossy surfaces"): at a camera vertex the caustic map's estimate is
 * read through the closures that store photons, reflect, and are diffuse
 * or at least max_roughness rough. The other closures that store photons
 * neither carry caustics nor receive them, and camera paths find the
 * caustics they show by tracing on: those that transmit (rough glass,
 * translucency; the photons under them arrived on the other side) and a
 * glossy dielectric layer smoother than max_roughness, whose lobe is too
 * narrow for a density estimate. */
int closure_receives_caustic(const closure *c, float max_roughness);
void bsdf_caustic_receivers(const bsdf *b, float max_roughness, bsdf *receivers);

/* The shares, per channel, of f(wo, bs->wi) that the closures carrying
 * caustics and those receiving them contribute, for a direction b sampled:
 * what a camera path that goes on from a receiver must leave out of the
 * light it finds (camera_path.c). A delta sample is all carrier. */
void bsdf_caustic_shares(const bsdf *b, vec3 wo, const bsdf_sample *bs, float max_roughness, vec3 *carry,
                         vec3 *receive);

/* Scales the weights of the closures that carry caustics by `scale`,
 * keeping their sampling weights: the mixture's pdf stays the one of the
 * BSDF the path samples, for MIS. */
void bsdf_scale_caustic_carriers(bsdf *b, float max_roughness, vec3 scale);
int closure_transmits(const closure *c);

/* Sum of transparent closure weights: how much light passes straight
 * through (used by shadow rays). */
vec3 bsdf_transparency(const bsdf *b);


#endif /* PHOS_BSDF_H */
