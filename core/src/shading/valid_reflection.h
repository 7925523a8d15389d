/*
 * valid_reflection.h — a bent shading normal tilted back toward the
 * geometric normal until the viewer's mirror reflection leaves the surface
 * (docs/algorithms.md §8.1).
 *
 * A bump or normal map can bend N so far that the mirror direction
 * R = 2(N·I)N − I of the viewer I points into the surface: a glossy lobe
 * about such an N reflects mostly into the geometry, and the surface goes
 * dark or black at grazing angles. Cycles moves N, in the plane of Ng and
 * N, just far enough that Ng·R reaches t = min(0.9 Ng·I, 0.01). Writing
 * N' = x X + z Ng with X the unit part of N across Ng, the condition
 * 2(N'·I) z − Ng·I = t with x² + z² = 1 is a quadratic in z²,
 *   z² = ((a + Iz t) ± sqrt(Ix² (a − t²))) / (2a),  a = Ix² + Iz²,
 * and the two Blender generations pick the root differently.
 */
#ifndef PHOS_VALID_REFLECTION_H
#define PHOS_VALID_REFLECTION_H

#include "phos.h"
#include "util/vec.h"

/* n unchanged if its reflection of i is already at least t above the
 * surface, else tilted as rule (enum phos_normal_correction) says:
 * BOTH_ROOTS (Blender 2.81 to 3.6) takes, of the roots in (0, 1], the one
 * whose reflection is above the surface, the shallower if both are, and
 * Ng if none is; ONE_ROOT (4.0 on) the root the sign of Ix selects, and
 * leaves n = Ng (a flat face) alone. ng, i, n unit; i on ng's side. */
vec3 valid_reflection_normal(vec3 ng, vec3 i, vec3 n, uint32_t rule);

#endif
