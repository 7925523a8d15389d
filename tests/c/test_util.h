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

#endif /* PHOS_TEST_UTIL_H */
