/*
 * vertex_normals.c — angle-weighted vertex normals of a polygon mesh
 * (Thürmer & Wüthrich, "Computing vertex normals from polygonal facets",
 * JGT 3(1), 1998), the sum Blender's smooth shading uses, computed in a
 * fixed order (phos.h, phos_vertex_normals; docs/reliability.md).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "phos.h"

/* Unit vector from a to b; zero for coincident points. */
static void unit_edge(const float *a, const float *b, double e[3])
{
    double d[3] = {(double)b[0] - a[0], (double)b[1] - a[1], (double)b[2] - a[2]};
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double inv = len > 0.0 ? 1.0 / len : 0.0;
    for (int k = 0; k < 3; k++)
        e[k] = d[k] * inv;
}

phos_status phos_vertex_normals(uint32_t vertex_count, const float *positions, uint32_t polygon_count,
                                const uint32_t *loop_starts, const uint32_t *loop_totals, const float *polygon_normals,
                                uint32_t loop_count, const uint32_t *loop_vertices, float *out_normals)
{
    if ((vertex_count && (!positions || !out_normals)) ||
        (polygon_count && (!loop_starts || !loop_totals || !polygon_normals || !loop_vertices)))
        return PHOS_ERROR_INVALID_ARGUMENT;
    for (uint32_t f = 0; f < polygon_count; f++) {
        uint64_t end = (uint64_t)loop_starts[f] + loop_totals[f];
        if (loop_totals[f] < 3 || end > loop_count)
            return PHOS_ERROR_INVALID_ARGUMENT;
    }
    for (uint32_t l = 0; l < loop_count; l++)
        if (loop_vertices[l] >= vertex_count)
            return PHOS_ERROR_INVALID_ARGUMENT;
    double *sum = calloc((size_t)vertex_count * 3 + 1, sizeof(double));
    if (!sum)
        return PHOS_ERROR_OUT_OF_MEMORY;
    for (uint32_t f = 0; f < polygon_count; f++) {
        const uint32_t *v = loop_vertices + loop_starts[f];
        uint32_t k = loop_totals[f];
        const float *n = polygon_normals + 3 * (size_t)f;
        /* The corner's angle lies between the edge to the next corner and
         * the reversed edge from the previous one; a zero-length edge has
         * no direction and weighs π/2 (cos 0), as its dot product is 0. */
        double prev[3], next[3];
        unit_edge(positions + 3 * (size_t)v[k - 1], positions + 3 * (size_t)v[0], prev);
        for (uint32_t i = 0; i < k; i++) {
            unit_edge(positions + 3 * (size_t)v[i], positions + 3 * (size_t)v[i + 1 < k ? i + 1 : 0], next);
            double c = -(prev[0] * next[0] + prev[1] * next[1] + prev[2] * next[2]);
            double angle = acos(c < -1.0 ? -1.0 : c > 1.0 ? 1.0 : c);
            double *s = sum + 3 * (size_t)v[i];
            for (int j = 0; j < 3; j++)
                s[j] += angle * (double)n[j];
            memcpy(prev, next, sizeof(prev));
        }
    }
    for (uint32_t i = 0; i < vertex_count; i++) {
        const double *s = sum + 3 * (size_t)i;
        double len = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
        double inv = len > 0.0 ? 1.0 / len : 0.0;
        for (int j = 0; j < 3; j++)
            out_normals[3 * (size_t)i + j] = (float)(s[j] * inv) + 0.0f; /* −0 → +0 */
    }
    free(sum);
    return PHOS_OK;
}
