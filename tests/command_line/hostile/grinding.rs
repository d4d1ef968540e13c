//! Selection grinding: what a quick audit re-runs is drawn from operating-system entropy as the
//! audit runs, never from the file, so padding a file or editing it again cannot choose an honest
//! batch; and the quick audit states how strong its PASS is. (A refused checkpoint or sweep point
//! is moved aside, so a resume cannot be retried until an honest batch is drawn:
//! `tests/numerics/checkpoints.rs` and [`super::field_parity`].)

use std::collections::BTreeSet;

use crate::common::{lorentz_in as lorentz, scratch};

/// The batch a quick audit of `file` re-ran (from its `report.json` in `out`), its `sampled`
/// block and the printed verdict line (the first).
fn quick_audit(dir: &std::path::Path, file: &str, out: &str) -> (u64, serde_json::Value, String) {
    let (code, stdout, err) = lorentz(dir, &["report", file, "--quick", "--out", out, "--quiet"]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(dir.join(out).join("report.json")).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let rerun = v["checks"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["name"] == "one batch re-run from its seed gives the recorded bits")
        .expect("the quick audit re-runs one batch");
    assert_eq!(rerun["verdict"], "PASS", "{rerun}");
    let batch = rerun["numbers"]["first_batch_rerun"].as_f64().unwrap() as u64;
    let first = stdout.lines().next().unwrap_or_default().to_string();
    (batch, v["sampled"].clone(), first)
}

/// The same bytes audited again, and copies padded with spaces (which changed the digest that
/// used to pick the batch): the batch re-run varies, whatever the file holds. Six audits of a
/// 16-batch result all drawing one batch has chance 16⁻⁵ ≈ 10⁻⁶. Every verdict states its
/// strength: 1 of 16 batches, and the chance 15/16 that one forged batch among the others passes.
#[test]
fn a_quick_audit_draws_its_batch_afresh_whatever_the_file_holds() {
    let tmp = scratch();
    let dir = tmp.path();
    let args = "diffusion --w 0.3 --collisions 1e6 --batches 16 --json --quiet";
    let (code, out, err) = lorentz(dir, &args.split(' ').collect::<Vec<_>>());
    assert_eq!(code, 0, "{err}");
    std::fs::write(dir.join("d.json"), &out).unwrap();
    let mut drawn = BTreeSet::new();
    for k in 0..6 {
        let file = if k % 2 == 0 {
            "d.json".to_string()
        } else {
            let padded = format!("p{k}.json");
            std::fs::write(dir.join(&padded), format!("{out}{}", " ".repeat(k))).unwrap();
            padded
        };
        let (batch, sampled, first) = quick_audit(dir, &file, &format!("r{k}"));
        assert!(batch < 16, "{batch}");
        drawn.insert(batch);
        assert_eq!(sampled["units"], "batches");
        assert_eq!(
            (sampled["rerun"].as_u64(), sampled["count"].as_u64()),
            (Some(1), Some(16))
        );
        assert_eq!(sampled["p_forged_pass"].as_f64(), Some(15.0 / 16.0));
        assert!(
            first.contains("PASS (quick audit: 1 of 16 batches re-run")
                && first.contains("15/16")
                && first.contains("publish with the full audit"),
            "{first}"
        );
    }
    assert!(
        drawn.len() >= 2,
        "six quick audits all re-ran batch {drawn:?}"
    );
}
