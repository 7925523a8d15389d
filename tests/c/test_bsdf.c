/*
 * test_bsdf.c — checks of the BSDF closures (bsdf.c, microfacet.c):
 *
 *  1. chi-square goodness of fit of bsdf_sample_direction's directions against the
 *     pdf reported by bsdf_eval, for every non-delta closure and a few
 *     mixtures, several incident angles and roughnesses, both sides of a
 *     dielectric (the test of Mitsuba and pbrt-v3: bin the sphere, integrate
 *     the pdf per bin, pool small bins, compare with the chi-square law);
 *  2. consistency of each sample: weight = eval / pdf, pdf = eval's pdf;
 *  3. energy: white albedos ≤ 1, Lambert = 1, delta lobes and Fresnel split;
 *  4. reciprocity of the reflection lobes and the η² law of refraction;
 *  5. the dielectric Fresnel against known values, and total internal
 *     reflection; plus the GGX normalisation and the closed-form values of
 *     the Cycles 3.4 formulas, written independently here.
 */
#include <float.h>
#include <stdint.h>
#include <string.h>

#include "shading/bsdf.h"
#include "shading/microfacet.h"
#include "chi2.h"
#include "test_util.h"

#define SAMPLES_PER_TEST 200000
#define COS_BINS 16  /* bins of cos θ in [−1, 1] (even: the horizon is a bin edge) */
#define PHI_BINS 32  /* bins of φ in [0, 2π) */
#define SUBCELLS 2   /* each bin starts as SUBCELLS² cells of adaptive Simpson */
#define MAX_DEPTH 8  /* adaptive Simpson refinements per cell */

static const float ROUGHNESS[3] = {0.1f, 0.3f, 0.7f};
static const float COS_VIEW[3] = {0.9f, 0.5f, 0.15f};

/* ------------------------------------------------------------ helpers */

static closure make_closure(uint32_t type, float roughness, float eta)
{
    closure c;
    memset(&c, 0, sizeof c);
    c.type = type;
    c.weight = v3s(1.0f);
    c.roughness = roughness;
    c.alpha = roughness * roughness;
    c.eta = eta;
    c.f0 = v3(0.9f, 0.5f, 0.1f);
    c.glass_fresnel = PHOS_GLASS_FRESNEL_MACRO;
    c.alpha_t = c.alpha;
    c.transmission_tint = v3s(1.0f);
    c.specular_tint = v3s(1.0f);
    c.fss = v3s(1.0f);
    c.film_ior = 1.33f;
    return c;
}

/* A closure with Cycles 4's GGX (height-correlated), or its Multiscatter GGX. */
static closure make_cycles4(uint32_t type, float roughness, float eta, uint32_t microfacet)
{
    closure c = make_closure(type, roughness, eta);
    c.microfacet = microfacet;
    if (type == PHOS_CLOSURE_GLASS)
        c.glass_fresnel = PHOS_GLASS_FRESNEL_MICROFACET;
    return c;
}

static closure make_glass(float roughness, float eta, uint32_t mode)
{
    closure c = make_closure(PHOS_CLOSURE_GLASS, roughness, eta);
    c.glass_fresnel = mode;
    return c;
}

/* A MACRO glass whose refraction lobe has its own roughness and tint, as
 * the Principled BSDF's transmission (Cycles 3.4). */
static closure make_glass_split(float roughness, float transmission_roughness, float eta, vec3 tint)
{
    closure c = make_glass(roughness, eta, PHOS_GLASS_FRESNEL_MACRO);
    c.alpha_t = transmission_roughness * transmission_roughness;
    c.transmission_tint = tint;
    return c;
}

static closure weighted(closure c, float w)
{
    c.weight = v3s(w);
    return c;
}

static void make_bsdf(bsdf *b, const closure *cl, int n, vec3 ns, vec3 ng)
{
    bsdf_init(b, v3_normalize(ns), v3_normalize(ng));
    for (int i = 0; i < n; i++)
        bsdf_add_closure(b, &cl[i]);
}

/* make_bsdf with a shading frame per closure: normal cn[i] (0: ns) and,
 * when ct is given and ct[i] is not 0, the tangent ct[i]. */
static void make_bsdf_tangent(bsdf *b, const closure *cl, const vec3 *cn, const vec3 *ct, int n, vec3 ns,
                              vec3 ng)
{
    bsdf_init(b, v3_normalize(ns), v3_normalize(ng));
    for (int i = 0; i < n; i++) {
        closure c = cl[i];
        vec3 t = ct ? ct[i] : v3s(0.0f);
        int own = v3_length2(cn[i]) > 0.0f || v3_length2(t) > 0.0f;
        vec3 nrm = v3_length2(cn[i]) > 0.0f ? v3_normalize(cn[i]) : b->frames[0].n;
        c.frame = own ? bsdf_add_frame(b, nrm, t) : 0;
        bsdf_add_closure(b, &c);
    }
}

static void make_bsdf_framed(bsdf *b, const closure *cl, const vec3 *cn, int n, vec3 ns, vec3 ng)
{
    make_bsdf_tangent(b, cl, cn, NULL, n, ns, ng);
}

/* An anisotropic GGX reflection closure: αx along the tangent, αy across. */
static closure make_aniso(uint32_t type, float ax, float ay, uint32_t microfacet)
{
    closure c = make_closure(type, sqrtf(ax), 1.45f);
    c.alpha = ax;
    c.alpha_y = ay;
    c.microfacet = microfacet;
    c.specular_tint = v3(0.9f, 0.6f, 0.3f);
    return c;
}

/* Direction at cos θ = z and azimuth phi in the frame f. */
static vec3 dir_in_frame(const frame *f, double z, double phi)
{
    double s = sqrt(fmax(0.0, 1.0 - z * z));
    return v3_normalize(frame_to_world(f, v3((float)(s * cos(phi)), (float)(s * sin(phi)), (float)z)));
}

/* wo at cos θ = z around n with a fixed, off-axis azimuth. */
static vec3 view_dir(vec3 n, float z)
{
    frame f = frame_from_normal(v3_normalize(n));
    return dir_in_frame(&f, z, 0.7);
}

static float avg3(vec3 v) { return (v.x + v.y + v.z) / 3.0f; }

static double rel_diff(double a, double b)
{
    double m = fmax(fabs(a), fabs(b));
    return m > 0.0 ? fabs(a - b) / m : 0.0;
}

/* ------------------------------------------- pdf integration per bin */

typedef struct integrand {
    const bsdf *b;
    vec3 wo;
    int pole; /* 0: the variable is cos θ; ∓1: s = √(1 ± cos θ), about cos θ = ∓1 */
} integrand;

/* The pdf times the Jacobian of the variable: dω = dz dφ, or about a
 * pole, z = ∓(1 − s²), dω = 2s ds dφ. In z the pdf of a lobe that covers
 * a pole varies as a function of √(1 ± z), which Simpson's rule and its
 * error estimate do not resolve (a Beckmann refraction lobe near the south
 * pole came out 10⁻⁴ short); in s it is smooth. */
static double pdf_at(const integrand *g, double v, double phi)
{
    double z = g->pole == 0 ? v : g->pole * (1.0 - v * v), jacobian = g->pole == 0 ? 1.0 : 2.0 * v;
    float pdf;
    bsdf_eval(g->b, g->wo, dir_in_frame(&g->b->frames[0], z, phi), &pdf);
    return pdf * jacobian;
}

/* Tensor-product Simpson rule on a 3×3 grid over a cell of the given area. */
static double simpson9(double f[3][3], double area)
{
    static const double w[3] = {1.0, 4.0, 1.0};
    double s = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            s += w[i] * w[j] * f[i][j];
    return s * area / 36.0;
}

/* Adaptive 2D Simpson over [z0,z1]×[p0,p1] in (cos θ, φ), where dω = dz dφ:
 * split into four until the halves agree (relative 5e-4 or 1e-10 absolute),
 * then apply the Richardson correction. f holds the cell's 3×3 values. */
static double integrate_cell(const integrand *g, double z0, double z1, double p0, double p1,
                             double f[3][3], double whole, int depth)
{
    double v[5][5];
    for (int a = 0; a < 5; a++)
        for (int c = 0; c < 5; c++)
            v[a][c] = (a % 2 == 0 && c % 2 == 0)
                          ? f[a / 2][c / 2]
                          : pdf_at(g, z0 + (z1 - z0) * a / 4.0, p0 + (p1 - p0) * c / 4.0);
    double area = 0.25 * (z1 - z0) * (p1 - p0);
    double q[2][2][3][3], part[2][2], total = 0.0;
    for (int qa = 0; qa < 2; qa++)
        for (int qc = 0; qc < 2; qc++) {
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++)
                    q[qa][qc][i][j] = v[2 * qa + i][2 * qc + j];
            part[qa][qc] = simpson9(q[qa][qc], area);
            total += part[qa][qc];
        }
    if (depth == 0 || fabs(total - whole) <= fmax(5e-4 * fabs(total), 1e-10))
        return total + (total - whole) / 15.0;
    double zm = 0.5 * (z0 + z1), pm = 0.5 * (p0 + p1), sum = 0.0;
    for (int qa = 0; qa < 2; qa++)
        for (int qc = 0; qc < 2; qc++)
            sum += integrate_cell(g, qa ? zm : z0, qa ? z1 : zm, qc ? pm : p0, qc ? p1 : pm,
                                  q[qa][qc], part[qa][qc], depth - 1);
    return sum;
}

static double integrate_bin(const integrand *g, double z0, double z1, double p0, double p1)
{
    double sum = 0.0;
    double dz = (z1 - z0) / SUBCELLS, dp = (p1 - p0) / SUBCELLS;
    for (int i = 0; i < SUBCELLS; i++)
        for (int j = 0; j < SUBCELLS; j++) {
            double a0 = z0 + i * dz, c0 = p0 + j * dp, f[3][3];
            for (int a = 0; a < 3; a++)
                for (int c = 0; c < 3; c++)
                    f[a][c] = pdf_at(g, a0 + 0.5 * dz * a, c0 + 0.5 * dp * c);
            sum += integrate_cell(g, a0, a0 + dz, c0, c0 + dp, f, simpson9(f, dz * dp), MAX_DEPTH);
        }
    return fmax(sum, 0.0);
}

/* ----------------------------------------------------- chi-square test */

#define NUM_CELLS (COS_BINS * PHI_BINS + 2) /* + a delta bin + an "absorbed" bin */

typedef struct fit_stats {
    int consistency_failures; /* samples whose weight/pdf disagree with bsdf_eval */
    int nonfinite;            /* samples with NaN/Inf */
    double mean_weight;       /* Monte Carlo albedo estimate (average over RGB) */
    double weight_sigma;      /* its standard error */
} fit_stats;

static int count_chi2_tests;

/* Draws SAMPLES_PER_TEST directions, bins them in the shading frame and
 * runs the chi-square test against the integrated pdf. delta_mass is the
 * probability of a delta (transparent) sample. Returns the p-value. */
static double chi2_fit(const bsdf *b, vec3 wo, double delta_mass, uint32_t seed, fit_stats *st)
{
    static double expected[NUM_CELLS];
    static double observed[NUM_CELLS];
    const int delta_cell = COS_BINS * PHI_BINS, absorbed_cell = delta_cell + 1;
    memset(observed, 0, sizeof observed);
    memset(st, 0, sizeof *st);
    count_chi2_tests++;

    double sum_w = 0.0, sum_w2 = 0.0;
    for (uint32_t i = 0; i < SAMPLES_PER_TEST; i++) {
        sampler s = sampler_independent(seed, 7, i);
        bsdf_sample bs;
        double w = 0.0;
        if (!bsdf_sample_direction(b, wo, sampler_1d(&s, 0), sampler_2d(&s, 1), &bs)) {
            observed[absorbed_cell] += 1.0;
        } else if (!v3_is_finite(bs.weight) || !isfinite(bs.pdf) || !v3_is_finite(bs.wi)) {
            st->nonfinite++;
        } else if (bs.flags & BSDF_DELTA) {
            observed[delta_cell] += 1.0;
            w = avg3(bs.weight);
        } else {
            vec3 l = frame_to_local(&b->frames[0], bs.wi);
            int iz = (int)((clampf(l.z, -1.0f, 1.0f) + 1.0f) * 0.5f * COS_BINS);
            double phi = atan2(l.y, l.x);
            if (phi < 0.0)
                phi += 2.0 * PHOS_PI;
            int ip = (int)(phi / (2.0 * PHOS_PI) * PHI_BINS);
            iz = iz < 0 ? 0 : (iz >= COS_BINS ? COS_BINS - 1 : iz);
            ip = ip < 0 ? 0 : (ip >= PHI_BINS ? PHI_BINS - 1 : ip);
            observed[iz * PHI_BINS + ip] += 1.0;

            /* Test 2: the sample agrees with an independent evaluation. */
            float pdf;
            vec3 f = bsdf_eval(b, wo, bs.wi, &pdf);
            vec3 expect = v3_scale(f, 1.0f / pdf);
            double scale = fmax(v3_max_component(v3_max(bs.weight, v3_neg(bs.weight))), 1e-6);
            if (!(pdf > 0.0f) || rel_diff(bs.pdf, pdf) > 1e-3 ||
                fabs(expect.x - bs.weight.x) > 1e-3 * scale ||
                fabs(expect.y - bs.weight.y) > 1e-3 * scale ||
                fabs(expect.z - bs.weight.z) > 1e-3 * scale)
                st->consistency_failures++;
            w = avg3(bs.weight);
        }
        sum_w += w;
        sum_w2 += w * w;
    }
    st->mean_weight = sum_w / SAMPLES_PER_TEST;
    st->weight_sigma = sqrt(fmax(sum_w2 / SAMPLES_PER_TEST - st->mean_weight * st->mean_weight, 0.0) /
                            SAMPLES_PER_TEST);

    /* Expected counts: N ∫_bin pdf dω; the bins at the poles in s. */
    double mass = 0.0;
    for (int iz = 0; iz < COS_BINS; iz++)
        for (int ip = 0; ip < PHI_BINS; ip++) {
            double z0 = -1.0 + 2.0 * iz / COS_BINS, z1 = -1.0 + 2.0 * (iz + 1) / COS_BINS;
            double p0 = 2.0 * PHOS_PI * ip / PHI_BINS, p1 = 2.0 * PHOS_PI * (ip + 1) / PHI_BINS;
            integrand g = {b, wo, iz == 0 ? -1 : iz == COS_BINS - 1 ? 1 : 0};
            double v0 = g.pole ? 0.0 : z0;
            double v1 = g.pole < 0 ? sqrt(1.0 + z1) : g.pole > 0 ? sqrt(1.0 - z0) : z1;
            double p = integrate_bin(&g, v0, v1, p0, p1);
            expected[iz * PHI_BINS + ip] = p * SAMPLES_PER_TEST;
            mass += p;
        }
    expected[delta_cell] = delta_mass * SAMPLES_PER_TEST;
    /* A uniform number of exactly 0 (probability 2⁻²⁴ for each of the two
     * direction dimensions) puts a cosine-weighted sample on the horizon,
     * where it has no density and is lost: a BSDF whose pdf covers the
     * whole sphere (diffuse + translucent) still loses that much. */
    const double horizon_mass = 2.0 * 0x1p-24;
    expected[absorbed_cell] = (fmax(1.0 - mass - delta_mass, 0.0) + horizon_mass) * SAMPLES_PER_TEST;

    /* Pool the cells expecting < 5 samples (smallest first) into one. */
    int order[NUM_CELLS];
    for (int i = 0; i < NUM_CELLS; i++)
        order[i] = i;
    for (int i = 1; i < NUM_CELLS; i++) { /* insertion sort by expected count */
        int k = order[i], j = i - 1;
        while (j >= 0 && expected[order[j]] > expected[k]) {
            order[j + 1] = order[j];
            j--;
        }
        order[j + 1] = k;
    }
    double chi2 = 0.0, pool_e = 0.0, pool_o = 0.0;
    int categories = 0, i = 0;
    for (; i < NUM_CELLS && (expected[order[i]] < 5.0 || pool_e < 5.0); i++) {
        if (expected[order[i]] >= 5.0 && pool_e == 0.0)
            break; /* nothing to pool */
        pool_e += expected[order[i]];
        pool_o += observed[order[i]];
    }
    if (pool_e > 0.0) {
        chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        categories++;
    } else if (pool_o > 0.0) {
        return 0.0; /* samples where the pdf says none can be */
    }
    for (; i < NUM_CELLS; i++) {
        double e = expected[order[i]], o = observed[order[i]];
        chi2 += (o - e) * (o - e) / e;
        categories++;
    }
    if (categories < 2)
        return 1.0;
    return chi2_survival(chi2, categories - 1);
}

/* A chi-square scenario: closures and normals (run at each of COS_VIEW). */
typedef struct scenario {
    char name[96];
    closure cl[4];
    vec3 cn[4];         /* a closure's own shading normal; 0: the surface's (ns) */
    vec3 ct[4];         /* its tangent (anisotropic GGX's x axis); 0: any */
    int n;
    vec3 ns, ng;
    int albedo_bounded; /* Burley diffuse is not energy conserving */
    double albedo_slack; /* how far above 1 its albedo may truly be */
} scenario;

static int build_scenarios(scenario *sc)
{
    int n = 0;
    const vec3 z = v3(0.0f, 0.0f, 1.0f);
    static const float etas[2] = {1.5f, 1.0f / 1.5f};
    static const char *mode_name[2] = {"macro", "microfacet"};

#define ADD(NAME, ...)                                                            \
    do {                                                                          \
        scenario *s_ = &sc[n++];                                                  \
        closure tmp_[] = {__VA_ARGS__};                                           \
        memset(s_, 0, sizeof *s_);                                                \
        snprintf(s_->name, sizeof s_->name, "%s", NAME);                          \
        s_->n = (int)(sizeof tmp_ / sizeof tmp_[0]);                              \
        memcpy(s_->cl, tmp_, sizeof tmp_);                                        \
        s_->ns = z;                                                               \
        s_->ng = z;                                                               \
        s_->albedo_bounded = 1;                                                   \
    } while (0)

    char name[96];
    ADD("diffuse", make_closure(PHOS_CLOSURE_DIFFUSE, 0.0f, 1.0f));
    for (int r = 0; r < 3; r++) {
        float rough = ROUGHNESS[r];
        snprintf(name, sizeof name, "principled diffuse r=%.1f", rough);
        ADD(name, make_closure(PHOS_CLOSURE_PRINCIPLED_DIFFUSE, rough, 1.0f));
        sc[n - 1].albedo_bounded = 0;
        snprintf(name, sizeof name, "reflection r=%.1f", rough);
        ADD(name, make_closure(PHOS_CLOSURE_REFLECTION, rough, 1.0f));
        snprintf(name, sizeof name, "reflection fresnel r=%.1f", rough);
        ADD(name, make_closure(PHOS_CLOSURE_REFLECTION_FRESNEL, rough, 1.45f));
        for (int e = 0; e < 2; e++) {
            snprintf(name, sizeof name, "refraction r=%.1f eta=%.3f", rough, etas[e]);
            ADD(name, make_closure(PHOS_CLOSURE_REFRACTION, rough, etas[e]));
            for (uint32_t m = 0; m < 2; m++) {
                snprintf(name, sizeof name, "glass %s r=%.1f eta=%.3f", mode_name[m], rough, etas[e]);
                ADD(name, make_glass(rough, etas[e], m));
            }
        }
    }
    for (int e = 0; e < 2; e++) {
        snprintf(name, sizeof name, "glass split r=0.2/0.6 tinted eta=%.3f", etas[e]);
        ADD(name, make_glass_split(0.2f, 0.6f, etas[e], v3(0.3f, 0.7f, 1.0f)));
        snprintf(name, sizeof name, "glass split sharp/0.4 eta=%.3f", etas[e]);
        ADD(name, make_glass_split(0.0f, 0.4f, etas[e], v3s(1.0f)));
    }
    /* Cycles 4's closures: height-correlated GGX, Multiscatter GGX (whose
     * albedo scaling changes values, not directions), F82 metal, thin
     * films, Oren-Nayar, sheen. */
    for (int r = 0; r < 3; r++) {
        float rough = ROUGHNESS[r];
        snprintf(name, sizeof name, "multiscatter reflection r=%.1f", rough);
        ADD(name, make_cycles4(PHOS_CLOSURE_REFLECTION, rough, 1.0f, PHOS_MICROFACET_GGX_MULTISCATTER));
        sc[n - 1].albedo_bounded = 0; /* 1 up to the tables' error: test_cycles4_shading.c */
        snprintf(name, sizeof name, "metal F82 r=%.1f", rough);
        ADD(name, make_cycles4(PHOS_CLOSURE_METAL, rough, 1.0f, PHOS_MICROFACET_GGX));
        sc[n - 1].cl[0].specular_tint = v3(0.9f, 0.6f, 0.3f);
        for (int e = 0; e < 2; e++) {
            snprintf(name, sizeof name, "multiscatter glass r=%.1f eta=%.3f", rough, etas[e]);
            ADD(name, make_cycles4(PHOS_CLOSURE_GLASS, rough, etas[e], PHOS_MICROFACET_GGX_MULTISCATTER));
            sc[n - 1].albedo_bounded = 0;
            snprintf(name, sizeof name, "glass tinted thin film r=%.1f eta=%.3f", rough, etas[e]);
            ADD(name, make_cycles4(PHOS_CLOSURE_GLASS, rough, etas[e], PHOS_MICROFACET_GGX));
            sc[n - 1].cl[0].specular_tint = v3(1.0f, 0.5f, 0.2f);
            sc[n - 1].cl[0].film_thickness = 400.0f;
        }
        snprintf(name, sizeof name, "oren-nayar r=%.1f", rough);
        ADD(name, make_closure(PHOS_CLOSURE_OREN_NAYAR, rough, 1.0f));
        snprintf(name, sizeof name, "sheen r=%.1f", rough);
        ADD(name, make_closure(PHOS_CLOSURE_SHEEN, rough, 1.0f));
    }
    ADD("mix principled: diffuse + specular",
        weighted(make_closure(PHOS_CLOSURE_PRINCIPLED_DIFFUSE, 0.5f, 1.0f), 0.8f),
        make_closure(PHOS_CLOSURE_REFLECTION_FRESNEL, 0.3f, 1.5f));
    sc[n - 1].albedo_bounded = 0;
    ADD("mix diffuse + glass + transparent",
        weighted(make_closure(PHOS_CLOSURE_DIFFUSE, 0.0f, 1.0f), 0.3f),
        weighted(make_glass(0.3f, 1.5f, PHOS_GLASS_FRESNEL_MACRO), 0.5f),
        weighted(make_closure(PHOS_CLOSURE_TRANSPARENT, 0.0f, 1.0f), 0.2f));
    ADD("translucent", make_closure(PHOS_CLOSURE_TRANSLUCENT, 0.0f, 1.0f));
    ADD("mix diffuse + translucent (a leaf)",
        weighted(make_closure(PHOS_CLOSURE_DIFFUSE, 0.0f, 1.0f), 0.4f),
        weighted(make_closure(PHOS_CLOSURE_TRANSLUCENT, 0.0f, 1.0f), 0.6f));
    ADD("translucent, tilted shading normal", make_closure(PHOS_CLOSURE_TRANSLUCENT, 0.0f, 1.0f));
    sc[n - 1].ns = v3_normalize(v3(0.35f, 0.1f, 1.0f));
    ADD("mix diffuse + glossy, tilted shading normal",
        weighted(make_closure(PHOS_CLOSURE_DIFFUSE, 0.0f, 1.0f), 0.5f),
        weighted(make_closure(PHOS_CLOSURE_REFLECTION, 0.5f, 1.0f), 0.5f));
    sc[n - 1].ns = v3_normalize(v3(0.35f, 0.1f, 1.0f));
    /* One shading frame per closure (a Mix of BSDFs with different Bump
     * normals): the mixture's density sums each closure's in its frame. */
    ADD("mix diffuse + glossy, each its own normal",
        weighted(make_closure(PHOS_CLOSURE_DIFFUSE, 0.0f, 1.0f), 0.4f),
        weighted(make_closure(PHOS_CLOSURE_REFLECTION, 0.3f, 1.0f), 0.6f));
    sc[n - 1].cn[0] = v3_normalize(v3(-0.3f, 0.2f, 1.0f));
    sc[n - 1].cn[1] = v3_normalize(v3(0.4f, -0.1f, 1.0f));
    ADD("mix glossy + glass, the glass's own normal",
        weighted(make_closure(PHOS_CLOSURE_REFLECTION_FRESNEL, 0.2f, 1.45f), 0.5f),
        weighted(make_glass(0.3f, 1.5f, PHOS_GLASS_FRESNEL_MICROFACET), 0.5f));
    sc[n - 1].cn[1] = v3_normalize(v3(0.1f, 0.35f, 1.0f));
    /* Anisotropic GGX (Cycles' Anisotropic/Glossy with Anisotropy,
     * Principled, Metallic): αx along a tangent turned 0.6 rad from the
     * frame's default x axis; separable (3.x), correlated (4.x), F82 metal,
     * Multiscatter, and on a tilted normal. */
    const vec3 tangent = v3(cosf(0.6f), sinf(0.6f), 0.0f);
    ADD("anisotropic reflection ax=0.05 ay=0.4", make_aniso(PHOS_CLOSURE_REFLECTION, 0.05f, 0.4f,
                                                           PHOS_MICROFACET_GGX_SEPARABLE));
    sc[n - 1].ct[0] = tangent;
    ADD("anisotropic reflection ax=0.6 ay=0.12 correlated",
        make_aniso(PHOS_CLOSURE_REFLECTION, 0.6f, 0.12f, PHOS_MICROFACET_GGX));
    sc[n - 1].ct[0] = tangent;
    ADD("anisotropic metal F82 ax=0.3 ay=0.03", make_aniso(PHOS_CLOSURE_METAL, 0.3f, 0.03f, PHOS_MICROFACET_GGX));
    sc[n - 1].ct[0] = tangent;
    ADD("anisotropic multiscatter fresnel ax=0.2 ay=0.7",
        make_aniso(PHOS_CLOSURE_REFLECTION_FRESNEL, 0.2f, 0.7f, PHOS_MICROFACET_GGX_MULTISCATTER));
    sc[n - 1].ct[0] = tangent;
    sc[n - 1].albedo_bounded = 0;
    ADD("mix diffuse + anisotropic reflection, tilted tangent frame",
        weighted(make_closure(PHOS_CLOSURE_DIFFUSE, 0.0f, 1.0f), 0.5f),
        weighted(make_aniso(PHOS_CLOSURE_REFLECTION, 0.1f, 0.5f, PHOS_MICROFACET_GGX), 0.5f));
    sc[n - 1].cn[1] = v3_normalize(v3(0.2f, -0.3f, 1.0f));
    sc[n - 1].ct[1] = v3(0.0f, 1.0f, 0.3f);
    /* Beckmann (Cycles 3.x: separable G, 4.x: correlated), sampled by its
     * visible normals: reflection, anisotropic, refraction and both glasses.
     * The value's G1(wo) by Walter's approximation of Λ exceeds the exact
     * one by up to 0.31 % (at a = 1.34), so the albedo may exceed 1 by that
     * much (1.0018 for the refraction at r = 0.6, cos θo = 0.5, by
     * quadrature); the visible-normal samples, whose weight varies little,
     * resolve it. */
    const int first_beckmann = n;
    for (int r = 0; r < 2; r++) {
        float rough = r ? 0.6f : 0.25f;
        snprintf(name, sizeof name, "beckmann reflection r=%.2f separable", rough);
        ADD(name, make_cycles4(PHOS_CLOSURE_REFLECTION, rough, 1.0f, PHOS_MICROFACET_BECKMANN_SEPARABLE));
        snprintf(name, sizeof name, "beckmann fresnel r=%.2f correlated", rough);
        ADD(name, make_cycles4(PHOS_CLOSURE_REFLECTION_FRESNEL, rough, 1.45f, PHOS_MICROFACET_BECKMANN));
        snprintf(name, sizeof name, "beckmann refraction r=%.2f", rough);
        ADD(name, make_cycles4(PHOS_CLOSURE_REFRACTION, rough, 1.5f, PHOS_MICROFACET_BECKMANN_SEPARABLE));
        snprintf(name, sizeof name, "beckmann glass macro r=%.2f eta=1/1.5", rough);
        ADD(name, make_glass(rough, 1.0f / 1.5f, PHOS_GLASS_FRESNEL_MACRO));
        sc[n - 1].cl[0].microfacet = PHOS_MICROFACET_BECKMANN_SEPARABLE;
        snprintf(name, sizeof name, "beckmann glass microfacet r=%.2f", rough);
        ADD(name, make_glass(rough, 1.5f, PHOS_GLASS_FRESNEL_MICROFACET));
        sc[n - 1].cl[0].microfacet = PHOS_MICROFACET_BECKMANN;
    }
    ADD("beckmann anisotropic ax=0.4 ay=0.05", make_aniso(PHOS_CLOSURE_REFLECTION, 0.4f, 0.05f,
                                                          PHOS_MICROFACET_BECKMANN));
    sc[n - 1].ct[0] = tangent;
    for (int k = first_beckmann; k < n; k++)
        sc[k].albedo_slack = 0.0032;
    /* Ashikhmin-Shirley (Cycles' Glossy): isotropic, anisotropic, rough. */
    ADD("ashikhmin-shirley r=0.3", make_cycles4(PHOS_CLOSURE_REFLECTION, 0.3f, 1.0f, PHOS_MICROFACET_ASHIKHMIN_SHIRLEY));
    ADD("ashikhmin-shirley r=0.9", make_cycles4(PHOS_CLOSURE_REFLECTION, 0.9f, 1.0f, PHOS_MICROFACET_ASHIKHMIN_SHIRLEY));
    ADD("ashikhmin-shirley anisotropic ax=0.3 ay=0.05",
        make_aniso(PHOS_CLOSURE_REFLECTION, 0.3f, 0.05f, PHOS_MICROFACET_ASHIKHMIN_SHIRLEY));
    sc[n - 1].ct[0] = tangent;
#undef ADD
    return n;
}

static void test_chi2_all(void)
{
    static scenario sc[96];
    int n = build_scenarios(sc);
    int total_tests = n * 3;
    double significance = 0.01 / total_tests; /* Bonferroni over all the tests */
    uint32_t seed = 1;
    for (int s = 0; s < n; s++) {
        bsdf b;
        make_bsdf_tangent(&b, sc[s].cl, sc[s].cn, sc[s].ct, sc[s].n, sc[s].ns, sc[s].ng);
        for (int a = 0; a < 3; a++) {
            vec3 wo = view_dir(sc[s].ns, COS_VIEW[a]);
            if (v3_dot(wo, sc[s].ng) <= 0.0f)
                wo = view_dir(sc[s].ng, COS_VIEW[a]);
            /* Probability of a delta sample: transparent closures, and the
             * mirror lobe of a MACRO glass whose reflection is sharp. */
            double delta_mass = 0.0;
            for (uint32_t k = 0; k < b.count; k++) {
                const closure *c = &b.closures[k];
                double pick = c->sample_weight / b.sample_weight_sum;
                if (c->type == PHOS_CLOSURE_TRANSPARENT)
                    delta_mass += pick;
                else if (c->type == PHOS_CLOSURE_GLASS && c->glass_fresnel == PHOS_GLASS_FRESNEL_MACRO &&
                         c->alpha < BSDF_SHARP_ALPHA && c->alpha_t >= BSDF_SHARP_ALPHA)
                    delta_mass += pick * fresnel_dielectric(v3_dot(wo, b.frames[0].n), c->eta);
            }
            fit_stats st;
            double p = chi2_fit(&b, wo, delta_mass, seed++, &st);
            CHECK_MSG(p > significance, "chi2 %s, cos(wo)=%.2f: p-value %.3g < %.3g", sc[s].name,
                      COS_VIEW[a], p, significance);
            CHECK_MSG(st.consistency_failures == 0, "%s cos(wo)=%.2f: %d samples disagree with eval",
                      sc[s].name, COS_VIEW[a], st.consistency_failures);
            CHECK_MSG(st.nonfinite == 0, "%s: %d non-finite samples", sc[s].name, st.nonfinite);
            /* Test 3: white albedo ≤ 1 up to Monte Carlo noise. */
            if (sc[s].albedo_bounded)
                CHECK_MSG(st.mean_weight <= 1.0 + sc[s].albedo_slack + 4.0 * st.weight_sigma + 1e-4,
                          "%s cos(wo)=%.2f: albedo %.4f > 1", sc[s].name, COS_VIEW[a], st.mean_weight);
        }
    }
    CHECK(count_chi2_tests == total_tests);
}

/* --------------------------------------------------------- energy */

/* Quadrature of Σ f·|cos θi| over the sphere: the directional albedo. */
static double albedo_quadrature(const bsdf *b, vec3 wo, int nz, int np)
{
    /* Midpoint rule in (cos θ, φ); fine enough for smooth lobes. */
    double sum = 0.0;
    for (int i = 0; i < nz; i++)
        for (int j = 0; j < np; j++) {
            double z = -1.0 + 2.0 * (i + 0.5) / nz, phi = 2.0 * PHOS_PI * (j + 0.5) / np;
            vec3 f = bsdf_eval(b, wo, dir_in_frame(&b->frames[0], z, phi), NULL);
            sum += avg3(f);
        }
    return sum * (2.0 / nz) * (2.0 * PHOS_PI / np);
}

/* Monte Carlo albedo: the mean RGB-averaged sample weight (0 if absorbed). */
static double mean_sample_weight(const bsdf *b, vec3 wo, int n, uint32_t seed)
{
    double sum = 0.0;
    for (int i = 0; i < n; i++) {
        sampler s = sampler_independent(seed, 3, (uint64_t)i);
        bsdf_sample bs;
        if (bsdf_sample_direction(b, wo, sampler_1d(&s, 0), sampler_2d(&s, 1), &bs))
            sum += avg3(bs.weight);
    }
    return sum / n;
}

static void test_energy(void)
{
    const vec3 z = v3(0.0f, 0.0f, 1.0f);
    bsdf b;

    /* Lambert: albedo 1 by quadrature of eval, and every sample weighs 1. */
    closure lambert = make_closure(PHOS_CLOSURE_DIFFUSE, 0.0f, 1.0f);
    make_bsdf(&b, &lambert, 1, z, z);
    for (int a = 0; a < 3; a++) {
        vec3 wo = view_dir(z, COS_VIEW[a]);
        CHECK_REL(albedo_quadrature(&b, wo, 400, 64), 1.0, 0.01);
        CHECK_REL(mean_sample_weight(&b, wo, 100000, 100 + a), 1.0, 0.01);
    }

    /* Sharp mirror: one direction, weight 1, pdf 1 (the only closure). */
    closure mirror = make_closure(PHOS_CLOSURE_REFLECTION, 0.0f, 1.0f);
    make_bsdf(&b, &mirror, 1, z, z);
    vec3 wo = view_dir(z, 0.6f);
    bsdf_sample bs;
    int ok = bsdf_sample_direction(&b, wo, 0.3f, (float2){0.2f, 0.9f}, &bs);
    CHECK(ok);
    if (ok) {
        CHECK(bs.flags & BSDF_DELTA);
        CHECK_REL(bs.weight.x, 1.0, 1e-6);
        CHECK_REL(bs.weight.z, 1.0, 1e-6);
        CHECK_REL(bs.pdf, 1.0, 1e-6);
        CHECK_REL(bs.wi.z, wo.z, 1e-5);
        CHECK(fabsf(bs.wi.x + wo.x) < 1e-5f && fabsf(bs.wi.y + wo.y) < 1e-5f);
    }
    float pdf = 1.0f;
    CHECK(avg3(bsdf_eval(&b, wo, v3(-wo.x, -wo.y, wo.z), &pdf)) == 0.0f && pdf == 0.0f);

    /* Sharp glass at normal incidence, η = 1.5: reflected with probability
     * F = 0.04, both outcomes weigh 1 (white), refraction goes straight on. */
    for (uint32_t mode = 0; mode < 2; mode++) {
        closure glass = make_glass(0.0f, 1.5f, mode);
        make_bsdf(&b, &glass, 1, z, z);
        int n = 100000, reflected = 0, bad = 0;
        for (int i = 0; i < n; i++) {
            sampler s = sampler_independent(99, mode, (uint64_t)i);
            if (!bsdf_sample_direction(&b, z, sampler_1d(&s, 0), sampler_2d(&s, 1), &bs)) {
                bad++;
                continue;
            }
            int refl = bs.wi.z > 0.0f;
            reflected += refl;
            if (!(bs.flags & BSDF_DELTA) || rel_diff(bs.weight.y, 1.0) > 1e-5 ||
                rel_diff(bs.pdf, refl ? 0.04 : 0.96) > 1e-4 || (!refl && bs.wi.z > -0.99999f) ||
                (!refl && !(bs.flags & BSDF_TRANSMISSION)))
                bad++;
        }
        double frac = (double)reflected / n, sigma = sqrt(0.04 * 0.96 / n);
        CHECK_MSG(fabs(frac - 0.04) < 4.0 * sigma, "sharp glass reflected fraction %.4f", frac);
        CHECK(bad == 0);
    }

    /* Sharp glass at 45°: the reflected fraction follows Fresnel (0.0502). */
    {
        closure glass = make_glass(0.0f, 1.5f, PHOS_GLASS_FRESNEL_MACRO);
        make_bsdf(&b, &glass, 1, z, z);
        vec3 w45 = v3_normalize(v3(1.0f, 0.0f, 1.0f));
        int n = 100000, reflected = 0;
        for (int i = 0; i < n; i++) {
            sampler s = sampler_independent(98, 0, (uint64_t)i);
            if (bsdf_sample_direction(&b, w45, sampler_1d(&s, 0), sampler_2d(&s, 1), &bs) && bs.wi.z > 0.0f)
                reflected++;
        }
        double F = 0.050240, frac = (double)reflected / n;
        CHECK_MSG(fabs(frac - F) < 4.0 * sqrt(F * (1.0 - F) / n), "glass 45° reflected %.4f", frac);
    }

    /* Sharp refraction under total internal reflection: nothing sampled. */
    {
        closure refr = make_closure(PHOS_CLOSURE_REFRACTION, 0.0f, 1.0f / 1.5f);
        make_bsdf(&b, &refr, 1, z, z);
        CHECK(!bsdf_sample_direction(&b, view_dir(z, 0.5f), 0.5f, (float2){0.5f, 0.5f}, &bs));
        /* ... but below the critical angle it refracts by Snell's law. */
        vec3 w = view_dir(z, 0.95f);
        CHECK(bsdf_sample_direction(&b, w, 0.5f, (float2){0.5f, 0.5f}, &bs));
        float sin_o = sqrtf(1.0f - w.z * w.z), sin_i = sqrtf(1.0f - bs.wi.z * bs.wi.z);
        CHECK_REL(sin_i * (1.0f / 1.5f), sin_o, 1e-4);
        CHECK(bs.wi.z < 0.0f && (bs.flags & BSDF_TRANSMISSION) && (bs.flags & BSDF_DELTA));
    }

    /* Transparent: straight through, weight / pick probability. */
    {
        closure cl[2] = {weighted(make_closure(PHOS_CLOSURE_TRANSPARENT, 0, 1), 0.25f),
                         weighted(make_closure(PHOS_CLOSURE_DIFFUSE, 0, 1), 0.75f)};
        cl[0].weight = v3(0.25f, 0.5f, 0.0f); /* sample weight 0.25 */
        make_bsdf(&b, cl, 2, z, z);
        CHECK(b.count == 2);
        CHECK(bsdf_sample_direction(&b, wo, 0.1f, (float2){0.5f, 0.5f}, &bs));
        CHECK(bs.flags == (BSDF_DELTA | BSDF_TRANSPARENT | BSDF_TRANSMISSION));
        CHECK_REL(bs.pdf, 0.25, 1e-6);
        CHECK_REL(bs.weight.y, 2.0, 1e-6);
        CHECK(v3_length(v3_add(bs.wi, wo)) < 1e-6f);
        vec3 t = bsdf_transparency(&b);
        CHECK(t.x == 0.25f && t.y == 0.5f && t.z == 0.0f);
        /* eval sees only the diffuse part; its pdf is scaled by 0.75. */
        vec3 wi = view_dir(z, 0.8f);
        vec3 f = bsdf_eval(&b, wo, wi, &pdf);
        CHECK_REL(f.x, 0.75 * wi.z / PHOS_PI, 1e-5);
        CHECK_REL(pdf, 0.75 * wi.z / PHOS_PI, 1e-5);
    }

    /* Bookkeeping: emission is never a BSDF closure, zero weights are
     * dropped, and a full BSDF refuses more. */
    {
        bsdf_init(&b, z, z);
        closure e = make_closure(PHOS_CLOSURE_EMISSION, 0, 1);
        CHECK(bsdf_add_closure(&b, &e) == 1 && b.count == 0);
        closure zero = weighted(make_closure(PHOS_CLOSURE_DIFFUSE, 0, 1), 0.0f);
        CHECK(bsdf_add_closure(&b, &zero) == 1 && b.count == 0);
        CHECK(!bsdf_sample_direction(&b, wo, 0.5f, (float2){0.5f, 0.5f}, &bs));
        closure d = weighted(make_closure(PHOS_CLOSURE_DIFFUSE, 0, 1), 0.5f);
        d.weight = v3(-0.3f, 0.6f, 0.9f);
        for (int i = 0; i < PHOS_MAX_CLOSURES; i++)
            CHECK(bsdf_add_closure(&b, &d) == 1);
        CHECK(bsdf_add_closure(&b, &d) == 0);
        CHECK_REL(b.closures[0].sample_weight, 0.6, 1e-6);
    }
}

/* The Translucent BSDF: f = colour/π on the far side only. A white
 * furnace (every direction of the far hemisphere lit by radiance 1)
 * transmits exactly the colour, by quadrature of eval and by the mean
 * sample weight; nothing is reflected; samples agree with eval; the
 * material transmits (two-sided light picking) and is traced with the
 * specular part, not gathered as diffuse. */
static void test_translucent(void)
{
    const vec3 z = v3(0.0f, 0.0f, 1.0f);
    closure t = make_closure(PHOS_CLOSURE_TRANSLUCENT, 0.0f, 1.45f); /* the add-on's default IOR: unused */
    t.weight = v3(0.8f, 0.5f, 0.2f);
    bsdf b;
    make_bsdf(&b, &t, 1, z, z);
    for (int a = 0; a < 3; a++) {
        vec3 wo = view_dir(z, COS_VIEW[a]);
        CHECK_REL(albedo_quadrature(&b, wo, 400, 64), avg3(t.weight), 0.01);
        int n = 50000, below = 0, consistent = 0;
        double sum_x = 0.0, sum_z = 0.0;
        for (int i = 0; i < n; i++) {
            sampler s = sampler_independent(31, (uint32_t)a, (uint64_t)i);
            bsdf_sample bs;
            if (!bsdf_sample_direction(&b, wo, sampler_1d(&s, 0), sampler_2d(&s, 1), &bs))
                continue;
            sum_x += bs.weight.x;
            sum_z += bs.weight.z;
            below += bs.wi.z < 0.0f && bs.flags == (BSDF_DIFFUSE | BSDF_TRANSMISSION) && bs.eta == 1.0f;
            float pdf;
            vec3 f = bsdf_eval(&b, wo, bs.wi, &pdf);
            consistent += rel_diff(pdf, bs.pdf) < 1e-4 && rel_diff(pdf, -bs.wi.z / PHOS_PI) < 1e-4 &&
                          rel_diff(f.x / pdf, bs.weight.x) < 1e-4;
        }
        /* Lambertian transmission, cosine sampled: every weight is the colour. */
        CHECK_REL(sum_x / n, 0.8, 1e-5);
        CHECK_REL(sum_z / n, 0.2, 1e-5);
        CHECK(below == n && consistent == n);
        /* The reflection side has neither value nor density. */
        for (int k = 0; k < 8; k++) {
            vec3 wi = view_dir(z, 0.1f + 0.1f * (float)k);
            float pdf = 1.0f;
            CHECK(v3_is_zero(bsdf_eval(&b, wo, wi, &pdf)) && pdf == 0.0f);
            vec3 wt = v3(wi.x, wi.y, -wi.z);
            vec3 f = bsdf_eval(&b, wo, wt, &pdf);
            CHECK_REL(f.y, 0.5 * wi.z / PHOS_PI, 1e-5);
            CHECK_REL(pdf, wi.z / PHOS_PI, 1e-5);
        }
    }
    CHECK(bsdf_transmits(&b) && bsdf_has_non_delta(&b) && !closure_is_diffuse(&b.closures[0]));
    bsdf diffuse, rest;
    closure leaf[2] = {weighted(make_closure(PHOS_CLOSURE_DIFFUSE, 0.0f, 1.0f), 0.5f), t};
    make_bsdf(&b, leaf, 2, z, z);
    bsdf_split(&b, &diffuse, &rest);
    CHECK(diffuse.count == 1 && rest.count == 1 && rest.closures[0].type == PHOS_CLOSURE_TRANSLUCENT);
    /* A holdout is not light: it never joins a BSDF. */
    closure h = make_closure(PHOS_CLOSURE_HOLDOUT, 0.0f, 1.0f);
    bsdf_init(&b, z, z);
    CHECK(bsdf_add_closure(&b, &h) == 1 && b.count == 0);
}

/* --------------------------------------------- geometric robustness */

static void test_light_leaks(void)
{
    /* Shading normal tilted 40° from the geometric normal. */
    vec3 ng = v3(0.0f, 0.0f, 1.0f);
    vec3 ns = v3_normalize(v3(sinf(0.7f), 0.0f, cosf(0.7f)));
    bsdf b;
    closure cl[3] = {make_closure(PHOS_CLOSURE_DIFFUSE, 0, 1),
                     make_closure(PHOS_CLOSURE_REFLECTION, 0.0f, 1),
                     make_closure(PHOS_CLOSURE_REFRACTION, 0.3f, 1.5f)};
    /* A direction above the shading horizon but below the geometric one. */
    vec3 wi = v3_normalize(v3(1.0f, 0.0f, -0.2f));
    vec3 wo = v3_normalize(v3(0.3f, 0.2f, 1.0f));
    CHECK(v3_dot(wi, ns) > 0.0f && v3_dot(wi, ng) < 0.0f);
    float pdf;
    make_bsdf(&b, &cl[0], 1, ns, ng);
    CHECK(avg3(bsdf_eval(&b, wo, wi, &pdf)) == 0.0f && pdf == 0.0f);

    /* Mirror direction below the geometric surface: rejected. */
    make_bsdf(&b, &cl[1], 1, ns, ng);
    vec3 grazing = v3_normalize(v3(-0.3f, 0.0f, 0.954f));
    bsdf_sample bs;
    CHECK(v3_dot(grazing, ns) > 0.0f && v3_dot(grazing, ng) > 0.0f);
    CHECK(v3_dot(v3_sub(v3_scale(ns, 2.0f * v3_dot(grazing, ns)), grazing), ng) < 0.0f);
    CHECK(!bsdf_sample_direction(&b, grazing, 0.5f, (float2){0.5f, 0.5f}, &bs));

    /* Transmission never returns a direction above the geometric normal. */
    make_bsdf(&b, &cl[2], 1, ns, ng);
    int leaks = 0;
    for (int i = 0; i < 20000; i++) {
        sampler s = sampler_independent(5, 0, (uint64_t)i);
        vec3 w = view_dir(ns, 0.3f + 0.7f * sampler_1d(&s, 3));
        if (v3_dot(w, ng) <= 0.0f)
            continue;
        if (bsdf_sample_direction(&b, w, sampler_1d(&s, 0), sampler_2d(&s, 1), &bs) && v3_dot(bs.wi, ng) >= 0.0f)
            leaks++;
    }
    CHECK(leaks == 0);

    /* Never NaN or Inf, even for grazing, degenerate or flipped directions. */
    closure all[6] = {make_closure(PHOS_CLOSURE_PRINCIPLED_DIFFUSE, 0.5f, 1),
                      make_closure(PHOS_CLOSURE_REFLECTION, 0.01f, 1),
                      make_closure(PHOS_CLOSURE_REFLECTION_FRESNEL, 0.02f, 1.5f),
                      make_closure(PHOS_CLOSURE_REFRACTION, 0.012f, 1.0f / 1.5f),
                      make_glass(0.011f, 1.5f, PHOS_GLASS_FRESNEL_MICROFACET),
                      make_glass(0.2f, 1.00001f, PHOS_GLASS_FRESNEL_MACRO)};
    make_bsdf(&b, all, 6, ns, ng);
    int bad = 0;
    for (int i = 0; i < 200000; i++) {
        sampler s = sampler_independent(6, 0, (uint64_t)i);
        float2 a = sampler_2d(&s, 3), c = sampler_2d(&s, 5);
        /* Includes exact poles and horizons. */
        double zo = (i % 7 == 0) ? 1.0 : (i % 11 == 0) ? 0.0 : 2.0 * a.x - 1.0;
        double zi = (i % 5 == 0) ? -1.0 : (i % 13 == 0) ? 0.0 : 2.0 * c.x - 1.0;
        vec3 o = dir_in_frame(&b.frames[0], zo, 2.0 * PHOS_PI * a.y);
        vec3 w = dir_in_frame(&b.frames[0], zi, 2.0 * PHOS_PI * c.y);
        vec3 f = bsdf_eval(&b, o, w, &pdf);
        if (!v3_is_finite(f) || !isfinite(pdf) || pdf < 0.0f)
            bad++;
        if (bsdf_sample_direction(&b, o, sampler_1d(&s, 0), sampler_2d(&s, 1), &bs) &&
            (!v3_is_finite(bs.weight) || !(bs.pdf > 0.0f) || !isfinite(bs.pdf)))
            bad++;
    }
    CHECK_MSG(bad == 0, "%d non-finite results", bad);
}

/* ------------------------------------------- one frame per closure */

/* A closure in its own frame is the closure of a BSDF whose surface normal
 * is that frame's: same values, densities and samples; the mixture is the
 * sum of its closures; a layer sees wo from its own closure's normal; a
 * delta sample reports its closure's normal (photon weights use it). */
static void test_closure_frames(void)
{
    const vec3 z = v3(0.0f, 0.0f, 1.0f), na = v3_normalize(v3(0.3f, -0.2f, 1.0f));
    closure glossy = weighted(make_closure(PHOS_CLOSURE_REFLECTION, 0.4f, 1.0f), 0.6f);
    closure diffuse = weighted(make_closure(PHOS_CLOSURE_DIFFUSE, 0.0f, 1.0f), 0.4f);
    bsdf own, alone, base, mix;
    make_bsdf(&alone, &glossy, 1, na, z);
    make_bsdf(&base, &diffuse, 1, z, z);
    closure both[2] = {glossy, diffuse};
    vec3 cn[2] = {na, v3s(0.0f)};
    make_bsdf_framed(&own, &glossy, cn, 1, z, z);
    make_bsdf_framed(&mix, both, cn, 2, z, z);
    CHECK(own.frame_count == 2 && own.closures[0].frame == 1);
    CHECK(bsdf_add_frame(&own, own.frames[1].n, v3s(0.0f)) == 1 && own.frame_count == 2); /* shared, not added */
    int mismatches = 0;
    for (int i = 0; i < 4000; i++) {
        sampler s = sampler_independent(21, 0, (uint64_t)i);
        vec3 wo = dir_in_frame(&base.frames[0], 0.05 + 0.95 * sampler_1d(&s, 0), 6.3 * sampler_1d(&s, 1));
        vec3 wi = dir_in_frame(&base.frames[0], 0.05 + 0.95 * sampler_1d(&s, 2), 6.3 * sampler_1d(&s, 3));
        float p_own, p_alone, p_base, p_mix;
        vec3 f_own = bsdf_eval(&own, wo, wi, &p_own), f_alone = bsdf_eval(&alone, wo, wi, &p_alone);
        vec3 f_base = bsdf_eval(&base, wo, wi, &p_base), f_mix = bsdf_eval(&mix, wo, wi, &p_mix);
        if (fabsf(f_own.x - f_alone.x) > 1e-6f * (1.0f + f_alone.x) || fabsf(p_own - p_alone) > 1e-6f * (1.0f + p_alone))
            mismatches++;
        /* Sample weights 0.6 and 0.4: the pdf is the weighted sum. */
        float p_expect = 0.6f * p_alone + 0.4f * p_base;
        if (fabsf(f_mix.x - (f_alone.x + f_base.x)) > 1e-5f * (1.0f + f_mix.x) ||
            fabsf(p_mix - p_expect) > 1e-5f * (1.0f + p_expect))
            mismatches++;
        bsdf_sample a, b;
        int ka = bsdf_sample_direction(&own, wo, 0.5f, sampler_2d(&s, 4), &a);
        int kb = bsdf_sample_direction(&alone, wo, 0.5f, sampler_2d(&s, 4), &b);
        if (ka != kb || (ka && (v3_length(v3_sub(a.wi, b.wi)) > 1e-6f || v3_length(v3_sub(a.ns, na)) > 1e-6f)))
            mismatches++;
    }
    CHECK_MSG(mismatches == 0, "%d mismatches between a closure in its own frame and alone", mismatches);

    /* A coat layer in the tilted frame over a diffuse in the surface's: its
     * scale depends on cos θo about the coat's normal. */
    bsdf layered;
    bsdf_init(&layered, z, z);
    bsdf_layer coat;
    memset(&coat, 0, sizeof coat);
    coat.type = PHOS_CLOSURE_REFLECTION_FRESNEL;
    coat.roughness = 0.2f;
    coat.eta = 1.5f;
    coat.f0 = v3s(fresnel_f0_from_ior(1.5f));
    coat.fss = v3s(1.0f);
    coat.weight = v3s(1.0f);
    coat.tint = v3(0.5f, 0.8f, 1.0f);
    coat.tint_weight = 1.0f;
    coat.frame = bsdf_add_frame(&layered, na, v3s(0.0f));
    CHECK(bsdf_add_layer(&layered, &coat) == 0);
    bsdf flat;
    bsdf_init(&flat, na, z);
    coat.frame = 0;
    bsdf_add_layer(&flat, &coat);
    vec3 wo = view_dir(z, 0.4f);
    vec3 s_tilted = bsdf_layer_scale(&layered, 1u, wo), s_flat = bsdf_layer_scale(&flat, 1u, wo);
    CHECK(v3_length(v3_sub(s_tilted, s_flat)) < 1e-6f);
    coat.frame = 0;
    bsdf untilted;
    bsdf_init(&untilted, z, z);
    bsdf_add_layer(&untilted, &coat);
    CHECK(fabsf(bsdf_layer_scale(&untilted, 1u, wo).x - s_tilted.x) > 1e-3f); /* the frame matters */

    /* A sharp mirror in its own frame: the delta sample reflects about it. */
    closure mirror = make_closure(PHOS_CLOSURE_REFLECTION, 0.0f, 1.0f);
    vec3 cm[1] = {na};
    bsdf m;
    make_bsdf_framed(&m, &mirror, cm, 1, z, z);
    bsdf_sample bs;
    CHECK(bsdf_sample_direction(&m, wo, 0.5f, (float2){0.5f, 0.5f}, &bs) && (bs.flags & BSDF_DELTA));
    vec3 mirrored = v3_sub(v3_scale(na, 2.0f * v3_dot(wo, na)), wo);
    CHECK(v3_length(v3_sub(bs.wi, mirrored)) < 1e-5f && v3_length(v3_sub(bs.ns, na)) < 1e-6f);
    CHECK(v3_length(v3_sub(bsdf_normal(&m), na)) < 1e-6f);

    /* Anisotropic GGX reflection is reciprocal, f(wo, wi) = f(wi, wo), in
     * a tangent frame (both G forms are symmetric in wo, wi); and turning
     * the tangent by 90° swaps the roles of αx and αy. */
    closure an[2] = {make_aniso(PHOS_CLOSURE_REFLECTION, 0.08f, 0.5f, PHOS_MICROFACET_GGX),
                     make_aniso(PHOS_CLOSURE_REFLECTION, 0.5f, 0.08f, PHOS_MICROFACET_GGX_SEPARABLE)};
    const vec3 zero[1] = {v3s(0.0f)};
    const vec3 tx[1] = {v3(1.0f, 0.2f, 0.0f)}, ty[1] = {v3(-0.2f, 1.0f, 0.0f)};
    bsdf ab, swapped, rotated;
    make_bsdf_tangent(&ab, &an[0], zero, tx, 1, z, z);
    make_bsdf_tangent(&swapped, &an[1], zero, ty, 1, z, z);
    make_bsdf_tangent(&rotated, &an[0], zero, ty, 1, z, z);
    CHECK(v3_length(v3_sub(ab.frames[ab.closures[0].frame].t, v3_normalize(tx[0]))) < 1e-6f);
    int asym = 0, differ = 0;
    an[1].microfacet = PHOS_MICROFACET_GGX;
    make_bsdf_tangent(&swapped, &an[1], zero, ty, 1, z, z);
    for (int i = 0; i < 2000; i++) {
        sampler s = sampler_independent(22, 0, (uint64_t)i);
        vec3 a = dir_in_frame(&ab.frames[0], 0.05 + 0.95 * sampler_1d(&s, 0), 6.3 * sampler_1d(&s, 1));
        vec3 c = dir_in_frame(&ab.frames[0], 0.05 + 0.95 * sampler_1d(&s, 2), 6.3 * sampler_1d(&s, 3));
        double f_ac = avg3(bsdf_eval(&ab, a, c, NULL)) / c.z, f_ca = avg3(bsdf_eval(&ab, c, a, NULL)) / a.z;
        if (fabs(f_ac - f_ca) > 1e-4 * (1.0 + f_ac))
            asym++;
        double f_sw = avg3(bsdf_eval(&swapped, a, c, NULL)) / c.z;
        if (fabs(f_ac - f_sw) > 1e-4 * (1.0 + f_ac))
            asym++;
        if (fabs(f_ac - avg3(bsdf_eval(&rotated, a, c, NULL)) / c.z) > 1e-3 * (1.0 + f_ac))
            differ++;
    }
    CHECK_MSG(asym == 0, "%d anisotropic evaluations not reciprocal or not swapped by the tangent", asym);
    CHECK(differ > 1000); /* the tangent matters */
}

/* ---------------------------------------------------- reciprocity */

static void test_reciprocity(void)
{
    const vec3 z = v3(0.0f, 0.0f, 1.0f);
    closure refl[6] = {make_closure(PHOS_CLOSURE_DIFFUSE, 0, 1),
                       make_closure(PHOS_CLOSURE_PRINCIPLED_DIFFUSE, 0.8f, 1),
                       make_closure(PHOS_CLOSURE_REFLECTION, 0.3f, 1),
                       make_closure(PHOS_CLOSURE_REFLECTION_FRESNEL, 0.4f, 1.45f),
                       make_glass(0.5f, 1.5f, PHOS_GLASS_FRESNEL_MICROFACET),
                       make_glass(0.5f, 1.0f / 1.5f, PHOS_GLASS_FRESNEL_MICROFACET)};
    int bad = 0, nonzero = 0;
    for (int k = 0; k < 6; k++) {
        bsdf b;
        make_bsdf(&b, &refl[k], 1, z, z);
        for (int i = 0; i < 2000; i++) {
            sampler s = sampler_independent(11, (uint32_t)k, (uint64_t)i);
            vec3 wo = dir_in_frame(&b.frames[0], 0.02 + 0.98 * sampler_1d(&s, 0), 6.3 * sampler_1d(&s, 1));
            vec3 wi = dir_in_frame(&b.frames[0], 0.02 + 0.98 * sampler_1d(&s, 2), 6.3 * sampler_1d(&s, 3));
            /* eval includes |cos θi|: f(wo,wi) = eval(wo,wi) / cos θi. */
            vec3 a = v3_scale(bsdf_eval(&b, wo, wi, NULL), 1.0f / wi.z);
            vec3 c = v3_scale(bsdf_eval(&b, wi, wo, NULL), 1.0f / wo.z);
            if (rel_diff(a.x, c.x) > 1e-3 || rel_diff(a.z, c.z) > 1e-3)
                bad++;
            nonzero += a.x > 0.0f;
        }
    }
    CHECK_MSG(bad == 0, "%d non-reciprocal reflection pairs", bad);
    CHECK(nonzero > 6 * 1900);

    /* Refraction (no 1/η² scaling, as Cycles): f(wo→wi; η) = η² f(wi→wo; 1/η),
     * the second seen from the other side (normal flipped). */
    closure refr[4] = {make_closure(PHOS_CLOSURE_REFRACTION, 0.4f, 1.5f),
                       make_closure(PHOS_CLOSURE_REFRACTION, 0.2f, 1.0f / 1.33f),
                       make_glass(0.4f, 1.5f, PHOS_GLASS_FRESNEL_MICROFACET),
                       make_glass(0.3f, 1.0f / 1.5f, PHOS_GLASS_FRESNEL_MICROFACET)};
    bad = 0;
    nonzero = 0;
    for (int k = 0; k < 4; k++) {
        bsdf front, back;
        closure inv = refr[k];
        inv.eta = 1.0f / refr[k].eta;
        make_bsdf(&front, &refr[k], 1, z, z);
        make_bsdf(&back, &inv, 1, v3_neg(z), v3_neg(z));
        for (int i = 0; i < 2000; i++) {
            sampler s = sampler_independent(12, (uint32_t)k, (uint64_t)i);
            vec3 wo = dir_in_frame(&front.frames[0], 0.02 + 0.98 * sampler_1d(&s, 0), 6.3 * sampler_1d(&s, 1));
            vec3 wi = dir_in_frame(&front.frames[0], -0.02 - 0.98 * sampler_1d(&s, 2), 6.3 * sampler_1d(&s, 3));
            double a = avg3(bsdf_eval(&front, wo, wi, NULL)) / fabs(wi.z);
            double c = avg3(bsdf_eval(&back, wi, wo, NULL)) / fabs(wo.z);
            double eta = refr[k].eta;
            /* Absolute floor: at the critical angle T ∝ √(η² − sin²θ) is
             * ill-conditioned in float, for values ~1e-7 of the lobe's O(1). */
            if (fabs(a - eta * eta * c) > 2e-3 * fmax(a, eta * eta * c) + 1e-5)
                bad++;
            nonzero += a > 0.0;
        }
    }
    CHECK_MSG(bad == 0, "%d refraction pairs break f = η² f'", bad);
    CHECK(nonzero > 1000);
}

/* ------------------------------------------------------- adjoint */

/* Photons are weighted by the adjoint BSDF (bsdf_adjoint_weight) and
 * sampled with bsdf_set_adjoint: the mean weight of the samples must equal
 * the adjoint's albedo, ∫ f(w_to, w_from)·|cos θ_to| dw_to, by quadrature
 * over the sphere (which needs no sampler). A sampling density that misses
 * part of the adjoint's support shows as a mean below the quadrature: the
 * MACRO glass sampled as camera paths sample it, from inside beyond the
 * critical angle, never refracts, and lost up to 58 % of the light there
 * (roughness 0.8, cos θ 0.5; 3.5 % at roughness 0.3). */
static void test_adjoint_albedo(void)
{
    const vec3 z = v3(0.0f, 0.0f, 1.0f);
    struct {
        const char *name;
        closure c;
    } cases[] = {
        {"MACRO glass r 0.8, inside", make_glass(0.8f, 1.0f / 1.5f, PHOS_GLASS_FRESNEL_MACRO)},
        {"MACRO glass r 0.3, inside", make_glass(0.3f, 1.0f / 1.5f, PHOS_GLASS_FRESNEL_MACRO)},
        {"MACRO glass r 0.8, outside", make_glass(0.8f, 1.5f, PHOS_GLASS_FRESNEL_MACRO)},
        {"microfacet glass r 0.5, inside", make_glass(0.5f, 1.0f / 1.5f, PHOS_GLASS_FRESNEL_MICROFACET)},
        {"refraction r 0.4", make_closure(PHOS_CLOSURE_REFRACTION, 0.4f, 1.5f)},
        {"rough metal r 0.5", make_closure(PHOS_CLOSURE_REFLECTION, 0.5f, 1.0f)},
        {"translucent", make_closure(PHOS_CLOSURE_TRANSLUCENT, 0.0f, 1.0f)},
    };
    const float cos_from[] = {0.9f, 0.5f, 0.2f}; /* the last two beyond the critical angle from inside */
    const int nz = 600, np = 600, n = 200000;
    for (size_t k = 0; k < sizeof(cases) / sizeof(cases[0]); k++) {
        bsdf b;
        make_bsdf(&b, &cases[k].c, 1, z, z);
        bsdf_set_adjoint(&b);
        for (size_t j = 0; j < sizeof(cos_from) / sizeof(cos_from[0]); j++) {
            vec3 w_from = view_dir(z, cos_from[j]);
            double quad = 0.0;
            for (int iz = 0; iz < nz; iz++)
                for (int ip = 0; ip < np; ip++) {
                    vec3 w_to = dir_in_frame(&b.frames[0], -1.0 + 2.0 * (iz + 0.5) / nz, 2.0 * PHOS_PI * (ip + 0.5) / np);
                    quad += avg3(bsdf_adjoint_weight(&b, w_from, w_to, 1.0f));
                }
            quad *= (2.0 / nz) * (2.0 * PHOS_PI / np);
            double sum = 0.0, sum2 = 0.0;
            for (int i = 0; i < n; i++) {
                sampler smp = sampler_independent(21, (uint32_t)(10 * k + j), (uint64_t)i);
                bsdf_sample bs;
                double w = 0.0;
                if (bsdf_sample_direction(&b, w_from, sampler_1d(&smp, 0), sampler_2d(&smp, 1), &bs))
                    w = avg3((bs.flags & BSDF_DELTA) ? bs.weight : bsdf_adjoint_weight(&b, w_from, bs.wi, bs.pdf));
                sum += w;
                sum2 += w * w;
            }
            double mean = sum / n, se = sqrt(fmax(sum2 / n - mean * mean, 0.0) / n);
            /* The quadrature's own error: a few 1e-3 for the peakiest lobe here. */
            CHECK_MSG(fabs(mean - quad) <= 5.0 * se + 5e-3 * quad,
                      "%s, cos %.1f: photons carry %.4f (± %.4f) of the adjoint albedo %.4f", cases[k].name,
                      cos_from[j], mean, se, quad);
        }
    }
}

/* ------------------------------------------------------- Fresnel */

static void test_fresnel(void)
{
    CHECK_REL(fresnel_dielectric(1.0f, 1.5f), 0.04, 1e-5);
    CHECK_REL(fresnel_dielectric(1.0f, 1.0f / 1.5f), 0.04, 1e-5);       /* symmetric at normal incidence */
    /* 45°: from Snell's law and the s/p amplitude ratios (Hecht, Optics §4.6). */
    {
        double ci = sqrt(0.5), ct = sqrt(1.0 - 0.5 / 2.25);
        double rs = (ci - 1.5 * ct) / (ci + 1.5 * ct), rp = (1.5 * ci - ct) / (1.5 * ci + ct);
        CHECK_REL(fresnel_dielectric((float)ci, 1.5f), 0.5 * (rs * rs + rp * rp), 1e-5);
        CHECK_REL(0.5 * (rs * rs + rp * rp), 0.050240, 1e-4);
    }
    /* Brewster's angle: R_p = 0, R = R_s / 2 = ((n² − 1)/(n² + 1))² / 2. */
    CHECK_REL(fresnel_dielectric(cosf(atanf(1.5f)), 1.5f), 0.5 * sqr(1.25f / 3.25f), 1e-4);
    CHECK_REL(fresnel_dielectric(0.0f, 1.5f), 1.0, 1e-6);                /* grazing */
    CHECK(fresnel_dielectric(1.0f, 1.0f) == 0.0f);                       /* index matched */
    CHECK(fresnel_dielectric(-1.0f, 1.5f) == fresnel_dielectric(1.0f, 1.5f));
    /* Total internal reflection beyond the critical angle asin(1/1.5) = 41.8°. */
    CHECK(fresnel_dielectric(cosf(0.75f), 1.0f / 1.5f) == 1.0f);
    CHECK(fresnel_dielectric(0.5f, 1.0f / 1.5f) == 1.0f);
    CHECK(fresnel_dielectric(cosf(0.72f), 1.0f / 1.5f) < 1.0f);
    /* Sharp glass refracts with probability 1 − F (computed without
     * cancellation inside bsdf.c): with one closure u_pick picks the lobe. */
    static const float cosines[5] = {1.0f, 0.8f, 0.5f, 0.2f, 0.05f};
    static const float etas[3] = {1.5f, 1.0f / 1.33f, 2.4f};
    for (int e = 0; e < 3; e++)
        for (int i = 0; i < 5; i++) {
            bsdf b;
            closure g = make_glass(0.0f, etas[e], PHOS_GLASS_FRESNEL_MACRO);
            vec3 n = v3(0.0f, 0.0f, 1.0f);
            make_bsdf(&b, &g, 1, n, n);
            bsdf_sample bs;
            float F = fresnel_dielectric(cosines[i], etas[e]);
            int ok = bsdf_sample_direction(&b, view_dir(n, cosines[i]), 0.9999f, (float2){0.5f, 0.5f}, &bs);
            if (F < 0.999f) {
                CHECK(ok && bs.wi.z < 0.0f);
                if (ok)
                    CHECK_REL(bs.pdf, 1.0 - F, 1e-4);
            } else {
                CHECK(!ok || bs.wi.z > 0.0f); /* total internal reflection */
            }
        }
    /* The same interface seen from both sides: F(θi, η) = F(θt, 1/η). */
    float ci = 0.7f, st = sqrtf(1.0f - ci * ci) / 1.5f, ct = sqrtf(1.0f - st * st);
    CHECK_REL(fresnel_dielectric(ci, 1.5f), fresnel_dielectric(ct, 1.0f / 1.5f), 1e-4);
}

/* ------------------------- GGX normalisation and closed-form values */

/* A quadrature over the hemisphere of microfacet normals, dense where a
 * lobe of roughness alpha is: θ = atan(α tan(π/2 · t)) at nt midpoints of
 * t, φ at np; f(h, dω, ctx) is called for every cell, dω its solid angle. */
typedef void (*normal_cell_fn)(vec3 h, double dw, void *ctx);

static void integrate_normals(float alpha, int nt, int np, normal_cell_fn f, void *ctx)
{
    for (int i = 0; i < nt; i++) {
        double t = (i + 0.5) / nt, u = 0.5 * PHOS_PI * t;
        double theta = atan(alpha * tan(u));
        double dtheta = alpha / (cos(u) * cos(u) * (1.0 + sqr(alpha * (float)tan(u)))) * 0.5 * PHOS_PI / nt;
        double s = sin(theta), c = cos(theta);
        for (int j = 0; j < np; j++) {
            double phi = 2.0 * PHOS_PI * (j + 0.5) / np;
            f(v3((float)(s * cos(phi)), (float)(s * sin(phi)), (float)c), s * dtheta * 2.0 * PHOS_PI / np, ctx);
        }
    }
}

/* ∫ D(h) cos θh dω and ∫ D_wo(h) dω of a lobe, through the functions
 * of its model. */
enum { SUM_GGX, SUM_GGX_ANISO, SUM_BECKMANN };
typedef struct {
    float ax, ay;
    int model;
    vec3 wo[4];
    int views;
    double proj, visible[4];
} normal_sums;

static void sum_normals(vec3 h, double dw, void *ctx)
{
    normal_sums *n = ctx;
    switch (n->model) {
    case SUM_GGX:
        n->proj += ggx_D(h, n->ax) * h.z * dw;
        for (int v = 0; v < n->views; v++)
            n->visible[v] += ggx_visible_normal_pdf(n->wo[v], h, n->ax) * dw;
        break;
    case SUM_GGX_ANISO:
        n->proj += ggx_D_aniso(h, n->ax, n->ay) * h.z * dw;
        for (int v = 0; v < n->views; v++)
            n->visible[v] += ggx_visible_normal_pdf_aniso(n->wo[v], h, n->ax, n->ay) * dw;
        break;
    default:
        n->proj += beckmann_D_aniso(h, n->ax, n->ay) * h.z * dw;
        for (int v = 0; v < n->views; v++)
            n->visible[v] += beckmann_visible_normal_pdf_aniso(n->wo[v], h, n->ax, n->ay) * dw;
    }
}

/* Moments E[hx], E[hy], E[hz], E[hz²] of the Beckmann visible normals. */
typedef struct {
    vec3 wo;
    float ax, ay;
    double e[4];
} visible_moments;

static void sum_moments(vec3 h, double dw, void *ctx)
{
    visible_moments *m = ctx;
    double p = beckmann_visible_normal_pdf_aniso(m->wo, h, m->ax, m->ay) * dw;
    m->e[0] += h.x * p;
    m->e[1] += h.y * p;
    m->e[2] += h.z * p;
    m->e[3] += h.z * h.z * p;
}

static void test_microfacet(void)
{
    /* ∫ D(h) cos θh dω = 1 and ∫ D_wo(h) dω = 1 (Heitz 2014 eq. 4 and 16),
     * by quadrature in θ with a substitution that resolves the peak. */
    static const float alphas[4] = {0.01f, 0.09f, 0.49f, 1.0f};
    for (int k = 0; k < 4; k++) {
        normal_sums n = {alphas[k], alphas[k], SUM_GGX, {v3_normalize(v3(0.6f, 0.2f, 0.4f))}, 1, 0.0, {0.0}};
        integrate_normals(alphas[k], 4000, 256, sum_normals, &n);
        CHECK_REL(n.proj, 1.0, 2e-3);
        CHECK_REL(n.visible[0], 1.0, 2e-3);
    }
    /* Anisotropic GGX: the same normalisations (Heitz 2014 eq. 4, 16, 85),
     * the θ substitution at the smaller α, the azimuth finely. */
    static const float axy[3][2] = {{0.05f, 0.4f}, {0.6f, 0.15f}, {0.3f, 0.3f}};
    for (int k = 0; k < 3; k++) {
        normal_sums n = {axy[k][0], axy[k][1], SUM_GGX_ANISO, {v3_normalize(v3(0.6f, 0.2f, 0.4f))}, 1, 0.0, {0.0}};
        integrate_normals(fminf(axy[k][0], axy[k][1]), 2000, 1024, sum_normals, &n);
        CHECK_REL(n.proj, 1.0, 3e-3);
        CHECK_REL(n.visible[0], 1.0, 3e-3);
    }
    {
        /* At αx = αy the isotropic forms; along x, Λ sees αx only. */
        vec3 h = v3_normalize(v3(0.3f, -0.2f, 0.9f)), wx = v3_normalize(v3(0.7f, 0.0f, 0.5f));
        CHECK_REL(ggx_D_aniso(h, 0.3f, 0.3f), ggx_D(h, 0.3f), 1e-5);
        CHECK_REL(ggx_lambda_aniso(h, 0.3f, 0.3f), ggx_lambda(h, 0.3f), 1e-5);
        CHECK_REL(ggx_lambda_aniso(wx, 0.5f, 0.05f), ggx_lambda(wx, 0.5f), 1e-5);
        /* The sampler draws from D_wo: the mean of h over many samples
         * leans toward the rough axis less than toward the smooth one. */
        vec3 wo = v3(0.0f, 0.0f, 1.0f);
        double mx2 = 0.0, my2 = 0.0;
        for (int i = 0; i < 20000; i++) {
            sampler sm = sampler_independent(31, 0, (uint64_t)i);
            vec3 hs = ggx_sample_visible_normal_aniso(wo, 0.5f, 0.05f, sampler_2d(&sm, 0));
            mx2 += hs.x * hs.x;
            my2 += hs.y * hs.y;
        }
        CHECK(mx2 > 20.0 * my2);
    }

    /* Beckmann: ∫ D(h) cos θh dω = 1 (Walter 2007 eq. 25), and the visible
     * normals' density integrates to 1 for every view, ∫ D_wo(h) dω = 1:
     * the microfacets seen from wo project onto the same area as the
     * macro surface (Heitz 2014 eq. 16), with the exact Λ — from the
     * normal to a grazing view, along either axis of an anisotropic α. */
    static const float beckmann_views[4][3] = {
        {0.0f, 0.0f, 1.0f}, {0.6f, 0.2f, 0.4f}, {-0.3f, 0.9f, 0.15f}, {0.99f, -0.1f, 0.03f}};
    for (int k = 0; k < 3; k++) {
        normal_sums n = {axy[k][0], axy[k][1], SUM_BECKMANN, {{0}}, 4, 0.0, {0.0}};
        for (int v = 0; v < 4; v++)
            n.wo[v] = v3_normalize(v3(beckmann_views[v][0], beckmann_views[v][1], beckmann_views[v][2]));
        integrate_normals(fminf(n.ax, n.ay), 2000, 1024, sum_normals, &n);
        CHECK_REL(n.proj, 1.0, 3e-3);
        for (int v = 0; v < 4; v++)
            CHECK_MSG(fabs(n.visible[v] - 1.0) < 3e-3, "Beckmann D_wo, α = (%g, %g), view %d: ∫ = %.5f",
                      (double)n.ax, (double)n.ay, v, n.visible[v]);
    }
    /* The exact Λ: its closed form against a quadrature of Heitz 2014's
     * integral Λ(μ) = ∫ (x tanθ − 1) P2(x) dx over x > cotθ, P2 the unit
     * Gaussian of slopes with variance ½ (α = 1, so a = cotθ); and the
     * approximation the BSDF's value uses stays within 0.4 % of its G1. */
    for (int k = 0; k < 4; k++) {
        static const double cot_t[4] = {0.05, 0.4, 1.0, 2.5};
        double a = cot_t[k], integral = 0.0;
        const int n = 200000;
        for (int i = 0; i < n; i++) {
            double x = a + 8.0 * (i + 0.5) / n;
            integral += (x / a - 1.0) * exp(-x * x) / sqrt(PHOS_PI) * 8.0 / n;
        }
        vec3 w = v3_normalize(v3(1.0f, 0.0f, (float)a));
        CHECK_REL(beckmann_lambda_exact_aniso(w, 1.0f, 1.0f), integral, 2e-4);
        CHECK_REL(1.0 / (1.0 + beckmann_lambda_aniso(w, 1.0f, 1.0f)),
                  1.0 / (1.0 + beckmann_lambda_exact_aniso(w, 1.0f, 1.0f)), 4e-3);
    }
    /* The sampler draws from D_wo: for views from the normal to 88°,
     * isotropic and anisotropic, every sample faces wo, and the sample
     * means of h and of h.z² match the moments of the density by the
     * quadrature above, within 5 standard errors. */
    {
        static const float cases[5][5] = {
            {0.0f, 0.0f, 1.0f, 0.3f, 0.3f},    /* normal incidence */
            {0.01f, 0.0f, 1.0f, 0.9f, 0.9f},   /* near it: the Gaussian start, corrected */
            {0.7f, 0.2f, 0.5f, 0.5f, 0.5f},    /* 45° or so */
            {0.99f, 0.0f, 0.035f, 0.2f, 0.2f}, /* 88° */
            {0.3f, 0.8f, 0.2f, 0.6f, 0.08f}};  /* anisotropic, oblique */
        for (int k = 0; k < 5; k++) {
            vec3 wo = v3_normalize(v3(cases[k][0], cases[k][1], cases[k][2]));
            float ax = cases[k][3], ay = cases[k][4], alpha = fminf(ax, ay);
            const int n = 200000;
            double m[4] = {0, 0, 0, 0}, m2[4] = {0, 0, 0, 0};
            int behind = 0;
            for (int i = 0; i < n; i++) {
                sampler sm = sampler_independent(97 + (uint32_t)k, 0, (uint64_t)i);
                vec3 h = beckmann_sample_visible_normal_aniso(wo, ax, ay, sampler_2d(&sm, 0));
                behind += !(v3_dot(wo, h) > 0.0f) || !(h.z > 0.0f);
                double f[4] = {h.x, h.y, h.z, h.z * h.z};
                for (int q = 0; q < 4; q++) {
                    m[q] += f[q];
                    m2[q] += f[q] * f[q];
                }
            }
            visible_moments dm = {wo, ax, ay, {0.0, 0.0, 0.0, 0.0}};
            integrate_normals(alpha, 2000, 1024, sum_moments, &dm);
            const double *e = dm.e;
            CHECK_MSG(behind == 0, "Beckmann sampler, case %d: %d normals facing away", k, behind);
            for (int q = 0; q < 4; q++) {
                double mean = m[q] / n, sigma = sqrt(fmax(m2[q] / n - mean * mean, 0.0) / n);
                CHECK_MSG(fabs(mean - e[q]) <= 5.0 * sigma + 1e-4,
                          "Beckmann sampler, case %d, moment %d: %.5f, density %.5f (σ %.1e)", k, q, mean,
                          e[q], sigma);
            }
        }
    }
    /* erf⁻¹ (Giles 2010) against C99's erff: erff(erf⁻¹(y)) = y over
     * (−1, 1) to a few float roundings, and erf⁻¹(erff(x)) = x where that
     * is well conditioned, |x| ≤ 2 (beyond, erff's last bit moves x more). */
    {
        double worst_y = 0.0, worst_x = 0.0;
        for (int i = 1; i < 400000; i++) {
            float y = -1.0f + 2.0f * (float)i / 400000.0f;
            worst_y = fmax(worst_y, fabs((double)erff(erfinvf_approx(y)) - y));
        }
        for (int i = -2000; i <= 2000; i++) {
            float x = (float)i / 1000.0f;
            worst_x = fmax(worst_x, fabs(erfinvf_approx(erff(x)) - x) / fmax(fabs(x), 1e-3));
        }
        CHECK_MSG(worst_y < 3e-7, "erff(erf⁻¹(y)) − y up to %.3g", worst_y);
        CHECK_MSG(worst_x < 2e-6, "erf⁻¹(erff(x)) − x up to %.3g |x|", worst_x);
        CHECK(erfinvf_approx(0.0f) == 0.0f);
        CHECK(isfinite(erfinvf_approx(1.0f)) && erfinvf_approx(1.0f) > 3.8f);
        CHECK(erfinvf_approx(-1.0f) == -erfinvf_approx(1.0f));
    }
    /* Ashikhmin-Shirley: p(h) is a density of h (eq. 6), isotropic or not. */
    static const float ns[3][2] = {{10.0f, 10.0f}, {200.0f, 5.0f}, {0.0f, 0.0f}};
    for (int k = 0; k < 3; k++) {
        double total = 0.0;
        const int nt = 4000, np = 1024;
        for (int i = 0; i < nt; i++) {
            double theta = 0.5 * PHOS_PI * (i + 0.5) / nt, dtheta = 0.5 * PHOS_PI / nt;
            for (int j = 0; j < np; j++) {
                double phi = 2.0 * PHOS_PI * (j + 0.5) / np;
                vec3 h = v3((float)(sin(theta) * cos(phi)), (float)(sin(theta) * sin(phi)), (float)cos(theta));
                total += ashikhmin_shirley_h_pdf(h, ns[k][0], ns[k][1]) * sin(theta) * dtheta * 2.0 * PHOS_PI / np;
            }
        }
        CHECK_REL(total, 1.0, 3e-3);
    }
    {
        vec3 steep = v3_normalize(v3(0.2f, 0.0f, 1.0f)), grazing = v3_normalize(v3(2.0f, 0.0f, 1.0f));
        CHECK(beckmann_lambda_aniso(steep, 0.3f, 0.3f) == 0.0f); /* a = 1/(0.3·0.2) ≥ 1.6 */
        double a = 1.0 / (0.5 * 2.0);
        double g1 = (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a);
        CHECK_REL(1.0 / (1.0 + beckmann_lambda_aniso(grazing, 0.5f, 0.5f)), g1, 1e-5);
    }

    /* Λ and G1 against the tan form of Walter 2007 eq. 34. */
    vec3 w = v3_normalize(v3(0.8f, 0.1f, 0.3f));
    double tan2 = (w.x * w.x + w.y * w.y) / (w.z * w.z);
    CHECK_REL(ggx_G1(w, 0.3f), 2.0 / (1.0 + sqrt(1.0 + 0.09 * tan2)), 1e-5);
    CHECK_REL(ggx_G_correlated(w, w, 0.3f),
              1.0 / (1.0 + 2.0 * ggx_lambda(w, 0.3f)), 1e-6);

    /* Closed forms, written with angles as in the papers. */
    const vec3 z = v3(0.0f, 0.0f, 1.0f);
    bsdf b;
    vec3 wo = v3_normalize(v3(0.5f, -0.2f, 0.8f));
    vec3 wi = v3_normalize(v3(-0.3f, 0.4f, 0.6f));
    double co = wo.z, ci = wi.z;

    /* GGX reflection (Cycles 3.4 bsdf_microfacet_ggx_eval_reflect):
     * f cos θi = D G1(o) G1(i) / (4 cos θo). */
    {
        double alpha = 0.3 * 0.3, a2 = alpha * alpha;
        vec3 h = v3_normalize(v3_add(wo, wi));
        double ch = h.z, t2 = (1.0 - ch * ch) / (ch * ch);
        double D = a2 / (PHOS_PI * pow(ch, 4) * sqr((float)(a2 + t2)));
        double g1o = 2.0 / (1.0 + sqrt(1.0 + a2 * (1.0 - co * co) / (co * co)));
        double g1i = 2.0 / (1.0 + sqrt(1.0 + a2 * (1.0 - ci * ci) / (ci * ci)));
        closure c = make_closure(PHOS_CLOSURE_REFLECTION, 0.3f, 1.0f);
        make_bsdf(&b, &c, 1, z, z);
        float pdf;
        vec3 f = bsdf_eval(&b, wo, wi, &pdf);
        CHECK_REL(f.y, D * g1o * g1i / (4.0 * co), 1e-4);
        CHECK_REL(pdf, D * g1o / (4.0 * co), 1e-4);

        /* Principled specular: the colour blends f0 → 1 with the Fresnel of η. */
        closure cf = make_closure(PHOS_CLOSURE_REFLECTION_FRESNEL, 0.3f, 1.45f);
        make_bsdf(&b, &cf, 1, z, z);
        vec3 ff = bsdf_eval(&b, wo, wi, NULL);
        double F0 = sqr(0.45f / 2.45f), F = fresnel_dielectric(v3_dot(wo, h), 1.45f);
        double t = (F - F0) / (1.0 - F0);
        CHECK_REL(ff.x, f.x * (0.9 * (1.0 - t) + t), 1e-4);
        CHECK_REL(ff.z, f.z * (0.1 * (1.0 - t) + t), 1e-4);
    }

    /* GGX refraction (Walter 2007 eq. 21, Cycles 3.4 eval_transmit) with η_i = 1
     * on the viewer side and η_o = 1.5: f |cos θi| =
     * |i·h||o·h| η² D G / (cos θo (i·h + η o·h)²). */
    {
        float eta = 1.5f;
        vec3 wt = v3_normalize(v3(-0.2f, 0.1f, -0.9f));
        vec3 ht = v3_normalize(v3_neg(v3_madd(wo, wt, eta)));
        double alpha = 0.4 * 0.4, a2 = alpha * alpha;
        double ch = ht.z, t2 = (1.0 - ch * ch) / (ch * ch);
        double D = a2 / (PHOS_PI * pow(ch, 4) * sqr((float)(a2 + t2)));
        double ct = wt.z;
        double g1o = 2.0 / (1.0 + sqrt(1.0 + a2 * (1.0 - co * co) / (co * co)));
        double g1t = 2.0 / (1.0 + sqrt(1.0 + a2 * (1.0 - ct * ct) / (ct * ct)));
        double oh = v3_dot(wo, ht), th = v3_dot(wt, ht);
        double expect = fabs(oh * th) * eta * eta * D * g1o * g1t / (co * sqr((float)(oh + eta * th)));
        closure c = make_closure(PHOS_CLOSURE_REFRACTION, 0.4f, eta);
        make_bsdf(&b, &c, 1, z, z);
        CHECK_REL(avg3(bsdf_eval(&b, wo, wt, NULL)), expect, 1e-4);
        CHECK(expect > 0.0);

        /* Cycles 3.4 Glass: the same refraction lobe times 1 − F(N·wo). */
        closure g = make_glass(0.4f, eta, PHOS_GLASS_FRESNEL_MACRO);
        make_bsdf(&b, &g, 1, z, z);
        CHECK_REL(avg3(bsdf_eval(&b, wo, wt, NULL)), expect * (1.0 - fresnel_dielectric(co, eta)), 1e-4);
    }

    /* Burley diffuse with retro-reflection (Cycles 3.4 PRINCIPLED_DIFFUSE_FULL). */
    {
        double rough = 0.6, fl = pow(1.0 - ci, 5), fv = pow(1.0 - co, 5);
        vec3 h = v3_normalize(v3_add(wo, wi));
        double cd = v3_dot(wi, h), rr = 2.0 * rough * cd * cd;
        double f = (1.0 - 0.5 * fl) * (1.0 - 0.5 * fv) + rr * (fl + fv + fl * fv * (rr - 1.0));
        closure c = make_closure(PHOS_CLOSURE_PRINCIPLED_DIFFUSE, (float)rough, 1.0f);
        make_bsdf(&b, &c, 1, z, z);
        CHECK_REL(avg3(bsdf_eval(&b, wo, wi, NULL)), f * ci / PHOS_PI, 1e-4);
    }
}

/* The chi-square law itself: textbook critical values. */
static void test_chi2_law(void)
{
    CHECK_REL(chi2_survival(3.841459, 1), 0.05, 1e-4);
    CHECK_REL(chi2_survival(18.307038, 10), 0.05, 1e-4);
    CHECK_REL(chi2_survival(6.634897, 1), 0.01, 1e-4);
    CHECK_REL(chi2_survival(124.342, 100), 0.05, 1e-3);
    CHECK_REL(chi2_survival(2.0, 2), exp(-1.0), 1e-9); /* dof 2: e^(−x/2) */
}

/* A diffuse closure on a normal bent away from the surface's (a Bump) is
 * darkened toward the terminator by the bump shadowing term (Chiang et
 * al. 2019, as Cycles): with n0 the surface's normal, n the closure's and
 * g = (n0·wi) / ((n·wi)(n0·n)), the value is Lambert's times 1 for g ≥ 1,
 * 0 for g < 0, and −g³ + g² + g between; the pdf is the lobe's own. A
 * closure on the surface's normal, or a glossy one, is not darkened. */
static void test_bump_shadowing(void)
{
    const vec3 n0 = v3(0.0f, 0.0f, 1.0f), n = v3_normalize(v3(0.6f, 0.0f, 1.0f));
    closure diffuse = weighted(make_closure(PHOS_CLOSURE_DIFFUSE, 0.0f, 1.0f), 1.0f);
    vec3 cn[1] = {n};
    bsdf bent, plain;
    make_bsdf_framed(&bent, &diffuse, cn, 1, n0, n0);
    make_bsdf(&plain, &diffuse, 1, n, n0); /* the same lobe with n as the surface's own normal */
    const vec3 wo = v3(0.0f, 0.0f, 1.0f);
    const float angles[] = {-80.0f, -60.0f, -20.0f, 10.0f, 40.0f, 75.0f, 85.0f};
    int shadowed = 0;
    for (size_t i = 0; i < sizeof(angles) / sizeof(angles[0]); i++) {
        float a = angles[i] * (float)(M_PI / 180.0);
        vec3 wi = v3(sinf(a), 0.0f, cosf(a));
        float p_bent, p_plain;
        vec3 f_bent = bsdf_eval(&bent, wo, wi, &p_bent), f_plain = bsdf_eval(&plain, wo, wi, &p_plain);
        float g = v3_dot(n0, wi) / (v3_dot(n, wi) * v3_dot(n0, n));
        float term = g >= 1.0f ? 1.0f : g < 0.0f ? 0.0f : -g * g * g + g * g + g;
        CHECK_MSG(fabsf(f_bent.x - term * f_plain.x) <= 1e-6f + 1e-5f * f_plain.x,
                  "wi at %g°: %g, expected %g × %g", (double)angles[i], (double)f_bent.x, (double)term,
                  (double)f_plain.x);
        CHECK_MSG(fabsf(p_bent - p_plain) <= 1e-6f + 1e-5f * p_plain, "pdf at %g°", (double)angles[i]);
        shadowed += term < 1.0f && f_plain.x > 0.0f;
    }
    CHECK_MSG(shadowed >= 2, "only %d directions test the masking", shadowed);
    /* A glossy closure on the bent normal keeps its value. */
    closure glossy = weighted(make_closure(PHOS_CLOSURE_REFLECTION, 0.5f, 1.0f), 1.0f);
    make_bsdf_framed(&bent, &glossy, cn, 1, n0, n0);
    make_bsdf(&plain, &glossy, 1, n, n0);
    vec3 wi = v3_normalize(v3(-0.9f, 0.0f, 0.3f));
    vec3 wo2 = v3_normalize(v3(0.2f, 0.0f, 1.0f));
    CHECK(fabsf(bsdf_eval(&bent, wo2, wi, NULL).x - bsdf_eval(&plain, wo2, wi, NULL).x) <= 1e-6f);
}

/* A Principled-like BSDF, a diffuse base of weight 0.55 under a white
 * dielectric specular of weight 1 (η = 1.5, returning about 5 % at normal
 * incidence): picked by weight the specular takes 1/1.55 of the samples;
 * picked by the light each returns (bsdf_weight_picks, as Cycles) it takes
 * its share of the albedo. The estimate stays unbiased (the mean sample
 * weight is the quadrature albedo either way) and its variance falls. */
static void test_pick_by_returned_light(void)
{
    const vec3 z = v3(0.0f, 0.0f, 1.0f);
    closure spec = make_closure(PHOS_CLOSURE_REFLECTION_FRESNEL, 0.25f, 1.5f);
    spec.f0 = v3s(0.04f);
    closure cl[2] = {weighted(make_closure(PHOS_CLOSURE_PRINCIPLED_DIFFUSE, 0.5f, 1.0f), 0.55f), spec};
    double mean[2], var[2];
    for (int picks = 0; picks < 2; picks++) {
        bsdf b;
        make_bsdf(&b, cl, 2, z, z);
        if (picks)
            bsdf_weight_picks(&b, z);
        float share = b.closures[1].sample_weight / b.sample_weight_sum;
        if (picks)
            CHECK_MSG(share > 0.02f && share < 0.15f, "the specular's pick share %g", (double)share);
        else
            CHECK_REL(share, 1.0 / 1.55, 1e-5);
        const int n = 200000;
        double sum = 0.0, sum2 = 0.0;
        for (int k = 0; k < n; k++) {
            sampler s = sampler_independent(77, 3, (uint64_t)k);
            bsdf_sample bs;
            double w = 0.0;
            if (bsdf_sample_direction(&b, z, sampler_1d(&s, 0), sampler_2d(&s, 1), &bs))
                w = avg3(bs.weight);
            sum += w, sum2 += w * w;
        }
        mean[picks] = sum / n;
        var[picks] = sum2 / n - mean[picks] * mean[picks];
        CHECK_REL(mean[picks], albedo_quadrature(&b, z, 400, 200), 0.01);
    }
    CHECK_MSG(var[1] < 0.5 * var[0], "sample weight variance %g picked by light, %g by weight", var[1], var[0]);
}

int main(void)
{
    test_chi2_law();
    test_fresnel();
    test_microfacet();
    test_energy();
    test_translucent();
    test_reciprocity();
    test_adjoint_albedo();
    test_light_leaks();
    test_closure_frames();
    test_bump_shadowing();
    test_chi2_all();
    test_pick_by_returned_light();
    return test_summary("test_bsdf");
}
