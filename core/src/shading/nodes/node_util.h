/*
 * node_util.h — scalar helpers the node families share, with Cycles'
 * conventions where they differ from C's, and the flag bits that select an
 * older Blender's definitions of a node.
 */
#ifndef PHOS_NODE_UTIL_H
#define PHOS_NODE_UTIL_H

#include <limits.h>

#include "util/vec.h"

/* Flag bits of MATH, VECTOR_MATH and HUE_SATURATION that select the
 * definitions of older Blender versions (converter.c and color.c list
 * what each changes): the add-on sets both for 3.4 to 4.2, PRE_5_0 alone
 * for 4.3 to 4.5, neither for 5.0 and later. */
#define PHOS_NODE_PRE_4_3 16u
#define PHOS_NODE_PRE_5_0 32u

/* The texture nodes' entry points and the noise library, compiled twice
 * on x86-64: for AVX2 and FMA (x86-64-v3, CPUs since 2013), which runs
 * the eight corners of a noise cell in one vector, and for the baseline;
 * the loader picks one by the CPU (GCC's function multi-versioning, an
 * ifunc). Not under the sanitizers, whose run-time starts after ifuncs
 * resolve, nor with other compilers. GCC 14 gives an ifunc and its
 * resolver default visibility whatever -fvisibility says: the library's
 * version script (core/phos.map) keeps them unexported. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(__SANITIZE_ADDRESS__) && \
    !defined(__SANITIZE_THREAD__)
#define NODE_VECTOR_CLONES __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define NODE_VECTOR_CLONES
#endif

/* A helper of the functions above, compiled into each of their copies
 * (a plain static function would be compiled once, for the baseline). */
#define NODE_INLINE static inline __attribute__((always_inline))

/* min and max as comparisons: a NaN first operand gives the second. */
static inline float node_min(float a, float b) { return a < b ? a : b; }
static inline float node_max(float a, float b) { return a > b ? a : b; }

/* min(max(x, lo), hi): a NaN x gives lo, and hi wins when lo > hi. */
static inline float node_clamp(float x, float lo, float hi) { return node_min(node_max(x, lo), hi); }
static inline vec3 node_saturate3(vec3 c)
{
    return v3(node_clamp(c.x, 0.0f, 1.0f), node_clamp(c.y, 0.0f, 1.0f), node_clamp(c.z, 0.0f, 1.0f));
}

/* Truncation toward zero as x86's cvttss2si does it: out of range and NaN
 * give INT_MIN (a plain (int) cast is undefined there). */
static inline int node_float_to_int(float x)
{
    return (x > -2147483648.0f && x < 2147483648.0f) ? (int)x : INT_MIN;
}

#endif /* PHOS_NODE_UTIL_H */
