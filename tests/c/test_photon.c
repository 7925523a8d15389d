/*
 * test_photon.c — the 20-byte photon record: RGBE power (Ward 1991), the
 * direction bytes and their lookup tables, the flag word, and the photon
 * map's lifecycle and memory (docs/algorithms.md §1, §9 checks 1-2).
 */
#include <float.h>
#include <string.h>

#include "photons/kdtree.h"
#include "photons/photon.h"
#include "sampling/sampler.h"
#include "test_util.h"

static float rnd(uint32_t *state)
{
    *state = hash_u32(*state + 0x9e3779b9U);
    return u32_to_unit_float(*state);
}

/* ---- lookup tables ----------------------------------------------------- */

/* The literal tables must be the float nearest to the double-precision
 * value at the bin centre (i + 0.5); one ulp of slack for libm. */
static int table_entry_ok(float entry, double exact)
{
    float f = (float)exact;
    return entry == f || entry == nextafterf(f, 2.0f) || entry == nextafterf(f, -2.0f);
}

static void test_tables(void)
{
    int bad = 0;
    for (int i = 0; i < 256; i++) {
        double t = (i + 0.5) * M_PI / 256.0, p = (i + 0.5) * 2.0 * M_PI / 256.0;
        bad += !table_entry_ok(photon_cos_theta[i], cos(t));
        bad += !table_entry_ok(photon_sin_theta[i], sin(t));
        bad += !table_entry_ok(photon_cos_phi[i], cos(p));
        bad += !table_entry_ok(photon_sin_phi[i], sin(p));
    }
    CHECK_MSG(bad == 0, "%d table entries differ from cos/sin at the bin centres", bad);
}

/* ---- RGBE ---------------------------------------------------------------- */

static vec3 rgbe_round_trip(vec3 c)
{
    uint8_t b[4];
    rgbe_encode(c, b);
    return rgbe_decode(b);
}

static int no_negative(vec3 c) { return c.x >= 0.0f && c.y >= 0.0f && c.z >= 0.0f; }

/* Every channel within 1/256 of the largest channel (Ward's precision). */
static int rgbe_within_bound(vec3 c, vec3 d)
{
    float tol = v3_max_component(c) / 256.0f * (1.0f + 1e-6f);
    return fabsf(d.x - c.x) <= tol && fabsf(d.y - c.y) <= tol && fabsf(d.z - c.z) <= tol;
}

static void test_rgbe_zero_and_invalid(void)
{
    uint8_t b[4] = {1, 2, 3, 4};
    rgbe_encode(v3s(0.0f), b);
    CHECK(b[0] == 0 && b[1] == 0 && b[2] == 0 && b[3] == 0);
    vec3 d = rgbe_decode(b);
    CHECK(d.x == 0.0f && d.y == 0.0f && d.z == 0.0f);
    /* Below Radiance's 1e-32 threshold: black. */
    d = rgbe_round_trip(v3s(1e-33f));
    CHECK(v3_is_zero(d));
    /* Negative and NaN channels encode as 0 and never decode negative. */
    d = rgbe_round_trip(v3(-1.0f, 2.0f, NAN));
    CHECK(no_negative(d) && d.x <= 2.0f / 256.0f && d.z <= 2.0f / 256.0f);
    CHECK_REL(d.y, 2.0f, 1.0 / 256.0);
    d = rgbe_round_trip(v3s(-5.0f));
    CHECK(v3_is_zero(d));
    /* Overflow saturates to a finite value instead of wrapping the exponent. */
    d = rgbe_round_trip(v3(INFINITY, 1.0f, FLT_MAX));
    CHECK(v3_is_finite(d) && d.x > 1e38f && no_negative(d));
}

/* Random colours over 1e-30 … 1e30: the bound, no negatives, and the mean
 * error of the largest channel: centred (the +0.5 decode; without it the
 * mean is −0.5 step ≈ −0.26 %) and about 1/768 in magnitude. */
static void test_rgbe_random(void)
{
    uint32_t s = 7;
    int bad_bound = 0, bad_sign = 0;
    double sum_rel = 0.0, sum_abs = 0.0;
    const int n = 200000;
    for (int i = 0; i < n; i++) {
        float scale = powf(10.0f, -30.0f + 60.0f * rnd(&s));
        vec3 c = v3_scale(v3(rnd(&s), rnd(&s), rnd(&s)), scale);
        vec3 d = rgbe_round_trip(c);
        bad_sign += !no_negative(d);
        float m = v3_max_component(c), md = v3_max_component(d);
        if (m < 1e-32f) { /* black by definition */
            bad_bound += !v3_is_zero(d);
        } else {
            bad_bound += !rgbe_within_bound(c, d);
            sum_rel += (md - m) / m;
            sum_abs += fabsf(md - m) / m;
        }
    }
    CHECK_MSG(bad_bound == 0, "%d of %d colours off by more than 1/256 of the max channel", bad_bound, n);
    CHECK(bad_sign == 0);
    CHECK_MSG(fabs(sum_rel / n) < 2e-4, "mean relative error of the max channel %g (biased)", sum_rel / n);
    CHECK_MSG(sum_abs / n < 1.0 / 512.0, "mean |relative error| %g > 1/512", sum_abs / n);
}

static void test_rgbe_photon_powers(void)
{
    /* Photon powers Φ/N: tiny (1e-9 W) and large (1e6 W) both survive. */
    const float grey[] = {1e-9f, 3.7e-7f, 1.0f, 1e6f};
    for (int i = 0; i < 4; i++) {
        vec3 c = v3(grey[i], 0.8f * grey[i], 0.3f * grey[i]);
        vec3 d = rgbe_round_trip(c);
        CHECK_MSG(rgbe_within_bound(c, d), "power %g", (double)grey[i]);
        CHECK_REL(d.x, c.x, 1.0 / 256.0);
        CHECK_REL(d.y, c.y, 1.0 / 128.0);
    }
    /* Exact bytes: 1.0 = 0.5·2^1 → mantissa 128, exponent byte 129. */
    uint8_t b[4];
    rgbe_encode(v3(1.0f, 0.5f, 0.25f), b);
    CHECK(b[0] == 128 && b[1] == 64 && b[2] == 32 && b[3] == 129);
    vec3 d = rgbe_decode(b);
    CHECK(d.x == 128.5f / 128.0f && d.y == 64.5f / 128.0f);
}

/* Every exponent byte decodes to (byte + 0.5)·2^(E − 136), exactly. */
static void test_rgbe_decode_all_exponents(void)
{
    int bad = 0;
    for (int e = 1; e < 256; e++)
        for (int m = 0; m < 256; m += 17) {
            uint8_t b[4] = {(uint8_t)m, 255, 128, (uint8_t)e};
            vec3 d = rgbe_decode(b);
            bad += d.x != (float)ldexp(m + 0.5, e - 136) || d.y != (float)ldexp(255.5, e - 136) ||
                   d.z != (float)ldexp(128.5, e - 136);
        }
    CHECK_MSG(bad == 0, "%d exponent/mantissa pairs decode wrongly", bad);
}

/* A strongly coloured power loses only its weak channel: red and blue stay
 * accurate, green (1e-4 of red, below one mantissa step) decodes to half a
 * step, i.e. its own value is gone but its error stays under 1/256 of red. */
static void test_rgbe_strong_colour(void)
{
    vec3 c = v3(1.0f, 1e-4f, 0.5f);
    uint8_t b[4];
    rgbe_encode(c, b);
    CHECK(b[1] == 0);
    vec3 d = rgbe_decode(b);
    CHECK_REL(d.x, c.x, 1.0 / 256.0);
    CHECK_REL(d.z, c.z, 1.0 / 128.0);
    CHECK(d.y > 0.0f && d.y <= c.x / 256.0f);
    CHECK(rgbe_within_bound(c, d));
}

/* ---- direction bytes ---------------------------------------------------- */

static vec3 dir_round_trip(vec3 w)
{
    uint8_t t, p;
    direction_encode(w, &t, &p);
    return direction_decode(t, p);
}

/* Uniform on the sphere. */
static vec3 random_direction(uint32_t *s)
{
    float z = 1.0f - 2.0f * rnd(s), phi = 2.0f * PHOS_PI * rnd(s);
    float r = safe_sqrtf(1.0f - z * z);
    return v3(r * cosf(phi), r * sinf(phi), z);
}

static void test_direction_random(void)
{
    /* Bin centres: the error is at most √(0.35² + 0.70²)° ≈ 0.79°; tables at
     * the lower bin edge would reach 1.57°, so the tight bound checks that
     * encode and decode agree on the bin centre. */
    const double cos_required = cos(1.6 * M_PI / 180.0), cos_centre = cos(0.8 * M_PI / 180.0);
    uint32_t s = 11;
    int bad = 0, bad_centre = 0;
    double worst = 1.0;
    for (int i = 0; i < 100000; i++) {
        vec3 w = random_direction(&s);
        double c = v3_dot(dir_round_trip(w), w);
        bad += !(c >= cos_required);
        bad_centre += !(c >= cos_centre);
        worst = fmin(worst, c);
    }
    CHECK_MSG(bad == 0, "%d of 100000 directions off by more than 1.6 degrees", bad);
    CHECK_MSG(bad_centre == 0, "%d directions off by more than 0.8 degrees (worst %.3f)", bad_centre,
              acos(worst) * 180.0 / M_PI);
}

static void test_direction_special(void)
{
    const double cos_centre = cos(0.8 * M_PI / 180.0);
    const float e = 1e-7f;
    /* Poles, axes, the atan2 seam at ±π (−x with y = ±0 and ±tiny) and just
     * below azimuth 0 (x > 0, y = −tiny: must land in bin 255, not 0). */
    const vec3 special[] = {
        {0, 0, 1},  {0, 0, -1}, {1, 0, 0},  {-1, 0, 0}, {0, 1, 0},   {0, -1, 0},
        {-1, e, 0}, {-1, -e, 0}, {-1, -0.0f, 0}, {1, -e, 0}, {1, e, 0}, {0.6f, -1e-3f, 0.8f},
        {-0.6f, -1e-3f, -0.8f}, {e, e, 1}, {-e, -e, -1},
    };
    for (size_t i = 0; i < sizeof(special) / sizeof(special[0]); i++) {
        vec3 w = v3_normalize(special[i]);
        double c = v3_dot(dir_round_trip(w), w);
        CHECK_MSG(c >= cos_centre, "direction %zu (%g %g %g): cos %g", i, (double)w.x, (double)w.y,
                  (double)w.z, c);
    }
    uint8_t t, p;
    direction_encode(v3(1, -e, 0), &t, &p);
    CHECK(p == 255);
    /* Slightly too long: clamped, not NaN. */
    direction_encode(v3(0, 0, 1.0000002f), &t, &p);
    CHECK(t == 0);
    direction_encode(v3(0, 0, -1.0000002f), &t, &p);
    CHECK(t == 255);
    CHECK(v3_is_finite(direction_decode(t, p)));
}

/* Every bin centre re-encodes to its own bin. */
static void test_direction_bins(void)
{
    int bad = 0;
    for (int t = 0; t < 256; t++)
        for (int p = 0; p < 256; p++) {
            uint8_t t2, p2;
            direction_encode(direction_decode((uint8_t)t, (uint8_t)p), &t2, &p2);
            bad += t2 != t || p2 != p;
        }
    CHECK_MSG(bad == 0, "%d of 65536 bin centres re-encode elsewhere", bad);
}

/* ---- record and flags ---------------------------------------------------- */

static void test_record(void)
{
    CHECK(sizeof(photon) == 20);
    photon p = photon_make(v3(1, 2, 3), v3(0.5f, 0.25f, 0.125f), v3(0, 0, -1), v3(0, 0, 1), PHOTON_CAUSTIC);
    CHECK(p.position[0] == 1.0f && p.position[1] == 2.0f && p.position[2] == 3.0f);
    CHECK(photon_is_caustic(&p) && !photon_is_direct(&p));
    CHECK((p.flags & PHOTON_SPARE_MASK) == 0);
    CHECK(photon_direction(&p).z < -0.9999f);
    CHECK(photon_normal(&p).z > 0.9999f);
    CHECK_REL(photon_power(&p).x, 0.5, 1.0 / 256.0);
    p = photon_make(v3s(0), v3s(1), v3(1, 0, 0), v3(-1, 0, 0), PHOTON_DIRECT | PHOTON_SPARE_MASK);
    CHECK(photon_is_direct(&p) && !photon_is_caustic(&p));
    CHECK(photon_normal(&p).x < -0.9999f);
    CHECK((p.flags & PHOTON_SPARE_MASK) == 0); /* the spare bits are not the caller's */
}

/* The 12-bit normal: over directions spread on the whole sphere (both
 * hemispheres, the octahedron's folds and its corners), the decoded normal
 * is unit length and within 3° of the encoded one, and it shares the flag
 * word without touching the other bits. */
/* photon_normal reads a table filled at load: it must be normal_decode,
 * bit for bit, for every code. */
static void test_normal_table(void)
{
    int differ = 0;
    for (uint32_t code = 0; code < 4096; code++) {
        vec3 a = photon_normal_table[code], b = normal_decode((uint16_t)code);
        differ += memcmp(&a, &b, sizeof a) != 0;
    }
    CHECK_MSG(differ == 0, "%d table entries differ from normal_decode", differ);
}

static void test_normal_encoding(void)
{
    double worst = 0.0;
    int not_unit = 0, flags_changed = 0;
    for (int i = 0; i < 20000; i++) {
        /* A Fibonacci spiral, plus the six axes and the folds' edges. */
        double z = 1.0 - 2.0 * (i + 0.5) / 20000.0, phi = i * 2.399963229728653;
        vec3 n = v3((float)(sqrt(1.0 - z * z) * cos(phi)), (float)(sqrt(1.0 - z * z) * sin(phi)), (float)z);
        if (i < 6)
            n = v3(i == 0 ? 1.0f : i == 1 ? -1.0f : 0.0f, i == 2 ? 1.0f : i == 3 ? -1.0f : 0.0f,
                   i == 4 ? 1.0f : i == 5 ? -1.0f : 0.0f);
        photon p = photon_make(v3s(0), v3s(1), v3(0, 0, -1), n, PHOTON_CAUSTIC);
        flags_changed += !photon_is_caustic(&p) || photon_is_direct(&p) || (p.flags & PHOTON_SPARE_MASK) != 0;
        vec3 m = photon_normal(&p);
        not_unit += fabsf(v3_length(m) - 1.0f) > 1e-5f;
        double angle = acos(fmin(1.0, v3_dot(m, n))) * 180.0 / M_PI;
        worst = fmax(worst, angle);
    }
    printf("  normals: worst angular error %.2f degrees\n", worst);
    CHECK_MSG(worst < 2.6, "a 12-bit normal is %.2f degrees off", worst);
    CHECK(not_unit == 0);
    CHECK(flags_changed == 0);
    /* Zero and NaN normals encode as +z, never as NaN. */
    photon z = photon_make(v3s(0), v3s(1), v3(0, 0, -1), v3s(0.0f), 0);
    photon nan_n = photon_make(v3s(0), v3s(1), v3(0, 0, -1), v3(NAN, 0, 0), 0);
    CHECK(photon_normal(&z).z > 0.999f && photon_normal(&nan_n).z > 0.999f);
}

/* ---- photon map ---------------------------------------------------------- */

static photon random_photon(uint32_t *s)
{
    vec3 pos = v3(rnd(s), rnd(s), rnd(s));
    return photon_make(pos, v3(rnd(s), rnd(s), rnd(s)), random_direction(s), random_direction(s), 0);
}

static void test_map_lifecycle(void)
{
    const uint32_t n = 5000;
    photon *src = malloc(sizeof(photon) * n);
    uint32_t s = 3;
    for (uint32_t i = 0; i < n; i++)
        src[i] = random_photon(&s);

    /* A: reserved exactly, appended in one call. B: no reserve, one by one
     * (the growth path). Same photons in the same order → identical maps. */
    photon_map a, b;
    photon_map_init(&a);
    photon_map_init(&b);
    CHECK(photon_map_reserve(&a, n));
    CHECK(photon_map_append(&a, src, n));
    int appended = 1;
    for (uint32_t i = 0; i < n; i++)
        appended &= photon_map_append(&b, &src[i], 1);
    CHECK(appended);
    CHECK(b.capacity > b.count); /* slack before the build */
    CHECK(photon_map_build(&a, NULL) && photon_map_build(&b, NULL));
    CHECK(a.count == n && b.count == n);
    CHECK(memcmp(a.photons, b.photons, sizeof(photon) * n) == 0);

    /* Memory: exactly 20 bytes per photon, the handle and the split
     * planes: one per bucket but one in each class, and buckets hold more
     * than KDTREE_BUCKET / 2 photons, so fewer than 2 · 12 / 16 = 1.5
     * bytes per photon. The test's bound: splits · KDTREE_BUCKET < 2n. */
    CHECK(a.capacity == n && b.capacity == n);
    CHECK(a.split_count == b.split_count && (uint64_t)a.split_count * KDTREE_BUCKET < 2u * (uint64_t)n);
    CHECK(photon_map_memory(&a) == sizeof(photon_map) + 20u * (size_t)n + sizeof(kdtree_split) * a.split_count);
    CHECK(photon_map_memory(&b) == photon_map_memory(&a));

    /* Read-only after the build. */
    CHECK(!photon_map_append(&a, src, 1));
    CHECK(!photon_map_reserve(&a, 2 * n));
    CHECK(photon_map_build(&a, NULL));
    CHECK(a.count == n);

    /* The built map answers queries. */
    kdtree_query q;
    CHECK(kdtree_query_init(&q, 10));
    CHECK(photon_map_knn(&a, v3s(0.5f), 1.0f, &q) == 10);

    /* A map that is not built finds nothing. */
    photon_map c;
    photon_map_init(&c);
    CHECK(photon_map_append(&c, src, 100));
    CHECK(photon_map_knn(&c, v3s(0.5f), 1.0f, &q) == 0);

    /* Non-finite positions are rejected with the whole call. */
    photon bad[2] = {src[0], src[1]};
    bad[1].position[2] = NAN;
    CHECK(!photon_map_append(&c, bad, 2));
    bad[1].position[2] = INFINITY;
    CHECK(!photon_map_append(&c, bad, 2));
    CHECK(c.count == 100);

    /* Empty map: builds, finds nothing, holds no photons. */
    photon_map e;
    photon_map_init(&e);
    CHECK(photon_map_build(&e, NULL));
    CHECK(photon_map_knn(&e, v3s(0), 1.0f, &q) == 0 && q.radius2 == 1.0f);
    CHECK(photon_map_memory(&e) == sizeof(photon_map));

    kdtree_query_free(&q);
    photon_map_free(&a);
    photon_map_free(&b);
    photon_map_free(&c);
    photon_map_free(&e);
    photon_map_free(NULL);
    CHECK(a.photons == NULL && a.count == 0);
    free(src);
}

int main(void)
{
    test_tables();
    test_normal_table();
    test_rgbe_zero_and_invalid();
    test_rgbe_random();
    test_rgbe_photon_powers();
    test_rgbe_decode_all_exponents();
    test_rgbe_strong_colour();
    test_direction_random();
    test_direction_special();
    test_direction_bins();
    test_record();
    test_normal_encoding();
    test_map_lifecycle();
    return test_summary("test_photon");
}
