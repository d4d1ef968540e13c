//! Field parity: a sweep in a field goes through the field-free sweep's guards — one shared
//! re-check of a reused point, drawn at random, which moves a refused point file aside.

use std::path::Path;

use crate::common::{lorentz_in as lorentz, scratch, words};

fn field_sweep(dir: &Path) -> (i32, String, String) {
    let args = "sweep --w 0.2 --fields 1,2 --collisions-per-run 2e5 --batches-per-run 4 \
                --localization-samples 1e4 --out s --quiet";
    lorentz(dir, &words(args))
}

/// Every point of a finished field sweep re-sealed with D_xx × 1.5 (its digest recomputed, as
/// anyone can): the resumed sweep computes one point again, refuses with status 4 naming it, and
/// moves its file aside, so a retry cannot draw until an honest point comes up; the next run
/// recomputes that point and, once every forged point has been drawn and refused, the sweep is
/// the honest one again.
#[test]
fn a_field_sweep_with_resealed_points_is_refused_like_the_field_free_one() {
    let tmp = scratch();
    let dir = tmp.path();
    let (code, _, err) = field_sweep(dir);
    assert_eq!(code, 0, "{err}");
    let honest = std::fs::read_to_string(dir.join("s/field-sweep.csv")).unwrap();
    let points = dir.join("s/field-points");
    for i in 0..2 {
        let path = points.join(format!("point-{i:04}.json"));
        let mut v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        v.as_object_mut().unwrap().remove("digest");
        v["row"]["D_xx"] = serde_json::json!(v["row"]["D_xx"].as_f64().unwrap() * 1.5);
        std::fs::write(&path, lorentz_gas::engine::resume::seal(&v).unwrap()).unwrap();
    }
    for refusal in 0..2 {
        let (code, _, err) = field_sweep(dir);
        assert_eq!(code, 4, "resume {refusal} accepted forged points: {err}");
        assert!(
            err.contains("computed again from its seed") && err.contains(".refused"),
            "{err}"
        );
    }
    let aside = std::fs::read_dir(&points)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .to_string_lossy()
                .ends_with(".refused")
        })
        .count();
    assert_eq!(aside, 2, "each forged point is moved aside once");
    let (code, _, err) = field_sweep(dir);
    assert_eq!(code, 0, "{err}");
    let again = std::fs::read_to_string(dir.join("s/field-sweep.csv")).unwrap();
    assert_eq!(again, honest);
}

/// A field typed as its range's bound is the bound (compared as the double nearest the exact
/// field, as every analysis compares it): `shadow --field 1e-3` runs. Beyond a range, or where
/// no start can be drawn, the refusal comes at once, in one line, with the field as typed:
/// `bench --field 1e9` (it had no range), `audit --field 1e6` (in range, but every circle is
/// pinned), `diffusion --field 1e300` (once printed as 301 digits).
#[test]
fn a_field_at_its_bound_runs_and_beyond_it_is_refused_at_once_in_one_line() {
    let tmp = scratch();
    let dir = tmp.path();
    let shadow = "shadow --w 0.1 --field 1e-3 --segments 1 --collisions-per-segment 20 --quiet";
    let (code, _, err) = lorentz(dir, &words(shadow));
    assert_eq!(code, 0, "{err}");
    for (args, says) in [
        (
            "bench --w 0.1 --field 1e9 --quiet",
            "1e-3 <= |field| <= 1e3",
        ),
        (
            "audit --w 0.1 --field 1e6 --collisions 1e3 --quiet",
            "weaker field",
        ),
        (
            "diffusion --w 0.1 --field 1e300 --quiet",
            "--field 1e300 is out of range",
        ),
    ] {
        let started = std::time::Instant::now();
        let (code, _, err) = lorentz(dir, &words(args));
        let took = started.elapsed().as_secs_f64();
        assert_eq!(code, 2, "{args}: {err}");
        assert!(
            err.contains(says) && err.lines().count() == 1 && err.len() < 400,
            "{args}: {err}"
        );
        assert!(took < 1.0, "{args}: refused after {took:.2} s");
    }
}
