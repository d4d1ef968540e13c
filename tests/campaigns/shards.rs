//! Campaigns split into parts: a sweep computed as N shards and merged gives the same bits as the
//! sweep computed in one piece, and merging refuses what does not belong together.

use std::path::{Path, PathBuf};

use lorentz_gas::campaigns::merge::{self, MergeConfig};
use lorentz_gas::campaigns::shard::{self, Shard, ShardConfig, SweepPart};
use lorentz_gas::engine::Engine;
use lorentz_gas::engine::options::RunOptions;
use lorentz_gas::estimators::sweep::stored::Finished;
use lorentz_gas::estimators::sweep::{self, SweepConfig, SweepReport};
use lorentz_gas::report::figures::sweep::write_sweep_figures;

fn options(engine: Engine, threads: usize, dir: &Path) -> RunOptions<'static> {
    RunOptions {
        engine,
        threads,
        resume: Some(dir.to_path_buf()),
        ..RunOptions::default()
    }
}

/// `lorentz sweep --out dir`: the points in `dir`, then the tables and figures.
fn sweep_on(cfg: &SweepConfig, dir: &Path, engine: Engine, threads: usize) -> SweepReport {
    let r = sweep::run(cfg, &options(engine, threads, dir)).unwrap();
    sweep::write_tables(&r, dir).unwrap();
    write_sweep_figures(&r, dir).unwrap();
    r
}

/// `lorentz sweep --shard I/N --out dir`.
fn run_shard(cfg: &SweepConfig, s: Shard, dir: &Path, engine: Engine, threads: usize) -> SweepPart {
    let part = ShardConfig {
        sweep: cfg.clone(),
        shard: s,
    };
    shard::run(&part, &options(engine, threads, dir)).unwrap()
}

/// `lorentz merge --out out parts…`: the merged points, tables and figures.
fn merge_into(parts: &[PathBuf], out: &Path) -> Result<SweepReport, lorentz_gas::Error> {
    let cfg = MergeConfig {
        parts: parts.to_vec(),
        out: out.to_path_buf(),
    };
    let Finished::OverW(r) = merge::run(&cfg, &crate::common::threads(1))? else {
        panic!("a sweep over w merged into a sweep in a field");
    };
    sweep::write_tables(&r, out)?;
    write_sweep_figures(&r, out)?;
    Ok(*r)
}

/// Resuming the sweep `config(1)` in `dir` after `edit` of point file `p` is refused, naming it.
fn refuse_resume(dir: &Path, p: &Path, edit: &dyn Fn(&str) -> String) {
    let text = std::fs::read_to_string(p).unwrap();
    std::fs::write(p, edit(&text)).unwrap();
    let e = sweep::run(&config(1), &options(Engine::Auto, 2, dir))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(&p.display().to_string()) && e.contains("digest"),
        "{e}"
    );
    std::fs::write(p, text).unwrap();
}

/// Raises every run's D by 5 % in each point file of `points` and reseals it, as someone who
/// knows the digest scheme could; returns the original files.
fn forge_points(points: &Path) -> Vec<(PathBuf, String)> {
    let mut originals = Vec::new();
    for entry in std::fs::read_dir(points).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|x| x != "json") {
            continue; // a point's kept batches
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
        v.as_object_mut().unwrap().remove("digest");
        for run in v["runs"].as_array_mut().unwrap() {
            run["D"] = serde_json::json!(run["D"].as_f64().unwrap() * 1.05);
        }
        std::fs::write(&path, lorentz_gas::engine::resume::seal(&v).unwrap()).unwrap();
        originals.push((path, text));
    }
    assert!(!originals.is_empty());
    originals
}

fn config(seed: u64) -> SweepConfig {
    SweepConfig {
        grid: lorentz_gas::estimators::sweep::Grid::Gaps(lorentz_gas::estimators::sweep::GapGrid {
            w_from: "0.2".into(),
            w_to: "0.3".into(),
            steps: 5,
            runs: 2,
        }),
        collisions: 200_000,
        batches: 4,
        seed,
    }
}

/// `sweep.json` without what differs by construction: `meta` (the process) and `resumed_points`.
fn science(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("sweep.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let o = v.as_object_mut().unwrap();
    o.remove("meta").expect("a meta block");
    o.remove("resumed_points").expect("resumed_points");
    v
}

fn same_bytes(a: &Path, b: &Path) {
    assert!(
        std::fs::read(a).unwrap() == std::fs::read(b).unwrap(),
        "{} and {} differ",
        a.display(),
        b.display()
    );
}

#[test]
fn shards_merged_equal_the_whole_sweep_bit_for_bit() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let cfg = config(1);
    sweep_on(&cfg, &dir.join("whole"), Engine::Auto, 2);
    // Three parts on different engines and thread counts: 5 points dealt as {0, 3}, {1, 4}, {2}.
    let mut parts = Vec::new();
    for (i, (engine, threads)) in [(Engine::Auto, 1), (Engine::Scalar, 2), (Engine::Auto, 2)]
        .into_iter()
        .enumerate()
    {
        let shard = Shard {
            index: i as u32,
            count: 3,
        };
        let d = dir.join(format!("part-{i}"));
        let r = run_shard(&cfg, shard, &d, engine, threads);
        let want: Vec<u32> = (0..5).filter(|p| p % 3 == i as u32).collect();
        assert_eq!(r.points, want);
        parts.push(d);
    }
    // Given in any order.
    parts.reverse();
    let merged = dir.join("merged");
    let r = merge_into(&parts, &merged).unwrap();
    assert_eq!(r.rows.len(), 5);
    let whole = dir.join("whole");
    for f in [
        "sweep.csv",
        "fig2-D-vs-w.svg",
        "fig7-boltzmann.svg",
        "fig8-residuals.svg",
        "fig8-residuals.png",
    ] {
        same_bytes(&whole.join(f), &merged.join(f));
    }
    assert_eq!(science(&whole), science(&merged));
    for i in 0..5 {
        let f = format!("points/point-{i:04}.json");
        same_bytes(&whole.join(&f), &merged.join(&f));
    }
    // The merged directory is a finished sweep: running the sweep there resumes every point.
    let again = sweep_on(&cfg, &merged, Engine::Auto, 2);
    assert_eq!(again.resumed_points, 5);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn merge_refuses_missing_duplicate_foreign_and_edited_parts() {
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let part = |cfg: &SweepConfig, i: u32, n: u32, name: &str| {
        let d = dir.join(name);
        run_shard(cfg, Shard { index: i, count: n }, &d, Engine::Auto, 2);
        d
    };
    let a = part(&config(1), 0, 2, "a");
    let b = part(&config(1), 1, 2, "b");
    let foreign = part(&config(2), 1, 2, "foreign");
    let other_split = part(&config(1), 2, 3, "other-split");
    let out = dir.join("out");
    let err = |dirs: &[PathBuf]| merge_into(dirs, &out).unwrap_err().to_string();

    let e = err(std::slice::from_ref(&a));
    assert!(
        e.contains("2 of 5 points missing") && e.contains("part 1/2"),
        "{e}"
    );
    let e = err(&[a.clone(), b.clone(), b.clone()]);
    assert!(e.contains("part 1/2 is in both"), "{e}");
    let e = err(&[a.clone(), foreign]);
    assert!(
        e.contains("different sweeps") && e.contains("seed: 1 vs 2"),
        "{e}"
    );
    let e = err(&[a.clone(), b.clone(), other_split]);
    assert!(e.contains("part 0/2") && e.contains("part 2/3"), "{e}");
    let e = err(&[dir.join("nothing")]);
    assert!(e.contains("no sweep points"), "{e}");
    // Nothing was written by the refused merges.
    assert!(!out.exists());
    // Edited, renamed and damaged files are refused by name.
    let refuse = |path: &Path, edit: &dyn Fn(&str) -> String, want: &str| {
        let text = std::fs::read_to_string(path).unwrap();
        let edited = edit(&text);
        assert_ne!(edited, text, "the edit changes {}", path.display());
        std::fs::write(path, &edited).unwrap();
        let e = err(&[a.clone(), b.clone()]);
        assert!(
            e.contains(&path.display().to_string()) && e.contains(want),
            "{e}"
        );
        std::fs::write(path, text).unwrap();
    };
    let p = b.join("points").join("point-0001.json");
    // One run's D changed by 1 %.
    let run_d = |t: &str| {
        let v: serde_json::Value = serde_json::from_str(t).unwrap();
        let d = v["runs"][0]["D"].as_f64().unwrap();
        t.replacen(&format!("{d}"), &format!("{}", d * 1.01), 1)
    };
    refuse(&p, &run_d, "digest");
    // Its w moved off the grid.
    let w1 = lorentz_gas::numbers::exact::decimal_grid("0.2", "0.3", 5).unwrap()[1];
    refuse(&p, &|t| t.replace(&format!(": {w1}"), ": 0.26"), "digest");
    // Cut short.
    refuse(&p, &|t| t[..t.len() / 2].to_string(), "sweep point");
    // The part's manifest edited.
    refuse(
        &b.join("shard.json"),
        &|t| t.replace("\"index\": 1", "\"index\": 0"),
        "digest",
    );
    // A point copied under another point's name.
    let copy = b.join("points").join("point-0002.json");
    std::fs::copy(&p, &copy).unwrap();
    let e = err(&[a.clone(), b.clone()]);
    assert!(
        e.contains("point-0002.json") && e.contains("holds point 1"),
        "{e}"
    );
    std::fs::remove_file(&copy).unwrap();
    // A sweep resumed in a directory with an edited point refuses it too.
    refuse_resume(&b, &p, &run_d);
    // Forged: every point's D raised by 5 % and its digest recomputed. The seals hold, but the
    // resumed sweep rebuilds one point (drawn at random) from its kept batches, one of them
    // computed again at its marks, and stops; without its batches, one of its runs is computed
    // again whole.
    let resumed_forged = |want: &str| {
        let originals = forge_points(&b.join("points"));
        let e = sweep::run(&config(1), &options(Engine::Auto, 2, &b))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("computed again from its seed") && e.contains(want),
            "{e}"
        );
        for (path, text) in originals {
            std::fs::write(path, text).unwrap();
        }
    };
    resumed_forged("rebuilt from its batches");
    for i in [1, 3] {
        let kept = lorentz_gas::estimators::sweep::points::batches_path(&b, i);
        assert!(kept.is_file(), "{} kept", kept.display());
        std::fs::remove_file(kept).unwrap();
    }
    resumed_forged(", run ");
    assert!(
        merge_into(&[a, b], &out).is_ok(),
        "the restored parts merge"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `lorentz merge` writes a sweep result that `lorentz report` audits exactly like the sweep it
/// equals: the merged file passes, and with one run's D edited by 1 % (and nothing else) it fails
/// — the point's D is no longer the mean of its runs.
#[test]
fn a_merged_sweep_with_one_run_edited_fails_its_report() {
    use crate::common::lorentz_in as lorentz;
    let tmp = crate::common::scratch();
    let dir = tmp.path();
    let sweep = crate::common::words(
        "sweep --w-from 0.2 --w-to 0.3 --steps 3 --runs 2 --collisions-per-run 2e5 \
         --batches-per-run 4 --quiet",
    );
    for part in ["0/2", "1/2"] {
        let out = format!("part-{}", &part[..1]);
        let mut args = sweep.to_vec();
        args.extend(["--shard", part, "--out", &out]);
        let (code, _, err) = lorentz(dir, &args);
        assert_eq!(code, 0, "{err}");
    }
    let (code, _, err) = lorentz(
        dir,
        &["merge", "part-0", "part-1", "--out", "merged", "--quiet"],
    );
    assert_eq!(code, 0, "{err}");
    let merged = dir.join("merged/sweep.json");
    let (code, out, err) = lorentz(
        dir,
        &["report", "merged/sweep.json", "--out", "rep", "--quiet"],
    );
    assert_eq!(code, 0, "{out}{err}");

    let text = std::fs::read_to_string(&merged).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let d = v["rows"][1]["run_D"][0].as_f64().unwrap();
    v["rows"][1]["run_D"][0] = serde_json::json!(d * 1.01);
    std::fs::write(
        dir.join("edited.json"),
        serde_json::to_string_pretty(&v).unwrap(),
    )
    .unwrap();
    let (code, _, err) = lorentz(dir, &["report", "edited.json", "--out", "rep-edited"]);
    assert_eq!(code, 1, "{err}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("rep-edited/report.json")).unwrap())
            .unwrap();
    assert_eq!(report["provenance"]["kind"], "sweep");
    let failed: Vec<&str> = report["checks"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["verdict"] == "FAIL")
        .map(|c| c["detail"].as_str().unwrap())
        .collect();
    // The record (the point's D is no longer the mean of its runs), and the full report's re-run
    // of the whole sweep (the recorded run is not the re-run's).
    assert_eq!(failed.len(), 2, "{failed:?}");
    assert!(
        failed[0].starts_with("the analysis of the recorded runs differs from the record in")
            && failed[0].contains("rows"),
        "{failed:?}"
    );
    assert!(failed[1].ends_with("rows differ"), "{failed:?}");
}

/// A sweep in a field (the triangular gas at w = 0.2, B = -1, 1, 2: three points) dealt into
/// three parts — on disk, as `lorentz sweep --shard I/3`, and in memory, as a process pool's
/// calls — and merged: the rows, Onsager–Casimir checks and point files of the sweep run in one
/// piece, bit for bit; a part's points carried in memory are its files' bytes.
#[test]
fn a_field_sweep_in_three_parts_merges_to_the_unsharded_bits() {
    use lorentz_gas::campaigns::merge::PartData;
    use lorentz_gas::estimators::sweep::field::{self, FieldGrid};
    let tmp = crate::common::scratch();
    let dir = tmp.path().to_path_buf();
    let cfg = SweepConfig {
        grid: lorentz_gas::estimators::sweep::Grid::InField(FieldGrid {
            gaps: vec!["0.2".into()],
            radius: None,
            fields: ["-1", "1", "2"].map(String::from).to_vec(),
            localization_samples: 10_000,
            table: None,
        }),
        collisions: 200_000,
        batches: 4,
        seed: 7,
    };
    let whole = field::run(&cfg, &options(Engine::Auto, 2, &dir.join("whole"))).unwrap();
    let science = |r: &field::FieldSweepReport| {
        let v = serde_json::to_value(r).unwrap();
        (v["rows"].clone(), v["onsager"].clone(), v["config"].clone())
    };
    let mut on_disk = Vec::new();
    let mut in_memory = Vec::new();
    for (i, (engine, threads)) in [(Engine::Auto, 1), (Engine::Scalar, 2), (Engine::Auto, 2)]
        .into_iter()
        .enumerate()
    {
        let part = ShardConfig {
            sweep: cfg.clone(),
            shard: Shard {
                index: i as u32,
                count: 3,
            },
        };
        let d = dir.join(format!("part-{i}"));
        let r = shard::run(&part, &options(engine, threads, &d)).unwrap();
        assert_eq!(r.points, vec![i as u32]);
        assert!(
            r.sealed_points.is_empty(),
            "a part on disk carries no points"
        );
        assert!(d.join("field-shard.json").is_file());
        on_disk.push(d);
        let opts = RunOptions {
            engine,
            threads,
            ..RunOptions::default()
        };
        let m = shard::run(&part, &opts).unwrap();
        let [p] = &m.sealed_points[..] else {
            panic!("part {i} carries {} points", m.sealed_points.len());
        };
        let file = dir.join(format!("whole/field-points/point-{i:04}.json"));
        assert_eq!(p.text, std::fs::read_to_string(file).unwrap());
        in_memory.push(PartData::in_memory(m));
    }
    on_disk.reverse();
    let merged = dir.join("merged");
    let cfg_m = MergeConfig {
        parts: on_disk,
        out: merged.clone(),
    };
    let threads1 = crate::common::threads(1);
    let Finished::InField(from_disk) = merge::run(&cfg_m, &threads1).unwrap() else {
        panic!("a field sweep merged into a sweep over w");
    };
    assert_eq!(science(&from_disk), science(&whole));
    assert_eq!(
        from_disk.resumed_points, 0,
        "the parts computed every point"
    );
    for i in 0..3 {
        let f = format!("field-points/point-{i:04}.json");
        same_bytes(&dir.join("whole").join(&f), &merged.join(&f));
    }
    let Finished::InField(from_memory) = merge::merge(in_memory, None, &threads1).unwrap() else {
        panic!("a field sweep merged into a sweep over w");
    };
    assert_eq!(science(&from_memory), science(&whole));
    // The merged directory is the finished sweep: running it there reuses every point.
    let again = field::run(&cfg, &options(Engine::Auto, 2, &merged)).unwrap();
    assert_eq!(
        (again.resumed_points, science(&again)),
        (3, science(&whole))
    );
    let _ = std::fs::remove_dir_all(&dir);
}
