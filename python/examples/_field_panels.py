"""What the field examples share: their command line (measure, or draw what an earlier run
measured), and the three panels D_xx(B), the Hall D_xy(B) and the localized share (exact and
sampled), each over the whole phase space, against a logarithmic field axis."""


def measured(description, collisions, out, measure):
    """The examples' command line: ``--collisions`` (default ``collisions``), ``--batches``,
    ``--out`` (default ``out``), ``--json`` (write the measurements there) and ``--load`` (draw
    from a file ``--json`` wrote instead of measuring). Returns the measurements,
    ``measure(collisions, batches)`` or the file's, and the parsed arguments."""
    import argparse
    import json

    p = argparse.ArgumentParser(description=description)
    p.add_argument("--collisions", default=collisions)
    p.add_argument("--batches", type=int, default=16)
    p.add_argument("--out", default=str(out))
    p.add_argument("--json", default=None, help="write the measurements here")
    p.add_argument("--load", default=None, help="draw from a file --json wrote")
    args = p.parse_args()
    if args.load:
        with open(args.load) as f:
            return json.load(f), args
    data = measure(args.collisions, args.batches)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(data, f)
    return data, args


def draw_rows(ax, rows, label, colour):
    """One curve per panel from the ``FieldResult`` dicts ``rows`` (bars: batch errors)."""
    import numpy as np

    b = np.array([r["field"] for r in rows])
    get = lambda k: np.array([r[k] for r in rows])  # noqa: E731
    ax[0].errorbar(b, get("D_xx"), yerr=get("D_xx_err"), fmt="o-", ms=3, color=colour,
                   label=label, capsize=2)
    ax[1].errorbar(b, get("D_xy"), yerr=get("D_xy_err"), fmt="o-", ms=3, color=colour,
                   label=label, capsize=2)
    ax[2].plot(b, get("localized_fraction_exact"), "-", color=colour, label=f"{label} exact")
    ax[2].errorbar(b, get("localized_fraction"), yerr=get("localized_fraction_err"), fmt="o",
                   ms=3, color=colour, label=f"{label} sampled")
    return b, get


def label_axes(ax, d_xx_title):
    """Axes, labels and titles of the three panels (the first panel's title is the caller's)."""
    for a in ax:
        a.set_xscale("log")
        a.set_xlabel("field B (cyclotron radius 1/B)")
        a.grid(alpha=0.3)
    ax[0].set_ylabel("$D_{xx}$ (whole phase space)")
    ax[0].set_title(d_xx_title, fontsize=10)
    ax[1].set_ylabel("Hall part $D_{xy}$ (whole phase space)")
    ax[1].set_title("$D_{xy}(B)$ from the Lévy area")
    ax[2].set_ylabel("share of phase space")
    ax[2].set_title("pinned + skipping share: exact (lines), sampled (dots)", fontsize=10)
