//! Work priced before it starts: each input a hostile tester found running for days, years or
//! for ever is refused before any work (well under a second on an idle machine), exit status 2,
//! with one line naming the estimate (the collisions, the time at the floor costs and the limit
//! of a week) and the parameters to lower.

use std::time::{Duration, Instant};

use crate::common::{lorentz_in as lorentz, scratch};

/// Runs `args` and checks the refusal: status 2 within a second, one line naming the estimate,
/// the week and a flag to lower.
fn refused(args: &str) {
    let dir = scratch();
    let start = Instant::now();
    let argv: Vec<&str> = args.split(' ').chain(["--quiet"]).collect();
    let (code, out, err) = lorentz(dir.path(), &argv);
    let took = start.elapsed();
    assert_eq!(code, 2, "`lorentz {args}` was not refused: {out}{err}");
    // Refused before the work starts (the work would take more than a week); the bound is loose
    // because the machine running the tests is shared (no timing claim is made here).
    assert!(
        took < Duration::from_secs(20),
        "`lorentz {args}` took {took:?} to refuse"
    );
    let line = err.trim();
    assert_eq!(line.lines().count(), 1, "one line: {err}");
    assert!(line.contains("would compute about"), "no estimate: {err}");
    assert!(
        line.contains("beyond the limit of a week"),
        "no limit: {err}"
    );
    assert!(line.contains("; lower --"), "no parameter to lower: {err}");
}

#[test]
fn mpfr_at_a_million_bits_is_priced_by_its_precision() {
    refused("diffusion --w 0.1 --precision 1048576 --collisions 1e12");
    refused("audit --w 0.1 --reference-bits 65536 --sample 1 --collisions 1e10");
    refused("diffusion --w 0.1 --collisions 1e10 --audit 1 --reference-bits 65536");
}

#[test]
fn walks_are_priced_per_cell() {
    refused("lyapunov --w 1048575 --collisions-per-batch 1e9");
    refused("free-paths --scene square --radius 1e-6 --flights walk --collisions 1e9");
    refused("bench --long-flights 2.33e-10");
    refused("audit --scene square --radius 1e-9 --collisions 1e9");
}

#[test]
fn shadows_plans_and_certificates_are_priced() {
    refused("shadow --w 0.1 --segments 10000 --reference-bits 65536");
    refused("trajectory --scene square --radius 1e-9 --start 0.5,0.5 --direction 1,0 --time 10");
    refused("certify --scene square --radius 1e-9 --collisions 10");
}

#[test]
fn the_field_goes_through_the_same_check() {
    refused("diffusion --w 0.1 --field 1 --collisions 1e17 --batches 1000");
    refused("lyapunov --w 0.1 --field 1 --collisions-per-batch 1e15 --batches 1000");
    refused("sweep --w 0.1 --fields 1,2,3 --collisions-per-run 1e15");
    // The exact pinned share's quadrature grows as the cube of the rows within rho + r, and an
    // arc crosses up to 2 pi rho / tau cells: both priced before anything starts. Sixty-four
    // fields from rho = 1000 down on r = 1e-4 (2001 rows and fewer) are 12 days at the
    // quadrature's floor on 2 threads (about seven times that measured with such thin annuli).
    refused("diffusion --scene square --radius 1e-4 --field 1e-3 --collisions 1e11");
    let fields: Vec<String> = (0..64)
        .map(|k| format!("{}", 1e-3 + 1e-5 * k as f64))
        .collect();
    let sweep = format!(
        "sweep --scene square --radius 1e-4 --fields {} --collisions-per-run 1e5",
        fields.join(",")
    );
    refused(&sweep);
}

/// The wall time of `lorentz args` on one thread, in seconds.
fn wall(args: &str) -> f64 {
    let dir = scratch();
    let argv: Vec<&str> = args
        .split(' ')
        .chain(["--threads", "1", "--quiet"])
        .collect();
    let start = Instant::now();
    let (code, out, err) = lorentz(dir.path(), &argv);
    assert_eq!(code, 0, "`lorentz {args}`: {out}{err}");
    start.elapsed().as_secs_f64()
}

/// The model's floor against a real run of each cost class: the measured wall time is at least
/// the floor (a floor can only be exceeded by noise), and at most 50 times it. The floors are
/// about half the bare engine's cost; a run adds its observers (up to a few times the bare
/// engine, `lorentz bench --observer-costs`), its set-up and the process's start, and a shared
/// machine may run it two or three times slower: 2 · 5 · 3 = 30 < 50. A floor 50 times too low
/// would accept work 50 times beyond the week.
#[test]
fn floors_are_below_real_runs_and_not_absurdly_so() {
    use lorentz_gas::engine::work::{
        self, ARC_SIMD_SECONDS_PER_COLLISION, SCALAR_SECONDS_PER_COLLISION, SECONDS_PER_CROSSING,
        Work, mpfr_seconds_per_collision, shadow_collisions_per_collision,
    };
    use lorentz_gas::scenes::square::SquareScene;
    let square = SquareScene::exact(rug::Rational::from((1, 10_000))).unwrap();
    let walk = work::crossings_per_collision(&square) * SECONDS_PER_CROSSING;
    let cases = [
        (
            "audit --w 0.1 --reference-bits 16384 --sample 1 --collisions 2000",
            2000.0 * (SCALAR_SECONDS_PER_COLLISION + mpfr_seconds_per_collision(16_384)),
        ),
        (
            "shadow --w 0.1 --segments 1 --collisions-per-segment 100 --reference-bits 1024",
            100.0 * shadow_collisions_per_collision(1024) * mpfr_seconds_per_collision(1024),
        ),
        (
            "free-paths --scene square --radius 1/10000 --flights walk --collisions 3000 --batches 2",
            3000.0 * walk,
        ),
        (
            "diffusion --w 0.1 --field 1 --collisions 4e6",
            4e6 * ARC_SIMD_SECONDS_PER_COLLISION,
        ),
    ];
    for (args, floor) in cases {
        let measured = wall(args);
        assert!(
            measured >= floor,
            "`{args}`: {measured} s, below the floor {floor} s"
        );
        assert!(
            measured <= 50.0 * floor,
            "`{args}`: {measured} s, over 50 x the floor {floor} s"
        );
    }
    // The check itself refuses what the model prices beyond the week.
    let e = Work::new("diffusion", &["collisions"], 1e12)
        .at(lorentz_gas::numbers::precision::Precision::Bits(1 << 20));
    assert!(e.check(1).is_err());
}
