/*
 * test_radiance_estimate.c — the density estimate's Lambertian shortcut
 * (radiance_estimate.c, bsdf_lambertian_about): summing the photons'
 * powers and multiplying by ρ/π once must give what evaluating the BSDF
 * per photon gives, including where a smooth shading normal leans past
 * the geometric one, so that photons from below the geometric surface
 * reflect nothing. And the shortcut must not be taken for a BSDF it does
 * not describe.
 *
 * Progressive photon mapping's fixed-radius estimate: it sums exactly the
 * photons inside its disc (against brute force over the whole map), its
 * mean over independent maps is the true radiance of uniform light
 * whatever the radius, and the radius sequence shrinks as i^((α−1)/2).
 *
 * Edges: the disc's coverage that the probes measure against the area of
 * a disc cut by one wall and by a corner, and the estimate beside a wall
 * of a closed box, whose disc the wall cuts, reads the true density on
 * average (without the correction it reads up to half as much).
 */
#include <string.h>

#include "photons/kdtree.h"
#include "photons/progressive_caustics.h"
#include "photons/radiance_estimate.h"
#include "sampling/sampler.h"
#include "scene/scene.h"
#include "shading/bsdf.h"
#include "test_scenes.h"
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
        if (kdtree_result_dist2(q, j) > kdtree_result_dist2(q, far))
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

/* Every photon of the map inside the disc, by brute force, f per photon. */
static vec3 brute_force_within(const photon_map *m, const bsdf *b, vec3 wo, vec3 x, vec3 n, float radius,
                               uint32_t *count)
{
    kdtree_filter f = {n, ESTIMATE_NORMAL_MIN_COS, 0, 1};
    float c2m1 = ESTIMATE_DISC_FLATTEN * ESTIMATE_DISC_FLATTEN - 1.0f;
    vec3 sum = v3s(0.0f);
    *count = 0;
    for (uint32_t i = 0; i < m->count; i++) {
        const photon *p = &m->photons[i];
        if (!(kdtree_disc_dist2(p, x, n, c2m1) < radius * radius) || !kdtree_filter_accepts(&f, p))
            continue;
        vec3 wi = v3_neg(photon_direction(p));
        sum = v3_add(sum, v3_mul(v3_scale(bsdf_eval(b, wo, wi, NULL), 1.0f / v3_dot(wi, n)), photon_power(p)));
        (*count)++;
    }
    return v3_scale(sum, 1.0f / (PHOS_PI * radius * radius));
}

static void test_fixed_radius_estimate(void)
{
    photon_map m;
    plane_map(&m, 20000);
    vec3 rho = v3(0.8f, 0.5f, 0.2f);
    closure c = diffuse_closure(PHOS_CLOSURE_DIFFUSE, rho);
    closure on = diffuse_closure(PHOS_CLOSURE_OREN_NAYAR, rho);
    on.roughness = 0.5f;
    vec3 wo = v3_normalize(v3(0.3f, -0.2f, 1.0f));
    const float radii[] = {0.01f, 0.05f, 0.2f};
    for (int shortcut = 0; shortcut < 2; shortcut++) {
        bsdf b;
        bsdf_init(&b, v3(0, 0, 1), v3(0, 0, 1));
        bsdf_add_closure(&b, shortcut ? &c : &on); /* Lambertian (summed once) or per photon */
        for (int r = 0; r < 3; r++) {
            uint32_t count;
            vec3 want = brute_force_within(&m, &b, wo, v3(0.1f, -0.05f, 0.0f), v3(0, 0, 1), radii[r], &count);
            vec3 got = photon_radiance_within(&m, &b, wo, v3(0.1f, -0.05f, 0.0f), v3(0, 0, 1), radii[r], 0, NULL);
            CHECK_MSG(count > 0 && rel_diff(got, want) < 1e-4f, "radius %g: %g against brute force %g (%u photons)",
                      (double)radii[r], (double)got.x, (double)want.x, count);
        }
    }
    photon_map_free(&m);

    /* Uniform light: photons of power Φ/N spread over a unit square, all
     * from straight above, carry irradiance E = Φ per m². Over independent
     * maps, the mean of the fixed-radius estimate is ρ/π·E for small and
     * large radii alike; the tolerance is four standard errors of the
     * mean, measured from the estimates themselves. */
    const uint32_t maps = 200, n = 4000;
    bsdf b;
    bsdf_init(&b, v3(0, 0, 1), v3(0, 0, 1));
    bsdf_add_closure(&b, &c);
    for (int r = 0; r < 2; r++) {
        float radius = r ? 0.1f : 0.02f;
        double sum = 0.0, sum2 = 0.0;
        uint32_t s = 99 + (uint32_t)r;
        photon *p = malloc(sizeof(photon) * n);
        for (uint32_t k = 0; k < maps; k++) {
            for (uint32_t i = 0; i < n; i++)
                p[i] = photon_make(v3(rnd(&s) - 0.5f, rnd(&s) - 0.5f, 0.0f), v3s(1.0f / (float)n), v3(0, 0, -1),
                                   v3(0, 0, 1), 0);
            photon_map_init(&m);
            CHECK(photon_map_append(&m, p, n) && photon_map_build(&m, NULL));
            double L = photon_radiance_within(&m, &b, wo, v3s(0.0f), v3(0, 0, 1), radius, 0, NULL).x;
            sum += L;
            sum2 += L * L;
            photon_map_free(&m);
        }
        free(p);
        double mean = sum / maps, var = (sum2 / maps - mean * mean) / (maps - 1);
        double want = rho.x / PHOS_PI;
        CHECK_MSG(fabs(mean - want) < 4.0 * sqrt(var), "radius %g: mean %g over %u maps, want %g (se %g)",
                  (double)radius, mean, maps, want, sqrt(var));
    }
}

/* R_i² = Π (j + α)/(j + 1): 1 at the first sample, falling as i^(α−1)
 * (the product is Γ(i + 1 + α)/(Γ(1 + α) Γ(i + 2)) ~ i^(α−1)/Γ(1 + α)). */
static void test_progressive_radius(void)
{
    CHECK(progressive_caustics_shrink(0, 0.7f) == 1.0f);
    float r1 = progressive_caustics_shrink(1, 0.7f);
    CHECK(fabsf(r1 * r1 - 0.85f) < 1e-6f);
    for (int a = 0; a < 3; a++) {
        float alpha = 0.3f + 0.3f * (float)a;
        double big = 1e5, r = progressive_caustics_shrink((uint32_t)big, alpha);
        double want = pow(big, alpha - 1.0) / tgamma(1.0 + alpha);
        CHECK_MSG(fabs(r * r / want - 1.0) < 1e-3, "alpha %g: R² %g at 1e5, asymptote %g", (double)alpha, r * r, want);
        float prev = 2.0f;
        for (uint32_t i = 0; i < 100; i++) {
            float ri = progressive_caustics_shrink(i, alpha);
            CHECK(ri < prev);
            prev = ri;
        }
    }
}

/* A closed box [−1, 1]² × [0, 2] of white quads, committed. */
static phos_scene *closed_box(void)
{
    const float a = 1.0f, h = 2.0f;
    float q[6][4][3] = {
        {{-a, -a, 0}, {a, -a, 0}, {a, a, 0}, {-a, a, 0}},   {{-a, -a, h}, {-a, a, h}, {a, a, h}, {a, -a, h}},
        {{-a, a, 0}, {a, a, 0}, {a, a, h}, {-a, a, h}},     {{-a, -a, 0}, {-a, -a, h}, {a, -a, h}, {a, -a, 0}},
        {{-a, -a, 0}, {-a, a, 0}, {-a, a, h}, {-a, -a, h}}, {{a, -a, 0}, {a, -a, h}, {a, a, h}, {a, a, 0}},
    };
    phos_scene *s = phos_scene_create();
    test_add_instance(s, test_add_quads(s, (const float(*)[4][3])q, 6), test_add_diffuse(s, 0.7f, 0.7f, 0.7f), 0, 0,
                      0);
    test_set_camera(s, 0, 0, 1.9f, 0.5f);
    CHECK(phos_scene_commit(s) == PHOS_OK);
    return s;
}

/* The share of a disc of radius 1 on the near side of a chord at distance
 * d from its centre: 1 − (acos d − d √(1 − d²))/π. */
static double disc_share_inside_chord(double d)
{
    return 1.0 - (acos(d) - d * sqrt(1.0 - d * d)) / PHOS_PI;
}

static void test_disc_coverage(void)
{
    phos_scene *s = closed_box();
    vec3 up = v3(0, 0, 1);
    /* Nothing within r: exactly the disc. */
    CHECK(estimate_disc_coverage(s, v3(0, 0, 0), up, 0.3f, ESTIMATE_BOX) == 1.0f);
    CHECK(estimate_disc_coverage(s, v3(0, 0, 0), up, 0.3f, ESTIMATE_CONE) == 1.0f);
    /* One wall at x = 1, at d = 0.1 … 0.9 of the radius: 16 probes at one
     * point come within 3 % of the exact share (measured: 2.2 % at worst),
     * and their mean over 400 points along the wall (each turning the
     * probes its own way) within 0.3 %. */
    float worst = 0.0f, worst_mean = 0.0f;
    for (int i = 1; i <= 9; i++) {
        double d = 0.1 * i, want = disc_share_inside_chord(d), mean = 0.0;
        float r = 0.2f;
        float got = estimate_disc_coverage(s, v3(1.0f - (float)d * r, 0.3f, 0.0f), up, r, ESTIMATE_BOX);
        worst = fmaxf(worst, fabsf(got / (float)want - 1.0f));
        for (int k = 0; k < 400; k++)
            mean += estimate_disc_coverage(s, v3(1.0f - (float)d * r, -0.5f + 0.0025f * (float)k, 0.0f), up, r,
                                           ESTIMATE_BOX);
        worst_mean = fmaxf(worst_mean, (float)fabs(mean / 400.0 / want - 1.0));
    }
    CHECK_MSG(worst < 0.03f, "one wall: the probes' coverage is off by %.3f at worst", (double)worst);
    CHECK_MSG(worst_mean < 0.003f, "one wall: the mean coverage is off by %.4f at worst", (double)worst_mean);
    /* A corner: a quarter of the disc. */
    float corner = estimate_disc_coverage(s, v3(0.999f, 0.999f, 0.0f), up, 0.3f, ESTIMATE_BOX);
    CHECK_MSG(fabsf(corner - 0.25f) < 0.02f, "corner coverage %g", (double)corner);
    phos_scene_destroy(s);
}

/* Photons spread uniformly over the box's floor, all from straight above,
 * carry irradiance E = Φ/4 W/m² on its 4 m². The estimate 2 cm from a wall
 * (its disc of about 8 cm cut by the wall) and in a corner, averaged over
 * independent maps, reads ρ/π·E within four standard errors of its mean
 * (measured from the estimates); the same estimate over the whole disc
 * reads dark there, which shows the case is one the correction decides. */
static void test_estimate_at_walls(void)
{
    phos_scene *s = closed_box();
    const uint32_t maps = 120, n = 20000;
    vec3 rho = v3s(0.7f);
    closure c = diffuse_closure(PHOS_CLOSURE_DIFFUSE, rho);
    bsdf b;
    bsdf_init(&b, v3(0, 0, 1), v3(0, 0, 1));
    bsdf_add_closure(&b, &c);
    vec3 wo = v3(0, 0, 1);
    /* Each map's estimate at a point of its own along the wall, or along
     * the corner's diagonal band, so that the probes' turns vary as they
     * do over an image. */
    const char *names[2] = {"beside a wall", "in a corner"};
    kdtree_query q;
    CHECK(kdtree_query_init(&q, 50));
    photon *p = malloc(sizeof(photon) * n);
    double sum[2][2] = {{0}}, sum2[2][2] = {{0}};
    uint32_t st = 1234;
    for (uint32_t k = 0; k < maps; k++) {
        for (uint32_t i = 0; i < n; i++)
            p[i] = photon_make(v3(2.0f * rnd(&st) - 1.0f, 2.0f * rnd(&st) - 1.0f, 0.0f), v3s(1.0f / (float)n),
                               v3(0, 0, -1), v3(0, 0, 1), 0);
        photon_map m;
        photon_map_init(&m);
        CHECK(photon_map_append(&m, p, n) && photon_map_build(&m, NULL));
        float along = 0.8f * rnd(&st) - 0.4f, off = 0.005f * rnd(&st);
        const vec3 where[2] = {v3(0.98f, along, 0.0f), v3(0.99f - off, 0.99f - off, 0.0f)};
        for (int w = 0; w < 2; w++)
            for (int clip = 0; clip < 2; clip++) {
                estimate_params ep = {50, 0.5f, ESTIMATE_BOX, 0, clip ? s : NULL};
                double L = photon_radiance(&m, &b, wo, where[w], v3(0, 0, 1), &ep, &q).x;
                sum[w][clip] += L;
                sum2[w][clip] += L * L;
            }
        photon_map_free(&m);
    }
    free(p);
    double want = 0.7 / PHOS_PI * 0.25;
    for (int w = 0; w < 2; w++) {
        double mean = sum[w][1] / maps, se = sqrt((sum2[w][1] / maps - mean * mean) / (maps - 1));
        CHECK_MSG(fabs(mean - want) < 4.0 * se, "%s: mean %g over %u maps, want %g (se %g)", names[w], mean, maps,
                  want, se);
        double whole = sum[w][0] / maps;
        CHECK_MSG(whole < 0.8 * want, "%s: the whole-disc estimate reads %g of the truth: not a case that tests it",
                  names[w], whole / want);
    }
    kdtree_query_free(&q);
    phos_scene_destroy(s);
}

/* An estimate takes the k its parameters give, whatever its query was
 * made for: the render's caustic query is sized for the larger of the
 * caustic estimate's k and progressive caustics' first-radius k. */
static void test_k_from_params(void)
{
    photon_map m;
    plane_map(&m, 20000);
    kdtree_query exact, larger;
    CHECK(kdtree_query_init(&exact, 10) && kdtree_query_init(&larger, 40));
    estimate_params ep = {10, 0.3f, ESTIMATE_CONE, 0};
    vec3 x = v3(0.1f, -0.05f, 0.0f), n = v3(0, 0, 1);
    vec3 want = photon_irradiance(&m, x, n, &ep, &exact);
    vec3 got = photon_irradiance(&m, x, n, &ep, &larger);
    CHECK_MSG(got.x == want.x && got.y == want.y && got.z == want.z,
              "k = 10 with a query for 40: %g, with a query for 10: %g", (double)got.x, (double)want.x);
    CHECK(larger.k == 40);
    kdtree_query_free(&exact);
    kdtree_query_free(&larger);
    photon_map_free(&m);
}

int main(void)
{
    test_disc_coverage();
    test_estimate_at_walls();
    test_fixed_radius_estimate();
    test_progressive_radius();
    test_radiance_photon_radius();
    test_lambertian_shortcut();
    test_k_from_params();
    return test_summary("test_radiance_estimate");
}
