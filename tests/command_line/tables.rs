//! `--table FILE`: a periodic table given as data, from the command line. A finite-horizon table
//! runs, meets Santaló's mean free path and PASSes `lorentz report`; an open corridor and overlapping disks are refused
//! with exit status 2 and one line naming the corridor or the two disks.

use crate::common::lorentz_in;

const EXAMPLE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/examples/tables/two-radius-square.toml"
);

fn table(dir: &std::path::Path, name: &str, centre_radius: &str) -> String {
    let text = format!(
        "[lattice]\ne1 = [\"1\", \"0\"]\ne2 = [\"0\", \"1\"]\n[[disks]]\ncentre = [\"0\", \"0\"]\n\
         radius = \"2/5\"\n[[disks]]\ncentre = [\"1/2\", \"1/2\"]\nradius = \"{centre_radius}\"\n"
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

#[test]
fn a_table_file_runs_diffusion_and_meets_santalos_mean_free_path() {
    let dir = crate::common::scratch();
    let args = [
        "diffusion",
        "--table",
        EXAMPLE,
        "--collisions",
        "4e6",
        "--batches",
        "8",
        "--json",
    ];
    let (code, out, err) = lorentz_in(dir.path(), &args);
    assert_eq!(code, 0, "{err}");
    let r: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!(
        r["scene"]
            .as_str()
            .unwrap()
            .starts_with("two-radius square"),
        "{out}"
    );
    let ids = r["identities"].as_array().unwrap();
    let mfp = ids.iter().find(|i| i["name"] == "mean free path").unwrap();
    // Santaló: π|Q|/|∂Q| = (1 − π/5)/(6/5), to the double.
    let exact = (1.0 - std::f64::consts::PI / 5.0) / 1.2;
    assert!((mfp["exact"].as_f64().unwrap() - exact).abs() < 1e-15);
    assert!(mfp["agrees"].as_bool().unwrap(), "{mfp}");
    let d = r["D"].as_f64().unwrap();
    assert!(d > 0.0 && r["D_err"].as_f64().unwrap() < 0.05 * d, "{out}");
    // The result records the table as written.
    assert_eq!(r["table"]["disks"][1]["radius"], "1/5", "{out}");
    // The publication audit re-runs it and PASSes; an edited D FAILs the record (exit 1), a
    // table edited to overlapping disks is refused as bad input naming the disks (exit 2).
    std::fs::write(dir.path().join("t.json"), &out).unwrap();
    let (code, report, err) = lorentz_in(dir.path(), &["report", "t.json", "--out", "rr"]);
    assert_eq!(code, 0, "{report}{err}");
    for check in [
        "mean free path = its closed form",
        "re-run gives the same bits",
    ] {
        assert!(report.contains(check), "{report}");
    }
    let mut edited = r.clone();
    edited["D"] = serde_json::json!(d * 1.001);
    std::fs::write(dir.path().join("d.json"), edited.to_string()).unwrap();
    let (code, report, err) = lorentz_in(dir.path(), &["report", "d.json", "--out", "rd"]);
    assert_eq!(code, 1, "{report}{err}");
    assert!(
        report.contains("FAIL  reproducibility  the record"),
        "{report}"
    );
    let mut edited = r.clone();
    edited["table"]["disks"][1]["radius"] = serde_json::json!("2/5");
    std::fs::write(dir.path().join("o.json"), edited.to_string()).unwrap();
    let (code, _, err) = lorentz_in(dir.path(), &["report", "o.json", "--out", "ro"]);
    assert_eq!((code, err.lines().count()), (2, 1), "{err}");
    assert!(err.contains("overlap"), "{err}");
}

#[test]
fn an_open_corridor_and_overlapping_disks_exit_2_with_one_line_naming_them() {
    let dir = crate::common::scratch();
    let open = table(dir.path(), "open.toml", "1/20");
    let (code, _, err) = lorentz_in(dir.path(), &["diffusion", "--table", &open]);
    assert_eq!(code, 2, "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(
        err.contains("infinite horizon") && err.contains("1 e1 + 0 e2"),
        "{err}"
    );
    let overlap = table(dir.path(), "overlap.toml", "0.31");
    for command in ["diffusion", "lyapunov", "audit"] {
        let (code, _, err) = lorentz_in(dir.path(), &[command, "--table", &overlap]);
        assert_eq!(code, 2, "{command}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains("disk 1 (centre (0, 0), radius 2/5)"), "{err}");
        assert!(
            err.contains("disk 2 (centre (1/2, 1/2), radius 0.31)"),
            "{err}"
        );
    }
    // The relative-error planner runs the triangular estimator only: refused in the flag's terms.
    let (code, _, err) = lorentz_in(
        dir.path(),
        &["diffusion", "--table", EXAMPLE, "--rel-err", "1e-3"],
    );
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--rel-err 0.001 is out of range"), "{err}");
    // A table replaces the scene and its parameter.
    let (code, _, err) = lorentz_in(dir.path(), &["diffusion", "--table", EXAMPLE, "--w", "0.1"]);
    assert_eq!(code, 2, "{err}");
    // A missing file names its path.
    let (code, _, err) = lorentz_in(dir.path(), &["diffusion", "--table", "no-such.toml"]);
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("no-such.toml"), "{err}");
}

/// `bench --table`: the table timed beside the triangular gas in one run, on the same engine
/// (its cell on the SIMD lanes where the CPU has them); a field or an MPFR precision beside a
/// table is refused in one line. (Speeds are not asserted here: they are measured by the
/// benchmark itself, never by a timed test.)
#[test]
fn bench_times_a_table_beside_the_triangular_gas() {
    let dir = crate::common::scratch();
    let args = [
        "bench",
        "--w",
        "0.1",
        "--table",
        EXAMPLE,
        "--collisions-per-thread",
        "2e5",
        "--repetitions",
        "2",
        "--json",
    ];
    let (code, out, err) = lorentz_in(dir.path(), &args);
    assert_eq!(code, 0, "{err}");
    let r: serde_json::Value = serde_json::from_str(&out).unwrap();
    let t = &r["table"];
    assert!(
        t["table"]
            .as_str()
            .unwrap()
            .starts_with("two-radius square"),
        "{out}"
    );
    assert_eq!(t["samples"].as_array().unwrap().len(), 2, "{out}");
    assert!(t["over_triangular"].as_f64().unwrap() > 0.0, "{out}");
    // About 0.21 crossings per collision (τ/ℓ = 4.71 collisions per crossing).
    let cpc = t["crossings_per_collision"].as_f64().unwrap();
    assert!((cpc - 1.0 / 4.712).abs() < 0.02, "{cpc}");
    for extra in [["--precision", "128"], ["--field", "1"]] {
        let mut bad = args.to_vec();
        bad.extend(extra);
        let (code, _, err) = lorentz_in(dir.path(), &bad);
        assert_eq!((code, err.lines().count()), (2, 1), "{extra:?}: {err}");
    }
}

/// A sweep over the field of a table in two parts (`--shard`), merged: the rows of the sweep run
/// in one piece, bit for bit, and `lorentz report` PASSes the merged result; a merge with a part
/// missing is refused naming the first missing point and its part (exit 2, before anything is
/// written).
#[test]
fn a_field_sweep_of_a_table_in_parts_merges_to_the_whole_sweep() {
    let dir = crate::common::scratch();
    let sweep = |extra: &[&str]| {
        let mut args = vec![
            "sweep",
            "--table",
            EXAMPLE,
            "--fields=-3,-1,1,3",
            "--collisions-per-run",
            "2e5",
            "--batches-per-run",
            "8",
            "--localization-samples",
            "1e5",
            "--quiet",
        ];
        args.extend(extra);
        let (code, out, err) = lorentz_in(dir.path(), &args);
        assert_eq!(code, 0, "{extra:?}: {out}{err}");
    };
    sweep(&["--shard", "0/2", "--out", "p0"]);
    sweep(&["--shard", "1/2", "--out", "p1"]);
    sweep(&["--out", "whole"]);
    let (code, _, err) = lorentz_in(dir.path(), &["merge", "p0", "--out", "half"]);
    assert_eq!((code, err.lines().count()), (2, 1), "{err}");
    assert!(err.contains("point 1, belongs to part 1/2"), "{err}");
    assert!(
        !dir.path().join("half").exists(),
        "a refused merge wrote {err}"
    );
    let (code, out, err) = lorentz_in(dir.path(), &["merge", "p0", "p1", "--out", "merged"]);
    assert_eq!(code, 0, "{out}{err}");
    let rows = |d: &str| {
        let text = std::fs::read_to_string(dir.path().join(d).join("field-sweep.json")).unwrap();
        serde_json::from_str::<serde_json::Value>(&text).unwrap()["rows"].clone()
    };
    assert_eq!(rows("merged"), rows("whole"));
    let (code, report, err) = lorentz_in(
        dir.path(),
        &["report", "merged/field-sweep.json", "--out", "rm"],
    );
    assert_eq!(code, 0, "{report}{err}");
}
