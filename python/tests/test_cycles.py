"""`lg.cycles`: the three-disk repeller by certified cycles, the command line's `lorentz cycles`
with its bits, as arrays."""

from fractions import Fraction

import numpy as np
import pytest

import lorentz_gas as lg

#: The escape rate of the three-disk repeller at R:a = 6 (a = 1, speed 1), ChaosBook's value as
#: `tests/numerics/cycles.rs` quotes it.
GAMMA_R6 = 0.4103384077693464893384613078192


def test_cycles_at_r_over_a_6_give_the_known_escape_rate(cli_json):
    r = lg.cycles(side=6, radius=1, max_length=7, threads=2)
    # 2 + 1 + 2 + 3 + 6 + 9 + 18 binary prime cycles of length 1 to 7, every one certified.
    assert r.certified == 41
    assert len(r.word) == len(r.order) == len(r.period) == len(r.stability) == 41
    assert r.word.dtype.kind == "U" and list(r.word[:3]) == ["0", "1", "01"]
    assert np.all(r.certificate_radius < 1e-60) and np.all(r.cycles["certified"])
    # The two-disk cycle "0": T_p = 2(R - 2a) = 8 over its order h = 2, and Λ = +(5 + √24)
    # (the closed forms of tests/numerics/cycles.rs).
    assert r.order[0] == 2 and r.period[0] == pytest.approx(4.0, rel=1e-15)
    assert r.stability[0] == pytest.approx(5 + 24 ** 0.5, rel=1e-14)
    # The table: one row per N, the truncation error NaN at N = 1, γ within it of the known
    # value at N = 7 (plus the rounding of γ to a double), and within the 1e-12.
    assert list(r.N) == list(range(1, 8))
    assert np.isnan(r.escape_rate_error[0]) and np.all(r.escape_rate_error[1:] >= 0)
    off = abs(r.escape_rate[-1] - GAMMA_R6)
    assert off <= r.escape_rate_error[-1] + 2 * np.finfo(float).eps * GAMMA_R6
    assert off < 1e-12
    assert np.allclose(r.entropy, r.lyapunov - r.escape_rate, rtol=0, atol=1e-15)
    assert len(r.zeta_escape_rate) == 7 and r.zeta_escape_rate_error[-1] > r.escape_rate_error[-1]
    # The command line's result, bit for bit (the meta block says how, not what).
    c = cli_json("cycles", "--side", "6", "--radius", "1", "--max-length", "7")
    d = r.to_dict()
    for k in ("config", "certified", "cycles", "spectral_determinant", "zeta_function"):
        assert d[k] == c[k], k
    assert repr(r).startswith("<CyclesResult: gamma = 0.410338407769346")
    assert str(r).startswith("three-disk repeller, side R = 6, radius a = 1: 41 of 41")
    t = r.to_pandas()
    assert list(t["max_length"]) == list(range(1, 8))
    assert len(r.to_pandas("cycles")) == 41


def test_side_and_radius_are_exact_and_bad_input_is_a_value_error():
    r = lg.cycles(side="13/2", radius=Fraction(1, 2), max_length=2)
    assert r.config["side"] == "13/2" and r.config["radius"] == "1/2"
    for kwargs, needle in [
        (dict(side=2, radius=1), "side=2 is out of range: use a finite side R > 2a = 2"),
        (dict(radius=0), "radius=0 is out of range: use a finite radius a > 0"),
        (dict(side="nan"), "use a finite side R > 2a"),
        (dict(max_length=17), "use 1 to 16"),
        (dict(max_length=0), "max_length"),
        (dict(bits=64), "bits=64 is out of range: use 128 to 4096 bits"),
        (dict(side="six"), "side"),
    ]:
        with pytest.raises(ValueError, match=needle.replace("(", r"\(").replace(")", r"\)")):
            lg.cycles(**kwargs)


def test_lattice_cycles_give_d_by_cycle_averaging(cli_json):
    r = lg.cycles(w="1/10", max_length=5, msd_collisions=0, threads=2)
    assert isinstance(r, lg.LatticeCyclesResult) and r.msd is None
    # 142 certified prime cycles of length <= 5 (C6v images included), each with its winding.
    assert len(r.word) == len(r.period) == len(r.stability) == len(r.certificate_radius) == 142
    assert r.winding.shape == (142, 2) and np.all(r.certificate_radius < 1e-29)
    # The nearest-neighbour bounce AD: T = 2w, winding 0 (tests/numerics/lattice_cycles.rs).
    k = list(r.word).index("AD")
    assert r.period[k] == pytest.approx(0.2, rel=1e-15) and list(r.winding[k]) == [0, 0]
    assert list(r.N) == [1, 2, 3, 4, 5] and np.isnan(r.change[0])
    assert r.table["certified"][-1] == 142
    assert r.diffusion[-1] == pytest.approx(0.13829500, abs=1e-8)
    c = cli_json("cycles", "--w", "1/10", "--max-length", "5", "--msd-collisions", "0")
    d = r.to_dict()
    for k in ("config", "cycles", "refused", "table"):
        assert d[k] == c[k], k
    assert repr(r).startswith("<LatticeCyclesResult: D_N = 0.138295 at N = 5")
    assert str(r).startswith("triangular Lorentz gas, w = 1/10: prime cycles of length 1 to 5")
    assert len(r.to_pandas()) == 5 and len(r.to_pandas("cycles")) == 142
    for kwargs, needle in [
        (dict(w="0.31"), "w"),
        (dict(w=0), "w"),
        (dict(w="1/10", max_length=8), "use 1 to 7"),
        (dict(w="1/10", side=6), "takes no side or radius"),
        (dict(msd_collisions=0), "msd_collisions"),
    ]:
        with pytest.raises(ValueError, match=needle):
            lg.cycles(**kwargs)


def test_escape_by_survival_on_the_repeller_and_on_disks_given_as_data(cli_json, tmp_path):
    r = lg.escape(repeller=True, side=6, radius=1, particles=2e6, threads=2)
    assert len(r.batch_gamma) == len(r.batch_lyapunov) == 32
    # The audit: the record from the batches, γ, λ and h_KS against the certified cycles.
    rep = lg.report(r, out=tmp_path / "s", quick=True)
    assert rep.verdict == "PASS", [c for c in rep.checks if c["verdict"] != "PASS"]
    assert any(c["name"] == "γ by survival = γ by cycles" for c in rep.checks)
    assert isinstance(r, lg.SurvivalResult)
    # γ of the cycles within 4 batch standard errors (32 batches; the window's transient,
    # about 3e-5, is far below the error of 2e6 particles).
    assert abs(r.gamma - GAMMA_R6) < 4 * r.gamma_err
    assert r.entropy == pytest.approx(r.lyapunov - r.gamma, abs=1e-15)
    assert list(r.windows["start"]) == [1, 2, 3, 4] and r.survival[0] == 1.0
    c = cli_json("escape", "--repeller", "--side", "6", "--radius", "1", "--particles", "2e6")
    d = r.to_dict()
    for k in ("config", "gamma", "gamma_err", "windows", "survival", "lyapunov"):
        assert d[k] == c[k], k
    assert repr(r).startswith("<SurvivalResult: gamma = 0.41")
    assert str(r).startswith("escape from the three-disk repeller R = 6, a = 1 by survival")
    # The same three disks as data: the same table up to √3's rounding, so the same γ within
    # the errors; every number exact as typed.
    h = "5.19615242270663188058"  # 3√3 to 21 digits
    disks = [{"centre": ["0", "0"], "radius": 1}, {"centre": [6, 0], "radius": "1"},
             {"centre": ["3", h], "radius": Fraction(1)}]
    o = lg.escape(open_table={"name": "three disks", "disks": disks}, particles=2e6, threads=2)
    assert o.table == "three disks" and o.config["scene"]["disks"][2]["centre"][1] == h
    assert abs(o.gamma - r.gamma) < 4 * np.hypot(o.gamma_err, r.gamma_err)
    for kwargs, needle in [
        (dict(repeller=True, side=2), "side=2 is out of range: use a side R > 2a = 2"),
        (dict(repeller=True, particles=10), "particles=10 is out of range: use 32000 to"),
        (dict(repeller=True, window=0), "window=0 is out of range: use 1 to 20"),
        (dict(repeller=True, w=0.1), "takes no w="),
        (dict(open_table={"disks": disks[:1]}), "disks=1 is out of range: use 2 to 64 disks"),
        (dict(), "w= is missing"),
    ]:
        with pytest.raises(ValueError, match=needle):
            lg.escape(**kwargs)
