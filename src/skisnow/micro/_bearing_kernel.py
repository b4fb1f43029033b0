"""The compiled search of :func:`skisnow.micro.bearing_area` (Scherge et al. 2021, eq. 5–7).

For every raster position of a grain of radius R, the first contact z0 (the grey-scale dilation
of the base by the sphere) and the contact of the ⌊N*⌋ pixels of largest F = h − s(r) plus the
fraction of the next one (see :mod:`skisnow.micro._bearing` for the model and its
discretisation). :func:`bearing_search` sets up the search (bounds, the sag table) and runs the
numba kernel; :func:`skisnow.micro.bearing_area` is the thin, validated entry point.

Algorithm (exact; no approximation beyond the discretisation above). Only ⌊N*⌋ + 1 pixels per
position matter — a few hundred for D = 450–750 µm at 1 µm pixels and 20 kPa — so the
positions are processed in tiles (default 8 × 8) grouped in super-tiles (default 2 × 2 tiles)
and everything else is pruned by bounds:

1. Any pixel with F(x) < τ (τ = (⌊N*⌋+1)-th largest F of that position) is irrelevant.
2. For a set B of positions, F_x0(x) ≤ h(x) − s(d_min(x, B)) and F_x0(x) ≥ h(x) − s(d_max(x, B))
   for every x0 in B (s increases with r). The (⌊N*⌋+1)-th largest of the lower bound is a lower
   bound τ_B of every position's τ; pixels whose upper bound is below τ_B are dropped.
   A super-tile applies this to its search window once; each tile applies it again, with its
   own tighter distances, to the super-tile's survivors.
3. For the tile's survivors the exact F is evaluated for every position of the tile, the
   (⌊N*⌋+1)-th largest found by a selection, and the contact summed (ties at the
   boundary taken in raster order, as the reference's stable sort does).

Steps 1–3 run in one compiled kernel (numba, GIL released; see the comment at
``_bearing_kernel`` for why). F is h − s read from a table of the sag at integer pixel offsets,
the very values the reference computes, so the selected pixels are the reference's.
The search window around a super-tile is bounded a priori: a pixel at distance r can only
compete if s(r) ≤ max h − min h + s(ρ*), ρ* the radius holding N*+1 pixels.
:func:`bearing_area_reference` is the naive search over the whole footprint, kept in the
library to check this one.

Selection in step 3 avoids a full selection per position: the threshold (the (⌊N*⌋+1)-th
largest F) of a position is guessed from the plane through those of its left, upper and
upper-left neighbours, one pass sums the candidates above guess + Δ and gathers the band
guess ± Δ (Δ = 3× the recent guess error), and only the band is selected; a guess that misses
is retried on the side the pass reports, in a bracket beside the last one and four times as
wide (an open bracket only after two such tries). The pass reads the tile's candidates as row
spans cut into chunks of 8 pixels, their h and w copied contiguously per tile: F over a chunk is
bounded by its least and largest h and the sag at its nearest and farthest columns, so a chunk
below the band is skipped and one above it counted whole (its Σw precomputed; the largest F of
the position is then read from the chunks that can hold it, starting from the pixel where the
previous position of the tile found it), and the others are read contiguously (h, w and a
mirrored sag row, no index arrays; the mirror is read flat, each chunk's row of it located once
per row of positions). Every selection (the band's and those of steps 1–2) is a quickselect
with a branch-free partition into scratch copies (:func:`_kth_largest`). The super-tile's
window is also shrunk to the rows and columns where max h − s(r) still reaches a first lower
bound of τ from its core, and its scans skip the blocks of 8 columns whose largest h
(:func:`block_max`) cannot reach the level they keep. The hot loops index with unsigned
integers: numba then omits the wraparound arithmetic of negative indices at every access.

Cost (measured, ``benchmarks/bench_speed.py --rows bearing``, preset S3, 1 mm² at 1 µm, 31
sizes 450–750 µm, 5.2 million position–size pairs): ~2.3 µs CPU per pair (11.6–12.0 s CPU at
load 11–17 where the fourth pass's code took 14.2–14.5 s; ~3.7 µs before the fourth pass of
issue 29, see ``docs/performance/speed.md``); against ~35–45 µs per pair for the earlier NumPy
block search and ~10 ms for the naive search. ``stride`` trades positions for time (stride 3
changed the mean A_fr by 4·10⁻⁵ relative on preset S3).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from skisnow.micro._bearing_select import _band_select, _kth_largest

__all__ = ["bearing_search", "block_max", "sag"]

#: numba wraps negative indices at every access of a signed index; the hot loops index with
#: this unsigned type (their indices are never negative) to drop that arithmetic
u8 = np.uint64

#: pixels per chunk of a row span in step 3 (bounded, counted or read as a whole)
_CHUNK = 8


def sag(r2: np.ndarray, radius: float, shape: str) -> np.ndarray:
    """Sag s(r) of the sphere surface [m] from r² [m²]; +inf outside the footprint r > R."""
    if shape == "paraboloid":
        s = r2 / (2.0 * radius)
    else:
        with np.errstate(invalid="ignore"):
            s = radius - np.sqrt(radius * radius - r2)
    return np.where(r2 <= radius * radius, s, np.inf)


def bearing_search(
    h: np.ndarray,
    w: np.ndarray,
    *,
    ii: np.ndarray,
    jj: np.ndarray,
    ci: int,
    cj: int,
    dx: float,
    dy: float,
    radius: float,
    shape: str,
    n: int,
    frac: float,
    stride: int,
    block: int | tuple[int, int],
    superblock: int | tuple[int, int],
    bmax: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The exact bearing contact at the positions ``ii × jj`` (pixel indices, raster order).

    ``h`` heights [m] and ``w`` slope factors √(1 + |∇h|²) per pixel; the footprint half-sizes
    ``ci``, ``cj`` [pixels]; ``n`` = ⌊N*⌋ and ``frac`` = N* − ⌊N*⌋. Returns, flat over the
    positions: Σw over the contact (with the fraction of the next pixel), the first-contact
    height z0 [m] and the level z0 − δ of the penetrated sphere [m].
    """
    # a priori search radius: s(r) <= range(h) + s(rho*), rho* holding N*+1 pixels
    rho = math.sqrt((n + 2) * dx * dy / math.pi) + math.hypot(dx, dy)
    s_rho = float(sag(np.array(min(rho, radius) ** 2), radius, shape))
    reach = float(np.ptp(h)) + s_rho
    r_max = radius if reach >= radius else math.sqrt(min(2 * radius * reach, radius**2))
    if shape == "paraboloid":
        r_max = min(math.sqrt(2 * radius * reach), radius)
    ux = min(math.ceil(r_max / dx), ci)
    uy = min(math.ceil(r_max / dy), cj)
    ii = np.asarray(ii, dtype=np.int64)
    jj = np.asarray(jj, dtype=np.int64)
    bx, by = (block, block) if np.isscalar(block) else block  # type: ignore[misc]
    bx, by = max(1, int(bx)), max(1, int(by))
    sx, sy = (superblock, superblock) if np.isscalar(superblock) else superblock  # type: ignore[misc]
    sx, sy = bx * max(1, int(sx)), by * max(1, int(sy))
    # sag at every integer pixel offset a window can hold, as the reference computes it
    ea = ux + (min(sx, ii.size) - 1) * stride
    eb = uy + (min(sy, jj.size) - 1) * stride
    oa = np.arange(ea + 1) * dx
    ob = np.arange(eb + 1) * dy
    table = np.ascontiguousarray(sag(oa[:, None] ** 2 + ob[None, :] ** 2, radius, shape))
    # the same sag mirrored along the columns: mirror[a, eb + d] = table[a, |d|], so that along
    # a row of pixels the sag of consecutive columns is read contiguously
    mirror = np.ascontiguousarray(np.concatenate([table[:, :0:-1], table], axis=1))
    grid_w = np.empty((ii.size, jj.size))
    grid_z = np.empty_like(grid_w)
    grid_l = np.empty_like(grid_w)
    _bearing_kernel(
        np.ascontiguousarray(h, dtype=np.float64),
        np.ascontiguousarray(w, dtype=np.float64),
        ii,
        jj,
        ux,
        uy,
        min(ux, math.ceil(rho / dx)),
        min(uy, math.ceil(rho / dy)),
        float(np.max(h)),
        block_max(h) if bmax is None else bmax,
        table,
        mirror,
        n,
        frac,
        bx,
        by,
        sx,
        sy,
        grid_w,
        grid_z,
        grid_l,
    )
    return grid_w.ravel(), grid_z.ravel(), grid_l.ravel()


def block_max(h: np.ndarray) -> np.ndarray:
    """The largest height of every row's blocks of _CHUNK columns (block jb: columns
    jb·_CHUNK … jb·_CHUNK + _CHUNK − 1; the last one padded with −inf)."""
    nx, ny = h.shape
    nb = -(-ny // _CHUNK)
    pad = np.full((nx, nb * _CHUNK), -np.inf)
    pad[:, :ny] = h
    return np.ascontiguousarray(pad.reshape(nx, nb, _CHUNK).max(axis=2))


# ---------------------------------------------------------------------------------------------
# Compiled kernel. Why numba: the exact search is a selection (the (N*+1)-th largest F) over a
# few hundred candidates per position, repeated 5 million times in the target case; in NumPy
# every step (bounds, F, partition, masked sums) is a separate pass over a temporary, and the
# best vectorised version measured (tiles of positions against a shared candidate list, value
# partition, batched masked sums) stayed at ~45 µs per position under load, 4× short of the
# target. A loop that computes F from a sag table and runs an in-place quickselect touches each
# candidate twice and releases the GIL, so ``bearing_sweep`` threads use both cores.
# ---------------------------------------------------------------------------------------------


@numba.njit(cache=True, nogil=True)
def _bearing_kernel(
    h: np.ndarray,
    w: np.ndarray,
    ii: np.ndarray,
    jj: np.ndarray,
    ux: int,
    uy: int,
    uci: int,
    ucj: int,
    h_max: float,
    bmax: np.ndarray,
    table: np.ndarray,
    mirror: np.ndarray,
    n: int,
    frac: float,
    bx: int,
    by: int,
    sx: int,
    sy: int,
    out_w: np.ndarray,
    out_z: np.ndarray,
    out_l: np.ndarray,
) -> None:  # pragma: no cover - jit
    """The pruned exact search of the module docstring for every position ii × jj.

    ``table[a, b]`` is the sag at the pixel offset (a, b) (+inf outside the footprint), so F is
    h − table[|Δi|, |Δj|], the reference's arithmetic. Super-tiles of sx × sy positions scan
    their window once (step 1); tiles of bx × by positions filter the super-tile's list with
    their own bounds (step 2); each position selects from its tile's list (step 3)."""
    n_i = ii.size
    n_j = jj.size
    # thresholds fn1 found so far: the guess for a position is the plane through its left,
    # upper and upper-left neighbours (all done before it in this loop order); the bracket
    # half-width follows the recent guess errors
    thr = np.empty((n_i, n_j))
    # the mirrored sag as one flat row-major array: the sag at row offset a and column offset
    # d is mflat[a * w_mir + c_mir + d]
    w_mir = mirror.shape[1]
    c_mir = (w_mir - 1) // 2
    mflat = mirror.ravel()
    err = -1.0
    for si in range(0, n_i, sx):
        se = min(si + sx, n_i)
        p0i = ii[si]
        p1i = ii[se - 1]
        for sj in range(0, n_j, sy):
            sje = min(sj + sy, n_j)
            p0j = jj[sj]
            p1j = jj[sje - 1]
            # step 1: the super-tile's window, bounds at the extreme distances
            i0 = p0i - ux
            i1 = p1i + ux + 1
            j0 = p0j - uy
            j1 = p1j + uy + 1
            size = (i1 - i0) * (j1 - j0)
            buf = np.empty(3 * size)  # (and two scratch copies for the selections)
            # a first lower bound L0 of τ from the core (the super-tile grown by uci, ucj,
            # which holds more than N*+1 pixels); the window's (N*+1)-th largest lower bound
            # is ≥ L0, so only the window pixels with a lower bound ≥ L0 enter the selection
            k = 0
            for i in range(max(i0, p0i - uci), min(i1, p1i + uci + 1)):
                dmi = max(abs(i - p0i), abs(i - p1i))
                for j in range(max(j0, p0j - ucj), min(j1, p1j + ucj + 1)):
                    dmj = max(abs(j - p0j), abs(j - p1j))
                    buf[k] = h[u8(i), u8(j)] - table[u8(dmi), u8(dmj)]
                    k += 1
            low0 = _kth_largest(buf, k, n + 1, k, 2 * k)
            # a pixel a rows beyond the super-tile has F ≤ max h − s(a·dx) for all its
            # positions: the window shrinks to the rows and columns where that reaches L0
            ra = 0
            while ra < ux and h_max - table[ra + 1, 0] >= low0:
                ra += 1
            rb = 0
            while rb < uy and h_max - table[0, rb + 1] >= low0:
                rb += 1
            i0 = p0i - ra
            i1 = p1i + ra + 1
            j0 = p0j - rb
            j1 = p1j + rb + 1
            size = (i1 - i0) * (j1 - j0)
            # (both scans skip a block of _CHUNK columns whose largest h cannot reach the
            # level they keep: the same pixels are kept, in the same order)
            midj = (p0j + p1j) // 2
            k = 0
            for i in range(i0, i1):
                dmi = max(abs(i - p0i), abs(i - p1i))
                for jb in range(j0 // _CHUNK, (j1 - 1) // _CHUNK + 1):
                    ja = max(j0, jb * _CHUNK)
                    je = min(j1, jb * _CHUNK + _CHUNK)
                    jc = min(max(midj, ja), je - 1)
                    if bmax[i, jb] - table[dmi, max(abs(jc - p0j), abs(jc - p1j))] < low0:
                        continue
                    for j in range(ja, je):
                        dmj = max(abs(j - p0j), abs(j - p1j))
                        v = h[u8(i), u8(j)] - table[u8(dmi), u8(dmj)]
                        buf[k] = v
                        k += v >= low0
            tau = _kth_largest(buf, k, n + 1, k, 2 * k)
            c_i = np.empty(size, np.int64)
            c_j = np.empty(size, np.int64)
            c_h = np.empty(size)
            c_w = np.empty(size)
            nc = 0
            for i in range(i0, i1):
                dni = max(0, p0i - i, i - p1i)
                for jb in range(j0 // _CHUNK, (j1 - 1) // _CHUNK + 1):
                    ja = max(j0, jb * _CHUNK)
                    je = min(j1, jb * _CHUNK + _CHUNK)
                    jc = min(max(midj, ja), je - 1)
                    if bmax[i, jb] - table[dni, max(0, p0j - jc, jc - p1j)] < tau:
                        continue
                    for j in range(ja, je):
                        dnj = max(0, p0j - j, j - p1j)
                        hv = h[u8(i), u8(j)]
                        if hv - table[u8(dni), u8(dnj)] >= tau:
                            c_i[nc] = i
                            c_j[nc] = j
                            c_h[nc] = hv
                            c_w[nc] = w[u8(i), u8(j)]
                            nc += 1
            low = np.empty(3 * nc)
            t_i = np.empty(nc, np.int64)
            t_j = np.empty(nc, np.int64)
            t_h = np.empty(nc)
            t_w = np.empty(nc)
            band = np.empty(3 * nc)  # the band and two scratch copies for its selection
            band_w = np.empty(nc)
            # chunks: at most one per candidate plus one per row of the window
            size_ch = nc + (i1 - i0) + 1
            ch_i = np.empty(size_ch, np.int64)
            ch_j0 = np.empty(size_ch, np.int64)
            ch_j1 = np.empty(size_ch, np.int64)
            ch_lo = np.empty(size_ch)
            ch_hi = np.empty(size_ch)
            ch_w = np.empty(size_ch)
            bulk = np.empty(size_ch, np.int64)
            ch_r = np.empty(size_ch, np.int64)
            # the chunks' heights and slope factors, copied contiguously: step 3 reads them
            # for every position of the tile, and the rows of the map they come from are far
            # apart in memory
            ch_hv = np.empty((size_ch, _CHUNK))
            ch_wv = np.empty((size_ch, _CHUNK))
            res = np.empty(6)
            seed = np.empty(2, np.int64)
            for ti in range(si, se, bx):
                te = min(ti + bx, se)
                q0i = ii[ti]
                q1i = ii[te - 1]
                for tj in range(sj, sje, by):
                    tje = min(tj + by, sje)
                    q0j = jj[tj]
                    q1j = jj[tje - 1]
                    # step 2: the tile's candidates. The tile's lower bounds are ≥ the
                    # super-tile's, whose (N*+1)-th largest is τ: only those ≥ τ compete
                    kl = 0
                    for c in range(nc):
                        gi = c_i[c]
                        gj = c_j[c]
                        dmi = max(abs(gi - q0i), abs(gi - q1i))
                        dmj = max(abs(gj - q0j), abs(gj - q1j))
                        v = c_h[c] - table[u8(dmi), u8(dmj)]
                        low[kl] = v
                        kl += v >= tau
                    tau_t = _kth_largest(low, kl, n + 1, kl, 2 * kl)
                    m = 0
                    for c in range(nc):
                        gi = c_i[c]
                        gj = c_j[c]
                        dni = max(0, q0i - gi, gi - q1i)
                        dnj = max(0, q0j - gj, gj - q1j)
                        if c_h[c] - table[u8(dni), u8(dnj)] >= tau_t:
                            t_i[m] = gi
                            t_j[m] = gj
                            t_h[m] = c_h[c]
                            t_w[m] = c_w[c]
                            m += 1
                    # the tile's candidates as row spans cut into chunks of at most _CHUNK
                    # pixels (raster order), each with its least and largest h and its Σw:
                    # step 3 bounds F over a chunk by the sag at its nearest and farthest
                    # columns, takes whole chunks that lie above or below the threshold's
                    # bracket at once and reads the others contiguously (pixels of a span
                    # that are not candidates have F < τ_t and never count)
                    nch = 0
                    c = 0
                    while c < m:
                        gi = t_i[c]
                        j0 = t_j[c]
                        while c + 1 < m and t_i[c + 1] == gi:
                            c += 1
                        j1 = t_j[c] + 1
                        c += 1
                        hrow = h[gi]
                        wrow = w[gi]
                        for k0 in range(j0, j1, _CHUNK):
                            k1 = min(k0 + _CHUNK, j1)
                            lo_h = np.inf
                            hi_h = -np.inf
                            sw = 0.0
                            for gj in range(k0, k1):
                                lo_h = min(lo_h, hrow[gj])
                                hi_h = max(hi_h, hrow[gj])
                                sw += wrow[gj]
                                ch_hv[nch, gj - k0] = hrow[gj]
                                ch_wv[nch, gj - k0] = wrow[gj]
                            ch_i[nch] = gi
                            ch_j0[nch] = k0
                            ch_j1[nch] = k1
                            ch_lo[nch] = lo_h
                            ch_hi[nch] = hi_h
                            ch_w[nch] = sw
                            nch += 1
                    n_span = 0
                    for c in range(nch):
                        n_span += ch_j1[c] - ch_j0[c]
                    if band_w.size < n_span:
                        band = np.empty(3 * n_span)
                        band_w = np.empty(n_span)
                    # step 3: exact selection for every position of the tile
                    seed[0] = -1
                    for a in range(ti, te):
                        pi = ii[a]
                        # where each chunk's row of the sag starts in the flat mirror, for the
                        # positions of this row
                        for c in range(nch):
                            ch_r[c] = abs(ch_i[c] - pi) * w_mir + c_mir
                        for b in range(tj, tje):
                            pj = jj[b]
                            # bracket the threshold near its neighbours'; if it falls
                            # outside, the pass tells on which side (res[5])
                            if a > 0 and b > 0:
                                guess = thr[a, b - 1] + thr[a - 1, b] - thr[a - 1, b - 1]
                            elif b > 0:
                                guess = thr[a, b - 1]
                            elif a > 0:
                                guess = thr[a - 1, b]
                            else:
                                guess = np.nan
                            lo, hi = tau_t, np.inf
                            if err >= 0.0 and guess == guess:
                                delta = 3.0 * err + 1e-300
                                lo, hi = max(guess - delta, tau_t), guess + delta
                            tries = 0
                            while not _band_select(
                                ch_hv, ch_wv, ch_r, ch_j0, ch_j1, ch_lo, ch_hi, ch_w, nch, bulk,
                                seed, pj,
                                mflat, n, lo, hi, band, band_w, res,
                            ):  # fmt: skip
                                # the next bracket beside the last, four times as wide (an open
                                # bracket reads every chunk on that side); open after two tries
                                tries += 1
                                wide = 4.0 * (hi - lo) if tries < 3 else np.inf
                                if res[5] > 0:
                                    lo, hi = hi, hi + wide
                                else:
                                    lo, hi = max(lo - wide, tau_t), lo
                            wsum, z0, fn, fn1 = res[0], res[1], res[2], res[3]
                            out_w[a, b] = wsum + frac * res[4]
                            out_z[a, b] = z0
                            out_l[a, b] = fn - frac * (fn - fn1)
                            thr[a, b] = fn1
                            if guess == guess:
                                e = abs(fn1 - guess)
                                err = e if err < 0.0 else 0.7 * err + 0.3 * e
