/*
 * hosek_wilkie.c — Hosek and Wilkie 2012, "An analytic model for full
 * spectral sky-dome radiance" (docs/algorithms.md §11.1), in its CIE XYZ
 * form, as Blender's Sky Texture uses it.
 *
 * Per channel, the radiance along a view at polar angle θ and angle γ from
 * the sun is R · F(θ, γ) with (the paper's eq. 9)
 *   F = (1 + A e^{B/(cos θ + 0.01)}) (C + D e^{Eγ} + F cos²γ + G χ(H, γ) + I √cos θ),
 *   χ(g, γ) = (1 + cos²γ) / (1 + g² − 2g cos γ)^{3/2}.
 * The nine coefficients and R are fitted to the sun's elevation by quintic
 * Bézier curves in (elevation / 90°)^{1/3}, one per turbidity 1..10 and
 * ground albedo 0 and 1, interpolated linearly between turbidities and
 * albedos (§5 of the paper). The fitted control points are the authors'
 * published dataset (third_party/hosek_wilkie/, version 1.4a, BSD
 * licence): the model is that data. Stored in the dataset's order,
 * A B C D E F G I H.
 */
#include "hosek_wilkie/ArHosekSkyModelData_CIEXYZ.h"

#include "shading/color_space.h"
#include "shading/sky/sky.h"

#define CONFIGS 9
#define POINTS 6     /* control points of a quintic Bézier curve */
#define TURBIDITIES 10

/* The quintic Bézier curve through the control points p[0], p[stride], …
 * at x ∈ [0, 1]. */
static double quintic(const double *p, int stride, double x)
{
    static const double binomial[POINTS] = {1.0, 5.0, 10.0, 10.0, 5.0, 1.0};
    double sum = 0.0;
    for (int i = 0; i < POINTS; i++)
        sum += binomial[i] * pow(1.0 - x, POINTS - 1 - i) * pow(x, i) * p[i * stride];
    return sum;
}

/* One value of a channel's dataset (`per` values per control point, one
 * curve per turbidity and albedo) at turbidity t ∈ [1, 10], albedo a and
 * elevation parameter x. */
static double cook(const double *dataset, int per, int value, double t, double a, double x)
{
    int low = (int)t;
    low = low < 1 ? 1 : low > TURBIDITIES ? TURBIDITIES : low;
    double rem = t - low;
    const int block = per * POINTS, albedo_one = block * TURBIDITIES;
    const double *lo = dataset + block * (low - 1) + value;
    double v = (1.0 - a) * (1.0 - rem) * quintic(lo, per, x) + a * (1.0 - rem) * quintic(lo + albedo_one, per, x);
    if (low < TURBIDITIES) {
        const double *hi = lo + block;
        v += (1.0 - a) * rem * quintic(hi, per, x) + a * rem * quintic(hi + albedo_one, per, x);
    }
    return v;
}

phos_status sky_hosek_wilkie_bake(const phos_sky_desc *d, float *data)
{
    vec3 sun = v3_normalize(v3_load(d->sun_direction));
    float theta = acosf(clampf(sun.z, -1.0f, 1.0f));
    data[SKY_ANALYTIC_THETA] = theta;
    data[SKY_ANALYTIC_PHI] = atan2f(sun.x, sun.y);
    /* The dataset covers the sun from the horizon to the zenith. */
    double elevation = fmax(0.5 * (double)PHOS_PI - theta, 0.0);
    double x = pow(elevation / (0.5 * (double)PHOS_PI), 1.0 / 3.0);
    double t = fmin(fmax(d->turbidity, 1.0), 10.0), a = d->ground_albedo;
    for (int c = 0; c < 3; c++) {
        for (int k = 0; k < CONFIGS; k++)
            data[SKY_ANALYTIC_CONFIG + CONFIGS * c + k] = (float)cook(datasetsXYZ[c], CONFIGS, k, t, a, x);
        data[SKY_ANALYTIC_ZENITH + c] = (float)cook(datasetsXYZRad[c], 1, 0, t, a, x);
    }
    return PHOS_OK;
}

static float channel(const float *c, float theta, float gamma)
{
    float ct = cosf(theta), cg = cosf(gamma);
    float mie = (1.0f + cg * cg) / powf(1.0f + c[8] * c[8] - 2.0f * c[8] * cg, 1.5f);
    return (1.0f + c[0] * expf(c[1] / (ct + 0.01f))) *
           (c[2] + c[3] * expf(c[4] * gamma) + c[5] * cg * cg + c[6] * mie + c[7] * sqrtf(ct));
}

/* X, Y, Z as above with θ held above the horizon, in W/(m²·sr·nm)
 * integrated against the matching functions; Cycles scales them by
 * 2π/683, and so does Phos, so the two agree. */
vec3 sky_hosek_wilkie_radiance(const float *data, vec3 d)
{
    float theta, gamma;
    sky_analytic_angles(data, d, &theta, &gamma);
    const float *c = data + SKY_ANALYTIC_CONFIG;
    vec3 xyz = v3(channel(c, theta, gamma) * data[SKY_ANALYTIC_ZENITH],
                  channel(c + CONFIGS, theta, gamma) * data[SKY_ANALYTIC_ZENITH + 1],
                  channel(c + 2 * CONFIGS, theta, gamma) * data[SKY_ANALYTIC_ZENITH + 2]);
    return v3_scale(xyz_to_rec709(xyz), 2.0f * PHOS_PI / 683.0f);
}
