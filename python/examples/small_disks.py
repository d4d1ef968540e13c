"""Small disks: the Boltzmann-Grad regime of the square Lorentz gas (the README's figure).

Usage:
    python small_disks.py --out small-disks.png

Left: the density of xi = tau/ell (tau the free path from one collision to the next, ell
Santalo's mean free path) at r = 1/100 and r = 1/10000, each bin's measured probability over its
width with its batch error, against the limit law of r -> 0 (lg.free_paths); middle: each bin
over the limit law's, less 1. Right: the
Lyapunov exponent of the disk-to-disk map less Dahlqvist's -2 ln r + C, against r, with a
weighted fit of a*r + b*r*ln(1/r) (lg.lyapunov, long flights jumped).
"""

import argparse
import math
from fractions import Fraction

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import lorentz_gas as lg  # noqa: E402

ZETA3 = 1.2020569031595942
C = 1 - 4 * math.log(2) + 27 * ZETA3 / (2 * math.pi ** 2)


def density_panels(ax, dev, radii, collisions):
    for r, colour, marker in zip(radii, ["C3", "C0"], ["s", "o"]):
        f = lg.free_paths(scene="square", radius=r, collisions=collisions, progress=False)
        b = f.bins[np.isfinite(f.bins["hi"])]
        mid, width = (b["lo"] + b["hi"]) / 2, b["hi"] - b["lo"]
        label = f"r = {r} ({f.samples:.1e} flights)"
        ax.errorbar(mid, b["probability"] / width, yerr=b["probability_err"] / width, fmt=marker,
                    ms=4, color=colour, mfc="none", label=label)
        dev.errorbar(mid, b["probability"] / b["limit"] - 1, yerr=b["probability_err"] / b["limit"],
                     fmt=marker, ms=4, color=colour, mfc="none", label=label)
        limit = b["limit"] / width
    edges = np.append(b["lo"], b["hi"][-1])
    ax.stairs(limit, edges, color="k", lw=1, label="limit law r → 0 (bin averages)")
    ax.set_yscale("log")
    ax.set_title("free paths between collisions")
    ax.set_ylabel("probability density of ξ")
    ax.legend(loc="lower left", fontsize=8)
    dev.axhline(0, color="k", lw=1)
    dev.set_title("each bin against the limit law")
    dev.set_ylabel("measured / limit − 1")
    dev.legend(loc="upper right", fontsize=8)
    for a in (ax, dev):
        a.set_xlabel("ξ = τ/⟨ℓ⟩ (free path over Santaló's mean free path)")


def lyapunov_panel(ax, radii, per_batch):
    r = np.array([float(Fraction(x)) for x in radii])
    d, e = [], []
    for x in radii:
        t = lg.lyapunov(scene="square", radius=x, collisions_per_batch=per_batch, starts=0,
                        progress=False).tangent
        d.append(t["per_collision"] + 2 * math.log(Fraction(x)) - C)
        e.append(t["per_collision_err"])
    d, e = np.array(d), np.array(e)
    design = np.stack([r, r * np.log(1 / r)], axis=1) / e[:, None]
    (a, b), *_ = np.linalg.lstsq(design, d / e, rcond=None)
    cov = np.linalg.inv(design.T @ design)
    chi2 = float(np.sum(((design @ [a, b]) - d / e) ** 2))
    for x, y, s in zip(radii, d, e):
        print(f"r = {x}: lambda + 2 ln r - C = {y:+.5f} ± {s:.5f}")
    print(f"fit: a = {a:.4f} ± {math.sqrt(cov[0, 0]):.4f}, b = {b:.4f} ± {math.sqrt(cov[1, 1]):.4f}, "
          f"correlation {cov[0, 1] / math.sqrt(cov[0, 0] * cov[1, 1]):+.3f}, "
          f"chi2 = {chi2:.2f} on {len(r) - 2} dof")
    ax.errorbar(r, d, yerr=e, fmt="o", color="C0", ms=4, label="measured (16 orbits each)")
    grid = np.geomspace(r.min(), r.max(), 100)
    ea, eb = math.sqrt(cov[0, 0]), math.sqrt(cov[1, 1])
    ax.plot(grid, a * grid + b * grid * np.log(1 / grid), "k-",
            label=f"fit ({a:.2f} ± {ea:.2f}) r + ({b:.3f} ± {eb:.3f}) r ln(1/r)")
    ax.axhline(0, color="grey", lw=0.5)
    ax.set_xscale("log")
    ax.set_xlabel("disk radius r (lattice spacing 1)")
    ax.set_ylabel("λ + 2 ln r − C (per collision)")
    ax.set_title("Lyapunov exponent against Dahlqvist's limit")
    ax.legend(loc="upper left", fontsize=8)
    return a, b


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--collisions", default="1.6e7")
    p.add_argument("--collisions-per-batch", default="2e6")
    p.add_argument("--out", default="small-disks.png")
    args = p.parse_args()
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.4), constrained_layout=True)
    density_panels(ax[0], ax[1], ["1/100", "1/10000"], args.collisions)
    lyapunov_panel(
        ax[2], ["1/30", "1/100", "1/300", "1/1000", "1/3000", "1/10000"], args.collisions_per_batch
    )
    fig.savefig(args.out, dpi=110)


if __name__ == "__main__":
    main()
