/*
 * photon.c — RGBE power, direction bytes and the photon map container.
 *
 * RGBE follows Ward 1991 ("Real Pixels", Graphics Gems II) as Radiance's
 * setcolr/colr_color implement it; the direction bytes follow Jensen 2001
 * §6 with bin-centre tables (docs/algorithms.md §1.3). The map is a flat
 * array, sorted into classes and bucketed into its kd-tree by kdtree.c.
 */
#include "photons/photon.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "photons/kdtree.h"
#include "util/parallel.h"

/* ---- RGBE ---------------------------------------------------------------- */

/* Below this the photon is treated as black (Radiance's threshold). */
#define RGBE_MIN 1e-32f
/* The largest encodable value: exponent byte 255 = 2^127 · (255/256). */
#define RGBE_MAX 0x1.fep126f

static float rgbe_channel_in(float c)
{
    /* NaN and negatives to 0 (!(c > 0) is true for NaN); +inf saturates. */
    return c > 0.0f ? fminf(c, RGBE_MAX) : 0.0f;
}

void rgbe_encode(vec3 power, uint8_t rgbe[4])
{
    float r = rgbe_channel_in(power.x), g = rgbe_channel_in(power.y), b = rgbe_channel_in(power.z);
    float v = fmaxf(r, fmaxf(g, b));
    if (v < RGBE_MIN) {
        memset(rgbe, 0, 4);
        return;
    }
    /* v = m·2^e with m in [0.5, 1): the mantissas are c·256/2^e, the largest
     * in [128, 256). Computed in double, as Ward does, so that c·scale of the
     * largest channel never rounds up to 256; the min() is a second guard. */
    int e;
    frexp(v, &e);
    double scale = ldexp(1.0, 8 - e);
    rgbe[0] = (uint8_t)fmin((double)r * scale, 255.0);
    rgbe[1] = (uint8_t)fmin((double)g * scale, 255.0);
    rgbe[2] = (uint8_t)fmin((double)b * scale, 255.0);
    rgbe[3] = (uint8_t)(e + 128);
}

vec3 rgbe_decode(const uint8_t rgbe[4])
{
    if (rgbe[3] == 0)
        return v3s(0.0f);
    /* (byte + 0.5)·2^(E − 128 − 8): the centre of the truncation bin. The
     * power of two is assembled from its bits (this runs for every photon of
     * every estimate); below E = 10 it would be subnormal, which the encoder
     * never produces (E ≥ 23 for powers ≥ 1e-32), so libm handles that. */
    float f;
    if (rgbe[3] >= 10) {
        uint32_t bits = (uint32_t)(rgbe[3] - 9) << 23; /* exponent field (E − 136) + 127 */
        memcpy(&f, &bits, sizeof f);
    } else {
        f = ldexpf(1.0f, (int)rgbe[3] - (128 + 8));
    }
    return v3(((float)rgbe[0] + 0.5f) * f, ((float)rgbe[1] + 0.5f) * f, ((float)rgbe[2] + 0.5f) * f);
}

/* ---- direction bytes ----------------------------------------------------- */

/* Bin angle = (i + 0.5)·π/256 for theta and (i + 0.5)·2π/256 for phi, as
 * literal floats so that the tables are const, need no initialisation and
 * are safe from any thread. Generated offline by rounding the double-precision
 * cos/sin to float (printed with 9 significant digits); test_photon.c
 * recomputes every entry. */
const float photon_cos_theta[256] = {
    0.999981165f, 0.999830604f, 0.999529421f, 0.999077737f, 0.998475552f, 0.997723043f,
    0.996820271f, 0.995767415f, 0.994564593f, 0.993211925f, 0.991709769f, 0.990058184f,
    0.988257587f, 0.986308098f, 0.984210074f, 0.981963873f, 0.979569793f, 0.977028131f,
    0.974339366f, 0.971503913f, 0.968522072f, 0.965394437f, 0.962121427f, 0.958703458f,
    0.955141187f, 0.95143503f, 0.947585583f, 0.943593442f, 0.939459205f, 0.935183525f,
    0.93076694f, 0.926210225f, 0.921514034f, 0.916679084f, 0.91170603f, 0.906595707f,
    0.901348829f, 0.895966232f, 0.890448749f, 0.884797096f, 0.879012227f, 0.873094976f,
    0.867046237f, 0.860866964f, 0.854557991f, 0.848120332f, 0.841554999f, 0.834862888f,
    0.82804507f, 0.8211025f, 0.81403631f, 0.806847572f, 0.799537241f, 0.792106569f,
    0.784556568f, 0.77688849f, 0.769103348f, 0.761202395f, 0.753186822f, 0.745057762f,
    0.736816585f, 0.728464365f, 0.720002532f, 0.711432219f, 0.702754736f, 0.693971455f,
    0.685083687f, 0.676092684f, 0.666999936f, 0.657806695f, 0.64851439f, 0.639124453f,
    0.629638255f, 0.620057225f, 0.610382795f, 0.600616455f, 0.590759695f, 0.580813944f,
    0.570780754f, 0.560661554f, 0.550457954f, 0.540171444f, 0.529803634f, 0.519356012f,
    0.50883013f, 0.498227656f, 0.487550169f, 0.47679922f, 0.465976506f, 0.455083579f,
    0.444122136f, 0.433093816f, 0.422000259f, 0.410843164f, 0.399624199f, 0.388345033f,
    0.377007425f, 0.365612984f, 0.354163527f, 0.342660725f, 0.331106305f, 0.319502026f,
    0.307849646f, 0.296150893f, 0.284407526f, 0.272621363f, 0.260794103f, 0.248927608f,
    0.237023607f, 0.225083917f, 0.213110313f, 0.201104641f, 0.18906866f, 0.177004218f,
    0.164913118f, 0.152797192f, 0.140658244f, 0.128498107f, 0.116318628f, 0.104121633f,
    0.0919089541f, 0.0796824396f, 0.0674439222f, 0.0551952459f, 0.0429382585f, 0.030674804f,
    0.0184067301f, 0.00613588467f, -0.00613588467f, -0.0184067301f, -0.030674804f, -0.0429382585f,
    -0.0551952459f, -0.0674439222f, -0.0796824396f, -0.0919089541f, -0.104121633f, -0.116318628f,
    -0.128498107f, -0.140658244f, -0.152797192f, -0.164913118f, -0.177004218f, -0.18906866f,
    -0.201104641f, -0.213110313f, -0.225083917f, -0.237023607f, -0.248927608f, -0.260794103f,
    -0.272621363f, -0.284407526f, -0.296150893f, -0.307849646f, -0.319502026f, -0.331106305f,
    -0.342660725f, -0.354163527f, -0.365612984f, -0.377007425f, -0.388345033f, -0.399624199f,
    -0.410843164f, -0.422000259f, -0.433093816f, -0.444122136f, -0.455083579f, -0.465976506f,
    -0.47679922f, -0.487550169f, -0.498227656f, -0.50883013f, -0.519356012f, -0.529803634f,
    -0.540171444f, -0.550457954f, -0.560661554f, -0.570780754f, -0.580813944f, -0.590759695f,
    -0.600616455f, -0.610382795f, -0.620057225f, -0.629638255f, -0.639124453f, -0.64851439f,
    -0.657806695f, -0.666999936f, -0.676092684f, -0.685083687f, -0.693971455f, -0.702754736f,
    -0.711432219f, -0.720002532f, -0.728464365f, -0.736816585f, -0.745057762f, -0.753186822f,
    -0.761202395f, -0.769103348f, -0.77688849f, -0.784556568f, -0.792106569f, -0.799537241f,
    -0.806847572f, -0.81403631f, -0.8211025f, -0.82804507f, -0.834862888f, -0.841554999f,
    -0.848120332f, -0.854557991f, -0.860866964f, -0.867046237f, -0.873094976f, -0.879012227f,
    -0.884797096f, -0.890448749f, -0.895966232f, -0.901348829f, -0.906595707f, -0.91170603f,
    -0.916679084f, -0.921514034f, -0.926210225f, -0.93076694f, -0.935183525f, -0.939459205f,
    -0.943593442f, -0.947585583f, -0.95143503f, -0.955141187f, -0.958703458f, -0.962121427f,
    -0.965394437f, -0.968522072f, -0.971503913f, -0.974339366f, -0.977028131f, -0.979569793f,
    -0.981963873f, -0.984210074f, -0.986308098f, -0.988257587f, -0.990058184f, -0.991709769f,
    -0.993211925f, -0.994564593f, -0.995767415f, -0.996820271f, -0.997723043f, -0.998475552f,
    -0.999077737f, -0.999529421f, -0.999830604f, -0.999981165f,
};
const float photon_sin_theta[256] = {
    0.00613588467f, 0.0184067301f, 0.030674804f, 0.0429382585f, 0.0551952459f, 0.0674439222f,
    0.0796824396f, 0.0919089541f, 0.104121633f, 0.116318628f, 0.128498107f, 0.140658244f,
    0.152797192f, 0.164913118f, 0.177004218f, 0.18906866f, 0.201104641f, 0.213110313f,
    0.225083917f, 0.237023607f, 0.248927608f, 0.260794103f, 0.272621363f, 0.284407526f,
    0.296150893f, 0.307849646f, 0.319502026f, 0.331106305f, 0.342660725f, 0.354163527f,
    0.365612984f, 0.377007425f, 0.388345033f, 0.399624199f, 0.410843164f, 0.422000259f,
    0.433093816f, 0.444122136f, 0.455083579f, 0.465976506f, 0.47679922f, 0.487550169f,
    0.498227656f, 0.50883013f, 0.519356012f, 0.529803634f, 0.540171444f, 0.550457954f,
    0.560661554f, 0.570780754f, 0.580813944f, 0.590759695f, 0.600616455f, 0.610382795f,
    0.620057225f, 0.629638255f, 0.639124453f, 0.64851439f, 0.657806695f, 0.666999936f,
    0.676092684f, 0.685083687f, 0.693971455f, 0.702754736f, 0.711432219f, 0.720002532f,
    0.728464365f, 0.736816585f, 0.745057762f, 0.753186822f, 0.761202395f, 0.769103348f,
    0.77688849f, 0.784556568f, 0.792106569f, 0.799537241f, 0.806847572f, 0.81403631f,
    0.8211025f, 0.82804507f, 0.834862888f, 0.841554999f, 0.848120332f, 0.854557991f,
    0.860866964f, 0.867046237f, 0.873094976f, 0.879012227f, 0.884797096f, 0.890448749f,
    0.895966232f, 0.901348829f, 0.906595707f, 0.91170603f, 0.916679084f, 0.921514034f,
    0.926210225f, 0.93076694f, 0.935183525f, 0.939459205f, 0.943593442f, 0.947585583f,
    0.95143503f, 0.955141187f, 0.958703458f, 0.962121427f, 0.965394437f, 0.968522072f,
    0.971503913f, 0.974339366f, 0.977028131f, 0.979569793f, 0.981963873f, 0.984210074f,
    0.986308098f, 0.988257587f, 0.990058184f, 0.991709769f, 0.993211925f, 0.994564593f,
    0.995767415f, 0.996820271f, 0.997723043f, 0.998475552f, 0.999077737f, 0.999529421f,
    0.999830604f, 0.999981165f, 0.999981165f, 0.999830604f, 0.999529421f, 0.999077737f,
    0.998475552f, 0.997723043f, 0.996820271f, 0.995767415f, 0.994564593f, 0.993211925f,
    0.991709769f, 0.990058184f, 0.988257587f, 0.986308098f, 0.984210074f, 0.981963873f,
    0.979569793f, 0.977028131f, 0.974339366f, 0.971503913f, 0.968522072f, 0.965394437f,
    0.962121427f, 0.958703458f, 0.955141187f, 0.95143503f, 0.947585583f, 0.943593442f,
    0.939459205f, 0.935183525f, 0.93076694f, 0.926210225f, 0.921514034f, 0.916679084f,
    0.91170603f, 0.906595707f, 0.901348829f, 0.895966232f, 0.890448749f, 0.884797096f,
    0.879012227f, 0.873094976f, 0.867046237f, 0.860866964f, 0.854557991f, 0.848120332f,
    0.841554999f, 0.834862888f, 0.82804507f, 0.8211025f, 0.81403631f, 0.806847572f,
    0.799537241f, 0.792106569f, 0.784556568f, 0.77688849f, 0.769103348f, 0.761202395f,
    0.753186822f, 0.745057762f, 0.736816585f, 0.728464365f, 0.720002532f, 0.711432219f,
    0.702754736f, 0.693971455f, 0.685083687f, 0.676092684f, 0.666999936f, 0.657806695f,
    0.64851439f, 0.639124453f, 0.629638255f, 0.620057225f, 0.610382795f, 0.600616455f,
    0.590759695f, 0.580813944f, 0.570780754f, 0.560661554f, 0.550457954f, 0.540171444f,
    0.529803634f, 0.519356012f, 0.50883013f, 0.498227656f, 0.487550169f, 0.47679922f,
    0.465976506f, 0.455083579f, 0.444122136f, 0.433093816f, 0.422000259f, 0.410843164f,
    0.399624199f, 0.388345033f, 0.377007425f, 0.365612984f, 0.354163527f, 0.342660725f,
    0.331106305f, 0.319502026f, 0.307849646f, 0.296150893f, 0.284407526f, 0.272621363f,
    0.260794103f, 0.248927608f, 0.237023607f, 0.225083917f, 0.213110313f, 0.201104641f,
    0.18906866f, 0.177004218f, 0.164913118f, 0.152797192f, 0.140658244f, 0.128498107f,
    0.116318628f, 0.104121633f, 0.0919089541f, 0.0796824396f, 0.0674439222f, 0.0551952459f,
    0.0429382585f, 0.030674804f, 0.0184067301f, 0.00613588467f,
};
const float photon_cos_phi[256] = {
    0.999924719f, 0.999322355f, 0.998118103f, 0.996312618f, 0.993906975f, 0.990902662f,
    0.987301409f, 0.983105481f, 0.97831738f, 0.972939968f, 0.966976464f, 0.960430503f,
    0.953306019f, 0.945607305f, 0.937339008f, 0.928506076f, 0.919113874f, 0.909168005f,
    0.898674488f, 0.887639642f, 0.876070082f, 0.863972843f, 0.851355195f, 0.838224709f,
    0.824589312f, 0.81045717f, 0.795836926f, 0.780737221f, 0.765167236f, 0.749136388f,
    0.732654274f, 0.715730846f, 0.698376238f, 0.680601001f, 0.662415802f, 0.643831551f,
    0.624859512f, 0.605511069f, 0.585797846f, 0.565731823f, 0.545324981f, 0.524589658f,
    0.50353837f, 0.482183784f, 0.460538715f, 0.438616246f, 0.416429549f, 0.393992037f,
    0.371317208f, 0.348418683f, 0.32531029f, 0.302005947f, 0.27851969f, 0.254865646f,
    0.231058106f, 0.207111374f, 0.183039889f, 0.15885815f, 0.134580702f, 0.110222206f,
    0.0857973099f, 0.061320737f, 0.0368072242f, 0.0122715384f, -0.0122715384f, -0.0368072242f,
    -0.061320737f, -0.0857973099f, -0.110222206f, -0.134580702f, -0.15885815f, -0.183039889f,
    -0.207111374f, -0.231058106f, -0.254865646f, -0.27851969f, -0.302005947f, -0.32531029f,
    -0.348418683f, -0.371317208f, -0.393992037f, -0.416429549f, -0.438616246f, -0.460538715f,
    -0.482183784f, -0.50353837f, -0.524589658f, -0.545324981f, -0.565731823f, -0.585797846f,
    -0.605511069f, -0.624859512f, -0.643831551f, -0.662415802f, -0.680601001f, -0.698376238f,
    -0.715730846f, -0.732654274f, -0.749136388f, -0.765167236f, -0.780737221f, -0.795836926f,
    -0.81045717f, -0.824589312f, -0.838224709f, -0.851355195f, -0.863972843f, -0.876070082f,
    -0.887639642f, -0.898674488f, -0.909168005f, -0.919113874f, -0.928506076f, -0.937339008f,
    -0.945607305f, -0.953306019f, -0.960430503f, -0.966976464f, -0.972939968f, -0.97831738f,
    -0.983105481f, -0.987301409f, -0.990902662f, -0.993906975f, -0.996312618f, -0.998118103f,
    -0.999322355f, -0.999924719f, -0.999924719f, -0.999322355f, -0.998118103f, -0.996312618f,
    -0.993906975f, -0.990902662f, -0.987301409f, -0.983105481f, -0.97831738f, -0.972939968f,
    -0.966976464f, -0.960430503f, -0.953306019f, -0.945607305f, -0.937339008f, -0.928506076f,
    -0.919113874f, -0.909168005f, -0.898674488f, -0.887639642f, -0.876070082f, -0.863972843f,
    -0.851355195f, -0.838224709f, -0.824589312f, -0.81045717f, -0.795836926f, -0.780737221f,
    -0.765167236f, -0.749136388f, -0.732654274f, -0.715730846f, -0.698376238f, -0.680601001f,
    -0.662415802f, -0.643831551f, -0.624859512f, -0.605511069f, -0.585797846f, -0.565731823f,
    -0.545324981f, -0.524589658f, -0.50353837f, -0.482183784f, -0.460538715f, -0.438616246f,
    -0.416429549f, -0.393992037f, -0.371317208f, -0.348418683f, -0.32531029f, -0.302005947f,
    -0.27851969f, -0.254865646f, -0.231058106f, -0.207111374f, -0.183039889f, -0.15885815f,
    -0.134580702f, -0.110222206f, -0.0857973099f, -0.061320737f, -0.0368072242f, -0.0122715384f,
    0.0122715384f, 0.0368072242f, 0.061320737f, 0.0857973099f, 0.110222206f, 0.134580702f,
    0.15885815f, 0.183039889f, 0.207111374f, 0.231058106f, 0.254865646f, 0.27851969f,
    0.302005947f, 0.32531029f, 0.348418683f, 0.371317208f, 0.393992037f, 0.416429549f,
    0.438616246f, 0.460538715f, 0.482183784f, 0.50353837f, 0.524589658f, 0.545324981f,
    0.565731823f, 0.585797846f, 0.605511069f, 0.624859512f, 0.643831551f, 0.662415802f,
    0.680601001f, 0.698376238f, 0.715730846f, 0.732654274f, 0.749136388f, 0.765167236f,
    0.780737221f, 0.795836926f, 0.81045717f, 0.824589312f, 0.838224709f, 0.851355195f,
    0.863972843f, 0.876070082f, 0.887639642f, 0.898674488f, 0.909168005f, 0.919113874f,
    0.928506076f, 0.937339008f, 0.945607305f, 0.953306019f, 0.960430503f, 0.966976464f,
    0.972939968f, 0.97831738f, 0.983105481f, 0.987301409f, 0.990902662f, 0.993906975f,
    0.996312618f, 0.998118103f, 0.999322355f, 0.999924719f,
};
const float photon_sin_phi[256] = {
    0.0122715384f, 0.0368072242f, 0.061320737f, 0.0857973099f, 0.110222206f, 0.134580702f,
    0.15885815f, 0.183039889f, 0.207111374f, 0.231058106f, 0.254865646f, 0.27851969f,
    0.302005947f, 0.32531029f, 0.348418683f, 0.371317208f, 0.393992037f, 0.416429549f,
    0.438616246f, 0.460538715f, 0.482183784f, 0.50353837f, 0.524589658f, 0.545324981f,
    0.565731823f, 0.585797846f, 0.605511069f, 0.624859512f, 0.643831551f, 0.662415802f,
    0.680601001f, 0.698376238f, 0.715730846f, 0.732654274f, 0.749136388f, 0.765167236f,
    0.780737221f, 0.795836926f, 0.81045717f, 0.824589312f, 0.838224709f, 0.851355195f,
    0.863972843f, 0.876070082f, 0.887639642f, 0.898674488f, 0.909168005f, 0.919113874f,
    0.928506076f, 0.937339008f, 0.945607305f, 0.953306019f, 0.960430503f, 0.966976464f,
    0.972939968f, 0.97831738f, 0.983105481f, 0.987301409f, 0.990902662f, 0.993906975f,
    0.996312618f, 0.998118103f, 0.999322355f, 0.999924719f, 0.999924719f, 0.999322355f,
    0.998118103f, 0.996312618f, 0.993906975f, 0.990902662f, 0.987301409f, 0.983105481f,
    0.97831738f, 0.972939968f, 0.966976464f, 0.960430503f, 0.953306019f, 0.945607305f,
    0.937339008f, 0.928506076f, 0.919113874f, 0.909168005f, 0.898674488f, 0.887639642f,
    0.876070082f, 0.863972843f, 0.851355195f, 0.838224709f, 0.824589312f, 0.81045717f,
    0.795836926f, 0.780737221f, 0.765167236f, 0.749136388f, 0.732654274f, 0.715730846f,
    0.698376238f, 0.680601001f, 0.662415802f, 0.643831551f, 0.624859512f, 0.605511069f,
    0.585797846f, 0.565731823f, 0.545324981f, 0.524589658f, 0.50353837f, 0.482183784f,
    0.460538715f, 0.438616246f, 0.416429549f, 0.393992037f, 0.371317208f, 0.348418683f,
    0.32531029f, 0.302005947f, 0.27851969f, 0.254865646f, 0.231058106f, 0.207111374f,
    0.183039889f, 0.15885815f, 0.134580702f, 0.110222206f, 0.0857973099f, 0.061320737f,
    0.0368072242f, 0.0122715384f, -0.0122715384f, -0.0368072242f, -0.061320737f, -0.0857973099f,
    -0.110222206f, -0.134580702f, -0.15885815f, -0.183039889f, -0.207111374f, -0.231058106f,
    -0.254865646f, -0.27851969f, -0.302005947f, -0.32531029f, -0.348418683f, -0.371317208f,
    -0.393992037f, -0.416429549f, -0.438616246f, -0.460538715f, -0.482183784f, -0.50353837f,
    -0.524589658f, -0.545324981f, -0.565731823f, -0.585797846f, -0.605511069f, -0.624859512f,
    -0.643831551f, -0.662415802f, -0.680601001f, -0.698376238f, -0.715730846f, -0.732654274f,
    -0.749136388f, -0.765167236f, -0.780737221f, -0.795836926f, -0.81045717f, -0.824589312f,
    -0.838224709f, -0.851355195f, -0.863972843f, -0.876070082f, -0.887639642f, -0.898674488f,
    -0.909168005f, -0.919113874f, -0.928506076f, -0.937339008f, -0.945607305f, -0.953306019f,
    -0.960430503f, -0.966976464f, -0.972939968f, -0.97831738f, -0.983105481f, -0.987301409f,
    -0.990902662f, -0.993906975f, -0.996312618f, -0.998118103f, -0.999322355f, -0.999924719f,
    -0.999924719f, -0.999322355f, -0.998118103f, -0.996312618f, -0.993906975f, -0.990902662f,
    -0.987301409f, -0.983105481f, -0.97831738f, -0.972939968f, -0.966976464f, -0.960430503f,
    -0.953306019f, -0.945607305f, -0.937339008f, -0.928506076f, -0.919113874f, -0.909168005f,
    -0.898674488f, -0.887639642f, -0.876070082f, -0.863972843f, -0.851355195f, -0.838224709f,
    -0.824589312f, -0.81045717f, -0.795836926f, -0.780737221f, -0.765167236f, -0.749136388f,
    -0.732654274f, -0.715730846f, -0.698376238f, -0.680601001f, -0.662415802f, -0.643831551f,
    -0.624859512f, -0.605511069f, -0.585797846f, -0.565731823f, -0.545324981f, -0.524589658f,
    -0.50353837f, -0.482183784f, -0.460538715f, -0.438616246f, -0.416429549f, -0.393992037f,
    -0.371317208f, -0.348418683f, -0.32531029f, -0.302005947f, -0.27851969f, -0.254865646f,
    -0.231058106f, -0.207111374f, -0.183039889f, -0.15885815f, -0.134580702f, -0.110222206f,
    -0.0857973099f, -0.061320737f, -0.0368072242f, -0.0122715384f,
};

void direction_encode(vec3 d, uint8_t *theta, uint8_t *phi)
{
    /* Clamp: a direction normalised in float can have |z| slightly above 1,
     * and acos would return NaN. */
    float t = acosf(clampf(d.z, -1.0f, 1.0f)) * (256.0f / PHOS_PI);
    *theta = (uint8_t)(t > 0.0f ? (int)fminf(t, 255.0f) : 0); /* NaN → 0 */
    /* floor, not a cast: truncation toward zero would send the azimuths just
     * below 0 (y < 0, x > 0) into bin 0 instead of bin 255 and make bin 0
     * twice as wide. atan2 returns [−π, π]; the & 255 wraps −π..0 to bins
     * 128..255 and +π (bin 128) onto −π's bin. */
    float p = floorf(atan2f(d.y, d.x) * (256.0f / (2.0f * PHOS_PI)));
    *phi = (uint8_t)(p == p ? (int)p & 255 : 0); /* NaN → 0 */
}

vec3 direction_decode(uint8_t theta, uint8_t phi)
{
    float s = photon_sin_theta[theta];
    return v3(s * photon_cos_phi[phi], s * photon_sin_phi[phi], photon_cos_theta[theta]);
}

/* Octahedral map: n/|n|₁ on the octahedron, its lower half folded over the
 * upper; each coordinate in [−1, 1] quantised to 6 bits, the levels 0..62
 * so that 0 (and with it the six axes) is exact. */
#define NORMAL_LEVELS 62.0f

static float sign_not_zero(float v) { return v < 0.0f ? -1.0f : 1.0f; }

uint16_t normal_encode(vec3 n)
{
    float l1 = fabsf(n.x) + fabsf(n.y) + fabsf(n.z);
    if (!(l1 > 0.0f))
        return normal_encode(v3(0.0f, 0.0f, 1.0f)); /* zero or NaN: +z */
    vec3 unit = v3_scale(n, 1.0f / sqrtf(v3_dot(n, n)));
    float u = n.x / l1, v = n.y / l1;
    if (n.z < 0.0f) {
        float fu = (1.0f - fabsf(v)) * sign_not_zero(u), fv = (1.0f - fabsf(u)) * sign_not_zero(v);
        u = fu;
        v = fv;
    }
    /* Of the four grid points around (u, v), the one that decodes nearest
     * to n (Cigolle et al. 2014, "precise" octahedral encoding): rounding
     * each coordinate alone can be 1.5 times as far off. */
    float gu = clampf(0.5f * (u + 1.0f), 0.0f, 1.0f) * NORMAL_LEVELS;
    float gv = clampf(0.5f * (v + 1.0f), 0.0f, 1.0f) * NORMAL_LEVELS;
    uint16_t best = 0;
    float best_dot = -2.0f;
    for (int k = 0; k < 4; k++) {
        float cu = (k & 1) ? ceilf(gu) : floorf(gu), cv = (k & 2) ? ceilf(gv) : floorf(gv);
        uint16_t code = (uint16_t)((unsigned)cu | ((unsigned)cv << 6));
        float d = v3_dot(normal_decode(code), unit);
        if (d > best_dot) {
            best_dot = d;
            best = code;
        }
    }
    return best;
}

vec3 normal_decode(uint16_t code)
{
    float u = (float)(code & 63u) * (2.0f / NORMAL_LEVELS) - 1.0f;
    float v = (float)((code >> 6) & 63u) * (2.0f / NORMAL_LEVELS) - 1.0f;
    float z = 1.0f - fabsf(u) - fabsf(v);
    if (z < 0.0f) {
        float fu = (1.0f - fabsf(v)) * sign_not_zero(u), fv = (1.0f - fabsf(u)) * sign_not_zero(v);
        u = fu;
        v = fv;
    }
    return v3_normalize(v3(u, v, z));
}

vec3 photon_normal_table[4096];

/* Runs when the library (or a test) is loaded, before any thread can read
 * the table; 4096 decodes take microseconds. */
__attribute__((constructor)) static void photon_normal_table_fill(void)
{
    for (uint32_t code = 0; code < 4096; code++)
        photon_normal_table[code] = normal_decode((uint16_t)code);
}

photon photon_make(vec3 position, vec3 power, vec3 direction, vec3 normal, unsigned flags)
{
    photon p;
    p.position[0] = position.x;
    p.position[1] = position.y;
    p.position[2] = position.z;
    rgbe_encode(power, p.power);
    direction_encode(direction, &p.theta, &p.phi);
    p.flags = (uint16_t)((flags & (PHOTON_CAUSTIC | PHOTON_DIRECT)) | (normal_encode(normal) << PHOTON_NORMAL_SHIFT));
    return p;
}

/* ---- photon map ---------------------------------------------------------- */

void photon_map_init(photon_map *m)
{
    m->photons = NULL;
    m->count = 0;
    m->capacity = 0;
    m->built = 0;
    memset(m->classes, 0, sizeof(m->classes));
    m->splits = NULL;
    m->split_count = 0;
}

void photon_map_free(photon_map *m)
{
    if (!m)
        return;
    free(m->photons);
    free(m->splits);
    photon_map_init(m);
}

/* Reallocates to exactly `capacity` photons (never below count). */
static int photon_map_resize(photon_map *m, uint32_t capacity)
{
    if (capacity < m->count || capacity > PHOTON_MAP_MAX_PHOTONS)
        return 0;
    if (capacity == m->capacity)
        return 1;
    if (capacity == 0) {
        free(m->photons);
        m->photons = NULL;
        m->capacity = 0;
        return 1;
    }
    photon *p = realloc(m->photons, sizeof(photon) * (size_t)capacity);
    if (!p)
        return 0;
    m->photons = p;
    m->capacity = capacity;
    return 1;
}

int photon_map_reserve(photon_map *m, uint32_t capacity)
{
    if (m->built)
        return 0;
    return capacity <= m->capacity || photon_map_resize(m, capacity);
}

static int position_is_finite(const photon *p)
{
    return isfinite(p->position[0]) && isfinite(p->position[1]) && isfinite(p->position[2]);
}

photon *photon_map_extend(photon_map *m, uint32_t count)
{
    if (m->built || count == 0 || count > PHOTON_MAP_MAX_PHOTONS - m->count)
        return NULL;
    uint32_t need = m->count + count;
    if (need > m->capacity) {
        /* Grow by half so that N appends of one photon cost O(N). */
        uint64_t grown = (uint64_t)m->capacity + m->capacity / 2 + 16;
        if (grown < need)
            grown = need;
        if (grown > PHOTON_MAP_MAX_PHOTONS)
            grown = PHOTON_MAP_MAX_PHOTONS;
        if (!photon_map_resize(m, (uint32_t)grown))
            return NULL;
    }
    photon *slots = m->photons + m->count;
    m->count = need;
    return slots;
}

int photon_map_append(photon_map *m, const photon *photons, uint32_t count)
{
    if (count == 0)
        return !m->built;
    for (uint32_t i = 0; i < count; i++)
        if (!position_is_finite(&photons[i]))
            return 0;
    photon *slots = photon_map_extend(m, count);
    if (!slots)
        return 0;
    memcpy(slots, photons, sizeof(photon) * count);
    return 1;
}

unsigned photon_facing(vec3 n)
{
    float ax = fabsf(n.x), ay = fabsf(n.y), az = fabsf(n.z);
    if (ax >= ay && ax >= az)
        return n.x >= 0.0f ? 0u : 1u;
    if (ay >= az)
        return n.y >= 0.0f ? 2u : 3u;
    return n.z >= 0.0f ? 4u : 5u;
}

unsigned photon_class(const photon *p)
{
    /* The decoded normal: the one the searches test. */
    return photon_facing(photon_normal(p)) * 4u + (photon_is_direct(p) ? 1u : 0u) +
           (photon_is_caustic(p) ? 2u : 0u);
}


static int cancelled(atomic_int *cancel) { return cancel && atomic_load_explicit(cancel, memory_order_relaxed); }

/* The counting sort by class runs in slices of this many photons, each on
 * one thread (a few ms; the cancel flag is looked at between them). */
#define SORT_SLICE (1u << 16)

typedef struct class_sort {
    photon_map *m;
    photon *sorted;
    uint8_t *cls;      /* per photon: its class */
    uint32_t *offsets; /* per slice and class: the slice's count, then its first slot */
    uint32_t slices;
} class_sort;

static void count_slice(void *ctx, uint32_t item, uint32_t thread)
{
    (void)thread;
    class_sort *cs = ctx;
    uint32_t *count = cs->offsets + (size_t)item * PHOTON_CLASSES;
    uint32_t end = (item + 1) * SORT_SLICE < cs->m->count ? (item + 1) * SORT_SLICE : cs->m->count;
    for (uint32_t c = 0; c < PHOTON_CLASSES; c++)
        count[c] = 0;
    for (uint32_t i = item * SORT_SLICE; i < end; i++) {
        cs->cls[i] = (uint8_t)photon_class(&cs->m->photons[i]);
        count[cs->cls[i]]++;
    }
}

static void scatter_slice(void *ctx, uint32_t item, uint32_t thread)
{
    (void)thread;
    class_sort *cs = ctx;
    uint32_t next[PHOTON_CLASSES];
    memcpy(next, cs->offsets + (size_t)item * PHOTON_CLASSES, sizeof(next));
    uint32_t end = (item + 1) * SORT_SLICE < cs->m->count ? (item + 1) * SORT_SLICE : cs->m->count;
    for (uint32_t i = item * SORT_SLICE; i < end; i++)
        cs->sorted[next[cs->cls[i]]++] = cs->m->photons[i];
}

/* Counting sort by class, stable, on `threads` threads: each slice counts
 * its photons' classes (which decodes their normals once), the counts give
 * every slice its first slot in each class, in slice order, and the slices
 * then scatter side by side; the result is that of one pass in order. The
 * sorted copy replaces the array, which also drops the growth slack. 0
 * when memory is exhausted or cancelled (the map then keeps its photons
 * in their order). */
static int sort_by_class(photon_map *m, uint32_t threads, atomic_int *cancel)
{
    class_sort cs = {m, NULL, NULL, NULL, (m->count + SORT_SLICE - 1) / SORT_SLICE};
    if (m->count == 0) {
        memset(m->classes, 0, sizeof(m->classes));
        return 1;
    }
    cs.cls = malloc(m->count);
    cs.offsets = malloc(sizeof(uint32_t) * PHOTON_CLASSES * (size_t)cs.slices);
    cs.sorted = malloc(sizeof(photon) * (size_t)m->count);
    int ok = cs.cls && cs.offsets && cs.sorted && parallel_for(cs.slices, threads, count_slice, &cs, cancel);
    if (ok) {
        uint32_t start = 0;
        for (unsigned c = 0; c < PHOTON_CLASSES; c++) {
            m->classes[c].start = start;
            for (uint32_t k = 0; k < cs.slices; k++) {
                uint32_t *slot = &cs.offsets[(size_t)k * PHOTON_CLASSES + c];
                uint32_t n = *slot;
                *slot = start;
                start += n;
            }
            m->classes[c].count = start - m->classes[c].start;
        }
        ok = parallel_for(cs.slices, threads, scatter_slice, &cs, cancel);
    }
    free(cs.cls);
    free(cs.offsets);
    if (!ok) {
        free(cs.sorted);
        return 0;
    }
    free(m->photons);
    m->photons = cs.sorted;
    m->capacity = m->count;
    return 1;
}

int photon_map_build_many(photon_map *const *maps, unsigned count, uint32_t threads, atomic_int *cancel)
{
    for (unsigned i = 0; i < count; i++)
        if (!maps[i]->built && (cancelled(cancel) || !sort_by_class(maps[i], threads, cancel)))
            return 0;
    photon_map **todo = malloc(sizeof(photon_map *) * (count ? count : 1));
    if (!todo)
        return 0;
    unsigned n = 0;
    for (unsigned i = 0; i < count; i++)
        if (!maps[i]->built)
            todo[n++] = maps[i];
    int ok = n == 0 || (!cancelled(cancel) && kdtree_build(todo, n, threads, cancel));
    for (unsigned i = 0; ok && i < n; i++) {
        /* Give back the growth slack: a shrinking realloc keeps the data
         * even if it fails, so failure here only means the slack stays. */
        photon_map_resize(todo[i], todo[i]->count);
        todo[i]->built = 1;
    }
    free(todo);
    return ok;
}

int photon_map_build(photon_map *m, atomic_int *cancel) { return photon_map_build_many(&m, 1, 1, cancel); }

size_t photon_map_memory(const photon_map *m)
{
    return sizeof(photon_map) + sizeof(photon) * (size_t)m->capacity + sizeof(kdtree_split) * (size_t)m->split_count;
}
