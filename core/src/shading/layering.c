/*
 * layering.c — tabulated directional albedo of the Fresnel-blended GGX
 * reflection closure. The Fresnel term F = f0 + (1 − f0)·t is linear in
 * f0, so E(f0) = f0·E₁ + (1 − f0)·E₀ with E₁ the albedo for f0 = 1 and E₀
 * for f0 = 0; both are integrated once per process by deterministic
 * quadrature through the closure's own sampling routine (weight = f·cos/pdf
 * averaged over a stratified grid of visible normals), so the table agrees
 * with what the BSDF actually reflects.
 */
#include "shading/layering.h"

#include <pthread.h>

#include "shading/bsdf.h"

#define N_MU 32
#define N_ROUGH 32
#define N_ETA 16
#define ETA_MIN 1.0f
#define ETA_MAX 3.0f
#define QUAD 16 /* QUAD × QUAD stratified samples per entry */

static float table[2][N_ETA][N_ROUGH][N_MU]; /* [f0 = 0 | f0 = 1] */
static pthread_once_t table_once = PTHREAD_ONCE_INIT;

static float grid_mu(int i) { return ((float)i + 0.5f) / N_MU; }
static float grid_rough(int j) { return (float)j / (N_ROUGH - 1); }
static float grid_eta(int k) { return ETA_MIN + (ETA_MAX - ETA_MIN) * (float)k / (N_ETA - 1); }

static float integrate(float mu, float roughness, float eta, float f0)
{
    bsdf b;
    bsdf_init(&b, v3(0.0f, 0.0f, 1.0f), v3(0.0f, 0.0f, 1.0f));
    closure c = {0};
    c.type = PHOS_CLOSURE_REFLECTION_FRESNEL;
    c.weight = v3s(1.0f);
    c.roughness = roughness;
    c.alpha = roughness * roughness;
    c.alpha_t = c.alpha;
    c.eta = eta;
    c.f0 = v3s(f0);
    c.transmission_tint = v3s(1.0f);
    bsdf_add_closure(&b, &c);
    vec3 wo = v3(safe_sqrtf(1.0f - mu * mu), 0.0f, mu);
    double sum = 0.0;
    for (int i = 0; i < QUAD; i++)
        for (int j = 0; j < QUAD; j++) {
            float2 u = {((float)i + 0.5f) / QUAD, ((float)j + 0.5f) / QUAD};
            bsdf_sample s;
            if (bsdf_sample_direction(&b, wo, 0.5f, u, &s))
                sum += s.weight.x;
        }
    return (float)(sum / (QUAD * QUAD));
}

static void build_table(void)
{
    for (int k = 0; k < N_ETA; k++)
        for (int j = 0; j < N_ROUGH; j++)
            for (int i = 0; i < N_MU; i++)
                for (int f = 0; f < 2; f++)
                    table[f][k][j][i] = integrate(grid_mu(i), grid_rough(j), grid_eta(k), (float)f);
}

static void locate(float x, float lo, float step, int n, int *i0, float *t)
{
    float p = (x - lo) / step;
    if (p <= 0.0f) {
        *i0 = 0;
        *t = 0.0f;
    } else if (p >= (float)(n - 1)) {
        *i0 = n - 2;
        *t = 1.0f;
    } else {
        *i0 = (int)p;
        *t = p - (float)*i0;
    }
}

static float lookup(int f, float mu, float roughness, float eta)
{
    int i, j, k;
    float ti, tj, tk;
    locate(mu, 0.5f / N_MU, 1.0f / N_MU, N_MU, &i, &ti);
    locate(roughness, 0.0f, 1.0f / (N_ROUGH - 1), N_ROUGH, &j, &tj);
    locate(eta, ETA_MIN, (ETA_MAX - ETA_MIN) / (N_ETA - 1), N_ETA, &k, &tk);
    float v = 0.0f;
    for (int dk = 0; dk < 2; dk++)
        for (int dj = 0; dj < 2; dj++)
            for (int di = 0; di < 2; di++) {
                float w = (dk ? tk : 1.0f - tk) * (dj ? tj : 1.0f - tj) * (di ? ti : 1.0f - ti);
                v += w * table[f][k + dk][j + dj][i + di];
            }
    return v;
}

vec3 specular_layer_albedo(float mu, float roughness, float eta, vec3 f0)
{
    pthread_once(&table_once, build_table);
    mu = clampf(mu, 0.0f, 1.0f);
    float e0 = lookup(0, mu, roughness, eta), e1 = lookup(1, mu, roughness, eta);
    return v3(f0.x * e1 + (1.0f - f0.x) * e0, f0.y * e1 + (1.0f - f0.y) * e0, f0.z * e1 + (1.0f - f0.z) * e0);
}
