"""`report.html` as a reader sees it: rendered by headless Chromium, it shows the headline and
its figures, and the figures are drawn (not blank, not missing).

Chromium is found as `chromium` (Debian's package; `.ci/run` installs it) or
`chromium-browser`. Without it the test is skipped, unless LORENTZ_REQUIRE_CHROMIUM=1 (set by CI),
where it fails."""

import os
import re
import shutil
import subprocess

import numpy as np
import pytest
from matplotlib import image


def chromium():
    path = shutil.which("chromium") or shutil.which("chromium-browser")
    if path is None:
        if os.environ.get("LORENTZ_REQUIRE_CHROMIUM") == "1":
            pytest.fail("headless Chromium is required (LORENTZ_REQUIRE_CHROMIUM=1) but not found")
        pytest.skip("no chromium on this machine: report.html is not rendered")
    return path


def screenshot(browser, html, png):
    p = subprocess.run(
        [browser, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars",
         "--window-size=1200,4000", f"--screenshot={png}", html.as_uri()],
        capture_output=True, text=True, timeout=120,
    )
    assert p.returncode == 0 and png.is_file(), p.stderr[-2000:]
    return image.imread(str(png))[..., :3]


def test_report_html_shows_its_headline_and_figures(cli, tmp_path):
    browser = chromium()
    code, out, err = cli("diffusion", "--w", "0.2", "--collisions", "2e6", "--batches", "8",
                         "--json", "--quiet")
    assert code == 0, err
    (tmp_path / "d.json").write_text(out)
    code, _, err = cli("report", str(tmp_path / "d.json"), "--quick", "--out",
                       str(tmp_path / "rep"), "--quiet")
    assert code == 0, err
    page = tmp_path / "rep" / "report.html"
    html = page.read_text(encoding="utf-8")
    # The headline: what was measured and the verdict, before any check row.
    head = html[: html.index("Checks")]
    for shown in ["Audit of", "d.json", "PASS", "0.2", "2000000", "D", "verdict"]:
        assert shown in head, shown
    # The figures are inline SVG.
    svg = re.compile(r"<svg\b.*?</svg>", re.S)
    figures = svg.findall(html)
    assert len(figures) >= 2, len(figures)
    with_figures = screenshot(browser, page, tmp_path / "with.png")
    # The verdict at the top of the page: the green of PASS within the first 120 px (the
    # heading), before any table.
    green = (with_figures[..., 1] > 0.3) & (with_figures[..., 0] < 0.1) & (with_figures[..., 2] < 0.1)
    assert green[:120].sum() > 50, "no PASS in the heading"
    # Each figure at its size: 800 x 600 (the SVG's own), inline.
    for f in figures:
        assert re.search(r'<svg[^>]*width="800"[^>]*height="600"', f), f[:200]
    # The same page without its figures: what the figures add to the picture.
    bare = tmp_path / "rep" / "bare.html"
    bare.write_text(svg.sub("", html), encoding="utf-8")
    without = screenshot(browser, bare, tmp_path / "without.png")
    h = min(len(with_figures), len(without))
    changed = np.any(np.abs(with_figures[:h] - without[:h]) > 0.1, axis=2)
    rows = np.flatnonzero(changed.any(axis=1))
    # Each figure is drawn 600 px high at this width (the rows it changes: most of its height,
    # the white margins aside); in colour (lines, bands, bars), not blank.
    assert len(rows) > 500 * len(figures), f"{len(rows)} rows differ"
    drawn = with_figures[rows]
    saturation = drawn.max(axis=2) - drawn.min(axis=2)
    assert (saturation > 0.3).mean() > 0.002, "the figures hold no coloured pixel"
