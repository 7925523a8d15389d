/*
 * phos.h — the public interface of libphos, the Phos render core.
 *
 * Conventions
 *  - Opaque handles with create/destroy pairs; destroying NULL is a no-op.
 *  - Every description struct has a phos_*_init() that fills the defaults;
 *    callers init, then set the fields they need.
 *  - Bulk inputs are pointer + count and are copied by the core: the caller
 *    may free them as soon as the call returns.
 *  - Every call that can fail returns a phos_status; the readable message is
 *    kept on the handle that was passed (phos_scene_error, phos_render_error).
 *  - Units: lengths in scene units (metres in Blender), angles in radians,
 *    radiometric quantities as documented on each field.
 *  - Pixels: (0,0) is the bottom-left pixel of the full frame, rows go up,
 *    as in Blender's render results.
 *  - Matrices: row-major 3x4 (the top three rows of a 4x4 affine matrix),
 *    mapping local coordinates to world coordinates.
 *
 * Thread safety: a scene is built from one thread. Once committed it is
 * read-only and may be shared by several renders. phos_render_cancel and
 * phos_render_progress may be called from any thread at any time.
 */
#ifndef PHOS_H
#define PHOS_H

#include <float.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define PHOS_API __declspec(dllexport)
#else
#define PHOS_API __attribute__((visibility("default")))
#endif

/* Version: major.minor.patch packed as (major << 16) | (minor << 8) | patch.
 * The add-on refuses a library whose major or minor differs from its own. */
#define PHOS_VERSION_MAJOR 0
#define PHOS_VERSION_MINOR 2
#define PHOS_VERSION_PATCH 0
#define PHOS_VERSION \
    ((PHOS_VERSION_MAJOR << 16) | (PHOS_VERSION_MINOR << 8) | PHOS_VERSION_PATCH)

PHOS_API uint32_t phos_version(void);

/* Size in bytes of a public struct, by its name ("phos_light_desc"), or 0
 * for an unknown name: lets a binding check that its mirror of the layout
 * matches the library it loaded. */
PHOS_API uint32_t phos_struct_size(const char *struct_name);

typedef enum phos_status {
    PHOS_OK = 0,
    PHOS_ERROR_INVALID_ARGUMENT = 1, /* a NULL handle, bad value, out-of-range index */
    PHOS_ERROR_INVALID_STATE = 2,    /* e.g. editing a committed scene */
    PHOS_ERROR_OUT_OF_MEMORY = 3,
    PHOS_ERROR_EMBREE = 4,           /* the ray-tracing kernel reported an error */
    PHOS_ERROR_CANCELLED = 5,        /* the render was cancelled */
    PHOS_ERROR_TIMEOUT = 6,          /* phos_render_wait returned before the end */
    PHOS_ERROR_INTERNAL = 7
} phos_status;

/* One line describing a status code ("invalid argument"). Never NULL. */
PHOS_API const char *phos_status_string(phos_status status);

/* Byte offset and size of a field of a public struct, by names
 * ("phos_light_desc", "radius"); PHOS_ERROR_INVALID_ARGUMENT for an unknown
 * struct or field. With phos_struct_size it lets a binding check every
 * field of its mirror against the library it loaded. */
PHOS_API phos_status phos_struct_field(const char *struct_name, const char *field_name, uint32_t *out_offset,
                                       uint32_t *out_size);

typedef struct phos_scene phos_scene;
typedef struct phos_render phos_render;

/* ------------------------------------------------------------------ scene */

/* Returns NULL only when memory is exhausted. */
PHOS_API phos_scene *phos_scene_create(void);
PHOS_API void phos_scene_destroy(phos_scene *scene);
/* The message of the last failed call on this scene, "" if none. */
PHOS_API const char *phos_scene_error(const phos_scene *scene);

/* Images: linear RGBA float pixels with straight alpha, rows bottom-up (as
 * Blender stores them). How an image is looked up (interpolation,
 * extension, projection) is the Image Texture instruction's (below). */
typedef struct phos_image_desc {
    uint32_t width, height;
    const float *pixels;        /* width*height*4 floats, linear RGBA */
} phos_image_desc;
PHOS_API void phos_image_desc_init(phos_image_desc *desc);
PHOS_API phos_status phos_scene_add_image(phos_scene *scene, const phos_image_desc *desc,
                                          uint32_t *out_image_id);

/*
 * Materials are weighted sums of closures, the way Cycles flattens a shader
 * node tree: Mix and Add shaders only scale and concatenate closure lists.
 * A closure's fields are constants, or set at each shading point by the
 * material's shader program (below) where textures feed them.
 */
enum phos_closure_type {
    PHOS_CLOSURE_DIFFUSE = 0,            /* Lambert, f = weight/π */
    PHOS_CLOSURE_PRINCIPLED_DIFFUSE = 1, /* Disney/Burley diffuse with roughness retro-reflection */
    PHOS_CLOSURE_REFLECTION = 2,         /* GGX microfacet reflection, F = 1 (Glossy BSDF); sharp if roughness = 0 */
    PHOS_CLOSURE_REFLECTION_FRESNEL = 3, /* GGX reflection with Fresnel blended from specular_color
                                            (f0) to white by the dielectric Fresnel of ior (Principled) */
    PHOS_CLOSURE_REFRACTION = 4,         /* GGX microfacet refraction, no Fresnel; sharp if roughness = 0 */
    PHOS_CLOSURE_GLASS = 5,              /* dielectric: reflection + refraction split by Fresnel */
    PHOS_CLOSURE_TRANSPARENT = 6,        /* straight pass-through */
    PHOS_CLOSURE_EMISSION = 7,           /* radiance weight W/(m²·sr), both faces */
    PHOS_CLOSURE_METAL = 8,              /* GGX reflection with the F82-tint Fresnel: specular_color at
                                            normal incidence, specular_tint near grazing (Principled metallic,
                                            Metallic BSDF; Cycles 4+) */
    PHOS_CLOSURE_OREN_NAYAR = 9,         /* energy-preserving Oren-Nayar diffuse of roughness (Fujii 2012,
                                            with the OpenPBR multiple-scattering term; Cycles 4.3+):
                                            specular_color the albedo of that term, specular_tint
                                            an extra colour of it (Cycles 4.3-5.0: the albedo again) */
    PHOS_CLOSURE_SHEEN = 10,             /* microfiber sheen of roughness (Zeltner et al. 2022, an LTC
                                            lobe; its weight is scaled by the lobe's albedo) */
    PHOS_CLOSURE_TRANSLUCENT = 11,       /* Lambertian transmission, f = weight/π toward the side
                                            opposite wo (Translucent BSDF) */
    PHOS_CLOSURE_HOLDOUT = 12,           /* not light: a camera ray that meets it, directly or through
                                            transparency, makes the pixel transparent by the average of
                                            weight × throughput and gets no light from it (Holdout) */
    PHOS_CLOSURE_TYPE_COUNT = 13
};

/* How GLASS splits reflection and refraction. */
enum phos_glass_fresnel {
    PHOS_GLASS_FRESNEL_MACRO = 0,     /* Fresnel at the shading normal (Cycles before 4.0) */
    PHOS_GLASS_FRESNEL_MICROFACET = 1 /* Fresnel per sampled microfacet (Cycles 4.0+) */
};

/* The GGX model of a microfacet closure (REFLECTION, REFLECTION_FRESNEL,
 * REFRACTION, GLASS, METAL), as the Cycles of each Blender defines it. */
enum phos_microfacet {
    PHOS_MICROFACET_GGX_SEPARABLE = 0,   /* Smith G1(wo)·G1(wi): Cycles up to 3.x */
    PHOS_MICROFACET_GGX = 1,             /* height-correlated Smith G (Heitz 2014): Cycles 4+ */
    PHOS_MICROFACET_GGX_MULTISCATTER = 2, /* GGX with the light that scatters between microfacets
                                            restored by albedo scaling (Kulla & Conty 2017): Cycles 4+'s
                                            Multiscatter GGX; not for REFRACTION */
    PHOS_MICROFACET_BECKMANN_SEPARABLE = 3, /* Beckmann (Walter 2007), separable G: Cycles up to 3.x */
    PHOS_MICROFACET_BECKMANN = 4,        /* Beckmann, height-correlated G: Cycles 4+ */
    PHOS_MICROFACET_ASHIKHMIN_SHIRLEY = 5, /* Ashikhmin & Shirley 2000, REFLECTION only (Glossy) */
};

/* How a closure's bent normal is kept from reflecting the viewer into the
 * surface (docs/algorithms.md §8.1): the add-on chooses as the running
 * Blender's Cycles does. */
enum phos_normal_correction {
    PHOS_NORMAL_CORRECTION_NONE = 0,       /* the normal as given (Cycles 4.0+: diffuse, sheen) */
    PHOS_NORMAL_CORRECTION_BOTH_ROOTS = 1, /* Cycles 2.81-3.6, every closure: of the two tilts that put the
                                              reflection at the threshold, the shallower one above it */
    PHOS_NORMAL_CORRECTION_ONE_ROOT = 2    /* Cycles 4.0+, glossy, glass, refraction, translucent, coat:
                                              the tilt the viewer's side selects; a flat face's untouched */
};

typedef struct phos_closure_desc {
    uint32_t type;             /* enum phos_closure_type */
    float weight[3];           /* linear RGB weight (colour × mix factors); radiance for EMISSION */
    float roughness;           /* Blender roughness in [0,1]; GGX alpha = roughness² */
    float ior;                 /* index of refraction, > 0 (GLASS, REFRACTION, REFLECTION_FRESNEL) */
    float specular_color[3];   /* REFLECTION_FRESNEL, METAL: reflectance at normal incidence;
                                  OREN_NAYAR: the albedo of its multiple-scattering term (its colour) */
    uint32_t glass_fresnel;    /* enum phos_glass_fresnel */
    float transmission_tint[3];/* GLASS: extra colour of the refracted light only (Principled: base colour) */
    float transmission_roughness; /* GLASS with MACRO Fresnel: roughness of the refraction lobe; < 0 = roughness */
    uint32_t microfacet;       /* enum phos_microfacet */
    float multiscatter_fresnel[3]; /* GGX_MULTISCATTER: the lobe's mean single-scattering Fresnel
                                      F_ss = ∫ F(μ) 2μ dμ (Glossy and Glass BSDF: their colour) */
    float specular_tint[3];    /* METAL: the F82 tint, reflectance at μ = 1/7 (about 82°) relative to Schlick's;
                                  GLASS (MICROFACET): f0 = F0(ior)·tint (Principled Specular Tint);
                                  OREN_NAYAR: colour of the multiple-scattering term; in [0,1] */
    float thin_film_thickness; /* nm; above 0.1 a thin film on REFLECTION_FRESNEL and GLASS (MICROFACET)
                                  reflects with interference colours (Belcour & Barla 2017) */
    float thin_film_ior;       /* the film's index of refraction */
    /* Layering (Cycles 4's Principled BSDF): this closure lies over the next
     * layer_span closures of the material, whose weights are scaled by
     * 1 − max over channels of layer_weight × this closure's directional
     * albedo toward the viewer, and, when layer_tint is not white, by
     * mix(1, layer_tint^(1/cos θt), layer_tint_weight) with θt the view
     * direction refracted into the layer (a coat's absorption, Beer's law
     * through a unit thickness). */
    uint32_t layer_span;
    float layer_weight[3];     /* the closure's weight relative to those under it (Coat Weight, Sheen
                                  Weight × Sheen Tint, 1 for the Principled specular) */
    float layer_tint[3];       /* colour of light crossing the layer once at normal incidence */
    float layer_tint_weight;   /* how much of the tint applies (Coat Weight) */
    /* Anisotropic GGX (REFLECTION, REFLECTION_FRESNEL, METAL; Cycles'
     * Anisotropy): roughness_y < 0 is isotropic; otherwise roughness is
     * along the closure's tangent (αx = roughness²) and roughness_y across
     * it (αy = roughness_y²), in [0,1]. The tangent is the program's
     * (PHOS_FIELD_TANGENT), else Cycles' default (Geometry's Tangent: about
     * the object's Z axis through its generated coordinates), turned about
     * the closure's normal by tangent_rotation turns (×2π radians). */
    float roughness_y;
    float tangent_rotation;
    /* enum phos_normal_correction: whether the closure's normal is tilted
     * back toward the geometric normal until the viewer's mirror
     * reflection leaves the surface, and by which of Cycles' rules
     * (docs/algorithms.md §8.1). */
    uint32_t normal_correction;
} phos_closure_desc;
PHOS_API void phos_closure_desc_init(phos_closure_desc *desc);

/*
 * Shader programs (docs/architecture.md, "Shader programs"). The add-on
 * compiles a Cycles node tree into a flat list of instructions over a
 * register file of floats; a colour or vector operand is three consecutive
 * registers. Registers [0, constant_count) hold the constants; every other
 * register is written by an instruction before any instruction reads it.
 * The core evaluates the program at each shading point (camera paths and
 * photon hits alike) and the bindings overwrite fields of the material's
 * closures with registers. An instruction is one node: `op` its type,
 * `mode` its enum settings, `flags` its switches, `param` its float
 * settings, `table` an image id or an offset into the program's table,
 * `inputs` and `outputs` its sockets in the order each op's comment lists
 * (PHOS_SHADER_NO_REGISTER for an output nobody reads). The core folds
 * instructions whose inputs are all constants when the material is added,
 * and a program that folds away entirely costs nothing at render time.
 */
#define PHOS_SHADER_NO_REGISTER 0xFFFFFFFFu
#define PHOS_SHADER_MAX_INPUTS 12
#define PHOS_SHADER_MAX_OUTPUTS 5
#define PHOS_SHADER_MAX_REGISTERS 2048
#define PHOS_SHADER_MAX_INSTRUCTIONS 4096
#define PHOS_SHADER_MAX_TABLE 65536

/* Ops. in/out: sockets (width 3 for colours and vectors, 1 otherwise). */
enum phos_shader_op {
    PHOS_OP_MATH = 0,            /* in a, b, c; out value. mode enum phos_math; flags 1 = clamp to [0,1];
                                    MATH, VECTOR_MATH, HUE_SATURATION: flags 16 = Blender before 4.3,
                                    32 = before 5.0 (shading/nodes/node_util.h) */
    PHOS_OP_VECTOR_MATH = 1,     /* in a(3), b(3), c(3), scale; out vector(3), value. mode enum phos_vector_math */
    PHOS_OP_MIX_FLOAT = 2,       /* in fac, a, b; out value. flags 2 = clamp factor */
    PHOS_OP_MIX_VECTOR = 3,      /* in fac(1 or 3), a(3), b(3); out (3). flags 2 = clamp factor, 4 = fac is 3 wide */
    PHOS_OP_MIX_COLOR = 4,       /* in fac, a(3), b(3); out (3). mode enum phos_blend; flags 1 = clamp result,
                                    2 = clamp factor */
    PHOS_OP_MAP_RANGE = 5,       /* in value, from_min, from_max, to_min, to_max, steps; out value.
                                    mode enum phos_map_range; flags 1 = clamp */
    PHOS_OP_MAP_RANGE_VECTOR = 6,/* the same, every socket 3 wide */
    PHOS_OP_CLAMP = 7,           /* in value, min, max; out value. mode enum phos_clamp */
    PHOS_OP_RAMP = 8,            /* in fac; out color(3), alpha. table: mode entries of RGBA (ColorRamp baked);
                                    flags 8 = constant interpolation */
    PHOS_OP_CURVES_RGB = 9,      /* in fac, color(3); out color(3). table: mode entries of (r, g, b, 0), the
                                    R, G, B curves after the combined one, over [param[0], param[1]];
                                    flags 1 = extrapolate */
    PHOS_OP_CURVES_VECTOR = 10,  /* in fac, vector(3); out vector(3). table: mode entries of (x, y, z, 0)
                                    over [param[0], param[1]]; flags 1 = extrapolate */
    PHOS_OP_CURVE_FLOAT = 11,    /* in fac, value; out value. table: mode entries of (value, 0, 0, 0) over
                                    [param[0], param[1]]; flags 1 = extrapolate */
    PHOS_OP_HUE_SATURATION = 12, /* in hue, saturation, value, fac, color(3); out color(3) */
    PHOS_OP_BRIGHT_CONTRAST = 13,/* in color(3), bright, contrast; out color(3) */
    PHOS_OP_GAMMA = 14,          /* in color(3), gamma; out color(3) */
    PHOS_OP_INVERT = 15,         /* in fac, color(3); out color(3) */
    PHOS_OP_SEPARATE_COLOR = 16, /* in color(3); out (3). mode enum phos_color_model */
    PHOS_OP_COMBINE_COLOR = 17,  /* in r, g, b; out color(3). mode enum phos_color_model */
    PHOS_OP_COMBINE_XYZ = 18,    /* in x, y, z; out vector(3) */
    PHOS_OP_RGB_TO_BW = 19,      /* in color(3); out value */
    PHOS_OP_BLACKBODY = 20,      /* in temperature (K); out color(3) */
    PHOS_OP_WAVELENGTH = 21,     /* in wavelength (nm); out color(3) */
    PHOS_OP_TEX_IMAGE = 22,      /* in vector(3); out color(3), alpha. table: image id; mode enum
                                    phos_image_projection; param[0] box blend; flags enum phos_image_flags */
    PHOS_OP_TEX_NOISE = 23,      /* in vector(3), w, scale, detail, roughness, lacunarity, offset, gain,
                                    distortion; out fac, color(3). mode enum phos_noise_type; flags: bits 0-2
                                    dimensions (1-4), 8 = normalize, 16 = Blender 3.x definitions */
    PHOS_OP_TEX_MUSGRAVE = 24,   /* (Blender 3.x and 4.0) in vector(3), w, scale, detail, dimension,
                                    lacunarity, offset, gain; out fac. mode enum phos_noise_type; flags bits 0-2
                                    dimensions */
    PHOS_OP_TEX_WHITE_NOISE = 25,/* in vector(3), w; out value, color(3). flags bits 0-2 dimensions */
    PHOS_OP_TEX_VORONOI = 26,    /* in vector(3), w, scale, detail, roughness, lacunarity, smoothness, exponent,
                                    randomness; out distance, color(3), position(3), w, radius. mode enum
                                    phos_voronoi_feature; flags: bits 0-2 dimensions, 8 = normalize,
                                    16 = Blender 3.x definitions, bits 5-6 enum phos_voronoi_metric,
                                    128 = Blender 5.0+'s cell hash (2-4D) */
    PHOS_OP_TEX_WAVE = 27,       /* in vector(3), scale, distortion, detail, detail_scale, detail_roughness,
                                    phase; out color(3), fac. mode enum phos_wave_type; flags: bits 0-3 bands
                                    direction, bits 4-7 rings direction, bits 8-11 profile (enum phos_wave_*),
                                    16 << 8 = Blender 3.x noise */
    PHOS_OP_TEX_BRICK = 28,      /* in vector(3), color1(3), color2(3), mortar(3), scale, mortar_size,
                                    mortar_smooth, bias, brick_width, row_height; out color(3), fac.
                                    param: offset, offset_frequency, squash, squash_frequency; flags 1 =
                                    Blender 3.x's mortar smoothing (solid mortar for a negative one) */
    PHOS_OP_TEX_CHECKER = 29,    /* in vector(3), color1(3), color2(3), scale; out color(3), fac */
    PHOS_OP_TEX_MAGIC = 30,      /* in vector(3), scale, distortion; out color(3), fac. mode depth (0-10);
                                    flags 1 = the scale applied before the 2π wrap (Blender 5.3) */
    PHOS_OP_TEX_GRADIENT = 31,   /* in vector(3); out color(3), fac. mode enum phos_gradient */
    PHOS_OP_TEXTURE_COORDINATE = 32, /* out generated(3), normal(3), uv(3), object(3), camera(3);
                                    a second instruction with mode 1: out window(3), reflection(3) */
    PHOS_OP_GEOMETRY = 33,       /* out position(3), normal(3), true_normal(3), incoming(3), backfacing */
    PHOS_OP_OBJECT_INFO = 34,    /* out location(3), random, object_index */
    PHOS_OP_FRESNEL = 35,        /* in ior, normal(3); out fac */
    PHOS_OP_LAYER_WEIGHT = 36,   /* in blend, normal(3); out fresnel, facing */
    PHOS_OP_LIGHT_PATH = 37,     /* out is_camera, is_shadow, is_diffuse, is_glossy, is_singular (a second
                                    instruction with mode 1: is_reflection, is_transmission, ray_length,
                                    ray_depth, transparent_depth; mode 2: diffuse_depth, glossy_depth,
                                    transmission_depth) */
    PHOS_OP_MAPPING = 38,        /* in vector(3), location(3), rotation(3) (Euler XYZ, radians), scale(3);
                                    out vector(3). mode enum phos_mapping */
    PHOS_OP_NORMAL_MAP = 39,     /* in strength, color(3); out normal(3). mode enum phos_normal_map_space;
                                    flags 1 = tangent space applies Strength in tangent space (Blender 4+;
                                    before, the normal is blended from the shading normal); flags 2 = the
                                    tangents of another UV map: the mesh attribute `table`, per corner
                                    (x, y, z, bitangent sign) in object space */
    PHOS_OP_BUMP = 40,           /* in strength, distance, height, height_dx, height_dy, normal(3); out
                                    normal(3). flags 1 = invert, 2 = keep the viewer's reflection above the
                                    surface (Blender before 4.0). The heights at the point and at the point
                                    moved by the two offsets the program's OFFSET instructions read; param[0]
                                    the filter width: the fraction of the pixel's footprint the offsets step
                                    (≥ 0; 0 means 1), the same as those OFFSET instructions' */
    PHOS_OP_BUMP_OFFSET = 41,    /* out position(3) moved along the footprint's axis mode (0: none, 1: dx,
                                    2: dy) by param[0] (the filter width, as BUMP's) of it, and the texture
                                    coordinates there: generated(3), uv(3), object(3), normal(3) */
    PHOS_OP_VECTOR_ROTATE = 42,  /* in vector(3), center(3), axis(3), angle, rotation(3); out vector(3).
                                    mode enum phos_vector_rotate; flags 1 = invert */
    PHOS_OP_VECTOR_TRANSFORM = 43,/* in vector(3); out vector(3). mode enum phos_vector_transform_type;
                                    flags: bits 0-3 from space, bits 4-7 to space (enum phos_space) */
    PHOS_OP_NORMAL = 44,         /* in normal(3); out normal(3) (param[0..2]), dot */
    PHOS_OP_ATTRIBUTE = 45,      /* out color(3), vector(3), fac, alpha: the mesh attribute whose id is `table`
                                    (phos_mesh_attribute), as Cycles' Attribute node converts its type; a mesh
                                    without it gives 0 and alpha 1 (flags 1: alpha 0, the Color Attribute
                                    node's). mode 0: at the point; 1, 2: at a Bump's moved points
                                    (BUMP_OFFSET's modes and param[0], its filter width), the
                                    barycentrics moved with them */
    PHOS_OP_TANGENT = 46,        /* out tangent(3). mode enum phos_tangent (Tangent node; Geometry's
                                    Tangent is RADIAL_Z) */
    PHOS_OP_TEX_SKY = 47,        /* in vector(3); out color(3). mode enum phos_sky_model; table: offset of the
                                    PHOS_SKY_DATA_FLOATS floats of phos_sky_bake (with the texture's image id
                                    at PHOS_SKY_DATA_IMAGE for the scattering models); flags 1: the vector is
                                    the world's direction, so the core may render the sun's disc as a sun
                                    light (docs/algorithms.md §11.1) */
    PHOS_OP_COUNT = 48
};

/* Node enums, named as Blender names their items so the add-on maps them by name. */
enum phos_math {
    PHOS_MATH_ADD = 0, PHOS_MATH_SUBTRACT = 1, PHOS_MATH_MULTIPLY = 2, PHOS_MATH_DIVIDE = 3,
    PHOS_MATH_MULTIPLY_ADD = 4, PHOS_MATH_POWER = 5, PHOS_MATH_LOGARITHM = 6, PHOS_MATH_SQRT = 7,
    PHOS_MATH_INVERSE_SQRT = 8, PHOS_MATH_ABSOLUTE = 9, PHOS_MATH_EXPONENT = 10, PHOS_MATH_MINIMUM = 11,
    PHOS_MATH_MAXIMUM = 12, PHOS_MATH_LESS_THAN = 13, PHOS_MATH_GREATER_THAN = 14, PHOS_MATH_SIGN = 15,
    PHOS_MATH_COMPARE = 16, PHOS_MATH_SMOOTH_MIN = 17, PHOS_MATH_SMOOTH_MAX = 18, PHOS_MATH_ROUND = 19,
    PHOS_MATH_FLOOR = 20, PHOS_MATH_CEIL = 21, PHOS_MATH_TRUNC = 22, PHOS_MATH_FRACT = 23,
    PHOS_MATH_MODULO = 24, PHOS_MATH_FLOORED_MODULO = 25, PHOS_MATH_WRAP = 26, PHOS_MATH_SNAP = 27,
    PHOS_MATH_PINGPONG = 28, PHOS_MATH_SINE = 29, PHOS_MATH_COSINE = 30, PHOS_MATH_TANGENT = 31,
    PHOS_MATH_ARCSINE = 32, PHOS_MATH_ARCCOSINE = 33, PHOS_MATH_ARCTANGENT = 34, PHOS_MATH_ARCTAN2 = 35,
    PHOS_MATH_SINH = 36, PHOS_MATH_COSH = 37, PHOS_MATH_TANH = 38, PHOS_MATH_RADIANS = 39,
    PHOS_MATH_DEGREES = 40, PHOS_MATH_COUNT = 41
};
enum phos_vector_math {
    PHOS_VECTOR_MATH_ADD = 0, PHOS_VECTOR_MATH_SUBTRACT = 1, PHOS_VECTOR_MATH_MULTIPLY = 2,
    PHOS_VECTOR_MATH_DIVIDE = 3, PHOS_VECTOR_MATH_MULTIPLY_ADD = 4, PHOS_VECTOR_MATH_CROSS_PRODUCT = 5,
    PHOS_VECTOR_MATH_PROJECT = 6, PHOS_VECTOR_MATH_REFLECT = 7, PHOS_VECTOR_MATH_REFRACT = 8,
    PHOS_VECTOR_MATH_FACEFORWARD = 9, PHOS_VECTOR_MATH_DOT_PRODUCT = 10, PHOS_VECTOR_MATH_DISTANCE = 11,
    PHOS_VECTOR_MATH_LENGTH = 12, PHOS_VECTOR_MATH_SCALE = 13, PHOS_VECTOR_MATH_NORMALIZE = 14,
    PHOS_VECTOR_MATH_ABSOLUTE = 15, PHOS_VECTOR_MATH_POWER = 16, PHOS_VECTOR_MATH_SIGN = 17,
    PHOS_VECTOR_MATH_MINIMUM = 18, PHOS_VECTOR_MATH_MAXIMUM = 19, PHOS_VECTOR_MATH_FLOOR = 20,
    PHOS_VECTOR_MATH_CEIL = 21, PHOS_VECTOR_MATH_FRACTION = 22, PHOS_VECTOR_MATH_MODULO = 23,
    PHOS_VECTOR_MATH_WRAP = 24, PHOS_VECTOR_MATH_SNAP = 25, PHOS_VECTOR_MATH_SINE = 26,
    PHOS_VECTOR_MATH_COSINE = 27, PHOS_VECTOR_MATH_TANGENT = 28, PHOS_VECTOR_MATH_COUNT = 29
};
enum phos_blend {
    PHOS_BLEND_MIX = 0, PHOS_BLEND_DARKEN = 1, PHOS_BLEND_MULTIPLY = 2, PHOS_BLEND_BURN = 3,
    PHOS_BLEND_LIGHTEN = 4, PHOS_BLEND_SCREEN = 5, PHOS_BLEND_DODGE = 6, PHOS_BLEND_ADD = 7,
    PHOS_BLEND_OVERLAY = 8, PHOS_BLEND_SOFT_LIGHT = 9, PHOS_BLEND_LINEAR_LIGHT = 10,
    PHOS_BLEND_DIFFERENCE = 11, PHOS_BLEND_EXCLUSION = 12, PHOS_BLEND_SUBTRACT = 13, PHOS_BLEND_DIVIDE = 14,
    PHOS_BLEND_HUE = 15, PHOS_BLEND_SATURATION = 16, PHOS_BLEND_VALUE = 17, PHOS_BLEND_COLOR = 18,
    PHOS_BLEND_COUNT = 19
};
enum phos_map_range {
    PHOS_MAP_RANGE_LINEAR = 0, PHOS_MAP_RANGE_STEPPED = 1, PHOS_MAP_RANGE_SMOOTHSTEP = 2,
    PHOS_MAP_RANGE_SMOOTHERSTEP = 3, PHOS_MAP_RANGE_COUNT = 4
};
enum phos_clamp { PHOS_CLAMP_MINMAX = 0, PHOS_CLAMP_RANGE = 1, PHOS_CLAMP_COUNT = 2 };
enum phos_color_model { PHOS_COLOR_MODEL_RGB = 0, PHOS_COLOR_MODEL_HSV = 1, PHOS_COLOR_MODEL_HSL = 2,
                        PHOS_COLOR_MODEL_COUNT = 3 };
/* EQUIRECTANGULAR and MIRROR_BALL are the Environment Texture's: the vector is a direction. */
enum phos_image_projection { PHOS_PROJECTION_FLAT = 0, PHOS_PROJECTION_BOX = 1, PHOS_PROJECTION_SPHERE = 2,
                             PHOS_PROJECTION_TUBE = 3, PHOS_PROJECTION_EQUIRECTANGULAR = 4,
                             PHOS_PROJECTION_MIRROR_BALL = 5, PHOS_PROJECTION_COUNT = 6 };
/* TEX_IMAGE flags: interpolation in bits 0-1, extension in bits 2-3, and whether the colour is
 * multiplied by alpha (Cycles' alpha handling of straight-alpha images used unassociated). */
enum phos_image_flags {
    PHOS_IMAGE_LINEAR = 0, PHOS_IMAGE_CLOSEST = 1, PHOS_IMAGE_CUBIC = 2,
    PHOS_IMAGE_REPEAT = 0 << 2, PHOS_IMAGE_EXTEND = 1 << 2, PHOS_IMAGE_CLIP = 2 << 2, PHOS_IMAGE_MIRROR = 3 << 2,
    PHOS_IMAGE_UNASSOCIATE = 1 << 4
};
enum phos_noise_type {
    PHOS_NOISE_FBM = 0, PHOS_NOISE_MULTIFRACTAL = 1, PHOS_NOISE_HYBRID_MULTIFRACTAL = 2,
    PHOS_NOISE_RIDGED_MULTIFRACTAL = 3, PHOS_NOISE_HETERO_TERRAIN = 4, PHOS_NOISE_COUNT = 5
};
enum phos_voronoi_feature {
    PHOS_VORONOI_F1 = 0, PHOS_VORONOI_F2 = 1, PHOS_VORONOI_SMOOTH_F1 = 2, PHOS_VORONOI_DISTANCE_TO_EDGE = 3,
    PHOS_VORONOI_N_SPHERE_RADIUS = 4, PHOS_VORONOI_FEATURE_COUNT = 5
};
enum phos_voronoi_metric {
    PHOS_VORONOI_EUCLIDEAN = 0, PHOS_VORONOI_MANHATTAN = 1, PHOS_VORONOI_CHEBYCHEV = 2,
    PHOS_VORONOI_MINKOWSKI = 3
};
enum phos_wave_type { PHOS_WAVE_BANDS = 0, PHOS_WAVE_RINGS = 1, PHOS_WAVE_TYPE_COUNT = 2 };
enum phos_wave_direction { PHOS_WAVE_X = 0, PHOS_WAVE_Y = 1, PHOS_WAVE_Z = 2, PHOS_WAVE_DIAGONAL = 3,
                           PHOS_WAVE_SPHERICAL = 3 };
enum phos_wave_profile { PHOS_WAVE_SIN = 0, PHOS_WAVE_SAW = 1, PHOS_WAVE_TRI = 2 };
enum phos_gradient {
    PHOS_GRADIENT_LINEAR = 0, PHOS_GRADIENT_QUADRATIC = 1, PHOS_GRADIENT_EASING = 2, PHOS_GRADIENT_DIAGONAL = 3,
    PHOS_GRADIENT_SPHERICAL = 4, PHOS_GRADIENT_QUADRATIC_SPHERE = 5, PHOS_GRADIENT_RADIAL = 6,
    PHOS_GRADIENT_COUNT = 7
};
enum phos_mapping { PHOS_MAPPING_POINT = 0, PHOS_MAPPING_TEXTURE = 1, PHOS_MAPPING_VECTOR = 2,
                    PHOS_MAPPING_NORMAL = 3, PHOS_MAPPING_COUNT = 4 };
enum phos_tangent { PHOS_TANGENT_RADIAL_X = 0, PHOS_TANGENT_RADIAL_Y = 1, PHOS_TANGENT_RADIAL_Z = 2,
                    PHOS_TANGENT_UV_MAP = 3, PHOS_TANGENT_COUNT = 4 };
enum phos_normal_map_space { PHOS_NORMAL_MAP_TANGENT = 0, PHOS_NORMAL_MAP_OBJECT = 1, PHOS_NORMAL_MAP_WORLD = 2,
                             PHOS_NORMAL_MAP_COUNT = 3 };
enum phos_vector_rotate { PHOS_VECTOR_ROTATE_AXIS_ANGLE = 0, PHOS_VECTOR_ROTATE_X_AXIS = 1,
                          PHOS_VECTOR_ROTATE_Y_AXIS = 2, PHOS_VECTOR_ROTATE_Z_AXIS = 3,
                          PHOS_VECTOR_ROTATE_EULER_XYZ = 4, PHOS_VECTOR_ROTATE_COUNT = 5 };
enum phos_vector_transform_type { PHOS_VECTOR_TRANSFORM_POINT = 0, PHOS_VECTOR_TRANSFORM_VECTOR = 1,
                                  PHOS_VECTOR_TRANSFORM_NORMAL = 2, PHOS_VECTOR_TRANSFORM_COUNT = 3 };
enum phos_space { PHOS_SPACE_WORLD = 0, PHOS_SPACE_OBJECT = 1, PHOS_SPACE_CAMERA = 2, PHOS_SPACE_COUNT = 3 };

/*
 * The Sky Texture (docs/algorithms.md §11.1). phos_sky_bake computes what
 * the node's settings give once: PHOS_SKY_DATA_FLOATS floats for a TEX_SKY
 * instruction's table and, for the scattering models, the texture it looks
 * up (RGBA floats, linear Rec. 709, W/(m²·sr), of the size
 * phos_sky_texture_size gives: Cycles' texture, laid out as the Blender
 * version's Cycles lays it out), which the caller adds with
 * phos_scene_add_image and whose id it writes at data[PHOS_SKY_DATA_IMAGE].
 * pixels may be NULL to compute the data alone.
 */
enum phos_sky_model { PHOS_SKY_SINGLE_SCATTERING = 0, PHOS_SKY_MULTIPLE_SCATTERING = 1, PHOS_SKY_PREETHAM = 2,
                      PHOS_SKY_HOSEK_WILKIE = 3, PHOS_SKY_MODEL_COUNT = 4 };
/* The scattering models' texture: 512 × 128 over the upper hemisphere, the
 * ground a fade of the horizon (Blender 2.90 to 4.x), or 512 × 256 over
 * the whole sphere (5.x). */
enum phos_sky_layout { PHOS_SKY_LAYOUT_HEMISPHERE = 0, PHOS_SKY_LAYOUT_SPHERE = 1, PHOS_SKY_LAYOUT_COUNT = 2 };
#define PHOS_SKY_DATA_FLOATS 32
#define PHOS_SKY_DATA_IMAGE 11
typedef struct phos_sky_desc {
    uint32_t model;             /* enum phos_sky_model */
    uint32_t layout;            /* enum phos_sky_layout; MULTIPLE_SCATTERING is SPHERE's only */
    /* The scattering models (the node's settings, Blender's units): */
    float sun_elevation;        /* rad above the horizon */
    float sun_rotation;         /* rad, clockwise seen from +z; 0 puts the sun toward +y */
    float sun_size;             /* the disc's angular diameter, rad */
    float sun_intensity;        /* multiplies the disc */
    uint32_t sun_disc;          /* whether the disc is drawn */
    float altitude;             /* m above sea level */
    float air_density, aerosol_density, ozone_density; /* multiples of Earth's, 0 to 1000 */
    /* Preetham and Hosek-Wilkie: */
    float turbidity;            /* 1 to 10 (Blender's range, and Hosek-Wilkie's data) */
    float ground_albedo;        /* Hosek-Wilkie: 0 to 1 */
    float sun_direction[3];     /* toward the sun, any length > 0 */
} phos_sky_desc;
PHOS_API void phos_sky_desc_init(phos_sky_desc *desc);
/* The texture's size for desc: 0 × 0 for the analytic models. */
PHOS_API phos_status phos_sky_texture_size(const phos_sky_desc *desc, uint32_t *width, uint32_t *height);
PHOS_API phos_status phos_sky_bake(const phos_sky_desc *desc, float *pixels, float *data);

typedef struct phos_shader_instruction {
    uint32_t op;                 /* enum phos_shader_op */
    uint32_t mode;               /* the node's main enum setting */
    uint32_t flags;              /* the op's switches and secondary enums */
    uint32_t table;              /* image id or table offset, by op */
    float param[4];              /* float settings that are not sockets */
    uint32_t inputs[PHOS_SHADER_MAX_INPUTS];   /* first register of each input socket */
    uint32_t outputs[PHOS_SHADER_MAX_OUTPUTS]; /* first register of each output, or PHOS_SHADER_NO_REGISTER */
} phos_shader_instruction;

/* Closure fields a program can set (phos_closure_desc's names; width 3 for colours). */
enum phos_closure_field {
    PHOS_FIELD_WEIGHT = 0, PHOS_FIELD_ROUGHNESS = 1, PHOS_FIELD_IOR = 2, PHOS_FIELD_SPECULAR_COLOR = 3,
    PHOS_FIELD_TRANSMISSION_TINT = 4, PHOS_FIELD_TRANSMISSION_ROUGHNESS = 5,
    PHOS_FIELD_MULTISCATTER_FRESNEL = 6, PHOS_FIELD_SPECULAR_TINT = 7, PHOS_FIELD_THIN_FILM_THICKNESS = 8,
    PHOS_FIELD_THIN_FILM_IOR = 9, PHOS_FIELD_LAYER_WEIGHT = 10, PHOS_FIELD_LAYER_TINT = 11,
    PHOS_FIELD_LAYER_TINT_WEIGHT = 12, PHOS_FIELD_NORMAL = 13, PHOS_FIELD_ROUGHNESS_Y = 14,
    PHOS_FIELD_TANGENT_ROTATION = 15, PHOS_FIELD_TANGENT = 16, PHOS_FIELD_COUNT = 17
};

typedef struct phos_shader_binding {
    uint32_t closure;            /* index in the material's closures */
    uint32_t field;              /* enum phos_closure_field */
    uint32_t reg;                /* first register of the value; the core clamps it to the field's range */
} phos_shader_binding;

typedef struct phos_shader_program_desc {
    uint32_t register_count;     /* <= PHOS_SHADER_MAX_REGISTERS */
    uint32_t constant_count;
    const float *constants;      /* loaded into registers [0, constant_count) */
    uint32_t instruction_count;  /* <= PHOS_SHADER_MAX_INSTRUCTIONS */
    const phos_shader_instruction *instructions;
    uint32_t table_size;         /* floats, <= PHOS_SHADER_MAX_TABLE */
    const float *table;          /* ramps and curves, baked */
    uint32_t binding_count;
    const phos_shader_binding *bindings;
} phos_shader_program_desc;

typedef struct phos_material_desc {
    uint32_t closure_count;               /* 0..PHOS_MAX_CLOSURES; 0 = black */
    const phos_closure_desc *closures;
    const phos_shader_program_desc *program; /* NULL: the closures are constant */
} phos_material_desc;
#define PHOS_MAX_CLOSURES 16
PHOS_API void phos_material_desc_init(phos_material_desc *desc);
PHOS_API phos_status phos_scene_add_material(phos_scene *scene, const phos_material_desc *desc,
                                             uint32_t *out_material_id);

/* A named per-corner attribute of a mesh (colour attributes, float and
 * vector attributes, other UV maps, and what Cycles derives at export:
 * pointiness, random per island), as the Attribute node reads it. The
 * add-on numbers the names a scene's programs read; ATTRIBUTE instructions
 * read the attribute by that number, interpolated barycentrically. */
enum phos_attribute_type {
    PHOS_ATTRIBUTE_FLOAT = 0,    /* one value */
    PHOS_ATTRIBUTE_FLOAT2 = 1,   /* x, y (a UV map) */
    PHOS_ATTRIBUTE_VECTOR = 2,   /* x, y, z */
    PHOS_ATTRIBUTE_COLOR = 3,    /* linear r, g, b, alpha */
    PHOS_ATTRIBUTE_TYPE_COUNT = 4
};
typedef struct phos_mesh_attribute {
    uint32_t id;                 /* the number ATTRIBUTE instructions read it by; unique within the mesh */
    uint32_t type;               /* enum phos_attribute_type */
    const float *values;         /* triangle_count*12: 4 floats per corner (unused ones ignored) */
} phos_mesh_attribute;
#define PHOS_MAX_MESH_ATTRIBUTES 64

/* A triangle mesh in its own (object) space. */
typedef struct phos_mesh_desc {
    uint32_t vertex_count;
    const float *positions;      /* vertex_count*3 */
    uint32_t triangle_count;
    const uint32_t *indices;     /* triangle_count*3 vertex indices */
    const float *normals;        /* triangle_count*9 per-corner normals, or NULL (flat shading) */
    const float *uvs;            /* triangle_count*6 per-corner UVs, or NULL */
    const uint32_t *material_slots; /* triangle_count slot indices into the instance's materials, or NULL (slot 0) */
    const float *tangents;       /* triangle_count*12 per-corner tangents of the UV map (x, y, z, bitangent
                                    sign ±1; MikkTSpace, as Blender computes them), or NULL */
    float texspace_location[3];  /* the texture space: Generated coordinates are
                                    (p − location) / size · ½ + ½ in object space */
    float texspace_size[3];      /* all 0: the bounding box of the positions (Blender's automatic texture space) */
    uint32_t attribute_count;    /* <= PHOS_MAX_MESH_ATTRIBUTES */
    const phos_mesh_attribute *attributes;
} phos_mesh_desc;
PHOS_API void phos_mesh_desc_init(phos_mesh_desc *desc);
PHOS_API phos_status phos_scene_add_mesh(phos_scene *scene, const phos_mesh_desc *desc,
                                         uint32_t *out_mesh_id);

/* Angle-weighted vertex normals of a polygon mesh (Thürmer & Wüthrich
 * 1998): each vertex sums the normals of the polygons around it, each
 * weighted by the polygon's angle at the vertex, in polygon order and in
 * double precision, so the result depends only on the input. Blender 3.4
 * computes the same sum with atomic adds on several threads, whose order,
 * and so the last bits of every smooth normal, change from one evaluation
 * to the next; the add-on takes these instead (docs/reliability.md).
 * Polygon i has loop_totals[i] >= 3 corners, loop_vertices[loop_starts[i]
 * ...], and the unit normal polygon_normals[3i..3i+2]; out_normals gets
 * vertex_count*3 floats (0,0,0 for a vertex no polygon uses, or whose
 * polygons' weighted normals cancel). PHOS_ERROR_INVALID_ARGUMENT for
 * NULL arrays, a corner outside loop_count or a vertex outside
 * vertex_count; non-finite positions give non-finite normals there. */
PHOS_API phos_status phos_vertex_normals(uint32_t vertex_count, const float *positions, uint32_t polygon_count,
                                         const uint32_t *loop_starts, const uint32_t *loop_totals,
                                         const float *polygon_normals, uint32_t loop_count,
                                         const uint32_t *loop_vertices, float *out_normals);

/* A placement of a mesh. Instances of one mesh share its acceleration
 * structure. Slot i of the mesh renders with materials[i]; a slot beyond
 * material_count renders with the default grey material. */
typedef struct phos_instance_desc {
    uint32_t mesh_id;
    float transform[12];         /* object → world, row-major 3x4 */
    uint32_t material_count;
    const uint32_t *materials;   /* material ids */
    float random;                /* Object Info's Random, in [0,1) */
    float pass_index;            /* Object Info's Object Index */
} phos_instance_desc;
PHOS_API void phos_instance_desc_init(phos_instance_desc *desc);
PHOS_API phos_status phos_scene_add_instance(phos_scene *scene, const phos_instance_desc *desc,
                                             uint32_t *out_instance_id);

/* Many instances in one call (a geometry-nodes scatter of a million, one
 * call instead of a million): instance k places mesh mesh_ids[k] by
 * transforms[12k … 12k+11] with the material ids materials[offsets[k] …
 * offsets[k+1] − 1]. randoms and pass_indices may be NULL (0). All are
 * checked before any is added: a refusal adds none, and its message names
 * the instance by its index k. Their ids are *out_first_id onwards. */
typedef struct phos_instances_desc {
    uint32_t count;
    const uint32_t *mesh_ids;         /* count */
    const float *transforms;          /* count × 12, each row-major 3x4 */
    const uint32_t *material_offsets; /* count + 1, non-decreasing, from 0 */
    const uint32_t *materials;        /* material_offsets[count] ids */
    const float *randoms;             /* count, or NULL */
    const float *pass_indices;        /* count, or NULL */
} phos_instances_desc;
PHOS_API phos_status phos_scene_add_instances(phos_scene *scene, const phos_instances_desc *desc,
                                              uint32_t *out_first_id);

/*
 * Lights, in physical quantities; the add-on converts Blender's units (which
 * differ between Blender versions) into these.
 */
enum phos_light_type {
    PHOS_LIGHT_POINT = 0, /* a sphere of `radius` (0: a point) */
    PHOS_LIGHT_SPOT = 1,  /* a point light restricted to a cone */
    PHOS_LIGHT_AREA = 2,  /* a one-sided rectangle or ellipse */
    PHOS_LIGHT_SUN = 3,   /* a distant light subtending `angle` */
    PHOS_LIGHT_PORTAL = 4 /* no light of its own: an opening (shaped as AREA, `direction` pointing into
                             the scene) through which the world's light samples are drawn (Cycles' portals) */
};
enum phos_area_shape { PHOS_AREA_RECTANGLE = 0, PHOS_AREA_ELLIPSE = 1 };
/* How a point or spot light of nonzero radius looks from a shading point. */
enum phos_point_shape {
    PHOS_POINT_DISK = 0,   /* a disk of the radius facing the shading point (Cycles < 4.0, soft falloff) */
    PHOS_POINT_SPHERE = 1  /* a sphere (Cycles 4.0+) */
};

typedef struct phos_light_desc {
    uint32_t type;             /* enum phos_light_type */
    float color[3];            /* POINT/SPOT: intensity W/sr; AREA: radiance W/(m²·sr);
                                  SUN: irradiance W/m² at normal incidence */
    float position[3];         /* POINT/SPOT/AREA centre */
    float direction[3];        /* SPOT axis, AREA normal (the emitting side), SUN direction of travel */
    float axis_u[3], axis_v[3];/* AREA: full edge vectors (size included), perpendicular to direction */
    uint32_t area_shape;       /* enum phos_area_shape */
    float radius;              /* POINT/SPOT radius */
    uint32_t point_shape;      /* enum phos_point_shape */
    float spot_angle;          /* SPOT full cone angle, (0, π] */
    float spot_blend;          /* SPOT smooth edge fraction, [0,1] */
    uint32_t spot_cosine;      /* SPOT: 1 multiplies the intensity by cos(angle to axis) (Cycles < 3.5) */
    float sun_angle;           /* SUN angular diameter, [0, π) */
    uint32_t camera_visible;   /* 1: camera rays see the light's shape (Blender: Object > Visibility > Camera) */
} phos_light_desc;
PHOS_API void phos_light_desc_init(phos_light_desc *desc);
PHOS_API phos_status phos_scene_add_light(phos_scene *scene, const phos_light_desc *desc,
                                          uint32_t *out_light_id);

/* The world: a constant background radiance, or a material whose EMISSION
 * closures, with its shader program run for each direction, give the
 * radiance arriving from that direction (an environment map, a sky; the
 * program sees the direction as P and Generated, −direction as N and I, as
 * Cycles' background shader does). */
#define PHOS_WORLD_NO_MATERIAL 0xFFFFFFFFu
typedef struct phos_world_desc {
    float color[3];            /* background radiance W/(m²·sr) (colour × strength), without a material */
    uint32_t material;         /* a material id, or PHOS_WORLD_NO_MATERIAL for `color` */
} phos_world_desc;
PHOS_API void phos_world_desc_init(phos_world_desc *desc);
PHOS_API phos_status phos_scene_set_world(phos_scene *scene, const phos_world_desc *desc);

enum phos_camera_type { PHOS_CAMERA_PERSPECTIVE = 0, PHOS_CAMERA_ORTHOGRAPHIC = 1 };
typedef struct phos_camera_desc {
    uint32_t type;             /* enum phos_camera_type */
    float transform[12];       /* camera → world; the camera looks down its −Z, +Y up */
    /* The full frame on the image plane, in camera space: PERSPECTIVE on the
     * plane z = −1 (so it holds tan of the half angles, with shift and sensor
     * fit applied); ORTHOGRAPHIC in scene units. */
    float frame_min[2], frame_max[2];
    float aperture_radius;     /* PERSPECTIVE depth of field: lens radius; 0 = pinhole */
    float focus_distance;      /* distance along −Z that is in focus, > 0 */
    float clip_start, clip_end;/* ray extent along the view direction */
} phos_camera_desc;
PHOS_API void phos_camera_desc_init(phos_camera_desc *desc);
PHOS_API phos_status phos_scene_set_camera(phos_scene *scene, const phos_camera_desc *desc);

/* Builds acceleration structures and light tables. A commit that fails or
 * is cancelled leaves the scene uncommitted: it may be committed again or
 * destroyed.
 *
 * Scene updates: while no render holds a committed scene (phos_render_create
 * takes a reference, phos_render_destroy drops it), the scene may be
 * changed again: anything added, the world or camera set, or a mesh,
 * instance, material or light replaced by id (phos_scene_update_*). A
 * change uncommits the scene, and the next commit rebuilds only what the
 * changes touched: the BVH of each replaced or added mesh and the top level
 * over the instances when geometry changed, the light table when geometry,
 * materials, lights or the world did, nothing for the camera. A change
 * while a render holds the scene fails with PHOS_ERROR_INVALID_STATE: the
 * caller cancels and destroys the render, changes, commits, and starts
 * another (the viewport, a second F12 of an unchanged scene, a farm's
 * frames). A change that is refused leaves the scene as it was. */
PHOS_API phos_status phos_scene_commit(phos_scene *scene);

PHOS_API phos_status phos_scene_update_mesh(phos_scene *scene, uint32_t mesh_id, const phos_mesh_desc *desc);
PHOS_API phos_status phos_scene_update_instance(phos_scene *scene, uint32_t instance_id,
                                                const phos_instance_desc *desc);
PHOS_API phos_status phos_scene_update_material(phos_scene *scene, uint32_t material_id,
                                                const phos_material_desc *desc);
PHOS_API phos_status phos_scene_update_light(phos_scene *scene, uint32_t light_id, const phos_light_desc *desc);

/* What the changes before the last commit touched, as a mask of
 * phos_scene_change bits (a first commit: all of them). A caller keeps what
 * does not depend on them: photon maps and the irradiance cache hold while
 * only the camera moved. */
enum phos_scene_change {
    PHOS_CHANGE_GEOMETRY = 1u << 0,  /* meshes or instances */
    PHOS_CHANGE_MATERIALS = 1u << 1, /* materials or images */
    PHOS_CHANGE_LIGHTS = 1u << 2,    /* lights or the world */
    PHOS_CHANGE_CAMERA = 1u << 3
};
PHOS_API uint32_t phos_scene_changes(const phos_scene *scene);

/* Asks a phos_scene_commit running on another thread to stop (the BVH
 * build of a large scene takes seconds): it returns PHOS_ERROR_CANCELLED
 * within a fraction of a second. Safe from any thread; a cancel that
 * arrives before the commit starts cancels it, and each commit that
 * returns clears it. */
PHOS_API void phos_scene_cancel(phos_scene *scene);

/* ----------------------------------------------------------------- render */

enum phos_integrator {
    PHOS_INTEGRATOR_PATH = 0,   /* unbiased path tracing, the reference */
    PHOS_INTEGRATOR_PHOTON = 1  /* photon mapping with final gathering (Jensen) */
};

/* How the random numbers of every path, photon and gather are drawn
 * (docs/algorithms.md §6): each is a pure function of (seed, pixel, sample,
 * dimension), so any of them renders the same image for any thread count.
 * The default is 0, so that settings zeroed rather than initialised still
 * get it. */
enum phos_sampler {
    PHOS_SAMPLER_SOBOL = 0,       /* Owen-scrambled Sobol points */
    PHOS_SAMPLER_RANDOM = 1,      /* independent numbers */
    PHOS_SAMPLER_STRATIFIED = 2,  /* jittered strata over a pixel's samples, multi-jittered in 2-D */
    PHOS_SAMPLER_HALTON = 3       /* scrambled Halton points, bases 2 and 3, per-pixel offsets */
};

/* The noise filters run over the image after rendering (the course's
 * "Filtering" slides; docs/algorithms.md §7): the slides' two examples,
 * then the three energy-preserving filters, which move a pixel's light to
 * its neighbours but never change the image's total. */
enum phos_noise_filter {
    PHOS_NOISE_FILTER_NONE = 0,
    PHOS_NOISE_FILTER_LOWPASS = 1,        /* 3×3 box */
    PHOS_NOISE_FILTER_MEDIAN = 2,         /* 3×3 median */
    PHOS_NOISE_FILTER_ADAPTIVE_WIDTH = 3, /* Rushmeier & Ward 1994 */
    PHOS_NOISE_FILTER_DIFFUSION = 4,      /* McCool 1999 */
    PHOS_NOISE_FILTER_SPLATTING = 5       /* Suykens & Willems 2000 */
};

/* What the noise filter is applied to; the rest of the image is added back
 * unfiltered, so what is not filtered stays sharp. */
enum phos_filter_target {
    PHOS_FILTER_TARGET_INDIRECT_IRRADIANCE = 0, /* the Indirect component over the surface's albedo, filtered,
                                                   times the albedo: textures stay sharp */
    PHOS_FILTER_TARGET_INDIRECT = 1,            /* the Indirect component as it is */
    PHOS_FILTER_TARGET_ALL = 2                  /* the whole image (the slides' "everything is filtered") */
};

/* Where the indirect light of diffuse surfaces is cached (Ward et al.
 * 1988): PHOTON's final gather (or path-traced gather), and with ALWAYS
 * also PATH's hemisphere of paths, which makes PATH biased (consistent). */
enum phos_irradiance_cache {
    PHOS_IRRADIANCE_CACHE_OFF = 0,
    PHOS_IRRADIANCE_CACHE_PHOTON = 1,  /* with the PHOTON integrator only: PATH stays the reference */
    PHOS_IRRADIANCE_CACHE_ALWAYS = 2
};

/* What a photon-mapping render shows for indirect diffuse light. */
enum phos_photon_view {
    PHOS_PHOTON_VIEW_FINAL_GATHER = 0, /* final gathering on the global map */
    PHOS_PHOTON_VIEW_FAST = 1,         /* the global map read at the first diffuse hit */
    PHOS_PHOTON_VIEW_PATH_TRACED = 2   /* gather rays continued as unbiased paths (no global map):
                                          the reference the other two converge to */
};

/*
 * Passes. The light components split the Combined pass (their sum) as in
 * Jensen's rendering-equation solution; both integrators fill them:
 *   EMISSION  emitters seen directly     DIRECT    after one scattering
 *   SPECULAR  after a specular/glossy first bounce
 *   CAUSTICS  diffuse, then only specular bounces (L S+ D E)
 *   INDIRECT  diffuse, then further non-specular bounces
 * Debug passes: PHOTON_MAP and CAUSTIC_MAP, each map's radiance estimate at
 * the first diffuse surface seen; PHOTONS, every stored photon drawn as a
 * dot where it lies in the image (colour = its power's hue). The debug
 * passes build the photon maps for either integrator. IRRADIANCE_CACHE:
 * each irradiance-cache record drawn as a dot (colour = its irradiance's
 * hue), over black; it needs the cache on.
 * Denoising passes, as Cycles defines them for denoisers (OpenImageDenoise
 * through Blender's Denoise node): the albedo and the normal of the first
 * surface that is not mostly specular, followed through mirrors, glass and
 * transparency (and the emitters seen on the way).
 */
enum phos_pass_group {
    PHOS_PASS_GROUP_COMBINED = 0,  /* the image */
    PHOS_PASS_GROUP_LIGHT = 1,     /* the light components, whose sum is Combined */
    PHOS_PASS_GROUP_DENOISING = 2, /* features for a denoiser */
    PHOS_PASS_GROUP_PHOTONS = 3,   /* debug: the photon maps (built for either integrator) */
    PHOS_PASS_GROUP_CACHE = 4,     /* debug: the irradiance cache's records (needs the cache on) */
    PHOS_PASS_GROUP_NOISE = 5      /* noise reduction: where the samples went, the image before filtering */
};

/* What a pass's values are. */
enum phos_pass_kind {
    PHOS_PASS_KIND_COLOR = 0,      /* RGB(A): radiance, or an albedo */
    PHOS_PASS_KIND_VECTOR = 1,     /* XYZ: a direction in camera space (x right, y up, z along the view, as Cycles) */
    PHOS_PASS_KIND_VALUE = 2       /* one number */
};

/* The passes: one table, from which enum phos_pass, phos_pass_channels
 * and the add-on's view-layer toggles and pass registration are made
 * (tools/gen_binding.py). One row per pass, in enum order:
 *   PASS(id, name, channels, group, kind, description)
 * name is the render pass's name in Blender. */
#define PHOS_PASSES(PASS)                                                                         \
    PASS(COMBINED, "Combined", 4, PHOS_PASS_GROUP_COMBINED, PHOS_PASS_KIND_COLOR,                \
         "The image: every light component, and alpha")                                         \
    PASS(EMISSION, "Emission", 3, PHOS_PASS_GROUP_LIGHT, PHOS_PASS_KIND_COLOR,                    \
         "Emitters seen directly (lights, emissive surfaces, the world)")                       \
    PASS(DIRECT, "Direct", 3, PHOS_PASS_GROUP_LIGHT, PHOS_PASS_KIND_COLOR,                        \
         "Light from the emitters after one diffuse scattering")                                \
    PASS(SPECULAR, "Specular", 3, PHOS_PASS_GROUP_LIGHT, PHOS_PASS_KIND_COLOR,                    \
         "Light seen through a specular or glossy first bounce (mirrors, glass)")               \
    PASS(CAUSTICS, "Caustics", 3, PHOS_PASS_GROUP_LIGHT, PHOS_PASS_KIND_COLOR,                    \
         "Light focused onto diffuse surfaces by specular bounces (L S+ D E)")                  \
    PASS(INDIRECT, "Indirect", 3, PHOS_PASS_GROUP_LIGHT, PHOS_PASS_KIND_COLOR,                    \
         "Diffuse interreflection: light after further non-specular bounces")                   \
    PASS(PHOTON_MAP, "Photon Map", 3, PHOS_PASS_GROUP_PHOTONS, PHOS_PASS_KIND_COLOR,              \
         "Debug: the global photon map's radiance estimate at the first diffuse surface seen")  \
    PASS(CAUSTIC_MAP, "Caustic Map", 3, PHOS_PASS_GROUP_PHOTONS, PHOS_PASS_KIND_COLOR,            \
         "Debug: the caustic photon map's radiance estimate at the first diffuse surface seen") \
    PASS(PHOTONS, "Photons", 3, PHOS_PASS_GROUP_PHOTONS, PHOS_PASS_KIND_COLOR,                    \
         "Debug: every stored photon drawn as a dot where it lies in the image")                \
    PASS(IRRADIANCE_CACHE, "Irradiance Cache", 3, PHOS_PASS_GROUP_CACHE, PHOS_PASS_KIND_COLOR,    \
         "Debug: every irradiance-cache record drawn as a dot where it lies in the image "      \
         "(needs the cache on)")                                                                \
    PASS(DENOISING_ALBEDO, "Denoising Albedo", 3, PHOS_PASS_GROUP_DENOISING, PHOS_PASS_KIND_COLOR, \
         "Albedo of the first surface that is not mostly specular, for the Denoise node")      \
    PASS(DENOISING_NORMAL, "Denoising Normal", 3, PHOS_PASS_GROUP_DENOISING, PHOS_PASS_KIND_VECTOR, \
         "Normal (camera space) of the first surface that is not mostly specular, for the "     \
         "Denoise node")                                                                        \
    PASS(SAMPLE_COUNT, "Sample Count", 1, PHOS_PASS_GROUP_NOISE, PHOS_PASS_KIND_VALUE,            \
         "Samples each pixel received, as a share of the Samples setting (adaptive sampling "   \
         "and the time limit make them differ)")                                                \
    PASS(NOISY_IMAGE, "Noisy Image", 4, PHOS_PASS_GROUP_NOISE, PHOS_PASS_KIND_COLOR,               \
         "The image before the noise filter (the Combined pass holds it filtered)")

#define PHOS_PASS_ENUM_(id, ...) PHOS_PASS_##id,
enum phos_pass { PHOS_PASSES(PHOS_PASS_ENUM_) PHOS_PASS_COUNT };
#undef PHOS_PASS_ENUM_

/* Channels of a pass (from PHOS_PASSES), 0 for an unknown pass. */
PHOS_API uint32_t phos_pass_channels(uint32_t pass);

/*
 * The render settings: one table, from which the struct below is declared,
 * phos_render_settings_init fills the defaults, phos_render_create checks
 * the ranges, and tools/gen_binding.py writes the add-on's mirror and its
 * Blender properties (docs/architecture.md, "One table of render
 * settings"). One row per field, in struct order:
 *
 *   USER(type, name, default, min, max, property, kind, soft max, label, description)
 *     chosen by the user: in Blender the scene.phos.<property> labelled and
 *     described as given; kind is NUMBER, PIXELS (pixels), LENGTH (scene
 *     units) or `enum phos_...` (a value of that enum); soft max is the end
 *     of Blender's slider, 0 for max.
 *   HOST(type, name, default, min, max, description)
 *     set by the host application from its own settings (Blender's
 *     resolution, border, thread count, passes, film transparency).
 *
 * min and max are inclusive; a float must also be finite.
 */
#define PHOS_RENDER_SETTINGS(USER, HOST)                                                          \
    USER(uint32_t, integrator, PHOS_INTEGRATOR_PATH, 0, PHOS_INTEGRATOR_PHOTON, integrator,       \
         enum phos_integrator, 0, "Integrator", "Method used to compute the light transport")     \
    HOST(uint32_t, width, 640, 1, 65536, "Full frame width in pixels")                            \
    HOST(uint32_t, height, 480, 1, 65536, "Full frame height in pixels")                          \
    /* The rendered region (Blender's border), full-frame pixel coordinates;                      \
     * width or height 0 means the full frame. */                                                 \
    HOST(uint32_t, region_x, 0, 0, 65535, "Left column of the rendered region")                   \
    HOST(uint32_t, region_y, 0, 0, 65535, "Bottom row of the rendered region")                    \
    HOST(uint32_t, region_width, 0, 0, 65536, "Width of the rendered region, 0: the full frame")  \
    HOST(uint32_t, region_height, 0, 0, 65536, "Height of the rendered region, 0: the full frame") \
    USER(uint32_t, samples, 128, 1, 1u << 24, samples, NUMBER, 4096, "Samples",                   \
         "Samples per pixel of a final render")                                                   \
    USER(uint32_t, seed, 0, 0, UINT32_MAX, seed, NUMBER, 0, "Seed",                               \
         "Seed of the random numbers: the same seed renders the same image, "                     \
         "whatever the thread count, tile order or border")                                       \
    USER(uint32_t, sampler, PHOS_SAMPLER_SOBOL, 0, PHOS_SAMPLER_HALTON, sampler, enum phos_sampler, 0, \
         "Sampler", "How the random numbers of paths, photons and gathers are drawn")           \
    USER(uint32_t, max_bounces, 12, 0, 1024, max_bounces, NUMBER, 0, "Max Bounces",               \
         "Scattering events a path may have after the camera ray")                                \
    HOST(uint32_t, threads, 0, 0, 1024, "Render threads, 0: one per core")                        \
    USER(uint32_t, tile_size, 64, 8, 8192, tile_size, PIXELS, 1024, "Tile Size",                  \
         "Edge of the square tiles the image is rendered and delivered in (halved, down to 8, "    \
         "until each thread has 16 tiles to choose from)")                                         \
    /* Passes of 1, 1, 2, 4 … samples over the whole frame, each pixel's sums                   \
     * kept between them in double: the image equals a one-pass render's bit                   \
     * for bit (docs/architecture.md, "Progressive refinement"). */                              \
    USER(uint32_t, progressive, 1, 0, 1, use_progressive_refine, BOOLEAN, 0, "Progressive Refine", \
         "Show the whole frame after one sample a pixel, then refine it in passes of doubling "   \
         "sample counts; the final image is the same (costs 8 bytes a pixel per channel "          \
         "of the enabled passes)")                                                                \
    /* Adaptive sampling (docs/algorithms.md §6): a pixel stops once its                      \
     * error, from its samples' variance, is below the threshold. */                          \
    USER(uint32_t, adaptive_sampling, 0, 0, 1, use_adaptive_sampling, BOOLEAN, 0,                \
         "Adaptive Sampling", "Stop sampling each pixel once its estimated noise is below the "    \
         "threshold (its count of samples depends only on its own samples)")                      \
    USER(float, adaptive_threshold, 0.01f, 0.0001f, 1.0f, adaptive_threshold, NUMBER, 0.1f,      \
         "Noise Threshold", "Error at which a pixel stops: the standard error of its mean over "    \
         "the square root of its value (over its value above 1)")                                 \
    USER(uint32_t, adaptive_min_samples, 16, 2, 1u << 24, adaptive_min_samples, NUMBER, 4096,     \
         "Min Samples", "Samples every pixel takes before its noise is first estimated")          \
    USER(float, time_limit, 0.0f, 0.0f, 1.0e7f, time_limit, SECONDS, 3600.0f, "Time Limit",       \
         "Stop sampling after this many seconds of rendering (after the photon and cache stages; "   \
         "0: none); every pixel gets at least one sample, and the image then depends on the "     \
         "machine's speed")                                                                       \
    /* The noise filter, after rendering (docs/algorithms.md §7). */                             \
    USER(uint32_t, noise_filter, PHOS_NOISE_FILTER_NONE, 0, PHOS_NOISE_FILTER_SPLATTING, filter,     \
         enum phos_noise_filter, 0, "Noise Filter", "Filter run over the rendered image")            \
    USER(uint32_t, filter_target, PHOS_FILTER_TARGET_INDIRECT_IRRADIANCE, 0,                       \
         PHOS_FILTER_TARGET_ALL, filter_target, enum phos_filter_target, 0, "Filter",              \
         "What the noise filter is applied to; the rest is added back unfiltered")                \
    /* Blackman-Harris, as Cycles' default filter (width 1.5). */                                 \
    USER(float, filter_width, 1.5f, 0.0f, 10.0f, filter_width, PIXELS, 0, "Filter Width",         \
         "Width of the Blackman-Harris pixel filter (0 is a box of one pixel)")                   \
    HOST(uint32_t, transparent_background, 0, 0, 1,                                               \
         "1: the world is not seen by camera rays, alpha = coverage")                             \
    HOST(uint32_t, caches_only, 0, 0, 1,                                                          \
         "1: trace the photon maps and fill the irradiance cache, render no pixel "               \
         "(a render farm's cache job, with phos_render_set_cache_file saving them)")              \
    HOST(uint32_t, pass_mask, 1u << PHOS_PASS_COMBINED, 0, (1u << PHOS_PASS_COUNT) - 1u,          \
         "Bit (1 << pass) per enabled pass; COMBINED is always on")                               \
    /* Photon mapping (PHOTON integrator, and the photon debug passes). */                        \
    USER(uint32_t, global_photons, 200000, 0, 1u << 28, global_photons, NUMBER, 10000000,         \
         "Global Photons",                                                                        \
         "Photons stored in the global photon map (indirect light); "                             \
         "photons are emitted until this many are stored")                                        \
    USER(uint32_t, caustic_photons, 800000, 0, 1u << 28, caustic_photons, NUMBER, 10000000,        \
         "Caustic Photons",                                                                       \
         "Photons stored in the caustic photon map (light focused by mirrors and glass); "        \
         "tracing stops after ten light paths per photon asked for, so a faint caustic stores "   \
         "fewer (still right, only sparser)")                                                     \
    /* 0.3: the rough metal and glass artists use for jewellery and                           \
     * bottles still focus light into a caustic, which path tracing from a                    \
     * diffuse floor finds only by chance (docs/algorithms.md §12). */                        \
    USER(float, caustic_roughness, 0.3f, 0.0f, 1.0f, caustic_roughness, FACTOR, 0,               \
         "Caustic Roughness",                                                                     \
         "Glossy reflection and refraction smoother than this focus light into caustics "         \
         "like mirrors and glass (photons pass them); rougher ones are lit by the caustic map "   \
         "like diffuse surfaces (0: only sharp mirrors and glass make caustics)")                 \
    USER(uint32_t, global_estimate_photons, 50, 1, 10000, global_estimate_photons, NUMBER, 1000,  \
         "Global Estimate", "Nearest photons used in a radiance estimate of the global map")      \
    /* 20: against references that resolve the caustic (Cycles on the Cornell              \
     * box, progressive photon mapping on the metal ring) it had 1.4× and 1.6–3.3×             \
     * less error × time than 80 (docs/benchmarks.md, "The caustic k chosen                    \
     * against consistent references"). */                                                    \
    USER(uint32_t, caustic_estimate_photons, 20, 1, 10000, caustic_estimate_photons, NUMBER,      \
         1000, "Caustic Estimate",                                                                \
         "Nearest photons used in a (cone-filtered) radiance estimate of the caustic map")        \
    /* A pixel's caustic is smooth at the scale of its samples (the demo's                     \
     * caustic discs are about a pixel wide), so reading the                                   \
     * map at every sample mostly repeats one value: docs/algorithms.md §4.7. */              \
    USER(float, caustic_sample_share, 0.25f, 0.0f, 1.0f, caustic_sample_share, FACTOR, 0,         \
         "Caustic Sample Share",                                                                  \
         "Share of a pixel's samples that read the caustic map, its first ones (at least one); "  \
         "the caustics are the mean over those alone and the other samples skip the estimate "    \
         "(1: every sample)")                                                                     \
    /* Stochastic progressive photon mapping for the caustics (Hachisuka &                     \
     * Jensen 2009; Knaus & Zwicker 2011): docs/algorithms.md §4.6. */                         \
    USER(uint32_t, progressive_caustics, 0, 0, 1, use_progressive_caustics, BOOLEAN, 0,          \
         "Progressive",                                                                           \
         "A new caustic map for every sample, read within a radius that shrinks from sample to "  \
         "sample, so caustics converge to the exact image as samples grow instead of staying "    \
         "blurred by a fixed number of nearest photons")                                          \
    /* 10 000 photons a sample, 4 in the first radius, α = 0.5: by error × time on           \
     * the metal ring and the glass sphere, in full and close up (docs/benchmarks.md,          \
     * "The ring's cusp close up"). */                                                         \
    USER(uint32_t, progressive_caustic_photons, 10000, 1, 1u << 26, progressive_caustic_photons,  \
         NUMBER, 1000000, "Photons per Sample",                                                   \
         "Caustic photons stored for each sample when caustics are progressive")                  \
    USER(uint32_t, progressive_first_photons, 4, 1, 10000, progressive_first_photons, NUMBER,     \
         100, "First Radius Photons",                                                             \
         "Photons within a point's first progressive radius (from the map of the sample before); " \
         "the radius then shrinks with every sample")                                             \
    USER(float, progressive_alpha, 0.5f, 0.01f, 0.99f, progressive_alpha, FACTOR, 0, "Alpha",      \
         "How fast the progressive radius shrinks: the squared radius falls as samples^(alpha-1); " \
         "lower shrinks faster, leaving less blur and more noise")                                \
    USER(float, max_radius, 0.0f, 0.0f, FLT_MAX, max_radius, LENGTH, 10.0f, "Max Radius",         \
         "Largest search radius of a radiance estimate; 0 chooses it from the "                   \
         "scene's size (its diagonal / 40)")                                                      \
    /* 4: the most image quality per second on the Cornell box and the sunlit                   \
     * room (docs/benchmarks.md): the sampler stratifies each ray's directions                  \
     * over the pixel's samples, so more samples with few rays each beat the                    \
     * reverse. */                                                                              \
    USER(uint32_t, final_gather_rays, 4, 1, 65536, final_gather_rays, NUMBER, 1024,               \
         "Final Gather Rays", "Gather rays per camera sample at the first diffuse surface "       \
         "(final gathering and the path-traced gather)")                                          \
    USER(uint32_t, photon_view, PHOS_PHOTON_VIEW_FINAL_GATHER, 0, PHOS_PHOTON_VIEW_PATH_TRACED,   \
         photon_view, enum phos_photon_view, 0, "Indirect Light",                                 \
         "Where the indirect light of diffuse surfaces comes from")                               \
    USER(uint32_t, max_photons_emitted_millions, 50, 1, 100000, max_photons_emitted, NUMBER,      \
         1000, "Max Emitted (Millions)",                                                          \
         "Stop filling the photon maps after this many million emitted photon paths "             \
         "(for scenes where most photons escape)")                                               \
    /* Irradiance caching (Ward et al. 1988): PATH's diffuse indirect light,                    \
     * or PHOTON's final gather, computed at records and interpolated. */                       \
    /* PHOTON, q = 5, 1024 rays, 4 pixels: the most image quality per second on the          \
     * bench scenes (docs/benchmarks.md, "The irradiance cache"). */                            \
    USER(uint32_t, irradiance_cache, PHOS_IRRADIANCE_CACHE_PHOTON, 0,                             \
         PHOS_IRRADIANCE_CACHE_ALWAYS, irradiance_cache, enum phos_irradiance_cache, 0,           \
         "Irradiance Cache",                                                                      \
         "Compute the indirect light of diffuse surfaces at a few points and interpolate "        \
         "between them (Ward's irradiance cache)")                                                \
    USER(float, ic_accuracy, 5.0f, 1.0f, 1000.0f, ic_accuracy, NUMBER, 50.0f, "Accuracy",         \
         "A record is used where its weight exceeds this (q in w > q): higher places "            \
         "records closer together")                                                               \
    USER(uint32_t, ic_rays, 1024, 4, 65536, ic_rays, NUMBER, 4096, "Rays per Record",            \
         "Stratified hemisphere rays that compute one record")                                    \
    USER(float, ic_min_spacing, 4.0f, 0.0f, 1000.0f, ic_min_spacing, PIXELS, 20.0f,               \
         "Min Spacing", "Smallest reach of a record, in pixels: records never crowd closer")      \
    USER(float, ic_max_spacing, 32.0f, 1.0f, 4096.0f, ic_max_spacing, PIXELS, 128.0f,             \
         "Max Spacing", "Largest reach of a record, in pixels: records never spread further")

#define PHOS_SETTING_FIELD_(type, name, ...) type name;
typedef struct phos_render_settings {
    PHOS_RENDER_SETTINGS(PHOS_SETTING_FIELD_, PHOS_SETTING_FIELD_)
} phos_render_settings;
#undef PHOS_SETTING_FIELD_
/* Fills every field with its default from the table. */
PHOS_API void phos_render_settings_init(phos_render_settings *settings);

/* Validates the settings against the committed scene and allocates the
 * film; the message of a failure is put on the scene. A render that would
 * need more memory than the machine (or the process's cgroup, on a render
 * farm) has available is refused with PHOS_ERROR_OUT_OF_MEMORY before
 * anything is allocated, its message saying how much it needs. The render
 * keeps the scene alive until it is destroyed. */
PHOS_API phos_status phos_render_create(phos_scene *scene, const phos_render_settings *settings,
                                        phos_render **out_render);
PHOS_API void phos_render_destroy(phos_render *render);
PHOS_API const char *phos_render_error(const phos_render *render);

/* Saved caches: the irradiance cache written to a file after its pre-pass,
 * or read from one instead of the pre-pass, and the photon maps likewise
 * around photon tracing, so that every frame of an animation and every
 * machine of a render farm reads the same records and photons
 * (docs/cache_files.md). A file made for another scene (geometry,
 * materials, lights) or with other settings that shape it is refused:
 * the render fails with a message naming what differs. The camera and
 * the image size may differ: records and photons are world-space. */
enum phos_cache_kind { PHOS_CACHE_IRRADIANCE = 0, PHOS_CACHE_PHOTON_MAPS = 1, PHOS_CACHE_KIND_COUNT = 2 };
enum phos_cache_file_mode {
    PHOS_CACHE_FILE_NONE = 0,  /* compute, keep nothing */
    PHOS_CACHE_FILE_SAVE = 1,  /* compute, then write the file */
    PHOS_CACHE_FILE_LOAD = 2   /* read the file instead of computing */
};
/* Before phos_render_start; path is copied (at most 1023 bytes). A render
 * that does not use the cache (or the photon maps) ignores it. */
PHOS_API phos_status phos_render_set_cache_file(phos_render *render, uint32_t kind, const char *path,
                                                uint32_t mode);

/* More views the caches are made for, besides the scene's camera: a
 * render farm's cache job makes one photon map and one irradiance cache
 * for a whole camera path (docs/farm.md). Before phos_render_start, in
 * order, at most PHOS_MAX_VIEWS; the camera is checked as
 * phos_scene_set_camera checks it. The global photons are aimed at what
 * every view reads, and the irradiance cache's pre-pass runs from each
 * view after the camera's, adding records only where those before leave
 * a gap, so the result depends on the views' order and nothing else. The
 * image is still rendered from the scene's camera (or not at all with
 * caches_only). */
#define PHOS_MAX_VIEWS 16384u
PHOS_API phos_status phos_render_add_view(phos_render *render, const phos_camera_desc *camera);

/* Photon maps kept between renders of one scene: the viewport keeps them
 * while only the view moves, and a second render of an unchanged scene
 * (Blender's Persistent Data) reads them instead of tracing again. Maps
 * are read-only once built, so several renders may hold them; each
 * reference is released once.
 *
 * phos_render_keep_photon_maps: once the render's photon stages have
 * finished (stage_index past them, or the render DONE), a reference to
 * its maps that outlives the render; PHOS_ERROR_INVALID_STATE before, or
 * for a render that uses no maps.
 *
 * phos_render_use_photon_maps: before phos_render_start, the render reads
 * these maps instead of making its own, and its plan leaves out the photon
 * stages. Refused with PHOS_ERROR_INVALID_ARGUMENT and a message saying
 * why when they were made for another scene, for this scene before a
 * change other than the camera, with other settings that shape them
 * (photon counts, bounces, seed, radii, caustic roughness), or without the
 * radiance photons final gathering reads. A scene with a sun, a world or a
 * lamp that reaches several objects aims those photons at what its camera
 * sees: such maps are refused after
 * a camera change unless any_view is 1 (they stay an unbiased map for any
 * view, if a less dense one where the first camera did not look; the
 * viewport takes them, a final render should not, so that its image does
 * not depend on an earlier view). So are maps without a global map
 * because no gather from the first camera's view would have read one (an
 * object alone in an empty world): a render given them path-traces its
 * gathers, right for any view but slower where gathers find surfaces.
 * Also refused for a render that uses no maps or reads or writes its
 * photon maps' file. */
typedef struct phos_photon_maps phos_photon_maps;
PHOS_API phos_status phos_render_keep_photon_maps(phos_render *render, phos_photon_maps **out_maps);
PHOS_API phos_status phos_render_use_photon_maps(phos_render *render, phos_photon_maps *maps, uint32_t any_view);
PHOS_API void phos_photon_maps_release(phos_photon_maps *maps);

/* Starts the worker threads and returns at once. A render starts once. */
PHOS_API phos_status phos_render_start(phos_render *render);

enum phos_render_state {
    PHOS_STATE_IDLE = 0, PHOS_STATE_RUNNING = 1, PHOS_STATE_DONE = 2,
    PHOS_STATE_CANCELLED = 3, PHOS_STATE_FAILED = 4
};

/* The stages a render goes through. Which of them it runs, in which order,
 * is its plan, fixed at create (phos_render_stages; less the photon stages
 * for a render given maps by phos_render_use_photon_maps): WAITING, then the
 * photon stages if it uses photon maps (the PHOTON integrator or a photon
 * debug pass; PRECOMPUTING_RADIANCE for final gathering only), the
 * irradiance cache's pre-pass if the cache is on, RENDERING and FILTERING
 * if a noise filter is on (neither with caches_only), FINISHED. */
enum phos_stage {
    PHOS_STAGE_WAITING = 0,
    PHOS_STAGE_TRACING_PHOTONS = 1,
    PHOS_STAGE_BUILDING_KDTREES = 2,
    PHOS_STAGE_PRECOMPUTING_RADIANCE = 3,
    PHOS_STAGE_FILLING_IRRADIANCE_CACHE = 4,
    PHOS_STAGE_RENDERING = 5,
    PHOS_STAGE_FILTERING = 6,
    PHOS_STAGE_FINISHED = 7,
    PHOS_STAGE_COUNT = 8
};

typedef struct phos_stage_info {
    uint32_t id;               /* enum phos_stage */
    char name[64];             /* as a status line shows it: "Tracing photons", "Path tracing" */
} phos_stage_info;
/* The plan of a render: *out_count is its number of stages (at most
 * PHOS_STAGE_COUNT), the first min(max, count) of which are written to out
 * in running order. */
PHOS_API phos_status phos_render_stages(const phos_render *render, phos_stage_info *out, uint32_t max,
                                        uint32_t *out_count);
/* The plan a render with these settings would have, without making one:
 * the stage ids (enum phos_stage) in running order, as phos_render_stages
 * would list them, so that a user interface shows the settings of the
 * stages that will run and hides the others by the core's own rule. Only
 * the settings that choose stages are read (integrator, photon_view,
 * irradiance_cache, pass_mask, noise_filter); phos_render_create still
 * validates them all. */
PHOS_API phos_status phos_settings_stages(const phos_render_settings *settings, uint32_t *stage_ids, uint32_t max,
                                          uint32_t *out_count);

/* The photon maps, as phos_progress names the one being traced. */
enum phos_photon_map { PHOS_MAP_GLOBAL = 0, PHOS_MAP_CAUSTIC = 1 };

typedef struct phos_progress {
    uint32_t state;            /* enum phos_render_state */
    float fraction;            /* of the whole render, 0..1 */
    uint32_t tiles_done, tiles_total;
    uint32_t samples;          /* samples per pixel of this render */
    uint32_t samples_done;     /* every pixel has this many (progressive refinement's passes done) */
    char stage[64];            /* what is running now, e.g. "Tracing photons" */
    uint32_t stage_id;         /* enum phos_stage */
    uint32_t stage_index;      /* position of stage_id in the plan (phos_render_stages) */
    uint32_t photons_stored;   /* global + caustic so far */
    uint64_t photons_emitted;  /* photon paths so far */
    uint32_t global_photons, caustic_photons; /* in the maps, once built */
    uint32_t photon_map;       /* TRACING_PHOTONS: the map being traced (enum phos_photon_map) */
    /* Once the maps are built: bit (1 << enum phos_photon_map) of each map
     * that ended short of its photon count, because its lights' photons
     * mostly leave the scene or are absorbed (the emission limit, or a
     * yield too low ever to fill it: the pass stops early). */
    uint32_t photon_maps_short;
    /* Wall time (s) each stage has run, by enum phos_stage: the whole of a
     * finished stage, the running one so far, 0 for one not reached or not
     * in the plan. What a photon render spends on its maps, and the part of
     * a render that does not grow with the pixel count (docs/benchmarks.md). */
    double stage_seconds[PHOS_STAGE_COUNT];
    /* Rays cast by the image's tiles so far (camera, bounce, shadow and
     * gather rays; not the photon maps'): with the rendering stage's time,
     * the path tracer's rays per second (docs/benchmarks.md). */
    uint64_t rays_traced;
    /* The irradiance cache: records made by its pre-pass and the rays it
     * cast, and the tiles' lookups so far and how many of them
     * interpolated (the rest gathered for that sample alone). */
    uint32_t cache_records;
    uint64_t cache_rays_traced, cache_lookups, cache_interpolated;
    /* Rays the stratified hemispheres of indirect diffuse light sent, in
     * the tiles (final gathering, the path-traced gather) and in the
     * irradiance cache's records; each counts once, whatever it did after. */
    uint64_t gather_rays;
} phos_progress;
PHOS_API phos_status phos_render_progress(phos_render *render, phos_progress *out);

typedef struct phos_tile {
    uint32_t x, y, width, height; /* full-frame pixel coordinates */
} phos_tile;
/* Hands out each finished tile once, in the order they finish. *out_count is
 * 1 if a tile was written to *out, 0 if none is waiting. */
PHOS_API phos_status phos_render_next_tile(phos_render *render, phos_tile *out, uint32_t *out_count);

/* Copies a rectangle of a pass (inside the region) into dst: rows bottom-up,
 * phos_pass_channels(pass) floats per pixel; dst_count is dst's length in
 * floats. Pixels not yet rendered read as zero; a tile returned by
 * phos_render_next_tile is complete. */
PHOS_API phos_status phos_render_read(phos_render *render, uint32_t pass, uint32_t x, uint32_t y,
                                      uint32_t width, uint32_t height, float *dst, size_t dst_count);

/* Asks the workers to stop; safe from any thread, returns at once. */
PHOS_API void phos_render_cancel(phos_render *render);

/* Waits for the workers; timeout_seconds < 0 waits without limit. Returns
 * PHOS_OK when finished, PHOS_ERROR_CANCELLED after a cancel,
 * PHOS_ERROR_TIMEOUT if still running, or the failure's status. */
PHOS_API phos_status phos_render_wait(phos_render *render, double timeout_seconds);

#ifdef __cplusplus
}
#endif
#endif /* PHOS_H */
