//! The fuzzing oracle (`lorentz_gas::verification::oracle`) driven by proptest, by the
//! committed seed corpora of `fuzz/corpus/`, and by one regression test per minimised fuzz
//! finding. Seeded (ChaCha, fixed seed) and shrinking; see `proofs-notes/fuzzing.md`.

use std::collections::HashSet;
use std::path::PathBuf;

use lorentz_gas::verification::oracle::{
    collision_primitive, decode_primitive, decode_scene, scene_stepper, PrimitiveCase,
};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

fn runner(cases: u32) -> TestRunner {
    let cfg = Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    };
    TestRunner::new_with_rng(cfg, TestRng::from_seed(RngAlgorithm::ChaCha, &[11; 32]))
}

/// Byte vectors of any length up to 64 (the decoders read at most ~40 bytes; shorter inputs
/// read zeros past their end).
fn bytes() -> impl Strategy<Value = Vec<u8>> {
    proptest::collection::vec(any::<u8>(), 0..64)
}

fn family(c: PrimitiveCase) -> u8 {
    match c {
        PrimitiveCase::Impact { .. } => 0,
        PrimitiveCase::NearSurface { .. } => 1,
        PrimitiveCase::DoubleTangent { .. } => 2,
        PrimitiveCase::GapPoint { .. } => 3,
        PrimitiveCase::Arbitrary => 4,
    }
}

#[test]
fn random_bytes_through_the_collision_primitive_oracle() {
    runner(4000)
        .run(&bytes(), |data| {
            if let Err(e) = collision_primitive(&data) {
                prop_assert!(false, "{e}");
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn random_bytes_through_the_scene_stepper_oracle() {
    runner(1000)
        .run(&bytes(), |data| {
            if let Err(e) = scene_stepper(&data) {
                prop_assert!(false, "{e}");
            }
            Ok(())
        })
        .unwrap();
}

/// Random bytes reach every family and every sub-case (disk, exponent range, motion, line),
/// so the proptest above exercises all of them.
#[test]
fn random_bytes_reach_every_decoded_case() {
    let mut seen = HashSet::new();
    let mut rng = TestRng::from_seed(RngAlgorithm::ChaCha, &[12; 32]);
    for _ in 0..4000 {
        let data: Vec<u8> = (0..48).map(|_| rng.random()).collect();
        let c = decode_primitive(&data).unwrap().case;
        seen.insert(match c {
            PrimitiveCase::Impact { disk, above, .. } => (0, disk, above as u8),
            PrimitiveCase::NearSurface { disk, motion, .. } => (1, disk, motion),
            PrimitiveCase::DoubleTangent { edge, line } => (2, edge, line),
            PrimitiveCase::GapPoint {
                edge,
                end,
                at_point,
            } => (3, edge, end * 2 + at_point as u8),
            PrimitiveCase::Arbitrary => (4, 0, 0),
        });
    }
    let expected = 3 * 2 + 3 * 3 + 3 * 3 + 3 * 4 + 1;
    assert_eq!(seen.len(), expected, "{seen:?}");
}

fn corpus(target: &str) -> Vec<(PathBuf, Vec<u8>)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/corpus")
        .join(target);
    let mut out: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("seed-"))
        })
        .map(|p| {
            let b = std::fs::read(&p).unwrap();
            (p, b)
        })
        .collect();
    out.sort();
    out
}

/// Every committed seed passes, and together the seeds cover all five families.
#[test]
fn committed_collision_primitive_seeds_pass_and_cover_every_family() {
    let seeds = corpus("collision_primitive");
    let mut fams = HashSet::new();
    for (p, b) in &seeds {
        let r = collision_primitive(b).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        fams.insert(family(r.case));
    }
    assert_eq!(fams.len(), 5, "families covered: {fams:?}");
}

#[test]
fn committed_scene_stepper_seeds_pass_and_cover_every_family() {
    let seeds = corpus("scene_stepper");
    let mut fams = HashSet::new();
    for (p, b) in &seeds {
        let s = decode_scene(b).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        scene_stepper(b).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
        fams.insert(family(s.primitive.case));
    }
    assert_eq!(fams.len(), 5, "families covered: {fams:?}");
}
