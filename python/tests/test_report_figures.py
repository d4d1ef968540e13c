"""`lorentz report`'s documents as a journal would take them: the verdict first (the first line
printed, the top of report.md and report.html), and figures drawn for print — a light grid at
the labelled ticks only (no minor grid), a histogram as bars, tick labels with the same decimals
along an axis, the legend below the axes (off the data). Measured on the figures themselves: the
PNG files' pixels and the SVG files' text."""

import re

import numpy as np
import pytest
from matplotlib import image

@pytest.fixture(scope="module")
def audit(cli, tmp_path_factory):
    """A quick audit of a small diffusion result: (what it printed, its folder)."""
    tmp = tmp_path_factory.mktemp("audit")
    code, out, err = cli("diffusion", "--w", "0.2", "--collisions", "2e6", "--batches", "16",
                         "--json", "--quiet")
    assert code == 0, err
    (tmp / "d.json").write_text(out)
    code, printed, err = cli("report", str(tmp / "d.json"), "--quick", "--out", str(tmp / "rep"),
                             "--quiet")
    assert code == 0, err
    return printed, tmp / "rep"


def test_the_verdict_comes_first(audit):
    printed, rep = audit
    first, second, *_, last = printed.splitlines()
    assert re.match(r".*d\.json: PASS \(quick audit: 1 of 16 batches re-run.*\(\d+ checks, 0 skipped; ",
                    first), first
    assert second.startswith("result = diffusion, w (gap) = 0.2"), second
    assert last == f"written: {rep}/report.{{md,html,json}}"
    assert (rep / "report.md").read_text().splitlines()[0].startswith("# Audit of ")
    assert "**PASS (quick audit" in (rep / "report.md").read_text().splitlines()[0]
    html = (rep / "report.html").read_text()
    body = html[html.index("<body>"):]
    assert re.match(r"<body>\s*<h1>Audit of [^<]*: <span class=\"PASS\">PASS", body), body[:200]


def _png(path):
    return image.imread(str(path))[..., :3]


def _plot_area(img):
    """Rows and columns inside the axes: right of the y axis line and above the x axis line (the
    longest dark horizontal and vertical runs)."""
    dark = img.max(axis=2) < 0.25
    x_axis = int(np.argmax(dark.sum(axis=1)))
    y_axis = int(np.argmax(dark.sum(axis=0)))
    return x_axis, y_axis


@pytest.mark.parametrize("figure", ["local-slope", "batch-histogram"])
def test_the_figures_have_a_light_major_grid_only_and_the_legend_below(audit, figure):
    _, rep = audit
    img = _png(rep / f"{figure}.png")
    assert img.shape == (600, 800, 3)
    x_axis, y_axis = _plot_area(img)
    assert 300 < x_axis < 560 and 40 < y_axis < 200, (x_axis, y_axis)
    inside = img[20:x_axis - 2, y_axis + 2:]
    # A grid line: grey (a minor grid's lighter grey too) in at least a third of the plot's
    # rows or columns (bands and bars tint it where they cover it).
    value = inside.mean(axis=2)
    grey = (inside.max(axis=2) - inside.min(axis=2) < 0.03) & (value > 0.75) & (value < 0.93)
    columns = np.flatnonzero(grey.mean(axis=0) > 0.3)
    lines = np.count_nonzero(np.diff(columns) > 1) + (len(columns) > 0)
    # (the shaded fit window and error band cover some: at least one shows)
    assert 1 <= lines <= 12, f"{lines} vertical grid lines (a minor grid has dozens)"
    rows = np.flatnonzero(grey.mean(axis=1) > 0.3)
    lines = np.count_nonzero(np.diff(rows) > 1) + (len(rows) > 0)
    assert 2 <= lines <= 12, f"{lines} horizontal grid lines"
    # The legend: coloured samples below the x axis (under its labels), none drawn in the
    # top right corner where a legend box used to sit over the data.
    below = img[x_axis + 40:]
    saturated = below.max(axis=2) - below.min(axis=2) > 0.3
    assert saturated.sum() > 100, "no legend sample below the axes"
    corner = img[40:160, 500:790]
    assert not np.any(np.all(corner < 0.05, axis=2).sum(axis=1) > 200), "a legend frame at top right"


def test_the_histogram_is_drawn_as_bars(audit):
    _, rep = audit
    img = _png(rep / "batch-histogram.png")
    x_axis, y_axis = _plot_area(img)
    inside = img[20:x_axis - 2, y_axis + 2:]
    # Filled bars: a large share of the plot in one saturated colour (a step outline covers
    # well under 1 %).
    saturated = inside.max(axis=2) - inside.min(axis=2) > 0.25
    assert saturated.mean() > 0.15, f"bars cover {saturated.mean():.1%} of the plot"


@pytest.mark.parametrize("figure", ["local-slope", "batch-histogram"])
def test_tick_labels_have_the_same_decimals_along_an_axis(audit, figure):
    _, rep = audit
    svg = (rep / f"{figure}.svg").read_text()
    labels = re.findall(r'<text[^>]*text-anchor="(end|middle)"[^>]*>\s*([-0-9.e]+)\s*</text>', svg)
    for anchor in ("end", "middle"):  # y ticks are right-aligned, x ticks centred
        ticks = [t for a, t in labels if a == anchor]
        assert len(ticks) >= 3, (anchor, labels)
        decimals = {len(t.split(".")[1]) if "." in t else 0 for t in ticks}
        assert len(decimals) == 1, f"{figure}: ticks {ticks}"
