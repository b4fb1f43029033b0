"""The selections of the bearing model's compiled search (:mod:`skisnow.micro._bearing_kernel`).

Step 3 of that search for one position (Scherge et al. 2021, eq. 5–7): the threshold F of the
(⌊N*⌋+1)-th largest pixel by a branch-free selection, from one pass over the tile's candidates
that counts the pixels above a bracket and gathers the band inside it. In a module of its own
(numba, GIL released) so that the kernel's module stays readable.
"""

from __future__ import annotations

import numba
import numpy as np

__all__ = ["_band_select", "_kth_largest"]

#: an unsigned index type: numba skips the wraparound of negative indices for it
u8 = np.uint64


@numba.njit(cache=True, nogil=True)
def _kth_largest(
    a: np.ndarray, m: int, k: int, s1: int, s2: int
) -> float:  # pragma: no cover - jit
    """The k-th largest of a[:m] (k = 1: the maximum), a[:m] left as it is; a[s1 : s1 + m] and
    a[s2 : s2 + m] are scratch (disjoint from a[:m] and from each other).

    Quickselect with a branch-free partition: each round copies its elements into the next
    scratch, those above the pivot packed from the front and those below from the back (every
    element stored at both ends, the counters advanced by the comparisons). The data-dependent
    branches of an in-place partition (Wirth's, used before), mispredicted about every other
    element, are gone. The value returned is the k-th largest whatever the algorithm."""
    src = 0
    dst = s1
    nxt = s2
    while True:
        x = a[u8(src + (m >> 1))]
        i = dst
        j = dst + m - 1
        for e in range(src, src + m):
            v = a[u8(e)]
            a[u8(i)] = v
            a[u8(j)] = v
            i += v > x
            j -= v < x
        ng = i - dst
        nl = dst + m - 1 - j
        if k <= ng:
            src = dst
            m = ng
        elif k <= m - nl:
            return x
        else:
            k -= m - nl
            src = j + 1
            m = nl
        dst, nxt = nxt, dst


@numba.njit(cache=True, nogil=True)
def _band_select(
    ch_hv: np.ndarray,
    ch_wv: np.ndarray,
    ch_r: np.ndarray,
    ch_j0: np.ndarray,
    ch_j1: np.ndarray,
    ch_lo: np.ndarray,
    ch_hi: np.ndarray,
    ch_w: np.ndarray,
    nch: int,
    bulk: np.ndarray,
    seed: np.ndarray,
    pj: int,
    mflat: np.ndarray,
    n: int,
    g_lo: float,
    g_hi: float,
    band: np.ndarray,
    band_w: np.ndarray,
    res: np.ndarray,
) -> bool:  # pragma: no cover - jit
    """Exact contact of the position (pi, pj) from the tile's candidates (chunks of row
    spans), if its threshold fn1 (the (n+1)-th largest F) lies in [g_lo, g_hi]; returns False
    otherwise.

    A chunk whose F is bounded below g_lo is skipped, one bounded above g_hi is counted whole
    (its pixels are all in the contact); the others are read pixel by pixel in one branch-free
    pass that sums the pixels above g_hi and gathers the band [g_lo, g_hi] in raster order. The
    selection runs on the band only. ``res`` receives (Σw over the n largest, z0 = max F, n-th
    largest F, fn1, w of the (n+1)-th pixel)."""
    khi = 0
    kb = 0
    nb = 0
    w_hi = 0.0
    z_hi = -np.inf
    fmin_hi = np.inf
    for c in range(nch):
        rb = ch_r[c] - pj  # the sag at the chunk's pixel column gj is mflat[rb + gj]
        j0 = ch_j0[c]
        j1 = ch_j1[c]
        # the sag is least at the chunk's column nearest pj, largest at its farthest end
        jn = min(max(pj, j0), j1 - 1)
        jf = j0 if pj - j0 > j1 - 1 - pj else j1 - 1
        if ch_hi[c] - mflat[u8(rb + jn)] < g_lo:
            continue
        if ch_lo[c] - mflat[u8(rb + jf)] > g_hi:
            khi += j1 - j0
            w_hi += ch_w[c]
            bulk[nb] = c
            nb += 1
            continue
        hrow = ch_hv[c]
        wrow = ch_wv[c]
        base = rb + j0
        for t in range(j1 - j0):
            ut = np.uint64(t)
            v = hrow[ut] - mflat[u8(base + t)]
            wv = wrow[ut]
            hi = v > g_hi
            khi += hi
            w_hi += wv if hi else 0.0
            z_hi = max(z_hi, v)
            fmin_hi = min(fmin_hi, v if hi else np.inf)
            ukb = np.uint64(kb)
            band[ukb] = v
            band_w[ukb] = wv
            kb += (not hi) and v >= g_lo
    if khi > n or khi + kb < n + 1:
        res[5] = 1.0 if khi > n else -1.0
        return False
    # the largest F (first contact) may lie in a chunk counted whole: read those that can hold
    # it. The pixel where the previous position found it (seed: chunk, offset) is a first
    # guess that prunes most of them (the result is the maximum whatever the guess)
    cs = seed[0]
    if cs >= 0:
        z_hi = max(z_hi, ch_hv[cs, seed[1]] - mflat[ch_r[cs] - pj + ch_j0[cs] + seed[1]])
    for k in range(nb):
        c = bulk[k]
        rb = ch_r[c] - pj
        j0 = ch_j0[c]
        j1 = ch_j1[c]
        if ch_hi[c] - mflat[rb + min(max(pj, j0), j1 - 1)] > z_hi:
            hrow = ch_hv[c]
            for t in range(j1 - j0):
                v = hrow[t] - mflat[rb + j0 + t]
                if v > z_hi:
                    z_hi = v
                    seed[0] = c
                    seed[1] = t
    fn1 = _kth_largest(band, kb, n + 1 - khi, kb, 2 * kb)
    cnt = khi
    wsum = w_hi
    fmin = fmin_hi
    w_next = 0.0
    need = -1
    for c in range(kb):
        v = band[c]
        if v > fn1:
            cnt += 1
            wsum += band_w[c]
            fmin = min(fmin, v)
    # ties at the boundary: taken in raster order, like the reference's stable sort
    need = n - cnt
    for c in range(kb):
        if band[c] == fn1:
            if need > 0:
                wsum += band_w[c]
                need -= 1
            else:
                w_next = band_w[c]
                break
    if n > 0 and cnt >= n and fmin == fmin_hi:
        # (the chunk-reading loop of the first-contact search above, repeated on purpose inside
        # this compiled kernel) the n-th largest F lies above the band: the least F above it,
        # chunks counted whole included (read those that can hold it)
        for k in range(nb):
            c = bulk[k]
            rb = ch_r[c] - pj
            j0 = ch_j0[c]
            j1 = ch_j1[c]
            jf = j0 if pj - j0 > j1 - 1 - pj else j1 - 1
            if ch_lo[c] - mflat[rb + jf] < fmin:
                hrow = ch_hv[c]
                for t in range(j1 - j0):
                    fmin = min(fmin, hrow[t] - mflat[rb + j0 + t])
    z0 = z_hi
    if n == 0 or cnt == 0:
        z0 = fn1
    fn = fn1 if (n == 0 or cnt < n) else fmin
    res[0] = wsum
    res[1] = z0
    res[2] = fn
    res[3] = fn1
    res[4] = w_next
    return True
