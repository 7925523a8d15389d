#!/usr/bin/env python3
"""fit_sheen_ltc.py -- fit Phos's LTC sheen table (core/src/shading/sheen_table.c).

Re-runs, with our own code, the method of Zeltner, Burley & Chiang 2022,
"Practical Multiple-Scattering Sheen Using Linearly Transformed Cosines"
(SIGGRAPH 2022 talk), which is the sheen of Cycles' Principled BSDF:

1. Reference BRDF: a slab of unit thickness filled with fibre-like SGGX
   microflakes (Heitz et al. 2015, "The SGGX microflake distribution"),
   fibres along the normal, projected-area matrix S = diag(1, 1, s^2) with
   s = r^2 (r = sheen roughness), unit density, white single-scattering
   albedo, specular microflake phase function, nothing below the slab.
   A light path enters from the top, scatters at most MAX_SCATTER = 16 times;
   what leaves through the top is the BRDF. As in the paper's fit, a path
   still inside after its last allowed scattering is counted as leaving along
   the direction that scattering gave it, if that direction points up.
2. For each node (mu, r) of a 32 x 32 grid (nodes max(0.01, j/31)) we trace
   4M random walks (numpy, vectorised, single precision, fixed seeds; a node
   where fewer than 20000 paths come out and the walks are cheap gets an
   extra batch, up to 4e7 free flights) and accumulate
     - R, the directional albedo: the fraction of paths leaving through the
       top (binomial standard error sqrt(R (1 - R) / n));
     - a 32 x 32 histogram of the exit directions over (theta_o, phi_o),
       theta_o in [0, pi/2], phi_o in [0, pi] (mirrored; phi_o = 0 is the
       side the light came from), turned into BRDF*cos (1/sr) averages over
       each bin's solid angle (the first theta row averaged over phi; at
       mu = 1 every row, the lobe being symmetric about the normal).
3. Per node we fit the inverse LTC matrix [[A,0,B],[0,A,0],[0,0,1]] (frame x
   axis toward the light's projection) so that R * LTC(omega) matches the
   histogram at the 32 x 32 bin centres, minimising the sum of |difference|^3
   (the metric of the paper's fitting code), with a hand-written Nelder-Mead,
   warm-started along each mu row from the next higher roughness (the row
   starting at r = 1 from A = 1, B = 0).  Nodes whose R < 3e-6 keep A = B = 0
   (the lobe is then unused); nodes where fewer than 1000 paths came out
   (R below ~1e-4, too few to resolve a shape) take the next rougher node's
   A, B.

Outputs core/src/shading/sheen_table.c and sheen_table.h (indexed
[roughness node][mu node][A, B, R]).  No numbers from the paper's authors are
used: everything is computed here.

Usage:
  tools/fit_sheen_ltc.py            full run (4M paths a node, 2 workers;
                                    ~20 min on 2 free cores)
  tools/fit_sheen_ltc.py --quick    fast low-sample run (~15 s), for testing
  tools/fit_sheen_ltc.py --selftest checks of the microflake sampler
  tools/fit_sheen_ltc.py --save-npz F / --from-npz F   keep the traced
                                    histograms / refit them without tracing
Only numpy is needed.  The results depend only on the options, not on
--jobs or the machine's load.
"""

import argparse
import ctypes
import ctypes.util
import math
import multiprocessing
import os
import sys
import time

import numpy as np

N = 32                                   # table resolution (both axes)
NODES = np.maximum(0.01, np.arange(N) / (N - 1.0))
MAX_SCATTER = 16                         # scattering events a path may have
R_SKIP = 3e-6                            # below this albedo the lobe is not fitted
N_THETA = 32                             # exit histogram: theta_o bins on [0, pi/2]
N_PHI = 32                               # ... and phi_o bins on [0, pi] (mirrored)
D_THETA = 0.5 * math.pi / N_THETA
D_PHI = math.pi / N_PHI
CHUNK = 1 << 17                          # paths traced together
BASE_SEED = 20240611

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT_C = os.path.join(REPO, "core", "src", "shading", "sheen_table.c")
OUT_H = os.path.join(REPO, "core", "src", "shading", "sheen_table.h")


# --------------------------------------------------------------------------
# The fibre-like SGGX medium, fibres along z: S = diag(1, 1, s^2).
#
# Projected area (extinction per unit density) along a unit direction w:
#     sigma(w) = sqrt(w_x^2 + w_y^2 + s^2 w_z^2).
# Normal distribution:  D(m) = 1 / (pi s (m_x^2 + m_y^2 + m_z^2 / s^2)^2).
# Visible normals seen from w: D_w(m) = max(0, w.m) D(m) / sigma(w).
# Specular phase function, wi toward where the light came from, wo the
# scattered direction:  p(wi -> wo) = D(h) / (4 sigma(wi)),  h = |wi + wo|^-1 (wi + wo).
#
# These normals are those of an ellipsoid with semi-axes proportional to
# (1, 1, 1/s); mapping it to the unit sphere (x -> diag(1, 1, s) x, up to
# scale) maps the view direction w to v ~ (w_x, w_y, s w_z), keeps the
# projected area uniform, and maps a sphere normal p back to the ellipsoid
# normal m ~ (p_x, p_y, s p_z).  So a visible normal is drawn by picking p
# with density ~ max(0, p.v) on the sphere (a cosine lobe around v, drawn as
# v + a uniform point of the sphere) and mapping it back.
# --------------------------------------------------------------------------

F32 = np.float32                         # the walks run in single precision


def sggx_sigma(x, y, z, s):
    return np.sqrt(x * x + y * y + (s * s) * (z * z))


def sggx_ndf(x, y, z, s):
    q = x * x + y * y + (z * z) / (s * s)
    return 1.0 / (math.pi * s * q * q)


def sample_visible_normal(wx, wy, wz, s, rng):
    """Visible normals of the fibre SGGX, seen from the unit directions w."""
    n = wx.shape[0]
    vx, vy, vz = wx, wy, s * wz
    inv = 1 / np.sqrt(vx * vx + vy * vy + vz * vz)
    vx, vy, vz = vx * inv, vy * inv, vz * inv
    u = rng.random((2, n), dtype=wx.dtype)
    cz = 2 * u[0] - 1
    rr = np.sqrt(np.maximum(0, 1 - cz * cz))
    ph = F32(2 * math.pi) * u[1] if wx.dtype == F32 else (2 * math.pi) * u[1]
    # p = v + (uniform point of the sphere); only its direction matters.
    px = vx + rr * np.cos(ph)
    py = vy + rr * np.sin(ph)
    pz = vz + cz
    mx, my, mz = px, py, s * pz
    inv = 1 / np.maximum(np.sqrt(mx * mx + my * my + mz * mz), 1e-30)
    return mx * inv, my * inv, mz * inv


def scatter(dx, dy, dz, s, rng):
    """New propagation direction after a specular microflake scattering."""
    ix, iy, iz = -dx, -dy, -dz                       # toward where light came from
    mx, my, mz = sample_visible_normal(ix, iy, iz, s, rng)
    c = 2 * (ix * mx + iy * my + iz * mz)
    ox, oy, oz = c * mx - ix, c * my - iy, c * mz - iz
    inv = 1 / np.sqrt(ox * ox + oy * oy + oz * oz)
    return ox * inv, oy * inv, oz * inv


def exit_bin(dx, dy, dz):
    theta = np.arccos(np.clip(dz, 0, 1))
    phi = np.arctan2(np.abs(dy), dx)
    it = np.minimum((theta * F32(1 / D_THETA)).astype(np.int64), N_THETA - 1)
    ip = np.minimum((phi * F32(1 / D_PHI)).astype(np.int64), N_PHI - 1)
    return it * N_PHI + ip


def trace(mu, rough, n_paths, rng, max_scatter=MAX_SCATTER):
    """Random walks for light arriving from direction (sqrt(1-mu^2), 0, mu).

    Returns (hist, n_exit, n_steps): hist[k] is the number of paths leaving
    through the top in exit bin k (theta_o, phi_o), n_exit their total, and
    n_steps the number of free flights traced (the work done)."""
    s = F32(rough * rough)
    hist = np.zeros(N_THETA * N_PHI, dtype=np.int64)
    done = 0
    n_steps = 0
    sin_i = math.sqrt(max(0.0, 1.0 - mu * mu))
    while done < n_paths:
        n = min(CHUNK, n_paths - done)
        done += n
        # Path state: direction of propagation (dx, dy, dz), depth z below
        # the top (0..1); the light enters at the top going down.
        st = np.empty((4, n), dtype=F32)
        st[0] = -sin_i
        st[1] = 0
        st[2] = -mu
        st[3] = 0
        for k in range(max_scatter):
            dx, dy, dz, z = st
            n_steps += st.shape[1]
            # Free flight to the next scattering (or out of the slab).
            u = rng.random(st.shape[1], dtype=F32)
            t = -np.log(1 - u) / sggx_sigma(dx, dy, dz, s)
            z = z - t * dz
            top = z < 0
            if top.any():
                hist += np.bincount(exit_bin(dx[top], dy[top], dz[top]),
                                    minlength=N_THETA * N_PHI)
            keep = (z >= 0) & (z <= 1)
            st[3] = z
            st = st[:, keep]
            if st.shape[1] == 0:
                break
            # Scattering.
            dx, dy, dz = scatter(st[0], st[1], st[2], s, rng)
            st[0], st[1], st[2] = dx, dy, dz
            if k == max_scatter - 1:
                # The last allowed scattering: the path leaves along its new
                # direction if that points up (the reference's truncation).
                up = dz >= 0
                hist += np.bincount(exit_bin(dx[up], dy[up], dz[up]),
                                    minlength=N_THETA * N_PHI)
    return hist, int(hist.sum()), n_steps


# Exit histogram geometry: bin solid angles (the two mirrored cells) and
# centre directions.
TH_EDGES = np.arange(N_THETA + 1) * D_THETA
BIN_SOLID = np.repeat(2.0 * D_PHI * (np.cos(TH_EDGES[:-1]) - np.cos(TH_EDGES[1:])), N_PHI)
TH_C = (np.arange(N_THETA) + 0.5) * D_THETA
PH_C = (np.arange(N_PHI) + 0.5) * D_PHI
_TC, _PC = np.meshgrid(TH_C, PH_C, indexing="ij")
WX = (np.sin(_TC) * np.cos(_PC)).ravel()
WY = (np.sin(_TC) * np.sin(_PC)).ravel()
WZ = np.cos(_TC).ravel()


def reference_lobe(hist, n_paths):
    """BRDF*cos (1/sr) averaged over each exit bin, shape (N_THETA, N_PHI)."""
    f = (hist / (n_paths * BIN_SOLID)).reshape(N_THETA, N_PHI)
    # The first theta row's bins are tiny and all point almost straight up:
    # average them (the lobe is smooth there).
    f[0, :] = f[0, :].mean()
    return f


def ltc_lobe(a, b, wx=WX, wy=WY, wz=WZ):
    """The normalised LTC lobe (1/sr) for inverse matrix [[a,0,b],[0,a,0],[0,0,1]]."""
    vx = a * wx + b * wz
    vy = a * wy
    l2 = vx * vx + vy * vy + wz * wz
    return (a * a / math.pi) * wz / (l2 * l2)


# --------------------------------------------------------------------------
# Fitting.
# --------------------------------------------------------------------------

def nelder_mead(f, x0, step, xtol=1e-6, ftol=1e-6, max_iter=20000):
    """Downhill simplex (Nelder & Mead 1965), standard coefficients."""
    n = len(x0)
    pts = [np.array(x0, dtype=float)]
    for i in range(n):
        p = np.array(x0, dtype=float)
        p[i] += step[i]
        pts.append(p)
    vals = [f(p) for p in pts]
    for _ in range(max_iter):
        order = np.argsort(vals)
        pts = [pts[i] for i in order]
        vals = [vals[i] for i in order]
        if (max(np.max(np.abs(p - pts[0])) for p in pts[1:]) <= xtol and
                max(abs(v - vals[0]) for v in vals[1:]) <= ftol):
            break
        c = sum(pts[:-1]) / n
        xr = c + (c - pts[-1])
        fr = f(xr)
        if fr < vals[0]:
            xe = c + 2.0 * (c - pts[-1])
            fe = f(xe)
            if fe < fr:
                pts[-1], vals[-1] = xe, fe
            else:
                pts[-1], vals[-1] = xr, fr
        elif fr < vals[-2]:
            pts[-1], vals[-1] = xr, fr
        else:
            if fr < vals[-1]:
                xc = c + 0.5 * (xr - c)          # outside contraction
                fc = f(xc)
                ok = fc <= fr
            else:
                xc = c + 0.5 * (pts[-1] - c)     # inside contraction
                fc = f(xc)
                ok = fc < vals[-1]
            if ok:
                pts[-1], vals[-1] = xc, fc
            else:
                for i in range(1, n + 1):
                    pts[i] = pts[0] + 0.5 * (pts[i] - pts[0])
                    vals[i] = f(pts[i])
    i = int(np.argmin(vals))
    return pts[i], vals[i]


def fit_node(ref, R, x0):
    """A, B minimising sum |R*LTC - ref|^3 over the bin centres."""
    target = ref.ravel()

    def loss(x):
        if x[0] <= 1e-4:          # keep A positive (the lobe degenerates at 0)
            return 1e30
        return float(np.sum(np.abs(R * ltc_lobe(x[0], x[1]) - target) ** 3))

    x0 = np.asarray(x0, dtype=float)
    step = np.array([max(0.05 * abs(x0[0]), 0.01), 0.02])
    x, fx = nelder_mead(loss, x0, step)
    # One restart from the optimum guards against a collapsed simplex.
    x2, fx2 = nelder_mead(loss, x, step * 0.5)
    return (x2, fx2) if fx2 <= fx else (x, fx)


# --------------------------------------------------------------------------
# Driver.
# --------------------------------------------------------------------------

def _tune_malloc():
    """Keeps glibc from returning every freed array of a walk to the system
    (mmap/munmap page faults otherwise cost a third of the run); elsewhere,
    or if it fails, nothing changes (and the results never depend on it)."""
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        libc.mallopt(-3, 16 << 20)      # M_MMAP_THRESHOLD: 16 MiB
        libc.mallopt(-1, 256 << 20)     # M_TRIM_THRESHOLD: 256 MiB
    except (OSError, AttributeError):
        pass


def node_task(args):
    """Traces one node: n_paths walks, then, where few paths come out and the
    walks are cheap, an extra batch (sized from the first batch's counts, so
    the result stays deterministic) to resolve the lobe's shape better."""
    ir, jm, n_paths, max_scatter, target_exits, extra_steps = args
    mu, rough = float(NODES[jm]), float(NODES[ir])
    rng = np.random.default_rng([BASE_SEED, ir, jm])
    hist, n_exit, n_steps = trace(mu, rough, n_paths, rng, max_scatter=max_scatter)
    total = n_paths
    if n_exit >= R_SKIP * n_paths and n_exit < target_exits:
        want = n_paths * (target_exits / max(n_exit, 1) - 1.0)
        cap = extra_steps * n_paths / max(n_steps, 1)
        extra = int(min(want, cap))
        if extra > 0:
            rng = np.random.default_rng([BASE_SEED, ir, jm, 1])
            h2, e2, s2 = trace(mu, rough, extra, rng, max_scatter=max_scatter)
            hist += h2
            total += extra
    return ir, jm, hist, total


def trace_table(n_paths, jobs, max_scatter=MAX_SCATTER, target_exits=20000,
                extra_steps=4e7, log=sys.stderr):
    """Exit histograms (N, N, N_THETA*N_PHI) and paths traced (N, N)."""
    tasks = [(ir, jm, n_paths, max_scatter, target_exits, extra_steps)
             for ir in range(N) for jm in range(N)]
    # Expensive nodes (rough, grazing) first, for load balance.
    tasks.sort(key=lambda t: -(NODES[t[0]] + (1.0 - NODES[t[1]])))
    hist = np.zeros((N, N, N_THETA * N_PHI), dtype=np.int64)
    paths = np.zeros((N, N), dtype=np.int64)
    t0 = time.time()

    def collect(res, k):
        ir, jm, h, total = res
        hist[ir, jm] = h
        paths[ir, jm] = total
        if (k + 1) % 64 == 0:
            print("  traced %4d/%d nodes, %.0f s" % (k + 1, len(tasks), time.time() - t0),
                  file=log, flush=True)

    _tune_malloc()
    if jobs > 1:
        with multiprocessing.Pool(jobs, initializer=_tune_malloc) as pool:
            for k, res in enumerate(pool.imap_unordered(node_task, tasks)):
                collect(res, k)
    else:
        for k, t in enumerate(tasks):
            collect(node_task(t), k)
    return hist, paths


def fit_table(hist, paths, min_exits=1000):
    """The table [roughness][mu][A, B, R] from the exit histograms.

    Along each mu row the fit runs from r = 1 down, each node starting from
    the previous one's solution.  Nodes with R < R_SKIP get A = B = 0; nodes
    with fewer than min_exits exit samples (too few to resolve a shape) take
    the previous node's A, B."""
    n_exit = hist.sum(axis=2)
    R = n_exit / paths
    R_se = np.sqrt(R * (1.0 - R) / paths)
    table = np.zeros((N, N, 3))
    table[:, :, 2] = R
    fit_err = np.zeros((N, N))
    refs = np.zeros((N, N, N_THETA, N_PHI))
    status = np.zeros((N, N), dtype=np.int8)     # 0 skipped, 1 fitted, 2 carried
    for jm in range(N):
        x = np.array([1.0, 0.0])
        for ir in range(N - 1, -1, -1):
            ref = reference_lobe(hist[ir, jm], paths[ir, jm])
            if jm == N - 1:
                # mu = 1: light arrives along the normal, the lobe is
                # symmetric about it.
                ref[:] = ref.mean(axis=1, keepdims=True)
            refs[ir, jm] = ref
            if R[ir, jm] < R_SKIP:
                continue
            if n_exit[ir, jm] < min_exits:
                table[ir, jm, 0:2] = x
                status[ir, jm] = 2
                continue
            x, fx = fit_node(ref, R[ir, jm], x)
            table[ir, jm, 0:2] = x
            fit_err[ir, jm] = fx
            status[ir, jm] = 1
    return dict(table=table, R=R, R_se=R_se, refs=refs, fit_err=fit_err,
                status=status, n_exit=n_exit)


def _c_float(v):
    s = "%.7g" % v
    if s in ("-0", "0"):
        return "0.0f"
    if "." not in s and "e" not in s:
        s += ".0"
    return s + "f"


def write_c(table, n_paths, mode_desc, min_exits):
    nodes_txt = "max(0.01, j/31), j = 0..31"
    head = (
        "/*\n"
        " * sheen_table.c -- GENERATED by tools/fit_sheen_ltc.py (%s); do not edit.\n"
        " *\n"
        " * The LTC fit of the microfiber sheen of Zeltner, Burley & Chiang 2022,\n"
        " * \"Practical Multiple-Scattering Sheen Using Linearly Transformed Cosines\"\n"
        " * (SIGGRAPH 2022 talk), recomputed here by re-running the method with our\n"
        " * own code: the reference is a unit-thickness, unit-density slab of\n"
        " * fibre-like SGGX microflakes (Heitz et al. 2015; S = diag(1, 1, r^4),\n"
        " * r the sheen roughness), white, specular microflakes, at most 16\n"
        " * scatterings, estimated by Monte Carlo random walks (%d paths a node,\n"
        " * more where few come out); A and B minimise sum |R LTC - reference|^3\n"
        " * over a 32 x 32 (theta, phi) grid of exit directions. These are NOT the\n"
        " * paper authors' numbers.\n"
        " *\n"
        " * sheen_ltc_table[i][j] = {A, B, R} at roughness node i and mu = cos(theta)\n"
        " * node j; both grids are %s (Phos reads them\n"
        " * bilinearly as if node j were at j/31). The inverse LTC matrix in the frame\n"
        " * whose x axis is the view direction's projection is\n"
        " * [[A, 0, B], [0, A, 0], [0, 0, 1]]; R is the directional albedo.\n"
        " * A = B = 0 where R < 3e-6 (no lobe); where fewer than %d paths came out\n"
        " * A and B are the next rougher node's.\n"
        " */\n" % (mode_desc, n_paths, nodes_txt, min_exits))
    lines = [head, '#include "shading/sheen_table.h"\n\n',
             "const float sheen_ltc_table[SHEEN_TABLE_SIZE][SHEEN_TABLE_SIZE][3] = {\n"]
    for ir in range(N):
        lines.append("    /* roughness node %d (%.4f) */\n    {\n" % (ir, NODES[ir]))
        for jm in range(N):
            a, b, r = table[ir, jm]
            lines.append("        {%s, %s, %s},\n" % (_c_float(a), _c_float(b), _c_float(r)))
        lines.append("    },\n")
    lines.append("};\n")
    text = "".join(lines)
    with open(OUT_C, "w") as f:
        f.write(text)
    hdr = (
        "/*\n"
        " * sheen_table.h -- GENERATED by tools/fit_sheen_ltc.py; do not edit.\n"
        " * The LTC sheen fit (sheen_table.c): [roughness node][mu node][A, B, R],\n"
        " * nodes max(0.01, j/31) for j = 0..31 on both axes (read as j/31).\n"
        " */\n"
        "#ifndef PHOS_SHEEN_TABLE_H\n"
        "#define PHOS_SHEEN_TABLE_H\n\n"
        "#define SHEEN_TABLE_SIZE 32\n"
        "extern const float sheen_ltc_table[SHEEN_TABLE_SIZE][SHEEN_TABLE_SIZE][3];\n\n"
        "#endif /* PHOS_SHEEN_TABLE_H */\n")
    with open(OUT_H, "w") as f:
        f.write(hdr)


def _check_density(x, y, z, density, nz=20, nphi=8):
    """Largest difference between the histogram of unit vectors (x, y, z)
    over nz bands of z times nphi sectors of phi and the integral of
    density(x, y, z) (1/sr) over the same cells; also the density's total."""
    n = x.shape[0]
    phi = np.mod(np.arctan2(y, x), 2 * math.pi)
    h = np.histogram2d(z, phi, bins=[nz, nphi],
                       range=[[-1, 1], [0, 2 * math.pi]])[0] / n
    kz, kp = 200 * nz, 90 * nphi            # midpoint rule, uniform in (z, phi)
    zs = -1 + (np.arange(kz) + 0.5) * (2.0 / kz)
    ps = (np.arange(kp) + 0.5) * (2 * math.pi / kp)
    Z, P = np.meshgrid(zs, ps, indexing="ij")
    r = np.sqrt(1 - Z * Z)
    d = density(r * np.cos(P), r * np.sin(P), Z) * (2.0 / kz) * (2 * math.pi / kp)
    cell = d.reshape(nz, kz // nz, nphi, kp // nphi).sum(axis=(1, 3))
    return float(np.max(np.abs(h - cell))), float(d.sum())


def selftest(rng):
    """Checks of the microflake sampler and phase function against the closed forms."""
    ok = True
    n = 1000000
    for s in (0.1, 0.3, 1.0):
        for mu in (0.1, 0.7, 1.0):
            wx, wz = math.sqrt(1 - mu * mu), mu
            mx, my, mz = sample_visible_normal(np.full(n, wx), np.zeros(n),
                                               np.full(n, wz), s, rng)
            sig = float(sggx_sigma(wx, 0.0, wz, s))
            err, tot = _check_density(
                mx, my, mz, lambda x, y, z: np.maximum(0, x * wx + z * wz)
                * sggx_ndf(x, y, z, s) / sig)
            print("  visible normals s=%.1f mu=%.1f: density total %.4f, "
                  "max cell error %.4f" % (s, mu, tot, err))
            ok = ok and err < 0.003 and abs(tot - 1) < 0.01
    for s in (0.1, 0.5, 1.0):
        wx, wz = 0.8, 0.6                    # light came from (0.8, 0, 0.6)
        ox, oy, oz = scatter(np.full(n, -wx), np.zeros(n), np.full(n, -wz), s, rng)
        sig = float(sggx_sigma(wx, 0.0, wz, s))

        def phase(x, y, z):
            hx, hy, hz = x + wx, y, z + wz
            hl = np.maximum(np.sqrt(hx * hx + hy * hy + hz * hz), 1e-12)
            return sggx_ndf(hx / hl, hy / hl, hz / hl, s) / (4 * sig)
        err, tot = _check_density(ox, oy, oz, phase)
        print("  phase function s=%.1f: total %.4f, max cell error %.4f" % (s, tot, err))
        ok = ok and err < 0.003 and abs(tot - 1) < 0.01
    return ok


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true",
                    help="fast low-sample run (for testing the script)")
    ap.add_argument("--paths", type=int, default=None,
                    help="random walks a node (default 4000000, --quick 20000)")
    ap.add_argument("--target-exits", type=int, default=None,
                    help="nodes with fewer exiting paths get an extra batch "
                         "(default 20000, --quick 0 = none)")
    ap.add_argument("--extra-steps", type=float, default=4e7,
                    help="cap of an extra batch, in free flights (default 4e7)")
    ap.add_argument("--min-exits", type=int, default=None,
                    help="nodes with fewer exiting paths are not fitted but take the "
                         "next rougher node's A, B (default 1000, --quick 100)")
    ap.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    ap.add_argument("--max-scatter", type=int, default=MAX_SCATTER,
                    help="scatterings a path may have (default 16, as the reference)")
    ap.add_argument("--save-npz", default=None,
                    help="also save the raw results (exit histograms, paths, table, "
                         "R and its standard error, reference lobes) to this .npz")
    ap.add_argument("--from-npz", default=None,
                    help="skip the tracing: refit the histograms saved by --save-npz")
    ap.add_argument("--no-write", action="store_true",
                    help="do not write core/src/shading/sheen_table.[ch]")
    ap.add_argument("--selftest", action="store_true", help="check the sampler and exit")
    args = ap.parse_args()

    if args.selftest:
        ok = selftest(np.random.default_rng(1))
        print("selftest", "passed" if ok else "FAILED")
        sys.exit(0 if ok else 1)

    n_paths = args.paths or (20000 if args.quick else 4000000)
    target = args.target_exits if args.target_exits is not None else (0 if args.quick else 20000)
    min_exits = args.min_exits if args.min_exits is not None else (100 if args.quick else 1000)
    t0 = time.time()
    if args.from_npz:
        d = np.load(args.from_npz)
        hist, paths = d["hist"], d["paths"]
        n_paths = int(d["n_paths"])
        t_trace = float(d["t_trace"])
        mode = str(d["mode"])
    else:
        print("tracing %d paths at each of %d nodes with %d job(s)..."
              % (n_paths, N * N, args.jobs), file=sys.stderr)
        hist, paths = trace_table(n_paths, args.jobs, max_scatter=args.max_scatter,
                                  target_exits=target, extra_steps=args.extra_steps)
        t_trace = time.time() - t0
        mode = "%s run" % ("quick" if args.quick else "full")
        if args.max_scatter != MAX_SCATTER:
            mode += ", %d scatterings" % args.max_scatter
        print("traced in %.0f s (%d paths in all)" % (t_trace, paths.sum()), file=sys.stderr)
    t1 = time.time()
    res = fit_table(hist, paths, min_exits=min_exits)
    t_fit = time.time() - t1
    print("fitted in %.0f s: %d nodes fitted, %d carried over (< %d exits), %d without a lobe"
          % (t_fit, (res["status"] == 1).sum(), (res["status"] == 2).sum(), min_exits,
             (res["status"] == 0).sum()), file=sys.stderr)
    if args.save_npz:
        np.savez_compressed(args.save_npz, hist=hist, paths=paths, n_paths=n_paths,
                            mode=mode, t_trace=t_trace, t_fit=t_fit, nodes=NODES, **res)
    if not args.no_write:
        write_c(res["table"], n_paths, mode, min_exits)
        print("wrote %s and %s" % (OUT_C, OUT_H), file=sys.stderr)
    rel = res["R_se"] / np.maximum(res["R"], 1e-12)
    for lim in (1e-3, 1e-2):
        m = res["R"] > lim
        print("R standard error where R > %g: max %.2e absolute, max %.2e relative"
              % (lim, res["R_se"][m].max() if m.any() else 0.0, rel[m].max() if m.any() else 0.0),
              file=sys.stderr)
    print("total %.0f s" % (time.time() - t0), file=sys.stderr)


if __name__ == "__main__":
    main()
