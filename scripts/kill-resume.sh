#!/usr/bin/env bash
# kill -9 a resumable run at uniformly random moments and resume it; print, per kill, the time
# to the kill, the resume's time, their excess over the uninterrupted run, and whether the
# resumed result has the uninterrupted bits (every field but timing and metadata).
#
#   scripts/kill-resume.sh diffusion [KILLS] [INTERVAL]   # --w 0.1 --collisions 8e9 --threads 2
#   scripts/kill-resume.sh sweep [KILLS] [INTERVAL]       # 3 points x 4 runs x 5e8 collisions
#
# Uses target/release/lorentz (cargo build --release first), or the binary in LORENTZ_BIN (a copy
# keeps a rebuild from changing the binary mid-measurement), and a scratch directory.
set -euo pipefail
kind=${1:?diffusion or sweep}
kills=${2:-20}
every=${3:-5}
bin=${LORENTZ_BIN:-$(cd "$(dirname "$0")/.." && pwd)/target/release/lorentz}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
case "$kind" in
  diffusion) args=(diffusion --w 0.1 --collisions 8e9 --threads 2 --json --quiet)
             keep() { echo --checkpoint run.ckpt --checkpoint-every "$every"; }
             fresh() { rm -f run.ckpt; } ;;
  sweep)     args=(sweep --w-from 0.1 --w-to 0.2 --steps 3 --runs 4 --collisions-per-run 5e8
                   --batches-per-run 8 --threads 2 --json --quiet --checkpoint-every "$every")
             keep() { echo --out killed; }
             fresh() { rm -rf killed; } ;;
  *) echo "kind must be diffusion or sweep" >&2; exit 2 ;;
esac
now() { date +%s.%N; }
extra=()
[ "$kind" = sweep ] && extra=(--out whole)
s=$(now); "$bin" "${args[@]}" "${extra[@]}" > whole.json; t0=$(echo "$(now) - $s" | bc -l)
printf 'uninterrupted %.2f s\n' "$t0"
for k in $(seq 1 "$kills"); do
  fresh
  f=$(python3 -c "import random; random.seed($k); print(random.random())")
  s=$(now)
  # shellcheck disable=SC2046
  "$bin" "${args[@]}" $(keep) > /dev/null & pid=$!
  sleep "$(echo "$f * $t0" | bc -l)"; kill -9 "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true
  m=$(now)
  # shellcheck disable=SC2046
  "$bin" "${args[@]}" $(keep) > resumed.json
  e=$(now)
  same=$(python3 - <<'PY'
import json
a, b = json.load(open("whole.json")), json.load(open("resumed.json"))
for d in (a, b):
    for k in ("meta", "seconds", "collisions_per_second", "resumed_batches", "resumed_points"):
        d.pop(k, None)
print(a == b)
PY
)
  printf 'kill %2d at %.3f: killed after %.2f s, resume %.2f s, excess %+.2f s, identical %s\n' \
    "$k" "$f" "$(echo "$m - $s" | bc -l)" "$(echo "$e - $m" | bc -l)" "$(echo "$e - $s - $t0" | bc -l)" "$same"
done
