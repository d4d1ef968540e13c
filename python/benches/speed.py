"""Python against the command line, side by side: the same diffusion run (w = 0.1, 4e8
collisions, one thread by default) alternately through `lorentz_gas.diffusion` and through the
`lorentz` binary, each reporting the collisions per second of its run (the library's own clock:
the run, without interpreter start-up or JSON printing). Prints every pair, the medians and the
median of the pair-by-pair ratios Python / CLI.

    python python/benches/speed.py [--pairs 7] [--collisions 4e8] [--threads 1]

The binary is LORENTZ_BIN or target/release/lorentz.
"""

import argparse
import json
import os
import pathlib
import statistics
import subprocess

import lorentz_gas as lg

REPO = pathlib.Path(__file__).resolve().parents[2]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--pairs", type=int, default=7)
    p.add_argument("--collisions", default="4e8")
    p.add_argument("--threads", default="1")
    p.add_argument("--w", default="0.1")
    a = p.parse_args()
    binary = os.environ.get("LORENTZ_BIN", str(REPO / "target" / "release" / "lorentz"))
    cli_args = [binary, "diffusion", "--w", a.w, "--collisions", a.collisions,
                "--threads", a.threads, "--json", "--quiet"]
    py, cli, ratio = [], [], []
    for k in range(a.pairs + 1):
        r = lg.diffusion(w=a.w, collisions=a.collisions, threads=int(a.threads))
        c = json.loads(subprocess.run(cli_args, check=True, capture_output=True, text=True).stdout)
        assert r.D == c["D"], "Python and the command line disagree on D"
        if k == 0:
            continue  # warm-up pair
        py.append(r.collisions_per_second)
        cli.append(c["collisions_per_second"])
        ratio.append(py[-1] / cli[-1])
        print(f"pair {k}: python {py[-1]:.4e}/s  cli {cli[-1]:.4e}/s  ratio {ratio[-1]:.4f}")
    print(f"median: python {statistics.median(py):.4e}/s  cli {statistics.median(cli):.4e}/s  "
          f"ratio {statistics.median(ratio):.4f} (min {min(ratio):.4f}, max {max(ratio):.4f})")


if __name__ == "__main__":
    main()
