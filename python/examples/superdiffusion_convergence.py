"""How slowly each superdiffusion estimator converges to its exact value (the README's figure).

Usage:
    lorentz superdiffusion --scene square --radius 1/4 --collisions 1.6e9 --batches 64 \
        --octaves 13 --json > r025.json
    python superdiffusion_convergence.py r025.json [more.json ...] --out convergence.png

or without files: python superdiffusion_convergence.py --radius 1/4 --collisions 2e8
(runs lg.superdiffusion). Each panel shows a measured quantity over its exact value against
t/ell (ell the mean free path), with batch errors (bars) and the bound on flights longer than
any seen (shaded): the tails s*P(tau > s) and s^2*mu(tau > s), t*C_xx(t), the local slope of
<dx^2>/t in ln t, and the limit law of dx/sqrt(D_sup t ln t).
"""

import argparse
import json

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load(args):
    if args.files:
        return [json.load(open(f)) for f in args.files]
    import lorentz_gas as lg

    r = lg.superdiffusion(scene="square", radius=args.radius, collisions=args.collisions,
                          progress=True)
    return [r.to_dict()]


def column(rows, key):
    return np.array([np.nan if r.get(key) is None else r[key] for r in rows], dtype=float)


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("files", nargs="*")
    p.add_argument("--radius", default="1/4")
    p.add_argument("--collisions", default="2e8")
    p.add_argument("--out", default="superdiffusion-convergence.png")
    args = p.parse_args()
    results = load(args)
    fig, ax = plt.subplots(2, 2, figsize=(11, 8), constrained_layout=True)
    for r, colour in zip(results, ["C0", "C3", "C2", "C1"]):
        rows, law = r["lags"], r["limit_law"]
        x = column(rows, "t_over_ell")
        ell = r["mean_free_path"]
        label = f"{r['scene']} ({r['collisions']:.1e} collisions)"
        panels = [
            (ax[0, 0], "s2_p_map", r["C_map_exact"], None, "-", "map: $s^2\\mu(\\tau>s)/C_{map}$"),
            (ax[0, 0], "s_p_flow", r["C_flow_exact"], "s_p_flow_unsampled", "--", "flow: $sP(\\tau>s)/C_{flow}$"),
            (ax[0, 1], "t_c", r["D_sup_exact"], "t_c_unsampled", "-", "$tC_{xx}(t)/D_{sup}$"),
            (ax[1, 0], "msd_local_slope", 2 * r["D_sup_exact"], "msd_local_slope_unsampled", "-",
             "$d(\\langle\\Delta x^2\\rangle/t)/d\\ln t\\,/\\,2D_{sup}$"),
        ]
        for a, key, exact, unsampled, style, what in panels:
            y = column(rows, key) / exact
            e = column(rows, key + "_err") / exact
            keep = np.isfinite(y) & (column(rows, "flights_longer") > 0 if "p_" in key else True)
            a.errorbar(x[keep], y[keep], yerr=e[keep], fmt="o" + style, ms=3, color=colour,
                       label=f"{what}, {label}" if a is ax[0, 0] else label)
            if unsampled and unsampled in rows[0]:
                u = column(rows, unsampled) / exact
                a.fill_between(x[keep], (y - u)[keep], (y + u)[keep], color=colour, alpha=0.15)
        t = column(law, "t") / ell
        ax[1, 1].errorbar(t, column(law, "variance_ratio"), yerr=column(law, "variance_ratio_err"),
                          fmt="o-", ms=3, color=colour, label=f"(IQR/1.349)$^2$ → 1, {label}")
        ax[1, 1].errorbar(t, column(law, "second_moment_ratio"),
                          yerr=column(law, "second_moment_ratio_err"), fmt="s--", ms=3,
                          color=colour, label="$\\langle u^2\\rangle$ → 2")
    titles = ["free-flight tails (→ 1)", "velocity autocorrelation (→ 1)",
              "local slope of the MSD in ln t (→ 1)",
              "limit law of $u = \\Delta x/\\sqrt{D_{sup}\\, t \\ln t}$"]
    for a, title in zip(ax.flat, titles):
        a.set_xscale("log")
        a.set_xlabel("$t/\\ell$ (lag or flight time in mean free paths)")
        a.set_title(title)
        a.axhline(1.0, color="k", lw=0.8)
        a.legend(fontsize=7)
    ax[1, 1].axhline(2.0, color="k", lw=0.8, ls=":")
    ax[1, 1].set_yscale("log")
    for a in (ax[0, 0], ax[0, 1], ax[1, 0]):
        a.set_ylim(0.5, 2.2)
    fig.suptitle("Superdiffusion: each estimator over its exact corridor value "
                 "(bars: batch errors; shaded: flights longer than any seen)")
    fig.savefig(args.out, dpi=110)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
