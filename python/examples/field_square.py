"""The square Lorentz gas in a magnetic field: D_xx(B) and the Hall D_xy(B) where, without a
field, D does not exist (the guide's figure on corridors closed by a field).

Usage:
    python field_square.py --collisions 1e7 --batches 16 --out field-square.png \
        --json field-square.json

Runs lg.diffusion(scene="square", radius=r, field=B) at r = 1/4 and 1/3 over fields from 1/1000
to the field at which every orbit is localized (2/B <= 1 - 2r: D = 0 exactly). The fit window
grows as the corridors reopen: the longest corridor flight is about sqrt(8W/B), so the window
starts at max(10, 10/sqrt(B)) crossing times (and the check window at twice that). The dashed
lines have the slope D_sup of the corridors' exact t ln t law (``lg.constants(radius=r)``) in
ln(1/B), for comparison only: the weak-field law is not derived. Bars are batch standard errors.
"""

import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from _field_panels import draw_rows, label_axes, measured  # noqa: E402

FIELDS = ["1/1000", "1/300", "1/100", "1/30", "1/10", "1/4", "1/2", "3/4", "1", "3/2", "2",
          "3", "4", "6"]


def window(b):
    """The fit and check windows at the field b, in crossing times."""
    lo = max(10, round(10 / math.sqrt(b)))
    return (lo, 4 * lo), (2 * lo, 8 * lo)


def measure(radius, collisions, batches):
    import lorentz_gas as lg
    from fractions import Fraction

    d_sup = lg.constants(radius=radius).to_dict()["superdiffusion"]["D_sup"]
    rows = []
    for b in FIELDS:
        fit, check = window(float(Fraction(b)))
        r = lg.diffusion(scene="square", radius=radius, field=b, collisions=collisions,
                         batches=batches, window=fit, check_window=check,
                         localization_samples=200_000).to_dict()
        rows.append(r)
        print(f"r = {radius}, B = {b}: D_xx = {r['D_xx']:.5f} ± {r['D_xx_err']:.5f}, "
              f"D_xy = {r['D_xy']:.5f} ± {r['D_xy_err']:.5f}, "
              f"localized {r['localized_fraction_exact']:.4f}", flush=True)
    return {"radius": radius, "D_sup": d_sup, "rows": rows}


def draw(data, out):
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
    for d, colour in zip(data, ["C0", "C3"]):
        b, get = draw_rows(ax, d["rows"], f"r = {d['radius']}", colour)
        weak = b <= 0.1
        anchor = np.mean(get("D_xx")[weak] + d["D_sup"] * np.log(b[weak]))
        ax[0].plot(b[weak], anchor - d["D_sup"] * np.log(b[weak]), "--", color=colour, lw=1,
                   label=f"slope $D_{{sup}}$ = {d['D_sup']:.4f} per e-fold")
    label_axes(ax, "$D_{xx}(B)$: no limit as $B \\to 0$ (corridors reopen)")
    ax[1].axhline(0, color="k", lw=0.5)
    ax[0].legend(loc="upper right", fontsize=8)
    ax[1].legend(loc="upper left")
    ax[2].legend(loc="upper left", fontsize=7)
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


def main():
    data, args = measured(
        __doc__.splitlines()[0], "1e7", "field-square.png",
        lambda n, k: [measure(r, n, k) for r in ("1/4", "1/3")],
    )
    draw(data, args.out)


if __name__ == "__main__":
    main()
