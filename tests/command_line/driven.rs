//! The driven gas (the Gaussian-thermostatted electric field) beside `diffusion --electric`:
//! `lyapunov --electric`, `trajectory --electric` and `bench --electric --electric-angle`. No bit
//! of a thermostatted flight is pinned (its march may change in the last bits): the tests assert
//! the sum rule within its statistical bound and its rounding bound, the pair against the
//! diffusion run's within a Welch bound, certified digits against a symmetry of the exact
//! trajectory, and E = 0 against the field-free bits.

use rug::ops::Pow;

use crate::common::{lorentz_json, physics_only, scratch, t4_welch, words};

/// A result's JSON without its metadata (the command line, the time), nested ones included.
fn bits_of(mut v: serde_json::Value) -> serde_json::Value {
    if let Some(t) = v.get_mut("tangent").and_then(|t| t.as_object_mut()) {
        t.remove("meta");
    }
    physics_only(v)
}

fn num(v: &serde_json::Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} in {v}"))
}

/// The pair of `lyapunov --electric` keeps the sum rule — on average within the paired Student-t
/// bound it reports, per trajectory within its rounding bound — and agrees with the pair the
/// steady-state run `diffusion --electric` measures on independent streams (Welch, the "4σ"
/// bound). Broken on purpose: with ⟨α⟩ taken with the wrong sign in the paired comparison the
/// sum rule fails at z = −53 (checked once, then restored).
#[test]
fn lyapunov_under_the_thermostat_keeps_the_sum_rule_and_matches_the_diffusion_run() {
    let tmp = scratch();
    let dir = tmp.path();
    let field = "--w 0.2 --electric 1/2 --electric-angle 30 --json --quiet";
    let l = lorentz_json(
        dir,
        &words(&format!(
            "lyapunov {field} --collisions-per-batch 4e4 --batches 8"
        )),
    );
    let rule = &l["sum_rule"];
    let (z, bound) = (num(rule, "z"), num(rule, "bound"));
    assert!(z.abs() <= bound, "sum rule on average: {rule}");
    let (residual, rounding) = (
        num(&l, "sum_rule_residual"),
        num(&l, "sum_rule_residual_bound"),
    );
    assert!(
        residual <= rounding,
        "per trajectory: {residual} > {rounding}"
    );
    let (plus, minus) = (num(&l, "lambda_plus"), num(&l, "lambda_minus"));
    assert!(plus > 0.0 && minus < 0.0, "{plus} {minus}");
    let ky = num(&l, "kaplan_yorke");
    assert!(ky > 2.0 && ky < 3.0, "Kaplan-Yorke {ky}");
    assert_eq!(l["tangent"]["per_time"], l["lambda_plus"]);
    let d = lorentz_json(
        dir,
        &words(&format!(
            "diffusion {field} --collisions 3.2e5 --batches 8 --seed 2"
        )),
    );
    for (ours, theirs) in [
        ("lambda_plus", "lambda_plus"),
        ("lambda_minus", "lambda_minus"),
        ("contraction", "entropy_production"),
    ] {
        let (a, ea) = (num(&l, ours), num(&l, &format!("{ours}_err")));
        let (b, eb) = (num(&d, theirs), num(&d, &format!("{theirs}_err")));
        let bound = t4_welch(ea, 8, eb, 8);
        let z = (a - b).abs() / ea.hypot(eb);
        assert!(
            z <= bound,
            "{ours} {a} ± {ea} against {theirs} {b} ± {eb}: {z:.2}σ > {bound:.2}σ"
        );
    }
}

/// `--electric 0` is the measurement without a field, with its bits (whatever the angle).
/// Broken on purpose: a zero field kept as a thermostat is refused ("needs a nonzero field"),
/// and the test fails (checked once, then restored).
#[test]
fn lyapunov_and_trajectory_at_zero_field_are_the_straight_runs() {
    let tmp = scratch();
    let dir = tmp.path();
    let base = "lyapunov --w 0.1 --collisions-per-batch 2e4 --batches 2 --starts 0 --json --quiet";
    let straight = bits_of(lorentz_json(dir, &words(base)));
    let zero = format!("{base} --electric 0/7 --electric-angle 30");
    assert_eq!(bits_of(lorentz_json(dir, &words(&zero))), straight);
    let base = "trajectory --scene triangular --w 1/10 --start 0,1.05 --direction 1,1/3 --time 20 --json --quiet";
    let straight = bits_of(lorentz_json(dir, &words(base)));
    let zero = format!("{base} --electric 0 --electric-angle 45");
    assert_eq!(bits_of(lorentz_json(dir, &words(&zero))), straight);
}

/// The printed decimal `text` with `digits` certified digits as an MPFR number, and the size of
/// one unit of its last digit (digits counted from the leading digit for |q| ≥ 1, from the first
/// decimal place below: `estimators::trajectory`'s rule).
fn value_and_unit(text: &str, digits: u32) -> (rug::Float, rug::Float) {
    let q = rug::Float::with_val(1024, rug::Float::parse(text).unwrap());
    let lead = if q.clone().abs() >= 1 {
        text.trim_start_matches('-')
            .split('.')
            .next()
            .unwrap()
            .len() as i32
    } else {
        0
    };
    let unit = rug::Float::with_val(1024, 10).pow(lead - digits as i32);
    (q, unit)
}

/// `trajectory --electric` certifies its digits under the thermostat, and the exact trajectory
/// under −E at θ + 180° is the one under E at θ: the two runs (different roundings of the field's
/// direction) go through the same events and their printed values, each within one unit of its
/// last digit of the exact value, differ by at most two such units — while the straight
/// trajectory differs from them far beyond that (the field is flown). Broken on purpose: with the
/// field's sign dropped (|E| along θ) the two runs part (checked once, then restored).
#[test]
fn trajectory_under_the_thermostat_is_certified_and_minus_e_is_e_turned_half_way() {
    let tmp = scratch();
    let dir = tmp.path();
    let base = "trajectory --scene triangular --w 1/10 --start 0,1.05 --direction 1,1/3 --time 20 --digits 30 --json --quiet";
    let run = |extra: &str| lorentz_json(dir, &words(&format!("{base} {extra}")));
    let a = run("--electric 3/10 --electric-angle 30");
    let b = run("--electric -0.3 --electric-angle 210");
    let straight = run("");
    assert_eq!(a["electric"], "3/10");
    assert_eq!(a["electric_angle"], "30");
    for k in ["collisions", "crossings"] {
        assert_eq!(a[k], b[k], "{k}");
    }
    let digits = a["certified_digits"]
        .as_u64()
        .unwrap()
        .min(b["certified_digits"].as_u64().unwrap()) as u32;
    assert!(digits >= 30, "{digits}");
    for k in ["x", "y", "distance"] {
        let (qa, unit) = value_and_unit(a[k].as_str().unwrap(), digits);
        let (qb, _) = value_and_unit(b[k].as_str().unwrap(), digits);
        let apart = (qa.clone() - &qb).abs();
        assert!(
            apart <= unit.clone() * 2u32,
            "{k}: {} against {}",
            a[k],
            b[k]
        );
        let (qs, _) = value_and_unit(straight[k].as_str().unwrap(), 1);
        assert!(
            (qa - qs).abs() > unit * 1000u32,
            "{k}: the field changed nothing"
        );
    }
}

/// `bench --electric E --electric-angle DEG` flies the field along the angle typed, exactly: at
/// 90° the direction is (0, 1) to the bit, at 45° its components are equal. Broken on purpose:
/// with the angle ignored the direction is (1, 0) (checked once, then restored).
#[test]
fn bench_takes_the_field_angle_exactly() {
    let tmp = scratch();
    let dir = tmp.path();
    let base = "bench --w 0.1 --electric 0.3 --collisions-per-thread 1e4 --repetitions 1 --engine scalar --json --quiet";
    let at = |angle: &str| {
        let r = lorentz_json(dir, &words(&format!("{base} --electric-angle {angle}")));
        assert_eq!(r["electric_angle"], angle);
        assert!(num(&r, "paired_ratio") > 0.0, "{r}");
        [
            r["direction"][0].as_f64().unwrap(),
            r["direction"][1].as_f64().unwrap(),
        ]
    };
    assert_eq!(at("90"), [0.0, 1.0]);
    let [x, y] = at("45");
    assert!(
        (x - y).abs() <= f64::EPSILON && (x - 0.5f64.sqrt()).abs() <= f64::EPSILON,
        "{x} {y}"
    );
}

/// `bench --electric E --oracle-floor`: a tape of the seed's thermostatted walk (the run's
/// collisions per thread), every event found again by the winner alone beside the full search;
/// the floor's numbers are those its definition gives (its rate 10⁹/ns, its ratio to straight
/// flights the median of each repetition's), and the tape is the seed's: two runs record
/// the same events and find the same number of them again identically.
#[test]
fn bench_times_the_thermostats_winner_only_floor_on_a_tape_of_its_walk() {
    let tmp = scratch();
    let dir = tmp.path();
    let cmd = "bench --w 0.2 --electric 0.3 --electric-angle 30 --collisions-per-thread 5000 --repetitions 3 --engine scalar --oracle-floor --json --quiet";
    let r = lorentz_json(dir, &words(cmd));
    let o = &r["oracle"];
    let count = |k: &str| o[k].as_u64().unwrap();
    assert_eq!(count("collisions"), 5000, "{o}");
    // 0.19 crossings a collision at w = 0.2: between one and two events a collision.
    assert!(count("events") > 5000 && count("events") < 10000, "{o}");
    assert!(count("identical") <= count("events"), "{o}");
    assert_eq!(
        num(o, "floor_collisions_per_second"),
        1e9 / num(o, "floor_ns_per_collision")
    );
    // Each repetition's floor rate over its straight flights' (one thread), the median of three.
    let samples = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let (floor, straight) = (samples(&o["samples"]), samples(&r["straight_samples"]));
    let mut over: Vec<f64> = floor
        .iter()
        .zip(&straight)
        .map(|(f, s)| 1e9 / f / s)
        .collect();
    over.sort_by(f64::total_cmp);
    assert_eq!((floor.len(), samples(&o["full_samples"]).len()), (3, 3));
    assert_eq!(num(o, "floor_over_straight"), over[1]);
    assert!(num(o, "paired_ratio") > 0.0 && num(o, "full_ns_per_collision") > 0.0);
    let again = lorentz_json(dir, &words(cmd));
    for k in ["events", "collisions", "identical"] {
        assert_eq!(again["oracle"][k], o[k], "{k}");
    }
    let plain = lorentz_json(dir, &words(&cmd.replace(" --oracle-floor", "")));
    assert!(plain.get("oracle").is_none(), "{plain}");
}

/// `shadow --electric`: a short thermostatted segment is shadowed by a true orbit with its
/// Newton–Kantorovich certificate (δ within 2K‖F(y⁰)‖₂, the correction bound 2Kε far below δ),
/// and E = 0 is the field-free run bit for bit. Broken on purpose: with the thermostat dropped
/// from the shadow's table (straight true flights against thermostatted f64 segments) no
/// segment converges (checked once, then restored).
#[test]
fn shadow_under_the_thermostat_is_certified_and_zero_field_is_the_straight_run() {
    let tmp = scratch();
    let dir = tmp.path();
    let base = "shadow --w 0.1 --collisions-per-segment 50 --segments 2 --json --quiet";
    let driven = format!("{base} --electric 0.3 --electric-angle 30");
    let r = lorentz_json(dir, &words(&driven));
    assert_eq!(r["config"]["electric"], "0.3", "{r}");
    assert_eq!(r["certified"], 2, "{r}");
    for s in r["segments"].as_array().unwrap() {
        let delta = num(s, "delta");
        assert!(delta <= num(s, "a_priori_bound"), "{s}");
        assert!(num(s, "correction_bound") < 1e-3 * delta, "{s}");
    }
    let straight = bits_of(lorentz_json(dir, &words(base)));
    let zero = format!("{base} --electric 0 --electric-angle 45");
    assert_eq!(bits_of(lorentz_json(dir, &words(&zero))), straight);
}
