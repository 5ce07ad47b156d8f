"""Mixed lubrication where the film carries the whole load (system/mixed.py, ``full_film``).

The kernels test once per call whether every slice contact has a film parameter λ >= 3, from
one bound per race (λ at the race's largest load and smallest entrainment speed), and then
compute the EHL law alone. References: the per-contact composition of the laws (film
parameter, share, mixed traction and slopes of physics/mixed.py) in a loop typed here, which
the kernels must equal bit for bit with and without the shortcut, on contact sets placed on
either side of λ = 3 and at the bound's margin; and, for a whole run, the same scene with
full-film lubrication (the share is 0 everywhere: the two models are one).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr
from numba import njit

from bearingdae import load_scene, simulate
from bearingdae.physics.mixed import (_mixed_slopes, _mixed_traction, asperity_share,
                                      film_constants, film_parameter)
from bearingdae.physics.traction import _traction_value_paper, _traction_value_slide_roll
from bearingdae.system import mixed as mx
from bearingdae.system.model import build_model
from bearingdae.system.param_vector import P_MX, P_RPI, P_RPO, P_SRU0, P_TLAW, P_W

#: yang20's contacts: 20 rollers x 10 slices x 2 races (race = index parity)
N_CONTACTS = 400


def _parameters(law):
    P = build_model(load_scene("yang20_baseline", {"physics.lubrication": "mixed",
                                                    "traction.law": law})).work_array("params")
    return (P[P_MX:].copy(), P[P_TLAW:P_SRU0 + 1].copy(), float(P[P_W]), float(P[P_RPI]),
            float(P[P_RPO]))


@njit
def _lam(q, u, M, width, Rpi, Rpo):
    """λ of every contact, one at a time (compiled, as the kernels' laws are: the same fused
    multiply-adds; physics/elementary.py)."""
    out = np.empty_like(q)
    for i in range(q.size):
        R = Rpo if i & 1 else Rpi
        k0, k1, k2 = film_constants(width, R, M[mx.M_VISC], M[mx.M_E], M[mx.M_CMIN],
                                    M[mx.M_SIGMA])
        out[i] = film_parameter(q[i], u[i], k0, k1, k2)[0]
    return out


def _contacts(rng, M, width, Rpi, Rpo, worst):
    """Loads (half of them an unloaded roller's 1e-7 N), slips, pressures and entrainment
    speeds, the speeds scaled (λ ∝ u^0.694) so that the worst case, λ at a race's largest load
    and smallest speed, is ``worst`` on the race where it is smaller."""
    loaded = rng.random(N_CONTACTS) < 0.5
    q = np.where(loaded, rng.uniform(5.0, 600.0, N_CONTACTS), 1e-7)
    v = rng.normal(0.0, 0.2, N_CONTACTS)
    p = 1.0e9 * np.sqrt(q / 100.0)
    u = rng.uniform(2.0, 6.0, N_CONTACTS)
    corner = _lam(np.array([q[0::2].max(), q[1::2].max()]),
                  np.array([u[0::2].min(), u[1::2].min()]), M, width, Rpi, Rpo)
    u = u * (worst / corner.min()) ** (1.0 / 0.694)
    return q, v, p, u


@njit
def _reference_tractions(M, T, q, p, v, u, lams):
    """The slice tractions contact by contact: EHL law, then the share of λ (``lams``) and the
    mixed traction."""
    out = np.empty_like(q)
    for i in range(q.size):
        if T[mx.T_LAW] > 0.5:
            F = _traction_value_slide_roll(q[i], v[i], u[i], T[mx.T_V], T[mx.T_SA], T[mx.T_SB],
                                           T[mx.T_SC], T[mx.T_SD], T[mx.T_SU0])
        else:
            F = _traction_value_paper(q[i], v[i], p[i], T[mx.T_V], T[mx.T_A], T[mx.T_B],
                                      T[mx.T_C], T[mx.T_D], T[mx.T_ALT] > 0.5)
        out[i] = _mixed_traction(F, q[i], v[i], asperity_share(lams[i])[0], M[mx.M_MUB],
                                 M[mx.M_VB])[0]
    return out


@njit
def _reference_slopes(M, q, v, u, o, width, Rpi, Rpo):
    """The mixed slopes contact by contact, from the EHL law's in ``o`` (changed in place)."""
    for i in range(q.size):
        R = Rpo if i & 1 else Rpi
        k0, k1, k2 = film_constants(width, R, M[mx.M_VISC], M[mx.M_E], M[mx.M_CMIN],
                                    M[mx.M_SIGMA])
        lam, lam_q, lam_u = film_parameter(q[i], u[i], k0, k1, k2)
        s, s_lam = asperity_share(lam)
        o[0, i], o[1, i], o[2, i], o[3, i] = _mixed_slopes(
            o[0, i], o[1, i], o[2, i], o[3, i], q[i], v[i], s, s_lam * lam_q, s_lam * lam_u,
            M[mx.M_MUB], M[mx.M_VB])


def _same_bits(a, b):
    return np.array_equal(np.asarray(a).view(np.int64), np.asarray(b).view(np.int64))


#: the worst-case λ of a contact set (:func:`_contacts`), and whether the kernels may take
#: the shortcut there (margin 1e-9 above 3)
REGIMES = {"full film": (3.5, True), "above the margin": (3.0 * (1.0 + 1e-6), True),
           "inside the margin": (3.0 * (1.0 + 1e-12), False), "just below 3": (2.999, False),
           "mixed": (0.6, False)}


@pytest.mark.parametrize("law", ["paper", "slide-roll"])
@pytest.mark.parametrize("regime", list(REGIMES))
def test_tractions_equal_the_contact_by_contact_laws(law, regime):
    """mixed_tractions (with its shortcut) is the per-contact composition bit for bit, on
    either side of λ = 3 and of the margin; where it takes the shortcut every contact's own λ
    is at least 3 (the bound is one); the mixed sets do have contacts below 3."""
    M, T, width, Rpi, Rpo = _parameters(law)
    worst, shortcut = REGIMES[regime]
    rng = np.random.default_rng(7)
    for _ in range(5):
        q, v, p, u = _contacts(rng, M, width, Rpi, Rpo, worst)
        lams = _lam(q, u, M, width, Rpi, Rpo)
        assert mx.full_film(M, q, u, width, Rpi, Rpo) is shortcut
        ref = _reference_tractions(M, T, q, p, v, u, lams)
        ff = u.copy()
        mx.mixed_tractions(M, T, q, p, v, ff, width, Rpi, Rpo)
        assert _same_bits(ff, ref)
        if shortcut:
            assert np.all(lams >= 3.0)
        if worst < 1.0:
            assert np.any(lams < 3.0)


@pytest.mark.parametrize("spoil", ["standstill", "unloaded", "nan load"])
def test_a_contact_outside_the_laws_range_is_computed_as_before(spoil):
    """A zero speed (λ = 0: boundary friction), a load that is not positive (the law's
    unloaded convention) or one that is not a number: the bound takes no shortcut on the first
    two, and the kernel stays the per-contact composition bit for bit in all three."""
    M, T, width, Rpi, Rpo = _parameters("paper")
    q, v, p, u = _contacts(np.random.default_rng(3), M, width, Rpi, Rpo, 4.0)
    assert mx.full_film(M, q, u, width, Rpi, Rpo)
    i = 17
    if spoil == "standstill":
        u[i] = 0.0
    elif spoil == "unloaded":
        q[i] = 0.0
    else:
        q[i] = np.nan
    lams = _lam(q, u, M, width, Rpi, Rpo)
    if spoil != "nan load":
        assert not mx.full_film(M, q, u, width, Rpi, Rpo)
    ref = _reference_tractions(M, T, q, p, v, u, lams)
    ff = u.copy()
    mx.mixed_tractions(M, T, q, p, v, ff, width, Rpi, Rpo)
    assert _same_bits(ff, ref)
    if spoil == "standstill":  # no film: the boundary friction acts there
        assert ff[i] != _traction_value_paper(q[i], v[i], p[i], T[mx.T_V], T[mx.T_A],
                                              T[mx.T_B], T[mx.T_C], T[mx.T_D], False)


@pytest.mark.parametrize("regime", list(REGIMES))
def test_slopes_equal_the_contact_by_contact_laws(regime):
    """mixed_slopes turns the EHL law's (F, dF/dV, dF/dq, dF/du) into the mixed ones contact by
    contact (share and its slopes through λ(q, u)); where the shortcut applies it leaves them."""
    M, T, width, Rpi, Rpo = _parameters("paper")
    rng = np.random.default_rng(11)
    q, v, p, u = _contacts(rng, M, width, Rpi, Rpo, REGIMES[regime][0])
    o = rng.normal(0.0, 1.0, (4, N_CONTACTS))
    ref = o.copy()
    _reference_slopes(M, q, v, u, ref, width, Rpi, Rpo)
    out = o.copy()
    mx.mixed_slopes(M, T, q, v, u, out, width, Rpi, Rpo)
    assert _same_bits(out, ref)
    lams = _lam(q, u, M, width, Rpi, Rpo)
    if np.all(lams >= 3.0):  # s = 0 everywhere, shortcut or not: the EHL law's values stay
        assert _same_bits(out, o)
    else:
        assert not REGIMES[regime][1] and not _same_bits(out, o)


def test_a_run_in_full_film_is_the_full_film_model():
    """harris36 at 5000 r/min has λ of 7-16 on every slice: with mixed lubrication switched
    on, every recorded variable equals the full-film run's, bit for bit, in the same steps."""
    w = {"numerics.warmup_cage_revolutions": 0.02, "numerics.cage_revolutions": 0.05}
    full = simulate(load_scene("paper/harris36_5000rpm", w), progress=False)
    mixed = simulate(load_scene("paper/harris36_5000rpm",
                                {**w, "physics.lubrication": "mixed"}), progress=False)
    compared = 0
    for name, var in full.data_vars.items():
        if var.dtype.kind == "f":  # (power loss: mixed lubrication adds a source)
            a, b = xr.align(var, mixed[name], join="inner")
            assert np.array_equal(a.values, b.values, equal_nan=True), name
            compared += 1
    assert compared > 50
    assert np.all(mixed.power_loss_W.sel(loss_source="asperity_friction").values == 0.0)
    steps = [json.loads(d.attrs["solver_statistics"])["steps"] for d in (full, mixed)]
    assert steps[0] == steps[1]
