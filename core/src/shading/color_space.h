/*
 * color_space.h — the core's colour space: scene-linear Rec. 709 with a
 * D65 white, as Blender's configurations define it (3.4 to 5.x), and CIE
 * XYZ (D65) into it, which the Wavelength node and the Sky Texture use
 * (Cycles converts through the configuration's XYZ, D65 in each of
 * those versions).
 */
#ifndef PHOS_COLOR_SPACE_H
#define PHOS_COLOR_SPACE_H

#include "util/vec.h"

/* CIE XYZ (D65) → linear Rec. 709: the inverse of IEC 61966-2-1's
 * Rec. 709 → XYZ (Lindbloom's matrix). */
static inline vec3 xyz_to_rec709(vec3 xyz)
{
    return v3(3.2404542f * xyz.x - 1.5371385f * xyz.y - 0.4985314f * xyz.z,
              -0.9692660f * xyz.x + 1.8760108f * xyz.y + 0.0415560f * xyz.z,
              0.0556434f * xyz.x - 0.2040259f * xyz.y + 1.0572252f * xyz.z);
}

#endif /* PHOS_COLOR_SPACE_H */
