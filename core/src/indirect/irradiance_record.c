/*
 * irradiance_record.c — computing an irradiance-cache record at a diffuse
 * point: the stratified hemisphere of the course notes (2002, "Irradiance
 * Sampling"), M×N strata θ_j = asin √((j+ξ)/M), φ_k = 2π(k+ψ)/N,
 *
 *   E ≈ π/(MN) Σ_jk L_jk,
 *
 * the harmonic mean distance R = MN / Σ 1/R_jk of the surfaces the rays
 * hit (Ward et al. 1988; misses count 1/R = 0), and the rotational and
 * translational gradients of E from the same samples (Ward & Heckbert
 * 1992, "Irradiance Gradients"; the formulas are in docs/algorithms.md
 * §10.1).
 */
#include "indirect/irradiance_record.h"

#include <stdlib.h>

#include "indirect/hemisphere.h"
#include "scene/ray.h"

static float luminance(vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

static float channel(vec3 v, int c) { return c == 0 ? v.x : (c == 1 ? v.y : v.z); }

/* 1/min(a, b) for two hit distances, 0 if both rays missed. */
static float inv_min_distance(float a, float b)
{
    float m = fminf(a, b);
    return m < INFINITY ? 1.0f / m : 0.0f;
}

/* The gradients of the M×N cells' radiance L (row j = elevation) and hit
 * distances R, in the frame of the record's normal (Ward & Heckbert 1992):
 *
 *   ∇_r E = π/(MN) Σ_k v̂(φ_k^c) Σ_j tan θ_j L_jk                  (θ_j, φ_k^c: cell centres)
 *   ∇_t E = Σ_k [ û(φ_k) 2π/N Σ_{j≥1} sin θ_j⁻ cos² θ_j⁻ (L_jk − L_{j−1,k}) / min(R_jk, R_{j−1,k})
 *               + v̂(φ_k) Σ_j (sin θ_j⁺ − sin θ_j⁻) (L_jk − L_{j,k−1}) / min(R_jk, R_{j,k−1}) ]
 *
 * with sin² θ_j⁻ = j/M, sin² θ_j⁺ = (j+1)/M, φ_k = 2πk/N the cells' lower
 * edges, û(φ) = (cos φ, sin φ, 0) and v̂(φ) = (−sin φ, cos φ, 0). */
static void gradients(const vec3 *L, const float *R, uint32_t M, uint32_t N, vec3 grad_r[3], vec3 grad_t[3])
{
    for (int c = 0; c < 3; c++)
        grad_r[c] = grad_t[c] = v3s(0.0f);
    for (uint32_t k = 0; k < N; k++) {
        float phi_c = 2.0f * PHOS_PI * ((float)k + 0.5f) / (float)N;
        float phi = 2.0f * PHOS_PI * (float)k / (float)N;
        vec3 v_c = v3(-sinf(phi_c), cosf(phi_c), 0.0f);
        vec3 u = v3(cosf(phi), sinf(phi), 0.0f), v = v3(-sinf(phi), cosf(phi), 0.0f);
        uint32_t k_prev = (k + N - 1) % N;
        vec3 rot = v3s(0.0f), du = v3s(0.0f), dv = v3s(0.0f);
        for (uint32_t j = 0; j < M; j++) {
            const vec3 Ljk = L[j * N + k];
            float sin2_c = ((float)j + 0.5f) / (float)M;
            float tan_c = sqrtf(sin2_c / (1.0f - sin2_c));
            rot = v3_madd(rot, Ljk, tan_c);
            float sin_lo = sqrtf((float)j / (float)M), sin_hi = sqrtf((float)(j + 1) / (float)M);
            if (j > 0) {
                float w = sin_lo * (1.0f - sin_lo * sin_lo) * inv_min_distance(R[j * N + k], R[(j - 1) * N + k]);
                du = v3_madd(du, v3_sub(Ljk, L[(j - 1) * N + k]), w);
            }
            float w = (sin_hi - sin_lo) * inv_min_distance(R[j * N + k], R[j * N + k_prev]);
            dv = v3_madd(dv, v3_sub(Ljk, L[j * N + k_prev]), w);
        }
        rot = v3_scale(rot, PHOS_PI / (float)(M * N));
        du = v3_scale(du, 2.0f * PHOS_PI / (float)N);
        for (int c = 0; c < 3; c++) {
            grad_r[c] = v3_madd(grad_r[c], v_c, channel(rot, c));
            grad_t[c] = v3_add(grad_t[c], v3_add(v3_scale(u, channel(du, c)), v3_scale(v, channel(dv, c))));
        }
    }
}

/* The largest R at which the translational gradient changes E by at most
 * E itself over R (Ward & Heckbert 1992), on luminance as Radiance does:
 * per channel, a dim channel's noisy gradient would shrink the record for
 * light that hardly shows. */
static float gradient_limit(vec3 E, const vec3 grad_t[3])
{
    vec3 g = v3_add(v3_add(v3_scale(grad_t[0], 0.2126f), v3_scale(grad_t[1], 0.7152f)), v3_scale(grad_t[2], 0.0722f));
    float len = v3_length(g);
    return len > 0.0f ? luminance(E) / len : INFINITY;
}

/* What the record keeps of its hemisphere: each stratum's radiance and
 * distance (for the gradients), and the sums. */
typedef struct record_walk {
    hemisphere_incoming incoming;
    vec3 *L;
    float *R;
    vec3 E, E_caustic, w_sum;
    float inv_R_sum;
} record_walk;

static void record_visit(void *ctx, const indirect_query *q, const hemisphere_ray *ray, const sampler *g)
{
    record_walk *w = ctx;
    q->scratch->gather_rays++;
    gather_estimate Li = w->incoming(q, ray->origin, ray->wi, g, ray->index, 0.0f);
    if (!v3_is_finite(Li.indirect) || !v3_is_finite(Li.caustic))
        return;
    w->L[ray->index] = Li.indirect;
    w->R[ray->index] = Li.distance;
    w->E = v3_add(w->E, Li.indirect);
    w->E_caustic = v3_add(w->E_caustic, Li.caustic);
    w->w_sum = v3_madd(w->w_sum, ray->wi, luminance(Li.indirect));
    if (Li.distance < INFINITY && Li.distance > 0.0f)
        w->inv_R_sum += 1.0f / Li.distance;
}

int irradiance_record_compute(const indirect_query *q, hemisphere_incoming incoming, uint32_t rays, float R_lo,
                              float R_hi, irradiance_record *out)
{
    const surface *sf = q->sf;
    uint32_t M, N;
    hemisphere_strata(rays, &M, &N);
    vec3 *L = malloc(sizeof(vec3) * M * N);
    float *R = malloc(sizeof(float) * M * N);
    if (!L || !R) {
        free(L);
        free(R);
        return 0;
    }
    for (uint32_t i = 0; i < M * N; i++) {
        L[i] = v3s(0.0f);
        R[i] = INFINITY; /* below the surface: no light, and no surface seen */
    }
    record_walk w = {incoming, L, R, v3s(0.0f), v3s(0.0f), v3s(0.0f), 0.0f};
    hemisphere_walk(q, M, N, record_visit, &w); /* cancelled: the fill discards the record */
    vec3 E = w.E, E_caustic = w.E_caustic, w_sum = w.w_sum;
    float inv_R_sum = w.inv_R_sum;
    frame f = frame_from_normal(sf->ns);
    float scale = PHOS_PI / (float)(M * N);
    out->p = sf->p;
    out->n = sf->ns;
    out->E = v3_scale(E, scale);
    out->E_caustic = v3_scale(E_caustic, scale);
    float len = v3_length(w_sum);
    out->w_mean = len > 0.0f ? v3_scale(w_sum, 1.0f / len) : sf->ns;
    vec3 gr[3], gt[3];
    gradients(L, R, M, N, gr, gt);
    free(L);
    free(R);
    for (int c = 0; c < 3; c++) {
        out->grad_r[c] = frame_to_world(&f, gr[c]);
        out->grad_t[c] = frame_to_world(&f, gt[c]);
    }
    float R_harmonic = inv_R_sum > 0.0f ? (float)(M * N) / inv_R_sum : INFINITY;
    out->R_lo = R_lo;
    out->R_hi = R_hi;
    out->R_free = fminf(R_harmonic, gradient_limit(out->E, out->grad_t));
    out->R = fminf(fmaxf(out->R_free, R_lo), R_hi);
    /* Raised to the smallest spacing: lower the translational gradient so
     * that it still changes E by at most E over R (as Radiance does). */
    for (int c = 0; c < 3; c++) {
        float g = v3_length(out->grad_t[c]) * out->R, e = channel(out->E, c);
        if (g > e)
            out->grad_t[c] = v3_scale(out->grad_t[c], g > 0.0f ? e / g : 0.0f);
    }
    out->next = UINT32_MAX;
    return 1;
}
