/*
 * test_util.h — the few assertions the C tests share. Each test program
 * prints one line per failed check and a summary "N passed, N failed",
 * and exits non-zero if anything failed.
 */
#ifndef PHOS_TEST_UTIL_H
#define PHOS_TEST_UTIL_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int test_passed_count;
static int test_failed_count;

#define CHECK(cond)                                                                   \
    do {                                                                              \
        if (cond) {                                                                   \
            test_passed_count++;                                                      \
        } else {                                                                      \
            test_failed_count++;                                                      \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);  \
        }                                                                             \
    } while (0)

#define CHECK_MSG(cond, ...)                                                          \
    do {                                                                              \
        if (cond) {                                                                   \
            test_passed_count++;                                                      \
        } else {                                                                      \
            test_failed_count++;                                                      \
            fprintf(stderr, "%s:%d: check failed: %s: ", __FILE__, __LINE__, #cond);  \
            fprintf(stderr, __VA_ARGS__);                                             \
            fputc('\n', stderr);                                                      \
        }                                                                             \
    } while (0)

/* |a − b| <= tol·|b| */
#define CHECK_REL(a, b, tol)                                                          \
    CHECK_MSG(fabs((double)(a) - (double)(b)) <= (tol) * fabs((double)(b)),           \
              "%g vs %g (relative tolerance %g)", (double)(a), (double)(b), (double)(tol))

static inline int test_summary(const char *name)
{
    printf("%s: %d passed, %d failed\n", name, test_passed_count, test_failed_count);
    return test_failed_count == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}

/* The sanitizer runs (`make test-asan`, `make test-tsan`) set
 * PHOS_TEST_SANITIZER. A test whose time goes to the statistics of large
 * renders, on code paths that smaller tests of its program also walk,
 * leaves itself to the plain builds there: under ASan it ran 2.5-3.5x
 * slower and doubled CI's C time, and a sanitizer finds a bad access on
 * the first pixel that makes it, not the millionth
 * (docs/reliability.md lists them). Returns whether to skip, and says so. */
static inline int test_left_to_plain_build(const char *name)
{
    const char *v = getenv("PHOS_TEST_SANITIZER");
    if (!v || !*v || (v[0] == '0' && !v[1]))
        return 0;
    printf("%s: left to the plain build under a sanitizer (PHOS_TEST_SANITIZER)\n", name);
    return 1;
}

#endif /* PHOS_TEST_UTIL_H */
