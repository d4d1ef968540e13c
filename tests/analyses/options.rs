//! Options that say what they support: a run option an analysis does not use (a checkpoint
//! given to Lyapunov exponents, certification, true shadowing or injection, an engine given to
//! the escape rate, an audit given to packed diffusion runs) is refused before any work with
//! `Error::UnusedOption` naming the analysis and the option, never ignored.

use std::time::Duration;

use lorentz_gas::engine::Engine;
use lorentz_gas::engine::options::{AuditSpec, RunOption, RunOptions};
use lorentz_gas::estimators::diffusion::{self, DiffusionConfig};
use lorentz_gas::estimators::escape::{self, EscapeConfig};
use lorentz_gas::estimators::hops::backscatter::{self, BackscatterConfig};
use lorentz_gas::scenes::spec::Table;
use lorentz_gas::scenes::triangular::TriangularScene;
use lorentz_gas::verification::certify::{self, CertifyConfig};
use lorentz_gas::verification::lyapunov::{self, LyapunovConfig};
use lorentz_gas::verification::shadowing::{self, ShadowConfig};
use lorentz_gas::{Error, ErrorKind};

fn refused(r: Result<impl std::fmt::Debug, Error>, analysis: &str, option: RunOption) {
    match r {
        Err(Error::UnusedOption {
            analysis: a,
            option: o,
        }) => {
            assert_eq!((a, o), (analysis, option));
            let e = Error::UnusedOption {
                analysis: a,
                option: o,
            };
            assert_eq!(e.kind(), ErrorKind::BadInput);
            assert!(e.to_string().contains(option.field()), "{e}");
        }
        other => panic!("{analysis} with {option} set: {other:?}"),
    }
}

fn with(option: RunOption) -> RunOptions<'static> {
    let o = RunOptions {
        threads: 1,
        ..RunOptions::default()
    };
    match option {
        RunOption::Engine => RunOptions {
            engine: Engine::Scalar,
            ..o
        },
        RunOption::Resume => RunOptions {
            resume: Some("never-written.ckpt".into()),
            ..o
        },
        RunOption::Audit => RunOptions {
            audit: Some(AuditSpec::new(1e-3, 128).unwrap()),
            ..o
        },
        RunOption::CheckpointEvery => RunOptions {
            checkpoint_every: Duration::from_secs(5),
            ..o
        },
    }
}

#[test]
fn verification_analyses_refuse_every_run_option() {
    let scene = TriangularScene::new(0.1).unwrap();
    for option in RunOption::ALL {
        let o = with(option);
        refused(
            lyapunov::run(&scene, &LyapunovConfig::new(), &o),
            "lyapunov",
            option,
        );
        refused(
            certify::run(&scene, &CertifyConfig::new(), &o),
            "certify",
            option,
        );
        let shadow = ShadowConfig {
            collisions_per_segment: 20,
            segments: 1,
            seed: 1,
            reference_bits: 256,
            motion: Default::default(),
        };
        refused(shadowing::run(&scene, &shadow, &o), "shadow", option);
        refused(
            backscatter::run(&BackscatterConfig::new(Table::triangular_at(0.1)), &o),
            "backscatter",
            option,
        );
    }
    assert!(!std::path::Path::new("never-written.ckpt").exists());
}

#[test]
fn estimators_refuse_the_options_they_do_not_use() {
    for option in [RunOption::Engine, RunOption::Audit] {
        refused(
            escape::run(&EscapeConfig::new(Table::triangular_at(0.1)), &with(option)),
            "escape",
            option,
        );
    }
    let cfg = DiffusionConfig {
        collisions: 1_000_000,
        batches: 4,
        ..DiffusionConfig::new(0.2)
    };
    refused(
        diffusion::run_many(std::slice::from_ref(&cfg), &with(RunOption::Audit)),
        "diffusion (packed runs)",
        RunOption::Audit,
    );
    // What an analysis uses is accepted: an engine for diffusion, every option at its default.
    assert!(diffusion::run(&cfg, &with(RunOption::Engine)).is_ok());
    let defaults = RunOptions {
        threads: 1,
        ..RunOptions::default()
    };
    for option in RunOption::ALL {
        assert!(!defaults.is_set(option), "{option}");
        assert!(with(option).is_set(option), "{option}");
    }
}
