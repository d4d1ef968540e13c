#!/usr/bin/env bash
# Builds the documentation site into target/docs/html: the user guide, the references and the
# verification dossier with Sphinx (MyST Markdown, autodoc of the installed `lorentz_gas`), every
# warning an error (a broken link between pages is one), then the Rust API with `cargo doc` beside
# it. Needs `pip install sphinx myst-parser` and the Python package installed in $PYTHON's
# environment. Prints the path of the site's front page.
set -euo pipefail
cd "$(dirname "$0")/.."
PY=${PYTHON:-python3}
OUT=target/docs/html
rm -rf "$OUT"
"$PY" -m sphinx -W --keep-going -q -b html -c docs . "$OUT"
cargo doc --release --no-deps --quiet
mkdir -p "$OUT/docs/reference/rust"
cp -r target/doc/. "$OUT/docs/reference/rust/"
printf '<!doctype html><meta http-equiv="refresh" content="0; url=docs/index.html"><a href="docs/index.html">lorentz-gas documentation</a>\n' > "$OUT/index.html"
"$PY" scripts/check_site_links.py "$OUT"
echo "$OUT/index.html"
