#!/usr/bin/env bash
# Writes the seed corpus fuzz/corpus/report_audit/: small real result files of every kind the
# publication audit knows, computed by the lorentz binary (a few seconds). Run from the
# repository's root after `cargo build --release`.
set -euo pipefail
L=${LORENTZ:-target/release/lorentz}
D=fuzz/corpus/report_audit
mkdir -p "$D"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
q="--json --quiet --threads 1"
$L diffusion --w 0.3 --collisions 1e6 --batches 8 $q > "$D/seed-diffusion.json"
$L hops --w 0.1 --collisions 2e5 --batches 2 --order 2 $q > "$D/seed-hops.json"
$L theory --w 0.1 --collisions 2e5 --batches 2 --order 1 $q > "$D/seed-theory.json"
$L lattice-walk --w 0.1 --collisions 2e5 --batches 2 --order 1 $q > "$D/seed-lattice-walk.json"
$L backscatter --w 0.1 --particles 2000 --batches 2 $q > "$D/seed-backscatter.json"
$L escape --w 0.2 --particles-per-width 3200 --widths 9,11,13 $q > "$D/seed-escape.json"
$L sweep --w-from 0.2 --w-to 0.3 --steps 3 --runs 2 --collisions-per-run 2e5 \
  --batches-per-run 4 --out "$tmp/sweep" $q > "$D/seed-sweep.json"
ls -l "$D"
