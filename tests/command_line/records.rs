//! Configurations recorded before `Table` and the one `SweepConfig` (in result files, checkpoints,
//! sweep points and parts) read as what they describe and are written back with every key they
//! had, so `report`, `merge` and resume take the files of every version.

use lorentz_gas::estimators::diffusion::DiffusionConfig;
use lorentz_gas::estimators::sweep::{Grid, SweepConfig};
use lorentz_gas::scenes::spec::{Motion, SceneSpec};
use serde_json::{Value, json};

/// `text` read as `T` and written back: the same object, or (`added`) the same with these keys
/// added.
fn round_trip<T: serde::de::DeserializeOwned + serde::Serialize>(text: &str, added: &[&str]) -> T {
    let before: Value = serde_json::from_str(text).unwrap();
    let t: T = serde_json::from_value(before.clone()).unwrap();
    let mut after = serde_json::to_value(&t).unwrap();
    for k in added {
        assert!(after.as_object_mut().unwrap().remove(*k).is_some(), "{k}");
    }
    assert_eq!(after, before);
    t
}

#[test]
fn a_diffusion_configuration_of_before_reads_as_its_table() {
    // `lorentz diffusion --w 0.1 --json` before the table: the gap as typed beside its double.
    let typed: DiffusionConfig = round_trip(
        r#"{"w": 0.1, "w_exact": "0.1", "collisions": 4000000, "batches": 8, "seed": 1, "run": 0, "precision": "f64", "window": {"lo": 2, "hi": 8}, "check_window": {"lo": 4, "hi": 16}}"#,
        &[],
    );
    assert_eq!(typed.table.scene, SceneSpec::Triangular { w: "0.1".into() });
    assert_eq!(typed.table.motion, Motion::Straight);
    // A configuration made from the double alone: that binary number is the gap, exactly.
    let double: DiffusionConfig = round_trip(
        r#"{"w": 0.1, "collisions": 4000000, "batches": 8, "seed": 1, "run": 0, "precision": "f64", "window": {"lo": 2, "hi": 8}, "check_window": {"lo": 4, "hi": 16}}"#,
        &["w_exact"],
    );
    assert_eq!(double.gap().unwrap(), 0.1);
    assert_eq!(
        lorentz_gas::numbers::exact::parse_exact(double.table.gap_text().unwrap()).unwrap(),
        rug::Rational::from_f64(0.1).unwrap()
    );
    // `lorentz diffusion --w 0.1 --field 1 --json` before: the field's scene and field.
    let field: DiffusionConfig = round_trip(
        r#"{"scene": {"scene": "triangular", "w": "0.1"}, "collisions": 8000000, "batches": 8, "seed": 1, "precision": "f64", "window": {"lo": 2, "hi": 8}, "check_window": {"lo": 4, "hi": 16}, "run": 0, "field": "1", "localization_samples": 10000}"#,
        &[],
    );
    assert_eq!(field.table.motion, Motion::Field("1".into()));
    assert_eq!(field.localization_samples, Some(10_000));
}

#[test]
fn a_record_that_names_two_tables_or_two_gaps_is_refused() {
    let base = json!({"collisions": 4000000, "batches": 8, "seed": 1, "precision": "f64",
        "window": {"lo": 2, "hi": 8}, "check_window": {"lo": 4, "hi": 16}});
    let with = |extra: Value| {
        let mut v = base.clone();
        v.as_object_mut()
            .unwrap()
            .extend(extra.as_object().unwrap().clone());
        serde_json::from_value::<DiffusionConfig>(v)
            .map(|_| ())
            .unwrap_err()
            .to_string()
    };
    let e = with(json!({"w": 0.1, "scene": {"scene": "square", "radius": "1/4"}}));
    assert!(e.contains("both a gap `w` and a `scene`"), "{e}");
    let e = with(json!({"w": 0.1, "w_exact": "1/5"}));
    assert!(e.contains("w_exact = '1/5': not w = 0.1"), "{e}");
    let e = with(json!({}));
    assert!(e.contains("no table"), "{e}");
    let e = with(json!({"w": 0.1, "field": "1"}));
    assert!(e.contains("a field's table is given as `scene`"), "{e}");
}

#[test]
fn sweep_configurations_of_before_read_as_one_sweep() {
    let over_w: SweepConfig = round_trip(
        r#"{"w_from": "0.1", "w_to": "0.2", "steps": 3, "runs": 2, "collisions_per_run": 1000000, "batches_per_run": 4, "seed": 1}"#,
        &[],
    );
    assert!(matches!(over_w.grid, Grid::Gaps(_)));
    assert_eq!((over_w.steps(), over_w.runs()), (3, 2));
    let in_field: SweepConfig = round_trip(
        r#"{"gaps": ["0.1"], "fields": ["-1", "1"], "collisions_per_run": 2000000, "batches_per_run": 8, "seed": 1, "localization_samples": 10000}"#,
        &[],
    );
    assert!(matches!(in_field.grid, Grid::InField(_)));
    assert_eq!((in_field.steps(), in_field.runs()), (2, 1));
}
