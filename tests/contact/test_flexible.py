"""The flexible ski on elastic snow: the beam operator against beam formulas, the coupled solve
against the virtual bench (stiff snow), the rigid solve (stiff ski) and Hetényi's free beam on a
Winkler foundation; balance laws, complementarity, refinement and bad input."""

from __future__ import annotations

import numpy as np
import pytest

from skisnow import ConvergenceError, InputError, UnsupportedLoadError
from skisnow.constants import STANDARD_GRAVITY
from skisnow.contact import (
    cantilever_compliance,
    contact_zones,
    effective_modulus,
    reference,
    snow,
    solve_contact,
    solve_flexible,
    solve_flexible_ski,
)
from skisnow.ski import cantilever_tip_deflection, get_ski, solve_beam

# ---- the beam operator ----------------------------------------------------------------------


def test_beam_operator_is_symmetric_psd_and_its_diagonal_is_exact() -> None:
    x = np.linspace(-1.0, 1.0, 161)
    op = cantilever_compliance(x, lambda xx: 40 + 20 * np.cos(2 * xx), load_position=0.137)
    k = op(np.eye(x.size))
    assert np.abs(k - k.T).max() <= 1e-12 * np.abs(k).max()
    assert np.linalg.eigvalsh(0.5 * (k + k.T)).min() >= -1e-12 * np.abs(k).max()
    assert np.allclose(np.diag(k), op.diagonal, rtol=1e-12, atol=0)
    # the compiled single-vector path is the batched one
    f = np.random.default_rng(1).normal(size=x.size)
    assert np.allclose(op(f), k @ f, rtol=1e-12, atol=1e-12 * np.abs(k @ f).max())
    # the clamp: the two halves do not see each other's loads
    rear = x < 0.137
    assert np.all(k[np.ix_(rear, ~rear)] == 0.0)


@pytest.mark.parametrize("n", [101, 201, 401])
def test_cantilever_tip_force_and_uniform_load(n: int) -> None:
    # Timoshenko & Gere: tip force w = F a²(3L − a)/(6EI), w(L) = FL³/3EI; uniform q: qL⁴/8EI.
    # Trapezoid in the moment integral: error O(Δx²), measured 5e-5·(100/(n−1))² relative for
    # the tip force and 1.0e-4·(100/(n−1))² for the uniform load; bound twice that.
    ei, ell, force = 55.0, 0.9, 7.0
    x = np.linspace(0.0, ell, n)
    op = cantilever_compliance(x, ei, load_position=0.0)
    f = np.zeros(n)
    f[-1] = force
    w = op(f)
    exact = force * x**2 * (3 * ell - x) / (6 * ei)
    bound = 2e-4 * (100 / (n - 1)) ** 2
    assert w[-1] == pytest.approx(cantilever_tip_deflection(force, ell, ei), rel=bound)
    assert np.abs(w - exact).max() <= bound * exact.max()
    # the boot plate: a uniform load over [−ℓ, ℓ] centred on the clamp, half on each side
    wb = op.boot_deflection(2 * force, 2 * ell)
    assert wb[-1] == pytest.approx(-force / ell * ell**4 / (8 * ei), rel=bound)


# ---- the coupled solve: references ----------------------------------------------------------


@pytest.mark.parametrize(("a", "n"), [(1.0, 256), (0.8, 256), (1.0, 512)])
def test_winkler_foundation_meets_hetenyi(a: float, n: int) -> None:
    # Hetényi (1946): free beam L = 2 m, EI = 50 N m², λL = 2 (the whole beam stays in contact,
    # checked on the reference), point load at a. Cells of L/n: second-order error, measured
    # 8.3e-6 (256) and 2.1e-6 (512) of the largest settlement; bound 3e-6·(512/n)².
    ell, ei, width, force = 2.0, 50.0, 0.044, 600.0
    k_line = 4 * ei * (2.0 / ell) ** 4
    ref = reference.winkler_free_beam(
        length=ell, stiffness=ei, foundation=k_line, force=force, load_position=a
    )
    x = (np.arange(n) + 0.5) * ell / n
    y = ref.deflection(x)
    assert y.min() > 0  # the load case keeps the whole beam in contact
    sol = solve_flexible(
        x - a, np.zeros(n), ei, load=force, load_position=0.0, modulus=k_line / width,
        width=width, foundation="winkler", boot_distribution="point", edge_contact="allow",
        tol=1e-12,
    )  # fmt: skip
    assert sol.converged
    assert sol.contact.contact.all()
    err = np.abs(sol.contact.displacement - y).max() / y.max()
    assert err <= 3e-6 * (512 / n) ** 2
    # the settlement is the ski sinking: gap = 0 everywhere
    assert np.allclose(-sol.shape, y, rtol=0, atol=3e-6 * (512 / n) ** 2 * y.max())


def test_hetenyi_reference_closed_form_and_equilibrium() -> None:
    for lam_l in (0.5, 2.0, 5.0):
        ell, ei = 2.0, 50.0
        k = 4 * ei * (lam_l / ell) ** 4
        ref = reference.winkler_free_beam(
            length=ell, stiffness=ei, foundation=k, force=100.0, load_position=ell / 2
        )
        assert ref.deflection(ell / 2) == pytest.approx(ref.centre_deflection_closed_form, 1e-12)
        xs = np.linspace(0, ell, 20001)
        q = k * ref.deflection(xs)
        assert np.trapezoid(q, xs) == pytest.approx(100.0, rel=1e-7)
        assert np.trapezoid(q * (xs - ell / 2), xs) == pytest.approx(0.0, abs=1e-7 * 100 * ell)
        assert np.allclose(ref.deflection(np.array([0.0, ell]), 2), 0.0, atol=1e-9)


def test_stiff_snow_reproduces_the_virtual_bench() -> None:
    # E' → ∞ (1e13 Pa: a few nm of snow displacement): the bent ski is the beam on the stone.
    # The bench's nodal contact converges as its mesh is refined (measured 0.16 µm at 2000
    # elements for this case, 4.6 → 1.0 → 0.5 µm for the classic at 1000/2000/4000).
    ski = get_ski("skate")
    mass, xm = 30.0, -0.12
    bench = solve_beam(ski, mass=mass, load_position=xm, n_elements=2000)
    sol = solve_flexible_ski(
        ski, load=mass * STANDARD_GRAVITY, load_position=xm, modulus=1e13, n_points=4096
    )
    assert sol.converged
    assert sol.penetration < 0.05e-6
    assert np.abs(sol.shape - bench.sample(sol.x)).max() < 1e-6


@pytest.mark.parametrize("model", ["strip", "surface"])
def test_stiff_ski_reproduces_the_rigid_solve(model: str) -> None:
    ski = get_ski("classic")
    n = 512
    edges = np.linspace(ski.x_tail, ski.x_tip, n + 1)
    x = 0.5 * (edges[1:] + edges[:-1])
    z0 = ski.free_camber(x)
    e = effective_modulus(snow(50e6))
    load = 40 * STANDARD_GRAVITY
    kw = dict(load=load, load_position=-0.1, modulus=e, width=ski.width, model=model, tol=1e-10)
    rigid = solve_contact(x, z0, n_across=4, **kw)  # type: ignore[arg-type]
    flex = solve_flexible(x, z0, np.inf, n_across=4, **kw)  # type: ignore[arg-type]
    assert np.abs(flex.contact.pressure - rigid.pressure).max() <= 1e-6 * rigid.pressure.max()
    assert flex.contact.translation == pytest.approx(rigid.translation, rel=1e-6)
    # a very stiff but finite ski converges to it
    stiff = solve_flexible(x, z0, ski.stiffness(x) * 1e6, n_across=4, **kw)  # type: ignore[arg-type]
    assert np.abs(stiff.contact.pressure - rigid.pressure).max() <= 1e-3 * rigid.pressure.max()


# ---- the coupled solve: laws and refinement -------------------------------------------------


@pytest.mark.parametrize(
    ("name", "mass", "xm", "e_snow", "model"),
    [
        ("classic", 60.0, -0.07, 20e6, "strip"),
        ("classic", 60.0, -0.07, 400e6, "strip"),
        ("skate", 35.0, -0.12, 100e6, "strip"),
        ("classic", 45.0, -0.12, 50e6, "surface"),
    ],
)
def test_balance_and_complementarity(
    name: str, mass: float, xm: float, e_snow: float, model: str
) -> None:
    ski = get_ski(name)
    load = mass * STANDARD_GRAVITY
    sol = solve_flexible_ski(
        ski, load=load, load_position=xm, modulus=effective_modulus(snow(e_snow)),
        n_points=1024, model=model, n_across=4, tol=1e-10,
    )  # fmt: skip
    c = sol.contact
    assert sol.converged
    assert c.total_force == pytest.approx(load, rel=1e-9)
    assert abs(c.total_moment) <= 1e-9 * load * ski.length
    assert np.all(c.pressure >= 0)
    u_scale = float(c.displacement.max())
    assert c.gap.min() >= -1e-6 * u_scale
    assert np.abs(c.gap[c.contact]).max() <= 1e-6 * u_scale
    assert sol.complementarity <= 1e-6
    # the bent ski: free camber + bending, positioned by δ and θ; it sinks as deep as the snow
    assert sol.penetration == pytest.approx(u_scale, rel=1e-5)
    # beam equilibrium through the clamp: the beam's reaction at the binding vanishes, i.e. the
    # contact force on each half balances the boot load on that half about the clamp — checked
    # through the identity Σ (x − x_m) q dx = 0 (moment) and Σ q dx = W (force) above


@pytest.mark.parametrize(("name", "mass", "xm", "e_snow"), [
    ("classic", 30.0, -0.12, None), ("skate", 30.0, -0.12, 100e6), ("classic", 60.0, -0.07, 20e6),
])  # fmt: skip
def test_candidate_iteration_gives_the_whole_grid_answer(
    name: str, mass: float, xm: float, e_snow: float | None
) -> None:
    # the candidate cells with dense blocks (used at >= 1024 stations) against the whole grid;
    # the pressure is fixed to ~1e4 × the gap tolerance, so both are solved to 1e-11
    ski = get_ski(name)
    e = effective_modulus(snow(e_snow)) if e_snow else 1.953e9
    out = [
        solve_flexible_ski(
            ski,
            load=mass * STANDARD_GRAVITY,
            load_position=xm,
            modulus=e,
            n_points=2048,
            candidates=c,
            tol=1e-11,
        )
        for c in (True, False)
    ]
    a, b = (s.contact for s in out)
    assert np.array_equal(a.contact, b.contact)
    assert np.abs(a.pressure - b.pressure).max() <= 1e-6 * b.pressure.max()


def _synthetic_ski(n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A 2 m ski built here (not a shipped one): a camber pocket with a waviness, EI varying
    1.6x along the ski."""
    x = np.linspace(-1.0, 1.0, n)
    z0 = 2e-3 * (1 - x**2) ** 2 + 2e-4 * np.sin(7 * x)
    ei = 40.0 + 60.0 * np.cos(1.4 * x) ** 2
    return x, z0, ei


@pytest.mark.parametrize(("dense_limit", "warm"), [(None, False), (0, False), (None, True)])
def test_active_set_path_gives_the_mprgp_answer(
    dense_limit: int | None, warm: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    # the primal–dual active-set steps on nested grids (the default at >= 1024 stations) and,
    # with the dense limit at 0, MPRGP started from their coarse solution, against the
    # whole-grid MPRGP (candidates=False): the MPRGP answers approach the new one as MPRGP's
    # tolerance shrinks, and the new one meets the KKT conditions to round-off; ``warm``: with a
    # lighter skier's pressure as the initial pressure (as in a load cycle)
    import skisnow.contact._flexible_pdas as pdas

    if dense_limit is not None:
        monkeypatch.setattr(pdas, "_PDAS_MAX_CELLS", dense_limit)
    x, z0, ei = _synthetic_ski(2048)
    load = 600.0
    kw = dict(load=load, load_position=-0.05, modulus=effective_modulus(snow(200e6)), width=0.045)
    start = None
    if warm:
        start = solve_flexible(x, z0, ei, **{**kw, "load": 0.8 * load}).contact.pressure
    new = solve_flexible(x, z0, ei, tol=1e-12, initial_pressure=start, **kw)
    c = new.contact
    assert new.converged
    assert ("active set" in c.message) == (dense_limit is None)
    assert c.total_force == pytest.approx(load, rel=1e-9)
    assert abs(c.total_moment) <= 1e-9 * load * 2.0
    assert np.all(c.pressure >= 0)
    # the stopping rule of solve_flexible: 1e-12 of the camber range plus the displacement
    rule = 1e-12 * (np.ptp(c.height) + float(c.displacement.max()))
    assert c.gap.min() >= -rule
    assert np.abs(c.gap[c.contact]).max() <= rule
    assert new.complementarity <= 1e-10
    dev = []
    for tol in (1e-10, 1e-12):
        old = solve_flexible(x, z0, ei, candidates=False, tol=tol, **kw).contact
        assert "active set" not in old.message
        dev.append(np.abs(c.pressure - old.pressure).max() / old.pressure.max())
    assert np.array_equal(c.contact, old.contact)
    if dense_limit is None:  # exact to round-off: MPRGP's error shrinks with its tolerance
        assert dev[1] < 0.1 * dev[0]
    assert dev[1] <= 1e-6


def test_beam_block_matches_the_operator() -> None:
    x = np.linspace(-1.0, 1.0, 161)
    op = cantilever_compliance(x, lambda xx: 40 + 20 * np.cos(2 * xx), load_position=0.137)
    k = op(np.eye(x.size))
    cells = np.sort(np.random.default_rng(2).choice(x.size, 60, replace=False))
    scale = np.abs(k).max()
    assert np.abs(op.block(cells) - k[np.ix_(cells, cells)]).max() <= 1e-12 * scale
    low = op.block(cells, lower_only=True)
    assert np.abs(np.tril(low) - np.tril(k[np.ix_(cells, cells)])).max() <= 1e-12 * scale


def test_refinement_converges() -> None:
    ski = get_ski("classic")
    e = effective_modulus(snow(20e6))
    pen, lengths, shares = [], [], []
    for n in (512, 1024, 2048, 4096):
        sol = solve_flexible_ski(ski, load=60 * STANDARD_GRAVITY, load_position=-0.07,
                                 modulus=e, n_points=n)  # fmt: skip
        z = contact_zones(sol.contact, kick_zone=ski.kick_zone)
        pen.append(sol.contact.translation)
        lengths.append((z.total.length, z.kick.length))
        shares.append(z.kick.load_share)
    # the approach δ (a smooth functional) converges monotonically, at least first order
    # (measured steps 1.2e-8, 6.0e-9, 9.4e-10 m)
    steps = np.abs(np.diff(pen))
    assert np.all(steps[1:] <= 0.6 * steps[:-1])
    assert steps[-1] < 1e-6 * pen[-1]
    # zone lengths are resolved to a couple of cells of each grid, the load share to 1 %
    cell = ski.length / np.array([512, 1024, 2048])
    assert np.all(np.abs(np.array(lengths[:-1]) - lengths[-1]).max(axis=1) <= 2.5 * cell)
    assert np.abs(np.array(shares[:-1]) - shares[-1]).max() < 0.01


def test_flexible_departs_from_rigid_on_soft_snow() -> None:
    # The classic, 60 kg at −70 mm: on 20 MPa the kick zone carries much less of the load when
    # the ski bends on the snow (a dense reference reported 48 % rigid against 30 % flexible).
    ski = get_ski("classic")
    n = 1024
    load = 60 * STANDARD_GRAVITY
    edges = np.linspace(ski.x_tail, ski.x_tip, n + 1)
    x = 0.5 * (edges[1:] + edges[:-1])
    h = solve_beam(ski, mass=60.0, load_position=-0.07).sample(x)
    e = effective_modulus(snow(20e6))
    rigid = contact_zones(
        solve_contact(x, h, load=load, load_position=-0.07, modulus=e, width=ski.width),
        kick_zone=ski.kick_zone,
    )
    flex = contact_zones(
        solve_flexible_ski(ski, load=load, load_position=-0.07, modulus=e, n_points=n).contact,
        kick_zone=ski.kick_zone,
    )
    assert rigid.kick.load_share > 0.4 and flex.kick.load_share < 0.35


@pytest.mark.parametrize(("mass", "position"), [(60, -0.07), (30, -0.07), (30, -0.12), (60, -0.21)])
def test_on_stone_the_flexible_ski_is_the_beam_on_the_plane(mass: float, position: float) -> None:
    """On a (nearly) rigid counter-surface the flexible ski must carry its load where the beam
    pressed on the rigid plane has its reactions (the same beam, the same unilateral contact):
    zone load shares within 1 point. The paper's rigid pipeline (the beam's loaded profile as
    a rigid body on the half-space) agrees with them only where the beam touches in one run of
    nodes in each glide zone and none between: with more contacts the rigid body on the stone
    is statically indeterminate and the half-space's compliance, not the beam, sets the split
    (the shipped classic of version 2 at 30 kg / −70 mm touches at four points: beam and
    flexible 50/50, rigid pipeline 57/43)."""
    ski = get_ski("classic")
    n = 1024
    load = mass * STANDARD_GRAVITY
    beam = solve_beam(ski, mass=mass, load_position=position)
    bx, r = np.asarray(beam.x), np.asarray(beam.reactions)
    k0, k1 = ski.kick_zone
    beam_shares = np.array([r[bx < k0].sum(), r[(bx >= k0) & (bx <= k1)].sum(), r[bx > k1].sum()])
    beam_shares /= load
    flex = contact_zones(
        solve_flexible_ski(
            ski, load=load, load_position=position, modulus=1e13, n_points=n
        ).contact,
        kick_zone=ski.kick_zone,
    )
    flex_shares = np.array([flex.rear.load_share, flex.kick.load_share, flex.front.load_share])
    np.testing.assert_allclose(flex_shares, beam_shares, atol=0.01)
    runs = beam.contact_intervals
    in_zone = [
        sum(1 for a, b in runs if lo <= 0.5 * (a + b) <= hi)
        for lo, hi in ((-np.inf, k0), (k0, k1), (k1, np.inf))
    ]
    if in_zone == [1, 0, 1]:  # determinate: two contact runs for two rigid-body freedoms
        edges = np.linspace(ski.x_tail, ski.x_tip, n + 1)
        x = 0.5 * (edges[1:] + edges[:-1])
        rigid = contact_zones(
            solve_contact(
                x, beam.sample(x), load=load, load_position=position, modulus=1e13,
                width=ski.width,
            ),
            kick_zone=ski.kick_zone,
        )  # fmt: skip
        rigid_shares = [rigid.rear.load_share, rigid.kick.load_share, rigid.front.load_share]
        np.testing.assert_allclose(rigid_shares, beam_shares, atol=0.01)


# ---- bad input ------------------------------------------------------------------------------


def test_bad_input_names_the_quantity() -> None:
    x = np.linspace(-1, 1, 128)
    z0 = 1e-3 * x**2
    kw = dict(load=500.0, load_position=0.0, modulus=1e8)
    ei = np.full(x.size, 50.0)
    ei[70] = -1.0
    with pytest.raises(InputError, match=r"bending stiffness EI .* x = "):
        solve_flexible(x, z0, ei, **kw)  # type: ignore[arg-type]
    ei[70] = np.nan
    with pytest.raises(InputError, match="bending stiffness EI"):
        solve_flexible(x, z0, ei, **kw)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="bending stiffness EI"):
        solve_flexible(x, z0, 0.0, **kw)  # type: ignore[arg-type]
    with pytest.raises(InputError, match=r"snow modulus.*E'"):
        solve_flexible(x, z0, 50.0, load=500.0, load_position=0.0, modulus=20.0)
    with pytest.raises(InputError, match="snow modulus"):
        solve_flexible(x, z0, 50.0, load=500.0, load_position=0.0, modulus=np.inf)
    with pytest.raises(UnsupportedLoadError, match="not on the ski"):
        solve_flexible(x, z0, 50.0, load=500.0, load_position=0.98, modulus=1e8)
    with pytest.raises(InputError, match="load"):
        solve_flexible(x, z0, 50.0, load=-1.0, load_position=0.0, modulus=1e8)


def test_load_the_free_ski_cannot_carry() -> None:
    # a load near the tip of a soft, flat ski: the contact reaches the tip
    x = np.linspace(-1, 1, 256)
    with pytest.raises(UnsupportedLoadError, match="cannot carry"):
        solve_flexible(x, 1e-3 * x**2, 1e6, load=800.0, load_position=0.9, modulus=1e8)


def test_unconverged_is_never_returned_as_converged() -> None:
    ski = get_ski("classic")
    e = effective_modulus(snow(20e6))
    with pytest.raises(ConvergenceError) as info:
        solve_flexible_ski(ski, load=600.0, load_position=-0.07, modulus=e, n_points=512,
                           max_iter=3)  # fmt: skip
    assert info.value.result is not None and not info.value.result.converged
    sol = solve_flexible_ski(ski, load=600.0, load_position=-0.07, modulus=e, n_points=512,
                             max_iter=3, raise_on_failure=False)  # fmt: skip
    assert not sol.converged and not sol.contact.converged
