//! Every configuration holds a [`Table`]: records written before it (a config with `w` alone, or
//! `w` and `w_exact`) read back as the same gap and pass the audit's key check (every key of the
//! file is in the struct written back), the gap keeps its bits, and a table the analysis cannot
//! run on (another scene, a field) is refused naming what it lacks.

use std::path::PathBuf;

use serde::Serialize;
use serde::de::DeserializeOwned;
use serde_json::Value;

use lorentz_gas::Error;
use lorentz_gas::estimators::escape::{self, EscapeConfig, EscapeReport};
use lorentz_gas::estimators::hops::backscatter::{self, BackscatterConfig, BackscatterReport};
use lorentz_gas::estimators::hops::{self, HopsConfig, HopsReport};
use lorentz_gas::estimators::observer_costs::ObserverCostsConfig;
use lorentz_gas::estimators::throughput::{self, ThroughputConfig};
use lorentz_gas::report::publication::file::ResultFile;
use lorentz_gas::report::speed_error::{self, SpeedErrorConfig};
use lorentz_gas::scenes::spec::{Motion, SceneSpec, Table};

/// `old` (a configuration as written before the table) read as `T`: every key of `old` is in
/// the struct written back (the audit's check), with the same value but for `w_exact`, which is
/// now always written and names the same double as `w`; the struct written back reads back to
/// itself.
fn reads_back<T: DeserializeOwned + Serialize + PartialEq + std::fmt::Debug>(old: &str) -> T {
    let t: T = serde_json::from_str(old).unwrap_or_else(|e| panic!("{old}: {e}"));
    let new = serde_json::to_value(&t).unwrap();
    let old: Value = serde_json::from_str(old).unwrap();
    for (k, v) in old.as_object().unwrap() {
        let now = new
            .get(k)
            .unwrap_or_else(|| panic!("key `{k}` lost: {new}"));
        if k != "w_exact" {
            assert_eq!(now, v, "key `{k}`");
        }
    }
    let text = new["w_exact"].as_str().expect("w_exact written");
    let exact = lorentz_gas::numbers::exact::ExactInput::parse(text).unwrap();
    assert_eq!(exact.value.to_bits(), new["w"].as_f64().unwrap().to_bits());
    assert_eq!(serde_json::from_value::<T>(new).unwrap(), t);
    t
}

#[test]
fn hops_config_of_before_reads_back_as_the_same_gap() {
    let old = r#"{"w": 0.1, "collisions": 2000000, "batches": 4, "order": 3, "seed": 1}"#;
    let cfg: HopsConfig = reads_back(old);
    assert_eq!(cfg.gap().unwrap().to_bits(), 0.1f64.to_bits());
    assert_eq!(cfg.run, 0);
    cfg.validate().unwrap();
    // Both keys, as a result of today: the text is kept as typed.
    let both = r#"{"w": 0.1, "w_exact": "1/10", "collisions": 2000000, "batches": 4,
                   "order": 3, "seed": 1, "run": 0}"#;
    let cfg: HopsConfig = reads_back(both);
    assert_eq!(cfg.table, Table::triangular("1/10").unwrap());
    // Two numbers that differ, or a key of no table, are refused.
    for bad in [
        r#"{"w": 0.2, "w_exact": "1/10", "collisions": 1, "batches": 4, "order": 3, "seed": 1}"#,
        r#"{"w": 0.1, "gap": 0.1, "collisions": 1, "batches": 4, "order": 3, "seed": 1}"#,
        r#"{"collisions": 1, "batches": 4, "order": 3, "seed": 1}"#,
    ] {
        assert!(serde_json::from_str::<HopsConfig>(bad).is_err(), "{bad}");
    }
}

#[test]
fn backscatter_config_of_before_reads_back_as_the_same_gap() {
    let old = r#"{"w": 0.1, "particles": 100000, "batches": 4, "seed": 1, "run": 0,
                  "precision": "f64"}"#;
    let cfg: BackscatterConfig = reads_back(old);
    assert_eq!(cfg.gap().unwrap().to_bits(), 0.1f64.to_bits());
    cfg.validate().unwrap();
    let old = r#"{"w": 0.1, "w_exact": "1/10", "particles": 20000, "batches": 4, "seed": 1,
                  "run": 0, "precision": "128"}"#;
    let cfg: BackscatterConfig = reads_back(old);
    assert_eq!(cfg.table.gap_text(), Some("1/10"));
    cfg.validate().unwrap();
}

#[test]
fn escape_config_of_before_reads_back_as_the_same_gap() {
    let old = r#"{"w": 0.2, "widths": [17.6, 26.400000000000002, 35.2, 52.800000000000004],
                  "particles_per_width": 4000, "seed": 1}"#;
    let cfg: EscapeConfig = reads_back(old);
    assert_eq!(cfg.gap().unwrap().to_bits(), 0.2f64.to_bits());
    assert_eq!(cfg.widths, escape::default_widths(0.2));
    cfg.validate().unwrap();
}

#[test]
fn bench_configs_of_before_read_back_as_the_same_gap() {
    let old = r#"{"w": 0.1, "precision": "f64", "observe": "none",
                  "collisions_per_thread": 1000, "repetitions": 1, "seed": 1}"#;
    let cfg: ThroughputConfig = reads_back(old);
    assert_eq!(
        cfg.table.gap_for("bench").unwrap().to_bits(),
        0.1f64.to_bits()
    );
    assert!(cfg.table_beside.is_none());
    let old = r#"{"w": 0.1, "collisions_per_thread": 1000, "repetitions": 1, "seed": 1}"#;
    let cfg: ObserverCostsConfig = reads_back(old);
    assert_eq!(cfg.gap().unwrap().to_bits(), 0.1f64.to_bits());
    cfg.validate().unwrap();
    let cfg: SpeedErrorConfig = reads_back(r#"{"w": 0.1, "seed": 1, "out": "results"}"#);
    assert_eq!(cfg.out, PathBuf::from("results"));
}

/// A result as written before the table (its config with `w` alone), as the audit reads files:
/// the kind recognised, every key known, the configuration the same.
fn audit_reads<T: DeserializeOwned + Serialize>(report: &impl Serialize, old_config: &str) -> T {
    let mut v = serde_json::to_value(report).unwrap();
    v["config"] = serde_json::from_str(old_config).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("old.json");
    std::fs::write(&path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
    let file = ResultFile::read(&path).unwrap();
    file.parse(&path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn hops_backscatter_and_escape_results_of_before_pass_the_audit_key_check() {
    let hops_cfg = HopsConfig {
        collisions: 400_000,
        batches: 2,
        order: 2,
        ..HopsConfig::new(Table::triangular("0.1").unwrap())
    };
    let h = hops::run(&hops_cfg, &crate::common::threads(2)).unwrap();
    let old = r#"{"w": 0.1, "collisions": 400000, "batches": 2, "order": 2, "seed": 1,
                  "run": 0}"#;
    let back: HopsReport = audit_reads(&h, old);
    assert_eq!(back.config.gap().unwrap().to_bits(), h.w.to_bits());
    let b = backscatter::run(
        &BackscatterConfig {
            particles: 1000,
            batches: 2,
            ..BackscatterConfig::new(Table::triangular("0.1").unwrap())
        },
        &crate::common::threads(2),
    )
    .unwrap();
    let old = r#"{"w": 0.1, "particles": 1000, "batches": 2, "seed": 1, "run": 0,
                  "precision": "f64"}"#;
    let back: BackscatterReport = audit_reads(&b, old);
    back.config.validate().unwrap();
    let e = escape::run(
        &EscapeConfig {
            widths: vec![11.0, 13.0, 15.0],
            particles_per_width: escape::MIN_PARTICLES,
            ..EscapeConfig::new(Table::triangular("0.3").unwrap())
        },
        &crate::common::threads(2),
    )
    .unwrap();
    let old = r#"{"w": 0.3, "widths": [11.0, 13.0, 15.0], "particles_per_width": 3200,
                  "seed": 1}"#;
    let back: EscapeReport = audit_reads(&e, old);
    back.config.validate().unwrap();
}

/// The gap as typed and the double it is nearest: the same bits in an `f64` run, and the JSON
/// of before (`w`) with the text as typed beside it.
#[test]
fn hops_runs_keep_their_bits_whichever_way_the_gap_is_given() {
    let cfg = |table| HopsConfig {
        collisions: 400_000,
        batches: 2,
        order: 3,
        ..HopsConfig::new(table)
    };
    let typed = hops::run(
        &cfg(Table::triangular("1/10").unwrap()),
        &crate::common::threads(2),
    )
    .unwrap();
    let double = hops::run(&cfg(Table::triangular_at(0.1)), &crate::common::threads(2)).unwrap();
    let physics = |r: &HopsReport| {
        let mut v = serde_json::to_value(r).unwrap();
        v.as_object_mut()
            .unwrap()
            .retain(|k, _| k != "meta" && k != "config");
        v
    };
    assert_eq!(physics(&typed), physics(&double));
    let json = serde_json::to_value(&typed.config).unwrap();
    assert_eq!(json["w"], 0.1);
    assert_eq!(json["w_exact"], "1/10");
}

/// A table the analysis cannot run on, refused before any work.
fn refusals() -> Vec<(Table, &'static str)> {
    let square = SceneSpec::parse("square", None, Some("1/4")).unwrap();
    let in_field = Table::triangular("0.1").unwrap().in_field("1/2");
    assert_eq!(in_field.motion, Motion::Field("1/2".into()));
    vec![
        (
            Table {
                scene: square,
                motion: Motion::Straight,
            },
            "square lacks trap symbols (the triangular scene's), which the",
        ),
        (in_field, "field = 1/2"),
    ]
}

#[test]
fn hops_backscatter_and_escape_refuse_other_tables_and_fields() {
    for (table, message) in refusals() {
        let t = || table.clone();
        let errors: [(&str, Error); 4] = [
            ("hops", HopsConfig::new(t()).validate().unwrap_err()),
            (
                "backscatter",
                BackscatterConfig::new(t()).validate().unwrap_err(),
            ),
            ("escape", EscapeConfig::new(t()).validate().unwrap_err()),
            (
                "observer costs",
                ObserverCostsConfig::new(t()).validate().unwrap_err(),
            ),
        ];
        for (analysis, e) in errors {
            let text = e.to_string();
            assert!(text.contains(message), "{analysis}: {text}");
            assert!(text.contains(analysis), "{analysis}: {text}");
            assert!(matches!(e, Error::Lacks { .. } | Error::Parameter { .. }));
        }
        // Through the entry points too, before any work (speed against error creates no
        // folder).
        let e = hops::theory::run(&HopsConfig::new(table.clone()), &crate::common::threads(2))
            .unwrap_err();
        assert!(e.to_string().contains(message), "{e}");
        let e = throughput::run(
            &ThroughputConfig::new(table.clone()),
            &crate::common::threads(2),
        );
        assert!(e.is_err());
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("speed");
        let cfg = SpeedErrorConfig {
            table,
            seed: 1,
            out: out.clone(),
        };
        let e = speed_error::run(&cfg, &crate::common::threads(2)).unwrap_err();
        assert!(e.to_string().contains(message), "{e}");
        assert!(!out.exists());
    }
}
