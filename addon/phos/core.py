# SPDX-License-Identifier: GPL-3.0-or-later
"""ctypes binding of libphos: a 1:1 mirror of core/include/phos.h.

This is the lowest module of the add-on; it imports nothing from bpy, so it
can be tested in a plain Python with numpy.

The library is found beside this file (``lib/libphos.so``) or at the path in
the environment variable ``PHOS_LIBRARY``. Loading checks the library's
version and the size of every public struct against the mirrors below, so a
stale or mismatched build is refused with a readable message instead of
corrupting memory. A failed load never raises at import: the message is kept
(``load_error()``) for the preferences panel and the render report.

On top of the raw functions sit two small owners, :class:`Scene` and
:class:`Render`, that raise :class:`PhosError` with the core's own message on
a failed call and free their handle deterministically (``close()`` or a
``with`` block), because a render engine must not rely on garbage collection
to release gigabytes of BVH and film.
"""

import ctypes
import os
import threading

import numpy as np

# ---------------------------------------------------------------- constants
# Mirrors of the #defines and enums of phos.h, same names and values.

PHOS_VERSION_MAJOR = 0
PHOS_VERSION_MINOR = 1
PHOS_VERSION_PATCH = 0
PHOS_VERSION = (PHOS_VERSION_MAJOR << 16) | (PHOS_VERSION_MINOR << 8) | PHOS_VERSION_PATCH

# enum phos_status
PHOS_OK = 0
PHOS_ERROR_INVALID_ARGUMENT = 1
PHOS_ERROR_INVALID_STATE = 2
PHOS_ERROR_OUT_OF_MEMORY = 3
PHOS_ERROR_EMBREE = 4
PHOS_ERROR_CANCELLED = 5
PHOS_ERROR_TIMEOUT = 6
PHOS_ERROR_INTERNAL = 7

# enum phos_image_interpolation
PHOS_INTERP_LINEAR = 0
PHOS_INTERP_CLOSEST = 1

# enum phos_image_extension
PHOS_EXTEND_REPEAT = 0
PHOS_EXTEND_EXTEND = 1
PHOS_EXTEND_CLIP = 2

# enum phos_closure_type
PHOS_CLOSURE_DIFFUSE = 0
PHOS_CLOSURE_PRINCIPLED_DIFFUSE = 1
PHOS_CLOSURE_REFLECTION = 2
PHOS_CLOSURE_REFLECTION_FRESNEL = 3
PHOS_CLOSURE_REFRACTION = 4
PHOS_CLOSURE_GLASS = 5
PHOS_CLOSURE_TRANSPARENT = 6
PHOS_CLOSURE_EMISSION = 7
PHOS_CLOSURE_TYPE_COUNT = 8

# enum phos_glass_fresnel
PHOS_GLASS_FRESNEL_MACRO = 0
PHOS_GLASS_FRESNEL_MICROFACET = 1

PHOS_MAX_CLOSURES = 16

# enum phos_light_type
PHOS_LIGHT_POINT = 0
PHOS_LIGHT_SPOT = 1
PHOS_LIGHT_AREA = 2
PHOS_LIGHT_SUN = 3

# enum phos_area_shape
PHOS_AREA_RECTANGLE = 0
PHOS_AREA_ELLIPSE = 1

# enum phos_point_shape
PHOS_POINT_DISK = 0
PHOS_POINT_SPHERE = 1

# enum phos_camera_type
PHOS_CAMERA_PERSPECTIVE = 0
PHOS_CAMERA_ORTHOGRAPHIC = 1

# enum phos_integrator
PHOS_INTEGRATOR_PATH = 0
PHOS_INTEGRATOR_PHOTON = 1

# enum phos_photon_view
PHOS_PHOTON_VIEW_FINAL_GATHER = 0
PHOS_PHOTON_VIEW_FAST = 1

# enum phos_pass
PHOS_PASS_COMBINED = 0
PHOS_PASS_EMISSION = 1
PHOS_PASS_DIRECT = 2
PHOS_PASS_SPECULAR = 3
PHOS_PASS_CAUSTICS = 4
PHOS_PASS_INDIRECT = 5
PHOS_PASS_PHOTON_MAP = 6
PHOS_PASS_CAUSTIC_MAP = 7
PHOS_PASS_PHOTONS = 8
PHOS_PASS_COUNT = 9

# enum phos_stage
PHOS_STAGE_WAITING = 0
PHOS_STAGE_TRACING_PHOTONS = 1
PHOS_STAGE_BUILDING_KDTREES = 2
PHOS_STAGE_PRECOMPUTING_RADIANCE = 3
PHOS_STAGE_RENDERING = 4
PHOS_STAGE_FINISHED = 5

# enum phos_render_state
PHOS_STATE_IDLE = 0
PHOS_STATE_RUNNING = 1
PHOS_STATE_DONE = 2
PHOS_STATE_CANCELLED = 3
PHOS_STATE_FAILED = 4

# The library version this add-on was written against: major and minor must
# match exactly (phos.h: "The add-on refuses a library whose major or minor
# differs from its own").
EXPECTED_VERSION = (PHOS_VERSION_MAJOR, PHOS_VERSION_MINOR)

# ------------------------------------------------------------------ structs

_f = ctypes.c_float
_u32 = ctypes.c_uint32
_i32 = ctypes.c_int32
_pf = ctypes.POINTER(ctypes.c_float)
_pu32 = ctypes.POINTER(ctypes.c_uint32)


class phos_image_desc(ctypes.Structure):
    _fields_ = [
        ("width", _u32),
        ("height", _u32),
        ("pixels", _pf),            # width*height*4 floats, linear RGBA
        ("interpolation", _u32),    # enum phos_image_interpolation
        ("extension", _u32),        # enum phos_image_extension
    ]


class phos_closure_desc(ctypes.Structure):
    _fields_ = [
        ("type", _u32),             # enum phos_closure_type
        ("weight", _f * 3),         # linear RGB; radiance W/(m²·sr) for EMISSION
        ("weight_image", _i32),     # image id multiplied into weight, -1 for none
        ("roughness", _f),          # Blender roughness, GGX alpha = roughness²
        ("ior", _f),
        ("specular_color", _f * 3), # REFLECTION_FRESNEL: reflectance at normal incidence
        ("glass_fresnel", _u32),    # enum phos_glass_fresnel
        ("transmission_tint", _f * 3),   # GLASS: colour of the refracted light only
        ("transmission_roughness", _f),  # GLASS (MACRO): refraction roughness, < 0 = roughness
        ("layered", _u32),               # 1: under the first REFLECTION_FRESNEL (Principled v2)
    ]


class phos_material_desc(ctypes.Structure):
    _fields_ = [
        ("closure_count", _u32),
        ("closures", ctypes.POINTER(phos_closure_desc)),
    ]


class phos_mesh_desc(ctypes.Structure):
    _fields_ = [
        ("vertex_count", _u32),
        ("positions", _pf),         # vertex_count*3
        ("triangle_count", _u32),
        ("indices", _pu32),         # triangle_count*3
        ("normals", _pf),           # triangle_count*9 or NULL
        ("uvs", _pf),               # triangle_count*6 or NULL
        ("material_slots", _pu32),  # triangle_count or NULL
    ]


class phos_instance_desc(ctypes.Structure):
    _fields_ = [
        ("mesh_id", _u32),
        ("transform", _f * 12),     # object → world, row-major 3x4
        ("material_count", _u32),
        ("materials", _pu32),
    ]


class phos_light_desc(ctypes.Structure):
    _fields_ = [
        ("type", _u32),             # enum phos_light_type
        ("color", _f * 3),          # W/sr (point/spot), W/(m²·sr) (area), W/m² (sun)
        ("position", _f * 3),
        ("direction", _f * 3),
        ("axis_u", _f * 3),
        ("axis_v", _f * 3),
        ("area_shape", _u32),       # enum phos_area_shape
        ("radius", _f),
        ("point_shape", _u32),      # enum phos_point_shape
        ("spot_angle", _f),         # full cone angle, radians
        ("spot_blend", _f),
        ("spot_cosine", _u32),
        ("sun_angle", _f),          # angular diameter, radians
        ("camera_visible", _u32),   # 1: camera rays see the light's shape
    ]


class phos_world_desc(ctypes.Structure):
    _fields_ = [
        ("color", _f * 3),          # background radiance W/(m²·sr)
    ]


class phos_camera_desc(ctypes.Structure):
    _fields_ = [
        ("type", _u32),             # enum phos_camera_type
        ("transform", _f * 12),     # camera → world, row-major 3x4
        ("frame_min", _f * 2),
        ("frame_max", _f * 2),
        ("aperture_radius", _f),
        ("focus_distance", _f),
        ("clip_start", _f),
        ("clip_end", _f),
    ]


class phos_render_settings(ctypes.Structure):
    _fields_ = [
        ("integrator", _u32),
        ("width", _u32),
        ("height", _u32),
        ("region_x", _u32),
        ("region_y", _u32),
        ("region_width", _u32),
        ("region_height", _u32),
        ("samples", _u32),
        ("seed", _u32),
        ("max_bounces", _u32),
        ("threads", _u32),
        ("tile_size", _u32),
        ("filter_width", _f),
        ("transparent_background", _u32),
        ("pass_mask", _u32),
        ("global_photons", _u32),
        ("caustic_photons", _u32),
        ("global_estimate_photons", _u32),
        ("caustic_estimate_photons", _u32),
        ("max_radius", _f),                 # scene units, 0 = automatic
        ("final_gather_rays", _u32),
        ("photon_view", _u32),              # enum phos_photon_view
        ("max_photons_emitted_millions", _u32),
    ]


class phos_progress(ctypes.Structure):
    _fields_ = [
        ("state", _u32),            # enum phos_render_state
        ("fraction", _f),
        ("tiles_done", _u32),
        ("tiles_total", _u32),
        ("samples", _u32),
        ("stage", ctypes.c_char * 64),
        ("stage_id", _u32),                 # enum phos_stage
        ("photons_stored", _u32),
        ("photons_emitted", ctypes.c_uint64),
        ("global_photons", _u32),
        ("caustic_photons", _u32),
    ]


class phos_tile(ctypes.Structure):
    _fields_ = [
        ("x", _u32),
        ("y", _u32),
        ("width", _u32),
        ("height", _u32),
    ]


# Every public struct, checked against phos_struct_size() at load.
STRUCTS = (
    phos_image_desc,
    phos_closure_desc,
    phos_material_desc,
    phos_mesh_desc,
    phos_instance_desc,
    phos_light_desc,
    phos_world_desc,
    phos_camera_desc,
    phos_render_settings,
    phos_progress,
    phos_tile,
)

# ---------------------------------------------------------------- functions
# name: (restype, argtypes). Handles are opaque pointers (c_void_p).

_vp = ctypes.c_void_p
_status = ctypes.c_int  # enum phos_status

_FUNCTIONS = {
    "phos_version": (_u32, []),
    "phos_struct_size": (_u32, [ctypes.c_char_p]),
    "phos_status_string": (ctypes.c_char_p, [_status]),
    # scene
    "phos_scene_create": (_vp, []),
    "phos_scene_destroy": (None, [_vp]),
    "phos_scene_error": (ctypes.c_char_p, [_vp]),
    "phos_image_desc_init": (None, [ctypes.POINTER(phos_image_desc)]),
    "phos_scene_add_image": (_status, [_vp, ctypes.POINTER(phos_image_desc), _pu32]),
    "phos_closure_desc_init": (None, [ctypes.POINTER(phos_closure_desc)]),
    "phos_material_desc_init": (None, [ctypes.POINTER(phos_material_desc)]),
    "phos_scene_add_material": (_status, [_vp, ctypes.POINTER(phos_material_desc), _pu32]),
    "phos_mesh_desc_init": (None, [ctypes.POINTER(phos_mesh_desc)]),
    "phos_scene_add_mesh": (_status, [_vp, ctypes.POINTER(phos_mesh_desc), _pu32]),
    "phos_instance_desc_init": (None, [ctypes.POINTER(phos_instance_desc)]),
    "phos_scene_add_instance": (_status, [_vp, ctypes.POINTER(phos_instance_desc), _pu32]),
    "phos_light_desc_init": (None, [ctypes.POINTER(phos_light_desc)]),
    "phos_scene_add_light": (_status, [_vp, ctypes.POINTER(phos_light_desc), _pu32]),
    "phos_world_desc_init": (None, [ctypes.POINTER(phos_world_desc)]),
    "phos_scene_set_world": (_status, [_vp, ctypes.POINTER(phos_world_desc)]),
    "phos_camera_desc_init": (None, [ctypes.POINTER(phos_camera_desc)]),
    "phos_scene_set_camera": (_status, [_vp, ctypes.POINTER(phos_camera_desc)]),
    "phos_scene_commit": (_status, [_vp]),
    # render
    "phos_pass_channels": (_u32, [_u32]),
    "phos_render_settings_init": (None, [ctypes.POINTER(phos_render_settings)]),
    "phos_render_create": (_status, [_vp, ctypes.POINTER(phos_render_settings),
                                     ctypes.POINTER(_vp)]),
    "phos_render_destroy": (None, [_vp]),
    "phos_render_error": (ctypes.c_char_p, [_vp]),
    "phos_render_start": (_status, [_vp]),
    "phos_render_progress": (_status, [_vp, ctypes.POINTER(phos_progress)]),
    "phos_render_next_tile": (_status, [_vp, ctypes.POINTER(phos_tile), _pu32]),
    "phos_render_read": (_status, [_vp, _u32, _u32, _u32, _u32, _u32, _pf, ctypes.c_size_t]),
    "phos_render_cancel": (None, [_vp]),
    "phos_render_wait": (_status, [_vp, ctypes.c_double]),
}

# ------------------------------------------------------------------ loading

LIBRARY_ENV = "PHOS_LIBRARY"
LIBRARY_NAME = "libphos.so"

_lock = threading.Lock()
_lib = None
_load_error = ""
_loaded_path = ""


class PhosError(RuntimeError):
    """A libphos call failed; the message is the core's own explanation."""

    def __init__(self, message, status=None):
        super().__init__(message)
        self.status = status


def library_path():
    """Where the library is looked for: $PHOS_LIBRARY, else lib/ beside this file."""
    override = os.environ.get(LIBRARY_ENV, "").strip()
    if override:
        return override
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "lib", LIBRARY_NAME)


def _bind(lib):
    """Declare argtypes/restype of every function; a missing symbol is an error."""
    for name, (restype, argtypes) in _FUNCTIONS.items():
        try:
            fn = getattr(lib, name)
        except AttributeError:
            raise PhosError("the library has no function %s() (built from an older phos.h?)" % name)
        fn.restype = restype
        fn.argtypes = argtypes


def _check(lib):
    """Refuse a library whose version or struct layouts differ from this binding."""
    v = lib.phos_version()
    major, minor, patch = (v >> 16) & 0xFFFF, (v >> 8) & 0xFF, v & 0xFF
    if (major, minor) != EXPECTED_VERSION:
        raise PhosError("library version %d.%d.%d, but this add-on needs %d.%d.x"
                        % (major, minor, patch, EXPECTED_VERSION[0], EXPECTED_VERSION[1]))
    for struct in STRUCTS:
        name = struct.__name__
        size = lib.phos_struct_size(name.encode("ascii"))
        if size != ctypes.sizeof(struct):
            raise PhosError("struct %s is %d bytes in the library but %d in the add-on: "
                            "the library was built from a different phos.h"
                            % (name, size, ctypes.sizeof(struct)))


def load():
    """Load and check the library once; return it, or None after a failure.

    A failed attempt is retried on the next call (the library may have been
    built since); a successful one is kept for the life of the process, since
    a shared library cannot be safely unloaded while Blender runs.
    """
    global _lib, _load_error, _loaded_path
    with _lock:
        if _lib is not None:
            return _lib
        path = library_path()
        try:
            if not os.path.isfile(path):
                raise PhosError("%s not found (build the core with CMake, or set %s)"
                                % (path, LIBRARY_ENV))
            try:
                lib = ctypes.CDLL(path)
            except OSError as ex:
                raise PhosError("cannot load %s: %s" % (path, ex))
            _bind(lib)
            _check(lib)
        except PhosError as ex:
            _load_error = "Phos core library: %s" % ex
            return None
        except Exception as ex:  # never let a broken library take the add-on down
            _load_error = "Phos core library: unexpected error loading %s: %r" % (path, ex)
            return None
        _lib, _load_error, _loaded_path = lib, "", path
        return _lib


def load_error():
    """The message of the last failed load, "" if the library is loaded or untried."""
    return _load_error


def loaded_path():
    """Path of the loaded library, "" if none is loaded."""
    return _loaded_path


def lib():
    """The loaded library, loading it if needed; raises PhosError if unavailable."""
    l = load()
    if l is None:
        raise PhosError(_load_error)
    return l


def version_string():
    """"major.minor.patch" of the loaded library, "" if none."""
    if _lib is None:
        return ""
    v = _lib.phos_version()
    return "%d.%d.%d" % ((v >> 16) & 0xFFFF, (v >> 8) & 0xFF, v & 0xFF)


# ------------------------------------------------------------------ helpers

def _decode(b):
    return b.decode("utf-8", "replace") if b else ""


def status_string(status):
    l = lib()
    return _decode(l.phos_status_string(status))


def _as_array(a, dtype, count, what):
    """A C-contiguous numpy array of dtype with exactly `count` elements."""
    arr = np.ascontiguousarray(a, dtype=dtype).reshape(-1)
    if arr.size != count:
        raise PhosError("%s has %d values, expected %d" % (what, arr.size, count))
    return arr


def _ptr(arr, ctype):
    return arr.ctypes.data_as(ctypes.POINTER(ctype)) if arr is not None else None


def matrix_to_3x4(matrix):
    """Row-major 3x4 (the top three rows) of a 4x4 matrix as 12 floats."""
    m = np.asarray(matrix, dtype=np.float64).reshape(4, 4)
    return tuple(float(x) for x in m[:3, :4].reshape(-1))


def new_closure():
    """A phos_closure_desc with the library's defaults."""
    d = phos_closure_desc()
    lib().phos_closure_desc_init(ctypes.byref(d))
    return d


def new_light():
    d = phos_light_desc()
    lib().phos_light_desc_init(ctypes.byref(d))
    return d


def new_camera():
    d = phos_camera_desc()
    lib().phos_camera_desc_init(ctypes.byref(d))
    return d


def new_world():
    d = phos_world_desc()
    lib().phos_world_desc_init(ctypes.byref(d))
    return d


def new_render_settings():
    d = phos_render_settings()
    lib().phos_render_settings_init(ctypes.byref(d))
    return d


# -------------------------------------------------------------------- scene

class _Handle:
    """What both handle owners share: close() frees the handle once (also on
    leaving a `with` block, and as a last resort when garbage collected), and
    a failed call raises PhosError with the message the core left on it."""

    _kind = "handle"
    _handle = None

    @property
    def handle(self):
        if not self._handle:
            raise PhosError("the %s was already closed" % self._kind, PHOS_ERROR_INVALID_STATE)
        return self._handle

    def close(self):
        if self._handle:
            handle, self._handle = self._handle, None
            self._destroy(handle)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __del__(self):
        # Safety net only; owners call close() deterministically.
        try:
            self.close()
        except Exception:
            pass

    def _raise_on(self, status, what):
        if status != PHOS_OK:
            msg = self._error_text(self._handle) or _decode(self._lib.phos_status_string(status))
            raise PhosError("%s: %s" % (what, msg), status)

    def error(self):
        return self._error_text(self.handle)


class Scene(_Handle):
    """Owner of a phos_scene handle.

    Use as a context manager or call close(); every add_* returns the new
    id and raises PhosError with phos_scene_error() on failure. Array
    arguments are converted to C-contiguous float32/uint32 and only need to
    live during the call (the core copies them).
    """

    _kind = "scene"

    def __init__(self):
        self._lib = lib()
        self._handle = self._lib.phos_scene_create()
        if not self._handle:
            raise PhosError("out of memory creating a scene", PHOS_ERROR_OUT_OF_MEMORY)

    def _destroy(self, handle):
        self._lib.phos_scene_destroy(handle)

    def _error_text(self, handle):
        return _decode(self._lib.phos_scene_error(handle))

    def add_image(self, pixels, width, height, interpolation=PHOS_INTERP_LINEAR,
                  extension=PHOS_EXTEND_REPEAT):
        """Add linear RGBA float pixels (rows bottom-up); returns the image id."""
        px = _as_array(pixels, np.float32, width * height * 4, "image pixels")
        d = phos_image_desc()
        self._lib.phos_image_desc_init(ctypes.byref(d))
        d.width, d.height = width, height
        d.pixels = _ptr(px, ctypes.c_float)
        d.interpolation, d.extension = interpolation, extension
        out = _u32()
        self._raise_on(self._lib.phos_scene_add_image(self.handle, ctypes.byref(d), ctypes.byref(out)),
                       "adding an image")
        return out.value

    def add_material(self, closures):
        """Add a material from a sequence of phos_closure_desc; returns its id."""
        n = len(closures)
        arr = (phos_closure_desc * max(n, 1))(*closures)
        d = phos_material_desc()
        self._lib.phos_material_desc_init(ctypes.byref(d))
        d.closure_count = n
        d.closures = ctypes.cast(arr, ctypes.POINTER(phos_closure_desc)) if n else None
        out = _u32()
        self._raise_on(self._lib.phos_scene_add_material(self.handle, ctypes.byref(d), ctypes.byref(out)),
                       "adding a material")
        return out.value

    def add_mesh(self, positions, indices, normals=None, uvs=None, material_slots=None):
        """Add a triangle mesh in object space; returns the mesh id.

        positions (V*3), indices (T*3), per-corner normals (T*9) and UVs (T*6),
        per-triangle slots (T); the optional ones may be None.
        """
        pos = np.ascontiguousarray(positions, dtype=np.float32).reshape(-1)
        idx = np.ascontiguousarray(indices, dtype=np.uint32).reshape(-1)
        if pos.size % 3 or idx.size % 3:
            raise PhosError("mesh arrays must hold whole vertices and triangles")
        v, t = pos.size // 3, idx.size // 3
        nrm = _as_array(normals, np.float32, t * 9, "normals") if normals is not None else None
        uv = _as_array(uvs, np.float32, t * 6, "uvs") if uvs is not None else None
        slots = _as_array(material_slots, np.uint32, t, "material slots") \
            if material_slots is not None else None
        d = phos_mesh_desc()
        self._lib.phos_mesh_desc_init(ctypes.byref(d))
        d.vertex_count, d.positions = v, _ptr(pos, ctypes.c_float)
        d.triangle_count, d.indices = t, _ptr(idx, ctypes.c_uint32)
        d.normals = _ptr(nrm, ctypes.c_float)
        d.uvs = _ptr(uv, ctypes.c_float)
        d.material_slots = _ptr(slots, ctypes.c_uint32)
        out = _u32()
        self._raise_on(self._lib.phos_scene_add_mesh(self.handle, ctypes.byref(d), ctypes.byref(out)),
                       "adding a mesh")
        return out.value

    def add_instance(self, mesh_id, transform, materials):
        """Place a mesh with a row-major 3x4 transform and per-slot material ids."""
        mats = np.ascontiguousarray(materials, dtype=np.uint32).reshape(-1)
        d = phos_instance_desc()
        self._lib.phos_instance_desc_init(ctypes.byref(d))
        d.mesh_id = mesh_id
        d.transform[:] = [float(x) for x in transform]
        d.material_count = mats.size
        d.materials = _ptr(mats, ctypes.c_uint32) if mats.size else None
        out = _u32()
        self._raise_on(self._lib.phos_scene_add_instance(self.handle, ctypes.byref(d), ctypes.byref(out)),
                       "adding an instance")
        return out.value

    def add_light(self, desc):
        out = _u32()
        self._raise_on(self._lib.phos_scene_add_light(self.handle, ctypes.byref(desc), ctypes.byref(out)),
                       "adding a light")
        return out.value

    def set_world(self, desc):
        self._raise_on(self._lib.phos_scene_set_world(self.handle, ctypes.byref(desc)),
                       "setting the world")

    def set_camera(self, desc):
        self._raise_on(self._lib.phos_scene_set_camera(self.handle, ctypes.byref(desc)),
                       "setting the camera")

    def commit(self):
        self._raise_on(self._lib.phos_scene_commit(self.handle), "building the scene")


# ------------------------------------------------------------------- render

class Render(_Handle):
    """Owner of a phos_render handle created from a committed Scene.

    The core runs its own threads; every method here returns quickly except
    wait(). cancel() is safe from any thread.
    """

    _kind = "render"

    def __init__(self, scene, settings):
        self._lib = lib()
        self._handle = None
        out = _vp()
        status = self._lib.phos_render_create(scene.handle, ctypes.byref(settings), ctypes.byref(out))
        if status != PHOS_OK:
            # The message of a failed create is put on the scene.
            msg = _decode(self._lib.phos_scene_error(scene.handle)) or \
                _decode(self._lib.phos_status_string(status))
            raise PhosError("creating the render: %s" % msg, status)
        self._handle = out.value
        self.settings = settings
        self._channels = {}

    def _destroy(self, handle):
        # A running render is cancelled and joined before it is freed.
        self._lib.phos_render_cancel(handle)
        self._lib.phos_render_wait(handle, -1.0)
        self._lib.phos_render_destroy(handle)

    def _error_text(self, handle):
        return _decode(self._lib.phos_render_error(handle))

    def start(self):
        self._raise_on(self._lib.phos_render_start(self.handle), "starting the render")

    def progress(self):
        p = phos_progress()
        self._raise_on(self._lib.phos_render_progress(self.handle, ctypes.byref(p)),
                       "reading progress")
        return p

    def next_tile(self):
        """The next finished tile (full-frame coordinates), or None."""
        t = phos_tile()
        n = _u32()
        self._raise_on(self._lib.phos_render_next_tile(self.handle, ctypes.byref(t), ctypes.byref(n)),
                       "reading finished tiles")
        return t if n.value else None

    def channels(self, pass_id):
        c = self._channels.get(pass_id)
        if c is None:
            c = self._channels[pass_id] = int(self._lib.phos_pass_channels(pass_id))
        return c

    def read(self, pass_id, x, y, width, height, out=None):
        """Pixels of a pass as a float32 array shaped (width*height, channels).

        Rows bottom-up, as Blender's render result wants them; `out` may be a
        preallocated C-contiguous float32 array of that shape.
        """
        ch = self.channels(pass_id)
        if ch == 0:
            raise PhosError("unknown pass %d" % pass_id, PHOS_ERROR_INVALID_ARGUMENT)
        shape = (width * height, ch)
        if out is None or out.shape != shape or out.dtype != np.float32 or not out.flags.c_contiguous:
            out = np.empty(shape, dtype=np.float32)
        self._raise_on(self._lib.phos_render_read(self.handle, pass_id, x, y, width, height,
                                                  _ptr(out, ctypes.c_float), out.size),
                       "reading pixels")
        return out

    def cancel(self):
        if self._handle:
            self._lib.phos_render_cancel(self._handle)

    def wait(self, timeout_seconds=-1.0):
        """Returns the status: PHOS_OK, PHOS_ERROR_CANCELLED or PHOS_ERROR_TIMEOUT.

        Any other status (a failed render) raises PhosError.
        """
        status = self._lib.phos_render_wait(self.handle, float(timeout_seconds))
        if status not in (PHOS_OK, PHOS_ERROR_CANCELLED, PHOS_ERROR_TIMEOUT):
            self._raise_on(status, "rendering")
        return status
