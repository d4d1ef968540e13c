"""D_xx(B), the Hall D_xy(B) and the bounded share at w = 0.2, B from 0 to 3 (the islands guide's
figure).

Usage (about 2 minutes on 2 cores; writes proofs-notes/figures/field-components.png):
    python python/examples/field_components.py --collisions 2e7 --batches 16 \
        --json field-components.json

Runs lg.diffusion(w=0.2, field=B) at B = 1/10, 2/10, ..., 3 and once without a field (B = 0:
D(w), and D_xy = 0 by symmetry), seed 1. Left: D_xx and the Hall D_xy over the whole phase space
(filled) and over the diffusing part alone (open: the batches neither pinned, skipping nor
bounded). Right: the exact localized share (pinned + skipping), the sampled one, and the bounded
share of the run's components (the exact share plus the bounded batches' share of the rest,
binomial error, the 95 % Clopper-Pearson upper bound dotted), with the fields where batches were
bounded beyond the exact share and where the diffusing batches split marked. Bars are batch
standard errors.
"""

import pathlib
from fractions import Fraction

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from _field_panels import measured  # noqa: E402

W = "0.2"
FIELDS = [str(Fraction(k, 10)) for k in range(1, 31)]
OUT = pathlib.Path(__file__).resolve().parents[2] / "proofs-notes" / "figures" / "field-components.png"


def measure(collisions, batches):
    import lorentz_gas as lg

    zero = lg.diffusion(w=W, collisions=collisions, batches=batches, seed=1).to_dict()
    print(f"B = 0: D = {zero['D']:.5f} ± {zero['D_err']:.5f}", flush=True)
    rows = []
    for b in FIELDS:
        r = lg.diffusion(w=W, field=b, collisions=collisions, batches=batches, seed=1).to_dict()
        c = r["components"]
        rows.append({k: r[k] for k in ("field", "D_xx", "D_xx_err", "D_xy", "D_xy_err",
                                       "diffusing", "localized_fraction_exact",
                                       "localized_fraction", "localized_fraction_err")}
                    | {"components": {k: c[k] for k in ("bounded", "diffusing", "ambiguous",
                                                        "bounded_fraction", "bounded_fraction_err",
                                                        "bounded_fraction_upper", "split")}})
        print(f"B = {b}: D_xx = {r['D_xx']:.5f} ± {r['D_xx_err']:.5f}, "
              f"D_xy = {r['D_xy']:.5f} ± {r['D_xy_err']:.5f}, "
              f"localized {r['localized_fraction_exact']:.4f}, bounded {c['bounded']} of "
              f"{batches} ({c['bounded_fraction']:.3f} ± {c['bounded_fraction_err']:.3f}, "
              f"< {c['bounded_fraction_upper']:.3f}){', split' if c['split'] else ''}", flush=True)
    return {"w": W, "collisions": float(collisions), "batches": batches,
            "zero": {"D": zero["D"], "D_err": zero["D_err"]}, "rows": rows}


def draw(data, out):
    rows = data["rows"]
    b = np.array([r["field"] for r in rows])
    get = lambda k: np.array([r[k] for r in rows])  # noqa: E731
    dif = lambda k: np.array([r["diffusing"][k] for r in rows])  # noqa: E731
    comp = lambda k: np.array([r["components"][k] for r in rows])  # noqa: E731
    b0 = np.r_[0.0, b]

    fig, ax = plt.subplots(1, 2, figsize=(12, 4.6), constrained_layout=True)
    a = ax[0]
    for key, colour, name in (("D_xx", "C0", "$D_{xx}$"), ("D_xy", "C3", "Hall $D_{xy}$")):
        y0, e0 = (data["zero"]["D"], data["zero"]["D_err"]) if key == "D_xx" else (0.0, 0.0)
        a.errorbar(b0, np.r_[y0, get(key)], yerr=np.r_[e0, get(key + "_err")], fmt="o-", ms=4,
                   color=colour, capsize=2, label=f"{name}, whole phase space")
        a.errorbar(b, dif(key), yerr=dif(key + "_err"), fmt="o", ms=5, mfc="none", color=colour,
                   capsize=2, label=f"{name}, diffusing part")
    a.set_ylabel("diffusion tensor (length$^2$/time)")
    a.set_title("(a) $D_{xx}(B)$ and the Hall $D_{xy}(B)$ (at B = 0: D(w) without a field)",
                fontsize=10)
    a.set_ylim(-0.01, 0.25)
    a.legend(loc="upper left", bbox_to_anchor=(0.1, 1.0), fontsize=8)

    a = ax[1]
    loc = get("localized_fraction_exact")
    a.plot(b0, np.r_[0.0, loc], "-", color="k", lw=1.2, label="localized (pinned + skipping), exact")
    a.errorbar(b, get("localized_fraction"), yerr=get("localized_fraction_err"), fmt="+", ms=6,
               color="k", label="localized, sampled")
    a.errorbar(b, comp("bounded_fraction"), yerr=comp("bounded_fraction_err"), fmt="o", ms=4,
               color="C2", capsize=2, label="bounded share of the run (binomial error)")
    a.plot(b, comp("bounded_fraction_upper"), ":", color="C2", lw=1.2,
           label="bounded share below this at 95 % (Clopper–Pearson)")
    beyond = comp("bounded") > 0
    a.plot(b[beyond], comp("bounded_fraction")[beyond], "o", ms=10, mfc="none", mew=1.2,
           color="C2", label=f"bounded batches beyond the exact share (how many of {data['batches']})")
    top = (comp("bounded_fraction") + comp("bounded_fraction_err"))[beyond]
    for x, y, k in zip(b[beyond], top, comp("bounded")[beyond]):
        a.annotate(f"{int(k)}", (x, y), xytext=(0, 2), textcoords="offset points",
                   ha="center", va="bottom", fontsize=7, color="C2")
    split = comp("split").astype(bool)
    if split.any():
        a.plot(b[split], comp("bounded_fraction")[split], "x", ms=9, mew=1.5, color="C3",
               label="diffusing batches not one component (split)")
    a.set_ylabel("share of phase space")
    a.set_title("(b) the share that never diffuses: exact and sampled", fontsize=10)
    a.set_ylim(bottom=-0.02)
    a.legend(loc="upper left", fontsize=8)

    m, e = f"{data['collisions']:.0e}".split("e+")
    fig.suptitle(f"w = {data['w']}, ${m} \\cdot 10^{{{int(e)}}}$ collisions in {data['batches']} "
                 "batches per field, seed 1", fontsize=10)
    for a in ax:
        a.set_xlabel("field B (cyclotron radius 1/B)")
        a.set_xlim(-0.05, 3.05)
        a.axhline(0, color="k", lw=0.5)
        a.grid(alpha=0.3)
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


def main():
    data, args = measured(__doc__.splitlines()[0], "2e7", OUT, measure)
    draw(data, args.out)


if __name__ == "__main__":
    main()
