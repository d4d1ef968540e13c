"""Observables on the user's grid: the MSD and VACF from t = 0 at the times given, the free-path
samples in the bins given, and the drawings of results (``r.plot()``).

The done-when numbers: MSD(0) = 0 exactly and C_x(0) = ⟨v_x(0)²⟩ = ½ within the crate's
agreement bound (the Student-t quantile equivalent to 4σ) of its standard error over the
batches; free-path samples (spread over the trajectories, so nearly independent) histogram to
the Boltzmann–Grad law in the user's bins: Pearson's chi-square below its 1 − 10⁻⁴ quantile.
"""

import json
import sys

import numpy as np
import pytest

import lorentz_gas as lg


def chi2_quantile(dof, z):
    """Wilson–Hilferty: the chi-square quantile of ``dof`` degrees of freedom at the normal
    quantile ``z`` (within 1 % for dof >= 3 in the upper tail)."""
    a = 2 / (9 * dof)
    return dof * (1 - a + z * np.sqrt(a)) ** 3


@pytest.fixture(scope="module")
def user_grid():
    times = np.array([0.0, 0.05, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0, 40.0, 100.0])
    return times, lg.diffusion(w=0.1, collisions=4e6, batches=16, msd_grid=times,
                               progress=False)


def test_the_msd_starts_at_zero_and_the_vacf_at_one_half_per_component(user_grid):
    """Broken on purpose (vacf_x read from the y column), the y component's ½ still passes but
    the x and y columns no longer sum to vacf at every time, which fails."""
    times, r = user_grid
    c = r.msd_curve
    assert np.array_equal(c["times"], times)
    assert c["msd"][0] == 0.0 and c["green_kubo"][0] == 0.0
    assert abs(c["vacf"][0] - 1.0) < 1e-14
    bound = lg.agreement_bound(16 - 1)
    for k in ("vacf_x", "vacf_y"):
        assert abs(c[k][0] - 0.5) <= bound * c[f"{k}_err"][0], (k, c[k][0], c[f"{k}_err"][0])
        assert 0 < c[f"{k}_err"][0] < 1e-3
    assert np.allclose(c["vacf_x"] + c["vacf_y"], c["vacf"], rtol=0, atol=1e-12)
    # The MSD never outruns the ballistic t², and D keeps the bits of the fit grid.
    assert np.all(c["msd"] <= times**2 * (1 + 1e-12))
    fit = lg.diffusion(w=0.1, collisions=4e6, batches=16, progress=False)
    assert fit.D == r.D


def test_the_grid_reads_as_text_and_bad_grids_are_refused(cli_json):
    r = lg.diffusion(w=0.2, collisions=1e6, batches=4, msd_grid="log:0.1,10,2", progress=False)
    assert r.msd_curve["times"][0] == 0.0 and len(r.msd_curve) == 1 + 14
    assert r.config["msd_grid"] == "log:0.1,10,2"
    cli = cli_json("diffusion", "--w", "0.2", "--collisions", "1e6", "--batches", "4",
                   "--msd-grid", "log:0.1,10,2")
    assert cli["msd_curve"] == json.loads(r.to_json())["msd_curve"]
    for bad, why in [([0.0, 1.0, 1.0], "increasing"), ([-1.0, 1.0], ">= 0"),
                     ([0.0, np.inf], "finite"), ("log:1,0.5,4", "FROM < TO"),
                     ([0.0, 1e7], "times from 0 to")]:
        with pytest.raises(ValueError, match="msd_grid"):
            lg.diffusion(w=0.2, collisions=1e6, batches=4, msd_grid=bad, progress=False)


def test_free_path_samples_follow_the_limit_law_in_the_users_bins():
    """Broken on purpose (each ξ divided by 1.05), the chi-square is far above its quantile."""
    edges = np.array([0, 0.25, 0.5, 0.75, 1, 1.25, 1.5, 2, 3, 4, 6])
    f = lg.free_paths(scene="square", radius="1/10000", collisions=1.6e6, bins=edges,
                      keep_samples=20_000, seed=7, progress=False)
    assert np.array_equal(f.bins["lo"], edges[:-1]) and np.array_equal(f.bins["hi"], edges[1:])
    assert f.max_z <= f.max_z_bound
    xi = f.free_path_samples
    assert len(xi) == 20_000
    counts, _ = np.histogram(xi, bins=np.append(edges, np.inf))
    # The limit law's probabilities: the report's `limit` column, and the rest above 6.
    p = np.append(f.bins["limit"], 1 - f.bins["limit"].sum())
    expected = len(xi) * p
    assert expected.min() > 20
    chi2 = ((counts - expected) ** 2 / expected).sum()
    assert chi2 < chi2_quantile(len(p) - 1, 3.719), chi2


def test_bad_bins_and_samples_are_refused():
    for bins in ([1.0], [1.0, 0.5], [0.0, np.nan]):
        with pytest.raises(ValueError, match="bins"):
            lg.free_paths(w="0.1", collisions=1e5, bins=bins, progress=False)
    with pytest.raises(ValueError, match="keep_samples"):
        lg.free_paths(w="0.1", collisions=1e5, keep_samples=2e6, progress=False)


def test_results_draw_themselves(user_grid):
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    _, r = user_grid
    ax = r.plot()
    assert ax.get_xscale() == "log" and len(ax.lines) >= 1
    f = lg.free_paths(scene="square", radius="1/1000", collisions=1e5, keep_samples=1000,
                      progress=False)
    fig, ax2 = plt.subplots()
    assert f.plot(ax2) is ax2
    plt.close("all")


def test_plot_without_matplotlib_names_the_extra(user_grid, monkeypatch):
    _, r = user_grid
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match=r"lorentz-gas\[plot\]"):
        r.plot()
