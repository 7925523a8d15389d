/*
 * chi2.h — Pearson's chi-square goodness-of-fit for the sampling tests:
 * the regularized upper incomplete gamma function Q(k/2, x/2) gives the
 * probability of a statistic at least this large under the null
 * hypothesis (Numerical Recipes §6.2: series for x < a+1, continued
 * fraction otherwise).
 */
#ifndef PHOS_TEST_CHI2_H
#define PHOS_TEST_CHI2_H

#include <math.h>

static double chi2_gamma_p_series(double a, double x)
{
    double sum = 1.0 / a, term = sum;
    for (int n = 1; n < 1000; n++) {
        term *= x / (a + n);
        sum += term;
        if (fabs(term) < fabs(sum) * 1e-15)
            break;
    }
    return sum * exp(-x + a * log(x) - lgamma(a));
}

static double chi2_gamma_q_fraction(double a, double x)
{
    const double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 1000; i++) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (fabs(d) < tiny)
            d = tiny;
        c = b + an / c;
        if (fabs(c) < tiny)
            c = tiny;
        d = 1.0 / d;
        double del = d * c;
        h *= del;
        if (fabs(del - 1.0) < 1e-15)
            break;
    }
    return exp(-x + a * log(x) - lgamma(a)) * h;
}

/* P(χ² with dof degrees of freedom >= chi2). */
static double chi2_survival(double chi2, int dof)
{
    if (dof <= 0)
        return 1.0;
    double a = 0.5 * dof, x = 0.5 * chi2;
    if (x <= 0.0)
        return 1.0;
    return x < a + 1.0 ? 1.0 - chi2_gamma_p_series(a, x) : chi2_gamma_q_fraction(a, x);
}

/* Pearson statistic over bins, pooling bins whose expected count is below
 * 5 into one. Returns the p-value; *dof_out receives the degrees of freedom. */
static double chi2_test(const double *observed, const double *expected, int bins, int *dof_out)
{
    double chi2 = 0.0, pooled_obs = 0.0, pooled_exp = 0.0;
    int used = 0;
    for (int i = 0; i < bins; i++) {
        if (expected[i] < 5.0) {
            pooled_obs += observed[i];
            pooled_exp += expected[i];
            continue;
        }
        double d = observed[i] - expected[i];
        chi2 += d * d / expected[i];
        used++;
    }
    if (pooled_exp >= 5.0) {
        double d = pooled_obs - pooled_exp;
        chi2 += d * d / pooled_exp;
        used++;
    } else if (pooled_obs > 10.0 + 10.0 * pooled_exp) {
        /* Samples where the pdf says there should be (almost) none. */
        chi2 += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / fmax(pooled_exp, 1.0);
        used++;
    }
    int dof = used - 1;
    if (dof_out)
        *dof_out = dof;
    return chi2_survival(chi2, dof);
}

#endif /* PHOS_TEST_CHI2_H */
