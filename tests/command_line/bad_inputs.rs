//! The bad inputs every subcommand must refuse with exit status 2 and one line naming the valid
//! range (`commands::bad_input_is_refused_with_status_2_one_line_and_no_files`).

/// (command line, split at white space; a word the one-line message must contain)
pub(crate) const BAD: &[(&str, &str)] = &[
    // diffusion
    ("diffusion --w 0", "0 < w < 4/sqrt(3) - 2"),
    ("diffusion --w -0.1", "trapped"),
    ("diffusion --w 0.31", "0.309"),
    ("diffusion --w 0.3094010767585031", "infinite"),
    ("diffusion --w NaN", "finite"),
    ("diffusion --w inf", "finite"),
    ("diffusion --w abc", "invalid value"),
    (
        "diffusion --w 1e-300 --collisions 1000",
        "more than any run",
    ),
    ("diffusion --w 0.1 --precision 52", "53"),
    ("diffusion --w 0.1 --rel-err 0", "[1e-7, 0.5]"),
    ("diffusion --w 0.1 --rel-err 0.7", "[1e-7, 0.5]"),
    ("diffusion --w 0.1 --rel-err NaN", "[1e-7, 0.5]"),
    ("diffusion --w 0.1 --rel-err 1e-9", "[1e-7, 0.5]"),
    ("diffusion --w 0.1 --precision double", "f64"),
    (
        "diffusion --w 0.1 --msd-grid fine",
        "use fit (the fit windows' lags), log",
    ),
    (
        "diffusion --w 0.1 --field 1 --msd-grid log",
        "measured without a field",
    ),
    ("diffusion --w 0.1 --collisions 0", "collisions"),
    ("diffusion --w 0.1 --collisions -5", "whole number"),
    ("diffusion --w 0.1 --collisions 1.5", "whole number"),
    ("diffusion --w 0.1 --collisions 1e20", "too large"),
    ("diffusion --w 0.1 --batches 0", "batches"),
    ("diffusion --w 0.1 --engine gpu", "simd"),
    (
        "diffusion --w 0.1 --engine simd --precision 128",
        "f64 only",
    ),
    ("diffusion --w 0.1 --collisions 1e18 --batches 2", "2^50"),
    ("hops --w 0.1 --engine fast", "scalar"),
    ("bench --w 0.1 --observe all", "diffusion"),
    ("diffusion --w 0.1 --batches 1", "batches"),
    ("diffusion --w 0.1 --batches 5e9", "4294967295"),
    (
        "diffusion --w 0.1 --batches 4e9 --collisions 1e19",
        "at most 1048576",
    ),
    (
        "sweep --w-from 0.1 --w-to 0.2 --steps 4e9 --out out",
        "2 to 10000",
    ),
    (
        "audit --w 0.1 --batches 4e9 --collisions 1e19",
        "at most 1048576",
    ),
    ("diffusion --w 0.1 --collisions 1000", "too small"),
    ("diffusion --w 0.1 --threads 0", "threads must be from 1"),
    ("diffusion --w 0.1 --threads 1e9", "threads must be from 1"),
    ("diffusion --w 0.1 --threads 4096", "4 per core"),
    ("bench --w 0.1 --threads 4096", "4 per core"),
    ("diffusion --w 0.1 --window 40:10", "window"),
    ("diffusion --w 0.1 --audit 2", "(0, 1]"),
    ("diffusion --w 0.1 --audit 0.1 --reference-bits 64", "128"),
    // audit
    ("audit --w 0", "trapped"),
    ("audit --w 0.1 --collisions 0", "collisions"),
    ("audit --w 0.1 --batches 0", "batches"),
    ("audit --w 0.1 --sample 0", "(0, 1]"),
    ("audit --w 0.1 --sample 1.5", "(0, 1]"),
    ("audit --w 0.1 --reference-bits 64", "128"),
    ("audit --w 0.1 --field 1e7", "1e6"),
    ("audit --w 0.1 --field -1e-7", "1e-6"),
    ("audit --w 0.1 --field one", "field"),
    ("diffusion --w 0.1 --field one", "field"),
    ("diffusion --w 0.1 --electric 11", "0 < |E| <= 10"),
    ("diffusion --w 0.1 --electric one", "electric"),
    (
        "diffusion --w 0.1 --electric 1 --electric-angle 361",
        "-360 to 360",
    ),
    ("diffusion --w 0.1 --electric-angle 30", "--electric"),
    (
        "diffusion --w 0.1 --electric 1 --field 1",
        "cannot be used with",
    ),
    (
        "diffusion --w 0.1 --electric 1 --rel-err 1e-3",
        "thermostatted field",
    ),
    (
        "diffusion --w 0.1 --electric 1 --checkpoint c.ck",
        "checkpoint",
    ),
    ("diffusion --w 0.1 --electric 1 --engine simd", "engine"),
    ("diffusion --w 0.1 --electric 1 --audit 0.1", "audit"),
    (
        "diffusion --scene square --radius 1/4 --electric 1",
        "lacks a finite horizon",
    ),
    // the thermostatted field beside diffusion: lyapunov, trajectory, bench
    ("lyapunov --w 0.1 --electric 11", "0 < |E| <= 10"),
    ("lyapunov --w 0.1 --electric one", "electric"),
    (
        "lyapunov --w 0.1 --electric 1 --electric-angle 361",
        "-360 to 360",
    ),
    ("lyapunov --w 0.1 --electric-angle 30", "--electric"),
    (
        "lyapunov --w 0.1 --electric 1 --field 1",
        "cannot be used with",
    ),
    (
        "lyapunov --w 0.1 --electric 1 --starts 4",
        "under the thermostat",
    ),
    (
        "lyapunov --w 0.1 --electric 1 --flights jump",
        "cell by cell",
    ),
    ("lyapunov --w 0.1 --electric 1 --batches 1", "at least 2"),
    (
        "trajectory --scene triangular --w 1/10 --start 0,1.05 --direction 1,0 --time 1 --electric 11",
        "0 < |E| <= 10",
    ),
    (
        "trajectory --scene triangular --w 1/10 --start 0,1.05 --direction 1,0 --time 1 --electric x",
        "electric",
    ),
    (
        "trajectory --scene triangular --w 1/10 --start 0,1.05 --direction 1,0 --time 1 --electric 1 --electric-angle -400",
        "-360 to 360",
    ),
    (
        "trajectory --scene triangular --w 1/10 --start 0,1.05 --direction 1,0 --time 1 --electric-angle 3",
        "--electric",
    ),
    (
        "trajectory --scene triangular --w 1/10 --start 0,1.05 --direction 1,0 --time 1 --electric 1 --field 1",
        "cannot be used with",
    ),
    (
        "bench --w 0.1 --electric 1 --electric-angle 1/0",
        "divides by zero",
    ),
    (
        "bench --w 0.1 --electric 1 --electric-angle 720",
        "-360 to 360",
    ),
    ("bench --w 0.1 --electric-angle 45", "--electric"),
    ("bench --w 0.1 --oracle-floor", "--field"),
    ("audit --w 0.1 --reference-bits 4000000000", "65536"),
    // scenes
    ("audit --scene square --radius 0.5", "0 < radius < 1/2"),
    ("audit --scene square --radius -1/3", "0 < radius < 1/2"),
    ("audit --scene square --radius 1/0", "divides by zero"),
    ("audit --scene square --radius x", "not a decimal"),
    ("audit --scene square", "needs --radius"),
    (
        "certify --scene square --radius inf",
        "radius must be a finite number",
    ),
    ("shadow --w nan", "w must be a finite number"),
    ("shadow --w 1/0", "divides by zero"),
    (
        "figure backscatter-map --w 1/0 --out out",
        "divides by zero",
    ),
    (
        "trajectory --scene square --radius nan --start 0,0 --direction 1,0 --time 1",
        "radius must be a finite number",
    ),
    (
        "audit --scene square --radius 0.3 --w 0.1",
        "does not apply",
    ),
    ("audit --scene hexagonal --w 0.1", "triangular"),
    ("lyapunov --w 0.1 --radius 0.3", "does not apply"),
    ("certify --scene square --radius 0.7", "0 < radius < 1/2"),
    (
        "diffusion --scene square --radius 1/3",
        "in a magnetic field every scene has a finite horizon",
    ),
    (
        "diffusion --scene square --radius 1/3 --field 1 --rel-err 1e-3",
        "not planned for a relative error",
    ),
    ("diffusion --collisions 1e6", "needs --w"),
    (
        "sweep --scene square --radius 1/4 --w-from 0.1 --w-to 0.2",
        "sweep over w without a field is the triangular scene's",
    ),
    (
        "sweep --scene square --fields=1,2",
        "the square scene needs --radius",
    ),
    // superdiffusion
    ("superdiffusion --w 0.1", "finite horizon"),
    (
        "superdiffusion --scene square --radius 1/2",
        "0 < radius < 1/2",
    ),
    (
        "superdiffusion --scene square --radius 1/4 --batches 4",
        "at least 16",
    ),
    ("superdiffusion --w 0.5 --msd-fit 64:8", "FROM:TO"),
    ("superdiffusion --w 0.5 --vacf-fit 64:8192", "2^octaves"),
    ("superdiffusion --w 0.5 --collisions 1e5", "per batch"),
    // lyapunov
    ("lyapunov --w -0.4", "trapped"),
    ("lyapunov --w 0.1 --batches 1", "batches"),
    ("lyapunov --w 0.1 --collisions-per-batch 0", "collisions"),
    ("lyapunov --w 0.1 --starts 1e6", "starts"),
    // certify
    ("certify --w 0", "trapped"),
    ("certify --w 0.1 --collisions 0", "collisions"),
    ("certify --w 0.1 --digits 0", "digits"),
    ("certify --w 0.1 --digits -3", "whole number"),
    ("diffusion --w 0.1 --seed -1", "whole number"),
    (
        "certify --w 0.1 --collisions 100000000000",
        "use at most 33007 collisions (where the memory limit of 4 GiB binds)",
    ),
    ("certify --w 0.1 --collisions 200000 --digits 10", "memory"),
    // shadow
    ("shadow --w 0.4", "0 < w < 0.309401"),
    (
        "shadow --w 0.1 --collisions-per-segment 0",
        "use 2 to 10000",
    ),
    (
        "shadow --w 0.1 --collisions-per-segment 2e4",
        "use 2 to 10000",
    ),
    ("shadow --w 0.1 --reference-bits 64", "use 128 to"),
    ("shadow --w 0.1 --segments 0", "use 1 to 10000"),
    ("shadow --w 0.1 --electric 11", "0 < |E| <= 10"),
    (
        "shadow --w 0.1 --electric 1 --electric-angle 361",
        "-360 to 360",
    ),
    ("shadow --w 0.1 --electric-angle 30", "--electric"),
    (
        "shadow --w 0.1 --electric 1 --field 1",
        "cannot be used with",
    ),
    // backscatter
    ("backscatter --w 0", "trapped"),
    ("backscatter --w 0.1 --particles 0", "particles"),
    ("backscatter --w 0.1 --batches 1", "batches"),
    ("backscatter --w 0.1 --precision 20", "53"),
    // hops
    ("hops --w 0.35", "infinite"),
    ("hops --w 0.1 --collisions 0", "collisions"),
    ("hops --w 0.1 --order 0", "order"),
    ("hops --w 0.1 --order 100", "order"),
    ("hops --w 0.1 --batches 1", "batches"),
    // checkpoint intervals
    ("diffusion --w 0.1 --checkpoint-every -1", "0 to 86400"),
    ("hops --w 0.1 --checkpoint-every 1e6", "0 to 86400"),
    ("escape --w 0.1 --checkpoint-every soon", "0 to 86400"),
    (
        "sweep --w-from 0.1 --w-to 0.2 --checkpoint-every NaN",
        "0 to 86400",
    ),
    // lyapunov in a field
    (
        "lyapunov --scene triangular --w 0.1 --field 1 --starts 4",
        "not measured in a field",
    ),
    (
        "lyapunov --scene triangular --w 0.1 --field 5000",
        "1e-3 <= |field| <= 1e3",
    ),
    // trajectory in a field
    (
        "trajectory --scene triangular --w 0.1 --start 1.05,0 --direction 0,1 --time 1 \
         --field 2000000",
        "|field| <= 1e6",
    ),
    // sweep in a field
    (
        "sweep --w 0.1 --fields=0,1 --out out",
        "1e-3 <= |field| <= 1e3",
    ),
    ("sweep --w 0.1 --fields=1,1 --out out", "appears twice"),
    (
        "sweep --w 0.1 --fields=1 --runs 2 --out out",
        "--runs 2: not used by a sweep in a field",
    ),
    (
        "sweep --w 0.1 --w-from 0.1 --w-to 0.2 --field 1",
        "not both",
    ),
    ("sweep --w 0.1 --out out", "--fields"),
    ("sweep --w 0.1 --field 1 --fields=2 --out out", "not both"),
    (
        "sweep --w-from 0.1 --w-to 0.2 --field 1 --shard 0/2000",
        "has parts 0 to N-1",
    ),
    // sweep
    ("sweep --w-from 0.1 --w-to 0.5 --out out", "infinite"),
    ("sweep --w-from 0.1 --w-to 0.2 --steps 1 --out out", "steps"),
    ("sweep --w-from 0.1 --w-to 0.2 --runs 0 --out out", "runs"),
    (
        "sweep --w-from 0.1 --w-to 0.2 --batches-per-run 1 --out out",
        "batches",
    ),
    ("sweep --w-from abc --w-to 0.2 --out out", "decimal"),
    (
        "sweep --w-from 0.1 --w-to 0.1 --steps 3 --out out",
        "distinct w",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.1 --array 2 --out out",
        "distinct w",
    ),
    (
        "sweep --w-from 0.1 --w-to 0.2 --collisions-per-run 1000 --out out",
        "too small",
    ),
    (
        "sweep --w-from 0.1 --w-to 0.2 --shard 3/3 --out out",
        "0 to N-1",
    ),
    ("sweep --w-from 0.1 --w-to 0.2 --shard a/b --out out", "I/N"),
    (
        "sweep --w-from 0.1 --w-to 0.2 --shard 11/12 --out out",
        "every part needs a point",
    ),
    // report, reproduce
    ("report r.json --reference-bits 64", "128 to 65536"),
    ("report r.json --reference-bits 1e6", "128 to 65536"),
    ("report r.json --seed 2", "unexpected argument '--seed'"),
    ("reproduce --budget huge --out out", "invalid value"),
    (
        "reproduce --budget quick --threads 0 --out out",
        "threads must be from 1 to",
    ),
    ("reproduce --seed -1 --out out", "is not a count"),
    // trajectory: the start, the direction, the time and the digits
    (
        "trajectory --scene square --radius 1/3 --start 0,0 --direction 1,0 --time 1",
        "distance >= the radius",
    ),
    (
        "trajectory --scene square --radius 1/3 --start 1/2 --direction 1,0 --time 1",
        "--start '1/2': not a pair",
    ),
    (
        "trajectory --scene square --radius 1/3 --start 1/2,1/10 --direction 0,0 --time 1",
        "use a nonzero direction",
    ),
    (
        "trajectory --scene square --radius 1/3 --start 1/2,1/10 --direction 1,0 --time 0",
        "use a time > 0",
    ),
    (
        "trajectory --scene square --radius 1/3 --start 1/2,1/10 --direction 1,0 --time 1e30",
        "use a shorter time",
    ),
    (
        "trajectory --scene square --radius 1/3 --start 1/2,1/10 --direction 1,0 --time 1 \
         --digits 20000",
        "use 1 to 10000",
    ),
    // one value is not an error bar; a check window equal to the fit window checks nothing
    (
        "lyapunov --w 0.1 --starts 1",
        "use 0 (no divergence measurement) or 2 to",
    ),
    (
        "diffusion --w 0.1 --window 10:40 --check-window 10:40",
        "is the fit window 10:40",
    ),
    ("sweep --w-from 1/0 --w-to 0.2 --out out", "divides by zero"),
    // merge
    ("merge no-such-dir --out out", "no sweep points"),
    ("merge --out out", "required"),
    ("merge d --seed 2", "unexpected argument '--seed'"),
    // slurm
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 0 --out out",
        "1 to 11 parts",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 12 --out out",
        "1 to 11 parts",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --time 2h --out out",
        "2:00:00",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --cpus-per-task 0 --out out",
        "cpus-per-task",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.5 --array 4 --out out",
        "infinite",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --threads 2 --out out",
        "unexpected argument '--threads'",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --account a;id --out out",
        "letters, digits",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --mem 4GB --out out",
        "K, M, G or T",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --sbatch=--qos=$(id) --out out",
        "--key=value",
    ),
    (
        "slurm sweep --w-from 0.1 --w-to 0.2 --array 4 --sbatch=--array=0-99 --out out",
        "written by the campaign",
    ),
    // figure
    ("figure fig9 --out out", "unrecognized subcommand"),
    (
        "figure backscatter --w 0.1 --out out",
        "unexpected argument '--w'",
    ),
    (
        "figure hierarchy --particles-per-gap 10 --out out",
        "unexpected argument",
    ),
    ("figure backscatter-map --w 0 --out out", "trapped"),
    (
        "figure backscatter-map --particles 0 --out out",
        "particles",
    ),
    // theory
    ("theory --w 0", "trapped"),
    ("theory --w 0.1 --order 0", "order"),
    ("theory --w 0.1 --order 100", "order"),
    // lattice-walk
    ("lattice-walk --w 0", "trapped"),
    ("lattice-walk --w 0.1 --order 0", "order"),
    ("lattice-walk --w 0.1 --order 100", "order"),
    // escape
    ("escape --w 0", "trapped"),
    (
        "escape --w 0.1 --widths 3,20,30",
        "--widths 3 is out of range: use widths L from",
    ),
    ("escape --w 0.1 --widths 20,30", "3 distinct"),
    ("escape --w 0.1 --particles-per-width 0", "particles"),
    ("escape --w 0.1 --particles-per-width 1e12", "particles"),
    (
        "escape --repeller --side 2",
        "--side 2 is out of range: use a side R > 2a = 2",
    ),
    (
        "escape --repeller --radius 0",
        "--radius 0 is out of range: use a radius a > 0",
    ),
    ("escape --repeller --side six", "--side"),
    (
        "escape --repeller --particles 10",
        "--particles 10 is out of range: use 32000 to",
    ),
    (
        "escape --repeller --window 0",
        "--window 0 is out of range: use 1 to 20",
    ),
    ("escape --repeller --window 21", "use 1 to 20"),
    ("escape --repeller --w 0.1", "cannot be used with"),
    ("escape --repeller --checkpoint c.jsonl", "checkpoint"),
    ("escape --side 5", "--repeller"),
    // constants
    ("constants --w 0", "trapped"),
    ("constants --scene square --radius 1/2", "0 < radius < 1/2"),
    ("constants --scene square --w 0.1", "--radius"),
    ("constants --scene square --radius 1/4096", "1/2048"),
    ("constants --w 10000", "w <= 2362"),
    ("constants --w 0.1 --precision 20", "53"),
    ("constants --w 0.1 --precision 2000000000", "1048576"),
    ("diffusion --w 0.1 --precision 99999999999", "1048576"),
    // bench
    ("bench --w 0.1 --collisions-per-thread 0", "collisions"),
    ("bench --w 0.1 --collisions 1e5", "unexpected argument"),
    ("bench --w -1", "trapped"),
    (
        "bench --w 0.1 --repetitions 0",
        "--repetitions 0 is out of range: use 1 to",
    ),
    ("bench --w 0.1 --threads 0", "threads"),
    (
        "bench --w 0.1 --observer-costs --repetitions 0",
        "--repetitions 0 is out of range: use 1 to",
    ),
    (
        "bench --w 0.1 --observer-costs --precision 128",
        "cannot be used with",
    ),
    ("bench --long-flights 1/4,1/3", "use 2^-32 <= radius <= 1/4"),
    (
        "bench --long-flights 1/4,r",
        "--long-flights r: 'r' is not a decimal number",
    ),
    (
        "bench --long-flights 1/4 --threads 2",
        "cannot be used with",
    ),
    ("bench --long-flights 1/4 --w 0.1", "cannot be used with"),
    (
        "bench --walk-collisions 10 --w 0.1",
        "--walk-collisions 10: applies with --long-flights only",
    ),
    (
        "bench --scene square --w 0.1",
        "--scene square: applies with --long-flights only",
    ),
    (
        "bench --scene triangular --long-flights 10,0.2",
        "use w_inf = 4/sqrt(3) - 2 < w <= 2^20 - 2",
    ),
    ("bench", "--w"),
    // cycles: R and a decided exactly (R = 2a touches), N and the bits in their ranges
    (
        "cycles --side 2 --radius 1",
        "--side 2 is out of range: use a finite side R > 2a = 2",
    ),
    ("cycles --side 6 --radius 3", "R > 2a = 6"),
    (
        "cycles --radius 0",
        "--radius 0 is out of range: use a finite radius a > 0",
    ),
    ("cycles --radius -1", "a > 0"),
    (
        "cycles --side nan",
        "--side NaN is out of range: use a finite side R > 2a",
    ),
    ("cycles --side six", "--side six"),
    ("cycles --max-length 0", "use 1 to 16"),
    ("cycles --max-length 17", "use 1 to 16"),
    (
        "cycles --bits 64",
        "--bits 64 is out of range: use 128 to 4096 bits",
    ),
    ("cycles --threads 0", "threads must be from 1"),
    ("cycles --out . --max-length 1", "directory"),
];

/// [`BAD`] for arguments with white space in them.
pub(crate) const BAD_WITH_SPACES: &[(&[&str], &str)] = &[(
    &[
        "slurm",
        "sweep",
        "--w-from",
        "0.1",
        "--w-to",
        "0.2",
        "--array",
        "4",
        "--partition",
        "a b",
        "--out",
        "out",
    ],
    "partition",
)];
