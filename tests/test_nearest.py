"""morph.nearest: closest points against brute force, the certified distance bound."""

import numpy as np

from morph import nearest as nr
from tests.test_piece import _plain_eval, _random_rational_stack


def test_nearest_params_many_against_brute_force():
    """The foot found is as near as the nearest of 20001 samples (up to the samples'
    own spacing), for points near and far from random rational pieces."""
    rng = np.random.default_rng(4)
    c = _random_rational_stack(rng, 6, 4)
    pts = rng.uniform(-1.2, 1.2, (6, 15, 2))
    s = nr.nearest_params_many(c, pts)
    t = np.linspace(0, 1, 20001)
    for k in range(len(c)):
        dense = _plain_eval(c[k], t)
        brute = np.sqrt(((pts[k][:, None] - dense[None]) ** 2).sum(-1)).min(axis=1)
        got = np.hypot(*(_plain_eval(c[k], s[k]) - pts[k]).T)
        slack = np.hypot(*np.diff(dense, axis=0).T).max()
        # a sampled start may miss a far branch: count, not all must hold
        assert np.mean(got <= brute + slack) >= 0.95
        assert np.all(got >= brute - slack - 1e-12)


def test_distance_bound_many_certifies_and_is_invariant():
    """bound >= max over dense samples of |R(s) - Q(s)|, tighter with more panels,
    unchanged by translating both curves, scaled with them."""
    rng = np.random.default_rng(5)
    c = _random_rational_stack(rng, 8, 5)
    q = np.array([_plain_eval(ck, np.linspace(0, 1, 4)) for ck in c])   # 4 points as
    q[:, 1:3] += rng.normal(0, 0.05, (8, 2, 2))                          # a rough cubic
    t = np.linspace(0, 1, 4001)
    import math
    bern = np.stack([math.comb(3, i) * t ** i * (1 - t) ** (3 - i) for i in range(4)], 1)
    b0, _ = nr.distance_bound_many(c, q, 0)
    b3, _ = nr.distance_bound_many(c, q, 3)
    for k in range(len(c)):
        sampled = np.hypot(*(_plain_eval(c[k], t) - bern @ q[k]).T).max()
        assert b0[k] >= b3[k] >= sampled * (1 - 1e-12)
        assert b3[k] <= 1.5 * sampled                 # refined: close to the maximum
    shift = np.array([1e3, -2e3])
    cs = c.copy()
    cs[:, :, :2] += cs[:, :, 2:] * shift
    assert np.allclose(nr.distance_bound_many(cs, q + shift, 3)[0], b3, rtol=1e-9)
    assert np.allclose(nr.distance_bound_many(c * [7.0, 7.0, 1.0], 7.0 * q, 3)[0], 7.0 * b3,
                       rtol=1e-12)


def test_power_jets_equal_jet2_power_many_bit_for_bit():
    """PowerJets (power coefficients made once, x and y apart) gives the very values of
    piece.jet2_power_many, degrees 2 to 12, so that the Newton searches of the
    export certificate find the same feet; and the jets are right (against the
    plain evaluation and its finite differences)."""
    from morph import piece as pc

    rng = np.random.default_rng(11)
    for n in range(2, 13):
        c = _random_rational_stack(rng, 7, n)
        s = rng.uniform(0, 1, (7, 24))
        s[0, :3] = [0.0, 1.0, 0.5]
        want = pc.jet2_power_many(c, s)
        got = nr.PowerJets(c)(s)
        for w, (gx, gy) in zip(want, got):
            assert np.array_equal(w[..., 0], gx) and np.array_equal(w[..., 1], gy)
        (px, py), (dx, dy) = nr.PowerJets(c)(s, second=False)
        assert np.array_equal(px, got[0][0]) and np.array_equal(dy, got[1][1])
    c = _random_rational_stack(rng, 3, 4)
    t, h = np.linspace(0.2, 0.8, 5), 1e-6
    (px, py), (dx, dy), _ = nr.PowerJets(c)(np.tile(t, (3, 1)))
    for k in range(3):
        assert np.allclose(np.stack([px[k], py[k]], 1), _plain_eval(c[k], t), atol=1e-9)
        fd = (_plain_eval(c[k], t + h) - _plain_eval(c[k], t - h)) / (2 * h)
        assert np.allclose(np.stack([dx[k], dy[k]], 1), fd, rtol=1e-5, atol=1e-5)
