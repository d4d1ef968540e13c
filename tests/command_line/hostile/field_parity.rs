//! Field parity: a sweep in a field goes through the field-free sweep's guards — one shared
//! re-check of a reused point, drawn at random, which moves a refused point file aside.

use std::path::Path;

use crate::common::{lorentz_in as lorentz, scratch};

fn field_sweep(dir: &Path) -> (i32, String, String) {
    let args = "sweep --w 0.2 --fields 1,2 --collisions-per-run 2e5 --batches-per-run 4 \
                --localization-samples 1e4 --out s --quiet";
    lorentz(dir, &args.split_whitespace().collect::<Vec<_>>())
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
        .filter(|e| e.as_ref().unwrap().path().to_string_lossy().ends_with(".refused"))
        .count();
    assert_eq!(aside, 2, "each forged point is moved aside once");
    let (code, _, err) = field_sweep(dir);
    assert_eq!(code, 0, "{err}");
    let again = std::fs::read_to_string(dir.join("s/field-sweep.csv")).unwrap();
    assert_eq!(again, honest);
}
