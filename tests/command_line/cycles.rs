//! `lorentz cycles`: the three-disk repeller by certified cycles from the command line (its bad
//! inputs are in the table of `bad_inputs.rs`).

use crate::common::{lorentz_in, scratch, words};

/// The escape rate of the three-disk repeller at R:a = 6 (a = 1, speed 1): ChaosBook's value,
/// as `tests/numerics/cycles.rs` quotes it (`proofs-notes/cycles.md`).
const GAMMA_R6: f64 = 0.410_338_407_769_346_5;

/// At R/a = 6 with cycles up to length 7: every cycle certified, one row per N, and γ of the
/// last row within its truncation error of the known value (plus the rounding of γ to a
/// double) and within the 1e-12 of it; the JSON of --out is what --json prints, the text shows the table, and the result
/// does not depend on the thread count.
#[test]
fn cycles_at_r_over_a_6_give_the_known_escape_rate_within_the_truncation_error() {
    let tmp = scratch();
    let dir = tmp.path();
    let line = "cycles --side 6 --radius 1 --max-length 7 --json --quiet --out c.json --threads 2";
    let (code, out, err) = lorentz_in(dir, &words(line));
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(
        std::fs::read_to_string(dir.join("c.json")).unwrap().trim(),
        out.trim()
    );
    // 2 + 1 + 2 + 3 + 6 + 9 + 18 binary prime cycles of length 1 to 7.
    assert_eq!(v["certified"], 41);
    assert_eq!(v["cycles"].as_array().unwrap().len(), 41);
    assert!(v["cycles"].as_array().unwrap().iter().all(|c| {
        c["cycle"]["certified"] == true && c["cycle"]["radius"].as_f64().unwrap() < 1e-60
    }));
    let rows = v["spectral_determinant"].as_array().unwrap();
    assert_eq!(rows.len(), 7);
    assert_eq!(v["zeta_function"].as_array().unwrap().len(), 7);
    assert!(
        rows[0]["escape_rate_error"].is_null(),
        "no estimate at N = 1"
    );
    let last = &rows[6];
    let gamma = last["escape_rate"].as_f64().unwrap();
    let error = last["escape_rate_error"].as_f64().unwrap();
    let off = (gamma - GAMMA_R6).abs();
    assert!(
        off <= error + 2.0 * f64::EPSILON * GAMMA_R6,
        "N = 7: |gamma - known| = {off:e} > truncation error {error:e}"
    );
    assert!(
        off < 1e-12 && error < 1e-12,
        "N = 7: |gamma - known| = {off:e}, truncation error {error:e}"
    );
    let h = last["entropy"].as_f64().unwrap();
    let lambda = last["lyapunov"].as_f64().unwrap();
    assert!((h - (lambda - gamma)).abs() < 1e-15);
    assert_eq!(v["config"]["side"], "6");
    assert_eq!(v["meta"]["precision"], "256");
    // One thread: the same physics.
    let (code, one, err) = lorentz_in(dir, &words(&line.replace("--threads 2", "--threads 1")));
    assert_eq!(code, 0, "{err}");
    let mut one: serde_json::Value = serde_json::from_str(&one).unwrap();
    let mut two = v.clone();
    one.as_object_mut().unwrap().remove("meta");
    two.as_object_mut().unwrap().remove("meta");
    assert!(one == two, "the result differs between --threads 1 and 2");
    // The text: the header, a row per N, the last row's γ.
    let (code, text, err) = lorentz_in(dir, &words("cycles --max-length 3 --quiet"));
    assert_eq!(code, 0, "{err}");
    assert!(
        text.starts_with("three-disk repeller, side R = 6, radius a = 1: 5 of 5"),
        "{text}"
    );
    assert!(text.contains("escape rate gamma"), "{text}");
    assert!(
        text.lines().any(|l| l.trim_start().starts_with("3  0.41")),
        "{text}"
    );
}

/// Lattice cycles up to length 2 at w = 1/10 all return (every winding 0): D_2 and ⟨n²⟩ are
/// zero, printed as 0.00000000 and recorded as 0.0, never with the sign of −0.
#[test]
fn lattice_cycles_that_all_return_give_an_unsigned_zero_d() {
    let tmp = scratch();
    let line = "cycles --w 1/10 --max-length 2 --msd-collisions 0";
    let (code, text, err) = lorentz_in(tmp.path(), &words(line));
    assert_eq!(code, 0, "{err}");
    assert!(!text.contains("-0.00000000"), "{text}");
    let (code, out, err) = lorentz_in(tmp.path(), &words(&format!("{line} --json --quiet")));
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let last = &v["table"][1];
    for key in ["diffusion", "mean_square_winding"] {
        let x = last[key].as_f64().unwrap();
        assert!(x == 0.0 && x.is_sign_positive(), "{key} = {x:?}");
    }
}
