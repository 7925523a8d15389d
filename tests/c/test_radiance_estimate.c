/*
 * test_radiance_estimate.c — the density estimate's Lambertian shortcut
 * (radiance_estimate.c, bsdf_lambertian_about): summing the photons'
 * powers and multiplying by ρ/π once must give what evaluating the BSDF
 * per photon gives, including where a smooth shading normal leans past
 * the geometric one, so that photons from below the geometric surface
 * reflect nothing. And the shortcut must not be taken for a BSDF it does
 * not describe.
 */
#include <string.h>

#include "photons/kdtree.h"
#include "photons/radiance_estimate.h"
#include "sampling/sampler.h"
#include "shading/bsdf.h"
#include "test_util.h"

static float rnd(uint32_t *state)
{
    *state = hash_u32(*state + 0x9e3779b9U);
    return u32_to_unit_float(*state);
}

static closure diffuse_closure(uint32_t type, vec3 rho)
{
    closure c;
    memset(&c, 0, sizeof c);
    c.type = type;
    c.weight = rho;
    return c;
}

/* Photons on the plane z = 0 (normal +z) around the origin, arriving from
 * every direction above the plane, grazing ones included; one in five
 * from just below it (as where a smooth shading normal leans past the
 * geometric one, and the search, which tests the shading normal, keeps
 * them). */
static void plane_map(photon_map *m, uint32_t n)
{
    photon *p = malloc(sizeof(photon) * n);
    uint32_t s = 7;
    for (uint32_t i = 0; i < n; i++) {
        float phi = 2.0f * PHOS_PI * rnd(&s), cos_t = i % 5 == 0 ? -0.3f * rnd(&s) : rnd(&s);
        float sin_t = sqrtf(1.0f - cos_t * cos_t);
        vec3 d = v3(sin_t * cosf(phi), sin_t * sinf(phi), -cos_t); /* travelling down */
        vec3 power = v3(0.2f + rnd(&s), 0.5f, 0.1f + 0.5f * rnd(&s));
        p[i] = photon_make(v3(rnd(&s) - 0.5f, rnd(&s) - 0.5f, 0.0f), power, d, v3(0, 0, 1), 0);
    }
    photon_map_init(m);
    CHECK(photon_map_append(m, p, n) && photon_map_build(m, NULL));
    free(p);
}

/* The estimate as radiance_estimate.c defines it, the BSDF evaluated per
 * photon: the search with the estimate's own filter, the k-th photon
 * only setting the radius. */
static vec3 reference_radiance(const photon_map *m, const bsdf *b, vec3 wo, vec3 x, vec3 n, const estimate_params *ep,
                               kdtree_query *q, uint32_t *below_ng)
{
    kdtree_filter f = {n, ESTIMATE_NORMAL_MIN_COS, ep->exclude_flags, 1};
    photon_map_knn_surface(m, x, ESTIMATE_DISC_FLATTEN, &f, ep->max_radius * ep->max_radius, q);
    CHECK(q->found == q->k);
    uint32_t far = 0;
    for (uint32_t j = 1; j < q->found; j++)
        if (q->dist2[j] > q->dist2[far])
            far = j;
    vec3 sum = v3s(0.0f);
    *below_ng = 0;
    for (uint32_t j = 0; j < q->found; j++) {
        if (j == far)
            continue;
        const photon *p = kdtree_result(m->photons, q, j);
        vec3 wi = v3_neg(photon_direction(p));
        *below_ng += v3_dot(wi, b->ng) <= 0.0f;
        sum = v3_add(sum, v3_mul(v3_scale(bsdf_eval(b, wo, wi, NULL), 1.0f / v3_dot(wi, n)), photon_power(p)));
    }
    return v3_scale(sum, 1.0f / (PHOS_PI * q->radius2));
}

static float rel_diff(vec3 a, vec3 b)
{
    float d = fmaxf(fabsf(a.x - b.x), fmaxf(fabsf(a.y - b.y), fabsf(a.z - b.z)));
    return d / fmaxf(fabsf(b.x), fmaxf(fabsf(b.y), fabsf(b.z)));
}

static void test_lambertian_shortcut(void)
{
    photon_map m;
    plane_map(&m, 20000);
    kdtree_query q;
    CHECK(kdtree_query_init(&q, 60));
    estimate_params ep = {60, 0.3f, ESTIMATE_BOX, 0};
    vec3 rho = v3(0.8f, 0.5f, 0.2f);
    closure c = diffuse_closure(PHOS_CLOSURE_DIFFUSE, rho);
    vec3 wo = v3_normalize(v3(0.3f, -0.2f, 1.0f));

    /* Shading normal = geometric normal: f = ρ/π for every photon kept,
     * so the radiance is ρ/π times the irradiance. */
    bsdf b;
    bsdf_init(&b, v3(0, 0, 1), v3(0, 0, 1));
    bsdf_add_closure(&b, &c);
    vec3 got_rho;
    CHECK(bsdf_lambertian_about(&b, v3(0, 0, 1), &got_rho) && got_rho.x == rho.x && got_rho.z == rho.z);
    uint32_t below = 0;
    vec3 want = reference_radiance(&m, &b, wo, v3s(0.0f), v3(0, 0, 1), &ep, &q, &below);
    vec3 got = photon_radiance(&m, &b, wo, v3s(0.0f), v3(0, 0, 1), &ep, &q);
    vec3 E = photon_irradiance(&m, v3s(0.0f), v3(0, 0, 1), &ep, &q);
    CHECK_MSG(rel_diff(got, want) < 1e-5f, "flat: shortcut %g against per photon %g", (double)got.x, (double)want.x);
    CHECK(rel_diff(got, v3_mul(v3_scale(rho, PHOS_INV_PI), E)) < 1e-5f);

    /* A smooth shading normal tilted 20° from the geometric one: photons
     * arriving from below the geometric surface but above the shading one
     * reflect nothing. The shortcut must leave them out too. */
    vec3 ns = v3(0.0f, sinf(0.349f), cosf(0.349f));
    bsdf_init(&b, ns, v3(0, 0, 1));
    bsdf_add_closure(&b, &c);
    CHECK(bsdf_lambertian_about(&b, ns, &got_rho));
    want = reference_radiance(&m, &b, wo, v3s(0.0f), ns, &ep, &q, &below);
    got = photon_radiance(&m, &b, wo, v3s(0.0f), ns, &ep, &q);
    CHECK_MSG(below > 0, "no photon arrived below the geometric surface: the case is not tested");
    CHECK_MSG(rel_diff(got, want) < 1e-5f, "tilted: shortcut %g against per photon %g (%u below ng)", (double)got.x,
              (double)want.x, below);

    /* Not Lambertian about n: another normal, another diffuse model, a
     * closure in a frame of its own, a layer over it. */
    CHECK(!bsdf_lambertian_about(&b, v3(0, 0, 1), &got_rho));
    closure on = diffuse_closure(PHOS_CLOSURE_OREN_NAYAR, rho);
    on.roughness = 0.5f;
    bsdf_init(&b, v3(0, 0, 1), v3(0, 0, 1));
    bsdf_add_closure(&b, &c);
    bsdf_add_closure(&b, &on);
    CHECK(!bsdf_lambertian_about(&b, v3(0, 0, 1), &got_rho));
    bsdf_init(&b, v3(0, 0, 1), v3(0, 0, 1));
    closure bent = c;
    bent.frame = bsdf_add_frame(&b, v3_normalize(v3(0.1f, 0.0f, 1.0f)), v3s(0.0f));
    bsdf_add_closure(&b, &bent);
    CHECK(bent.frame != 0 && !bsdf_lambertian_about(&b, v3(0, 0, 1), &got_rho));
    bsdf_init(&b, v3(0, 0, 1), v3(0, 0, 1));
    closure under = c;
    under.under_layers = 1;
    bsdf_add_closure(&b, &under);
    CHECK(!bsdf_lambertian_about(&b, v3(0, 0, 1), &got_rho));
    bsdf_init(&b, v3(0, 0, 1), v3(0, 0, 1));
    CHECK(!bsdf_lambertian_about(&b, v3(0, 0, 1), &got_rho)); /* no closure: black, not Lambertian */

    kdtree_query_free(&q);
    photon_map_free(&m);
}

/* A radiance photon's radius survives its 16 bits: never smaller, at
 * most 0.3 % larger, over 60 octaves; zero and NaN decode as the least. */
static void test_radiance_photon_radius(void)
{
    int bad = 0;
    photon p = photon_make(v3s(0.0f), v3s(1.0f), v3(0, 0, 1), v3(0, 0, 1), 0);
    for (float r = 1e-9f; r < 1e9f; r *= 1.0371f) {
        radiance_photon_set_radius(&p, r);
        float back = radiance_photon_radius(&p);
        bad += !(back >= r && back <= r * 1.003f);
    }
    CHECK_MSG(bad == 0, "%d radii not kept within [r, 1.003 r]", bad);
    radiance_photon_set_radius(&p, 0.0f);
    float least = radiance_photon_radius(&p);
    CHECK(least > 0.0f && least < 1e-30f);
    radiance_photon_set_radius(&p, NAN);
    CHECK(radiance_photon_radius(&p) == least);
}

int main(void)
{
    test_radiance_photon_radius();
    test_lambertian_shortcut();
    return test_summary("test_radiance_estimate");
}
