"""The primal–dual active-set steps of the flexible ski, compiled (numba), on a dense block.

The loop of :func:`skisnow.contact._flexible_pdas._active_set_steps` (Hintermüller, Ito &
Kunisch 2002, SIAM J. Optim. 13, Algorithm 1 with the force and moment balances of Kalliorinne
et al. 2023 eq. 3 kept as Lagrange multipliers) on the candidate cells S of one grid: each step
solves K_AA p_A + h_A = δ + θξ_A, Σp_A = total, Σξ_A p_A = 0 on the contact set A, computes the
gap λ on S and moves every cell whose sign is wrong. On a few hundred cells the interpreted loop
costs more than its arithmetic (~40 NumPy calls of a few µs per step); compiled, a step costs its
factorisations and products.

Successive sets differ by a few cells at the contact edges; the cells deep inside the set (I:
farther than a few cells from a cell off it) stay in contact. In the order [I, B], B = A \\ I,
the Cholesky factor of K_AA is the block factor (Golub & Van Loan 2013, Matrix Computations,
§4.2.9)

    K_AA = [L_I   0 ] [L_Iᵀ  W  ],   W = L_I⁻¹ K_IB,   L_S L_Sᵀ = K_BB − Wᵀ W,
           [Wᵀ   L_S] [ 0   L_Sᵀ]

so L_I is factored once, the column of W of a border cell once, and each step factors only the
small Schur complement: O(|I|·|B|²) a step instead of |A|³/3, with the backward stability of a
Cholesky factorisation (it is one, of K_AA reordered; a bordered update that deletes the cells
that left through multipliers is not: measured 1e-12 instead of 1e-16 on the gap). When a cell
of I leaves, I is chosen again. The factorisations and triangular solves call LAPACK and BLAS
(SciPy's ``cython_lapack``/``cython_blas``) through function pointers passed as arguments, so
the compiled code is cached on disk like the other kernels.
"""

from __future__ import annotations

import ctypes
import functools

import numba
import numpy as np

__all__ = ["CONVERGED", "CYCLE", "MAX_STEPS", "SINGULAR", "SIZE", "lapack", "pdas_dense"]

#: status codes of :func:`pdas_dense`
CONVERGED, SIZE, CYCLE, SINGULAR, MAX_STEPS = range(5)


@functools.cache
def lapack() -> tuple[object, object]:
    """(dpotrf, dtrsm) of SciPy's LAPACK and BLAS as ctypes functions (for :func:`pdas_dense`)."""
    from numba.extending import get_cython_function_address

    vp = ctypes.c_void_p
    potrf = ctypes.CFUNCTYPE(None, vp, vp, vp, vp, vp)(
        get_cython_function_address("scipy.linalg.cython_lapack", "dpotrf")
    )
    trsm = ctypes.CFUNCTYPE(None, vp, vp, vp, vp, vp, vp, vp, vp, vp, vp, vp)(
        get_cython_function_address("scipy.linalg.cython_blas", "dtrsm")
    )
    return potrf, trsm


@numba.njit(cache=True, nogil=True)
def _cholesky(potrf, a):  # pragma: no cover - compiled
    """a (n × n, C order, symmetric) → its Cholesky factor L in the lower triangle (the upper
    one is left as it was); returns LAPACK's info (0: positive definite)."""
    n = np.array([a.shape[0]], dtype=np.int32)
    info = np.zeros(1, dtype=np.int32)
    upper = np.array([ord("U")], dtype=np.uint8)
    if a.shape[0] > 0:
        # C's lower triangle is the upper one of the same memory read in Fortran order
        potrf(upper.ctypes, n.ctypes, a.ctypes, n.ctypes, info.ctypes)
    return info[0]


@numba.njit(cache=True, nogil=True)
def _triangular(trsm, factor, b, transpose):  # pragma: no cover - compiled
    """Solve L x = b (or Lᵀ x = b) in place for every row of b (k × n, C order), L the lower
    triangle of ``factor`` (n × n, C order) from :func:`_cholesky`."""
    m = np.array([factor.shape[0]], dtype=np.int32)
    k = np.array([b.shape[0]], dtype=np.int32)
    one = np.ones(1)
    if factor.shape[0] == 0 or b.shape[0] == 0:
        return
    # in Fortran order the factor is U = Lᵀ and b is n × k: L x = b is Uᵀ x = b
    chars = np.array([ord("L"), ord("U"), ord("T") if not transpose else ord("N"), ord("N")],
                     dtype=np.uint8)  # fmt: skip
    trsm(chars[0:].ctypes, chars[1:].ctypes, chars[2:].ctypes, chars[3:].ctypes, m.ctypes,
         k.ctypes, one.ctypes, factor.ctypes, m.ctypes, b.ctypes, m.ctypes)  # fmt: skip


@numba.njit(cache=True, nogil=True)
def _key(cells, index):  # pragma: no cover - compiled
    """A hash of the grid cells ``cells[index]`` (a set seen before is a cycle)."""
    key = np.uint64(1469598103934665603)
    for j in index:
        key = (key ^ np.uint64(cells[j] + 1)) * np.uint64(1099511628211)
    return key


@numba.njit(cache=True, nogil=True)
def pdas_dense(potrf, trsm, kss, h, xi, act, total, threshold, scale, max_cells, max_steps,
               cells, deep, seen, n_seen, history, n_hist):  # fmt: skip  # pragma: no cover
    """Primal–dual active-set steps on the cells S of the dense block ``kss`` (see the module).

    ``act`` (the contact set on S) is updated in place; ``seen`` holds the hashes of the sets
    solved so far (its first ``n_seen``), ``history`` the residuals (first ``n_hist``): both
    are appended to. A cell enters when λ < −``threshold``; the residual is max(|λ| on A, the
    deepest penetration off A)/``scale``. The cells farther than ``deep`` grid cells from a cell
    off A (``cells``: the grid index of each cell of S) are factored once.

    Returns (pressure on S, δ, θ, steps, status, n_seen, n_hist); the pressure is zero before
    the first solve; status :data:`CONVERGED` when the set repeats (the KKT point on S),
    :data:`SIZE` (fewer than 2 or more than ``max_cells`` cells), :data:`CYCLE`,
    :data:`SINGULAR` (K_AA not positive definite) or :data:`MAX_STEPS`.
    """
    ns = h.size
    rhs = np.empty((3, ns))  # the right-hand sides −h, 1, ξ of the solves, as rows
    for j in range(ns):
        rhs[0, j] = -h[j]
        rhs[1, j] = 1.0
        rhs[2, j] = xi[j]
    p = np.zeros(ns)
    a = 0.0
    b = 0.0
    in_inner = np.zeros(ns, dtype=np.bool_)
    inner = np.empty(0, dtype=np.int64)
    l_i = np.empty((0, 0))
    z_i = np.empty((3, 0))
    w = np.empty((ns, 0))  # rows: L_I⁻¹ K_Ib of the border cells b, by slot
    slot = np.full(ns, -1, dtype=np.int64)
    n_cols = 0
    based = False
    status = MAX_STEPS
    step = 0
    for step in range(1, max_steps + 1):
        index = np.flatnonzero(act)
        na = index.size
        if na < 2 or na > max_cells:
            status = SIZE
            step -= 1
            break
        key = _key(cells, index)
        repeated = False
        for s in range(n_seen):
            if seen[s] == key:
                repeated = True
        if repeated or n_seen >= seen.size:
            status = CYCLE
            step -= 1
            break
        seen[n_seen] = key
        n_seen += 1
        # the interior I: factored again when one of its cells has left the set
        if based:
            for j in inner:
                if not act[j]:
                    based = False
        if not based:
            count = 0
            for j in index:
                c = cells[j]
                ok = j >= deep and j + deep < ns and cells[j - deep] == c - deep
                ok = ok and cells[j + deep] == c + deep
                if ok:
                    for q in range(j - deep, j + deep + 1):
                        if not act[q]:
                            ok = False
                            break
                in_inner[j] = ok
                if ok:
                    count += 1
            for j in range(ns):
                if not act[j]:
                    in_inner[j] = False
            inner = np.flatnonzero(in_inner)
            l_i = np.empty((count, count))
            for r in range(count):
                for c in range(count):
                    l_i[r, c] = kss[inner[r], inner[c]]
            if _cholesky(potrf, l_i) != 0:
                status = SINGULAR
                step -= 1
                break
            z_i = np.empty((3, count))
            for r in range(3):
                for c in range(count):
                    z_i[r, c] = rhs[r, inner[c]]
            _triangular(trsm, l_i, z_i, False)
            w = np.empty((ns, count))
            slot[:] = -1
            n_cols = 0
            based = True
        n_i = inner.size
        border = index[~in_inner[index]]
        n_b = border.size
        # the columns of W of the cells new to the border
        n_new = 0
        for j in border:
            if slot[j] < 0:
                n_new += 1
        if n_new and n_i:
            fresh = np.empty((n_new, n_i))
            r = 0
            for j in border:
                if slot[j] < 0:
                    for c in range(n_i):
                        fresh[r, c] = kss[j, inner[c]]
                    r += 1
            _triangular(trsm, l_i, fresh, False)
            r = 0
            for j in border:
                if slot[j] < 0:
                    w[n_cols] = fresh[r]
                    slot[j] = n_cols
                    n_cols += 1
                    r += 1
        w_b = np.empty((n_b, n_i))
        if n_i:
            for r in range(n_b):
                w_b[r] = w[slot[border[r]]]
        schur = np.empty((n_b, n_b))
        for r in range(n_b):
            for c in range(n_b):
                schur[r, c] = kss[border[r], border[c]]
        if n_i and n_b:
            schur -= np.dot(w_b, w_b.T)
        if _cholesky(potrf, schur) != 0:
            status = SINGULAR
            step -= 1
            break
        # forward: z_B = L_S⁻¹ (r_B − Wᵀ z_I); back: y_B = L_S⁻ᵀ z_B, y_I = L_I⁻ᵀ (z_I − W y_B)
        z_b = np.empty((3, n_b))
        for r in range(3):
            for c in range(n_b):
                z_b[r, c] = rhs[r, border[c]]
        if n_i and n_b:
            z_b -= np.dot(z_i, w_b.T)
        _triangular(trsm, schur, z_b, False)
        _triangular(trsm, schur, z_b, True)
        y_i = z_i.copy()
        if n_i and n_b:
            y_i -= np.dot(z_b, w_b)
        _triangular(trsm, l_i, y_i, True)
        y = np.empty((3, ns))
        for c in range(n_i):
            for r in range(3):
                y[r, inner[c]] = y_i[r, c]
        for c in range(n_b):
            for r in range(3):
                y[r, border[c]] = z_b[r, c]
        # p_A = y0 + δ y1 + θ y2 with Σp_A = total, Σξp_A = 0
        s0 = s1 = s2 = t0 = t1 = t2 = 0.0
        for j in index:
            s0 += y[0, j]
            s1 += y[1, j]
            s2 += y[2, j]
            t0 += xi[j] * y[0, j]
            t1 += xi[j] * y[1, j]
            t2 += xi[j] * y[2, j]
        det = s1 * t2 - s2 * t1
        if not np.isfinite(det) or det == 0.0:
            status = SINGULAR
            step -= 1
            break
        a = ((total - s0) * t2 + s2 * t0) / det
        b = (-s1 * t0 - (total - s0) * t1) / det
        p = np.zeros(ns)
        for j in index:
            p[j] = y[0, j] + a * y[1, j] + b * y[2, j]
        lam = np.dot(kss, p)
        on = 0.0
        off = 0.0
        changed = False
        for j in range(ns):
            lam[j] += h[j] - a - b * xi[j]
            if act[j]:
                on = max(on, abs(lam[j]))
                if p[j] <= 0.0:
                    changed = True
            else:
                off = max(off, -lam[j])
                if lam[j] < -threshold:
                    changed = True
        history[n_hist] = max(on, off) / scale
        n_hist += 1
        if not changed:
            status = CONVERGED
            break
        for j in range(ns):
            if act[j]:
                if p[j] <= 0.0:
                    act[j] = False
            elif lam[j] < -threshold:
                act[j] = True
    return p, a, b, step, status, n_seen, n_hist
