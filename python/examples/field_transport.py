"""The diffusion tensor in a magnetic field against the field (the README's figure).

Usage:
    python field_transport.py --collisions 2e7 --batches 16 --out field-transport.png \
        --json field-transport.json

Runs lg.diffusion(w, field=B) at w = 0.1, 0.2, 0.3 over a grid of fields and draws D_xx(B) over
the whole phase space (with D(w) at B = 0 from the run without a field), the Hall part D_xy(B),
and the exact localized share with the sampled one. Bars are batch standard errors; fields at
which every orbit is localized (2/|B| <= w) have D = 0 exactly and are drawn as such.
"""


import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from _field_panels import draw_rows, label_axes, measured  # noqa: E402

FIELDS = ["1/20", "1/10", "1/5", "7/20", "1/2", "3/4", "1", "3/2", "2", "3", "4", "5", "7",
          "10", "14", "20"]


def measure(w, collisions, batches):
    import lorentz_gas as lg

    zero = lg.diffusion(w=w, collisions=collisions, batches=batches).to_dict()
    rows = []
    for b in FIELDS:
        r = lg.diffusion(w=w, field=b, collisions=collisions, batches=batches,
                         localization_samples=200_000).to_dict()
        rows.append(r)
        print(f"w = {w}, B = {b}: D_xx = {r['D_xx']:.5f} ± {r['D_xx_err']:.5f}, "
              f"D_xy = {r['D_xy']:.5f} ± {r['D_xy_err']:.5f}, "
              f"localized {r['localized_fraction_exact']:.4f}", flush=True)
    return {"w": w, "zero": zero, "rows": rows}


def main():
    data, args = measured(
        __doc__.splitlines()[0], "2e7", "field-transport.png",
        lambda n, k: [measure(w, n, k) for w in ("0.1", "0.2", "0.3")],
    )
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
    for d, colour in zip(data, ["C0", "C3", "C2"]):
        draw_rows(ax, d["rows"], f"w = {d['w']}", colour)
        ax[0].errorbar([0.02], [d["zero"]["D"]], yerr=[d["zero"]["D_err"]], fmt="s",
                       color=colour, ms=5)
    label_axes(ax, "$D_{xx}(B)$; squares: $D(w)$ without a field")
    ax[0].legend(loc="lower left")
    ax[1].legend(loc="upper left")
    ax[2].legend(loc="upper left", fontsize=7)
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
