"""The block network itself: wiring of Figure 3 of Kalliorinne et al. (2023), shapes, scaling,
domain guard."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from _extras import NETWORK_REASON
from skisnow import DomainWarning, InputError

jax = pytest.importorskip("jax", reason=NETWORK_REASON)
jnp = pytest.importorskip("jax.numpy")
ravel_pytree = pytest.importorskip("jax.flatten_util").ravel_pytree

from skisnow.network import (  # noqa: E402  (after the skip: they need JAX)
    Architecture,
    BlockNetwork,
    CamberNetwork,
    Domain,
    Scaling,
)
from skisnow.network._network import x64  # noqa: E402

ARCH = Architecture.from_widths("3,5,4,6,4,3")


def _member(seed: int = 0) -> BlockNetwork:
    with x64():
        return BlockNetwork(ARCH, key=jax.random.PRNGKey(seed))


def _toy_network(n_members: int = 1) -> CamberNetwork:
    scaling = Scaling(
        x_center=0.02,
        x_scale=1.0,
        mass_center=67.5,
        mass_scale=62.5,
        position_center=-0.14,
        position_scale=0.1,
        height_center=0.015,
        height_scale=0.015,
    )
    domain = Domain(
        mass_min=5.0,
        mass_max=130.0,
        position_min=-0.24,
        position_max=-0.04,
        x_min=-0.98,
        x_max=1.02,
    )
    members = tuple(_member(k) for k in range(n_members))
    return CamberNetwork(
        architecture=ARCH, scaling=scaling, domain=domain, members=members, metadata={"ski": "toy"}
    )


def test_architecture_widths_and_parameter_count():
    """Six widths in Figure 3's order; the parameter count equals the Equinox leaves' size."""
    assert ARCH.widths == (3, 5, 4, 6, 4, 3)
    with x64():
        theta, _ = ravel_pytree(_member())
    assert theta.size == ARCH.n_parameters()
    assert theta.dtype == jnp.float64
    with pytest.raises(InputError, match="six integers"):
        Architecture.from_widths("3,5,4")
    with pytest.raises(InputError, match="positive"):
        Architecture.from_widths([3, 5, 0, 6, 4, 3])


def test_layers_per_block_as_in_figure_3():
    """1 load layer on (m, x_m); 3 collapse layers, the first on x + load features; 2 camber
    layers, the first on x alone; a linear prediction layer on collapse + camber outputs."""
    m = _member()
    assert m.load.weight.shape == (3, 2)
    assert [c.weight.shape for c in m.collapse] == [(5, 1 + 3), (4, 5), (6, 4)]
    assert [c.weight.shape for c in m.camber] == [(4, 1), (3, 4)]
    assert m.prediction.weight.shape == (1, 6 + 3)


def test_camber_block_sees_x_only():
    """The camber block's output and its parameters' influence do not depend on (m, x_m).

    (a) Its output on an x grid is the same for every load case (it takes no load input).
    (b) ∂h/∂m and ∂h/∂x_m do not depend on the camber block's weights: the mixed derivative
        ∂²h/∂m∂θ_camber is exactly zero, while ∂²h/∂m∂θ_collapse is not.
    """
    m = _member()
    with x64():
        xs = jnp.linspace(-1, 1, 7)
        # (a) all load cases share the same camber features: the full output changes with load
        # only through the collapse path.
        out = m.grid(xs, jnp.array([-0.5, 0.3]), jnp.array([0.2, -0.9]))
        assert out.shape == (2, 7)

        def load_sensitivity(model):
            # Σ_x (∂h/∂m + ∂h/∂x_m) at one load case
            def total(mp):
                ones = jnp.ones_like(xs)
                return model.points(xs, mp[0] * ones, mp[1] * ones).sum()

            return jax.grad(total)(jnp.array([0.1, -0.3])).sum()

        g = jax.grad(load_sensitivity)(m)
    camber_grads = [np.asarray(layer.weight) for layer in g.camber] + [
        np.asarray(layer.bias) for layer in g.camber
    ]
    assert all(np.all(a == 0.0) for a in camber_grads)
    assert np.any(np.asarray(g.collapse[0].weight) != 0.0)
    # and the load does change the output (the collapse path is live)
    out = np.asarray(out)
    assert np.max(np.abs(out[0] - out[1])) > 0


def test_grid_equals_points():
    """The grid evaluation (camber block once per x, load block once per case) is the pointwise
    network evaluated at every (case, x) pair, to round-off."""
    m = _member(1)
    with x64():
        xs = jnp.linspace(-1, 1, 11)
        ms = jnp.array([-1.0, 0.0, 0.7])
        ps = jnp.array([0.5, -0.2, 1.0])
        grid = m.grid(xs, ms, ps)
        pts = m.points(jnp.tile(xs, 3), jnp.repeat(ms, xs.size), jnp.repeat(ps, xs.size)).reshape(
            3, -1
        )
    np.testing.assert_allclose(np.asarray(grid), np.asarray(pts), rtol=0, atol=1e-14)


def test_scaling_round_trip_and_range():
    """mapminmax: data land on [-1, 1] (to round-off, 1e-15); scale → unscale is the identity
    to round-off (a few ulp of h)."""
    rng = np.random.default_rng(0)
    x = rng.uniform(-0.9, 1.1, 200)
    m = rng.uniform(5, 130, 200)
    p = rng.uniform(-0.24, -0.04, 200)
    h = rng.uniform(0, 0.035, 200)
    s = Scaling.from_data(x, m, p, h)
    for u in (*s.scale_inputs(x, m, p), s.scale_height(h)):
        assert u.min() == pytest.approx(-1.0, abs=1e-15)
        assert u.max() == pytest.approx(1.0, abs=1e-15)
    np.testing.assert_allclose(
        s.unscale_height(s.scale_height(h)), h, rtol=0, atol=2 * np.spacing(h.max())
    )


def test_predict_shapes_vectorised_over_load_cases():
    """(n,) for one load case, (k, n) for k cases; each row equals the single-case call."""
    net = _toy_network()
    x = np.linspace(-0.9, 1.0, 50)
    one = net.predict(x, 60.0, -0.1)
    assert one.shape == (50,)
    many = net.predict(x, np.array([60.0, 20.0, 100.0]), -0.1)
    assert many.shape == (3, 50)
    np.testing.assert_allclose(many[0], one, rtol=0, atol=1e-15)
    assert np.all(many >= 0)  # clipped: a gap is never negative


def test_domain_guard_warns_or_raises():
    """Inside the trained (m, x_m, x) range: silent. Outside: DomainWarning, or InputError on
    request, naming the offending quantity and the valid range."""
    net = _toy_network()
    x = np.linspace(-0.9, 1.0, 20)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        net.predict(x, 130.0, -0.04)  # corners of the domain are inside
    with pytest.warns(DomainWarning, match="mass 150 kg outside"):
        net.predict(x, 150.0, -0.1)
    with pytest.raises(InputError, match="load position 20 mm outside"):
        net.predict(x, 50.0, 0.02, on_domain_error="raise")
    with pytest.raises(InputError, match=r"x .* outside"):
        net.predict(np.array([1.5]), 50.0, -0.1, on_domain_error="raise")
    net.predict(x, 150.0, -0.1, on_domain_error="ignore")  # no warning (filter is 'error')


def test_predict_rejects_bad_input():
    net = _toy_network()
    with pytest.raises(InputError, match="finite"):
        net.predict(np.array([0.0, np.nan]), 50.0, -0.1)
    with pytest.raises(InputError, match="1-D"):
        net.predict(np.zeros((2, 2)), 50.0, -0.1)
    with pytest.raises(InputError, match="broadcast"):
        net.predict(np.zeros(3), np.ones(2) * 50, np.ones(3) * -0.1)


def test_ensemble_spread():
    """Spread = sample standard deviation of the members; zero for a single member."""
    x = np.linspace(-0.5, 0.5, 9)
    single = _toy_network(1)
    _, s1 = single.predict_with_spread(x, 50.0, -0.1)
    assert np.all(s1 == 0)
    ens = _toy_network(3)
    mean, spread = ens.predict_with_spread(x, 50.0, -0.1, clip=False)
    each = [
        CamberNetwork(
            architecture=ens.architecture,
            scaling=ens.scaling,
            domain=ens.domain,
            members=(m,),
        ).predict(x, 50.0, -0.1, clip=False)
        for m in ens.members
    ]
    np.testing.assert_allclose(mean, np.mean(each, axis=0), rtol=1e-13)
    np.testing.assert_allclose(spread, np.std(each, axis=0, ddof=1), rtol=1e-10)
    assert np.all(spread > 0)


def test_x64_does_not_leak():
    """Using the network leaves JAX's global float64 switch as the caller had it."""
    before = jax.config.jax_enable_x64
    _toy_network().predict(np.linspace(-0.5, 0.5, 5), 50.0, -0.1)
    assert jax.config.jax_enable_x64 == before
