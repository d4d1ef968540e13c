#!/bin/sh
# The README's speed table, measured side by side in one run on this machine: the scalar engine,
# the SIMD engine on every instruction path the CPU has (bare and with the observers of
# `lorentz diffusion`), production `diffusion` runs on 1 and 2 threads, and the wall time of D(0.1)
# to 0.1 % relative error. Medians of repetitions; other work on the machine moves the numbers.
#
#   scripts/speed-table.sh            (after `cargo build --release`; LORENTZ=path overrides)
set -eu
B=${LORENTZ:-target/release/lorentz}
W=${W:-0.1}
num() { grep -o "\"$1\": *[-0-9.e+]*" | head -n 1 | cut -d: -f2 | tr -d ' '; }
field() { grep -o "\"$1\": *\"[a-z0-9]*\"" | head -n 1 | cut -d'"' -f4; }

echo "| what (w = $W) | engine | ns / collision / core | collisions / s | × scalar |"
echo "|---|---|---|---|---|"
scalar=$("$B" bench --w "$W" --threads 1 --engine scalar --collisions-per-thread 2e7 --repetitions 7 --json --quiet)
s_cps=$(echo "$scalar" | num collisions_per_second)
line() { # label engine cps threads
    awk -v l="$1" -v e="$2" -v c="$3" -v t="$4" -v s="$s_cps" \
        'BEGIN { printf "| %s | %s | %.2f | %.3g | %.2f× |\n", l, e, 1e9 * t / c, c, c / s }'
}
line "bare engine, 1 thread (\`bench --engine scalar\`)" scalar "$s_cps" 1
for p in avx512 avx2 portable; do
    out=$(LORENTZ_SIMD=$p "$B" bench --w "$W" --threads 1 --collisions-per-thread 1e8 --repetitions 7 --json --quiet 2>/dev/null) || continue
    line "bare engine, 1 thread (\`LORENTZ_SIMD=$p bench\`)" "simd ($p)" "$(echo "$out" | num collisions_per_second)" 1
done
best=$("$B" bench --w "$W" --threads 1 --collisions-per-thread 1e8 --repetitions 7 --observe diffusion --json --quiet)
line "engine + counters + MSD, 1 thread (\`bench --observe diffusion\`)" "simd ($(echo "$best" | field simd))" "$(echo "$best" | num collisions_per_second)" 1
for t in 1 2; do
    d=$("$B" diffusion --w "$W" --collisions 4e8 --threads $t --json --quiet)
    line "\`diffusion --collisions 4e8 --threads $t\`" "simd ($(echo "$d" | field simd))" "$(echo "$d" | num collisions_per_second)" $t
done
# D(0.1) to 0.1 %: the default run's relative error is 0.046 % at 2e9 collisions, so 5e8 give
# about 0.092 % (the error estimate itself scatters by ~12 % with 32 batches).
d=$("$B" diffusion --w 0.1 --collisions 5e8 --threads 2 --json --quiet)
echo
awk -v D="$(echo "$d" | num D)" -v e="$(echo "$d" | num D_err)" -v t="$(echo "$d" | num seconds)" \
    'BEGIN { printf "D(0.1) to 0.1 %%: `diffusion --w 0.1 --collisions 5e8 --threads 2`: D = %.5f ± %.5f (%.3f %%) in %.1f s wall on 2 threads.\n", D, e, 100 * e / D, t }'
