//! The audit of a `diffusion --electric` result (the driven gas's steady state): the record
//! recomputed from its batches and its exact field, the batches' statistics (an average over
//! attractors shows as an outlying batch), the Lyapunov sum rule and its per-trajectory identity,
//! no current across a field along a mirror line of the table, a shadow audit of thermostatted
//! events at the recorded table and field, and the configuration re-run (one batch, drawn at
//! random, with `quick`).

use std::path::Path;

use super::diffusion::refused_config;
use super::file::ResultFile;
use super::same_bits::rerun_check;
use super::statistics::batch_statistics;
use super::{Checks, Ctx, Verdict};
use crate::Error;
use crate::estimators::current::{self, CurrentReport, Steady, WARM_UP_SHARE};
use crate::estimators::diffusion::DiffusionConfig;
use crate::numbers::exact::parse_exact;
use crate::scenes::motion::MotionInput;
use crate::scenes::spec::{Motion, SceneSpec};
use crate::statistics::mean_se;
use crate::verification::audited::AuditConfig;

/// Collisions of the shadow audit of thermostatted events (every event replayed): with `quick`,
/// and without.
const AUDIT_COLLISIONS: [u64; 2] = [20_000, 200_000];

/// The file as a result under the thermostat whose configuration the command line would accept.
pub(super) fn parse(file: &ResultFile, path: &Path) -> Result<CurrentReport, Error> {
    let r: CurrentReport = file.parse(path)?;
    r.config.validate().map_err(|e| refused_config(path, e))?;
    if !matches!(r.config.table.motion, Motion::Thermostat { .. }) {
        return Err(Error::malformed(
            path,
            "a current result whose configuration has no thermostatted field",
        ));
    }
    Ok(r)
}

/// The re-runs, in the order the checks take them: the shadow audit, then the whole run (or one
/// batch of it with `quick`), each with its warm-up.
pub(super) fn reruns(r: &CurrentReport, quick: bool) -> Vec<u64> {
    let cfg = &r.config;
    let observed = if quick {
        cfg.collisions / u64::from(cfg.batches)
    } else {
        cfg.collisions
    };
    let warm = (observed as f64 * (1.0 + 1.0 / WARM_UP_SHARE)).ceil() as u64;
    vec![AUDIT_COLLISIONS[usize::from(!quick)], warm]
}

/// The checks: the record, the batches, the identities, the shadow audit, the re-run.
pub(super) fn checks(r: &CurrentReport, ctx: &Ctx<'_>, checks: &mut Checks) -> Result<(), Error> {
    let cfg = &r.config;
    let (bits, batches) = (cfg.precision.to_string(), u64::from(cfg.batches));
    let mut bad = super::meta_problems(&r.meta, Some(cfg.seed), Some(batches), &bits);
    bad.extend(record_problems(r)?);
    super::record_check(bad, checks);
    batch_statistics(&r.batch_J_parallel, checks);
    sum_rule_checks(r, checks);
    mirror_check(r, checks)?;
    audit_check(cfg, ctx, checks)?;
    if ctx.quick {
        let recorded = [("J∥", &r.batch_J_parallel[..]), ("J⊥", &r.batch_J_perp[..])];
        return ctx.one_batch_rerun(checks, (cfg.batches, None), &recorded, |b, o| {
            current::rerun_batch(cfg, b, o).map(Vec::from)
        });
    }
    let what = format!(
        "{} collisions in {} batches (seed {}, {})",
        cfg.collisions, cfg.batches, cfg.seed, cfg.precision
    );
    let units = cfg.collisions;
    rerun_check(r, units, &what, ctx, checks, |o| current::run(cfg, o))
}

/// What of the record differs from its exact field and its own batch values: the field's
/// strength and direction, J∥, J⊥, the mobility and the entropy production with their errors,
/// all to the bit.
fn record_problems(r: &CurrentReport) -> Result<Vec<String>, Error> {
    let cfg = &r.config;
    let mut bad = Vec::new();
    let world = current::field_at::<f64>(cfg, ())?;
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
    if !same(r.electric, world.strength)
        || !same(r.direction[0], world.dir.x)
        || !same(r.direction[1], world.dir.y)
    {
        bad.push("the field's strength or direction is not the configuration's".into());
    }
    let n = cfg.batches as usize;
    if r.batch_J_parallel.len() != n || r.batch_J_perp.len() != n {
        bad.push(format!("not {n} batches with one J∥ and one J⊥ each"));
        return Ok(bad);
    }
    bad.extend(steady_problems(
        &r.steady,
        (&r.batch_J_parallel, Some(&r.batch_J_perp)),
        world.strength,
    ));
    Ok(bad)
}

/// What of the steady state `s` differs from its batches' currents along E (and across it, when
/// recorded) under the field's strength `eps`: J∥, J⊥, the mobility and the entropy production
/// with their errors, to the bit.
pub(super) fn steady_problems(
    s: &Steady,
    (along, across): (&[f64], Option<&[f64]>),
    eps: f64,
) -> Vec<String> {
    let scaled = |f: &dyn Fn(f64) -> f64| along.iter().map(|&j| f(j)).collect::<Vec<f64>>();
    let mut pairs = vec![
        (
            "J_parallel",
            (s.J_parallel, s.J_parallel_err),
            mean_se(along),
        ),
        (
            "mobility",
            (s.mobility, s.mobility_err),
            mean_se(&scaled(&|j| j / eps)),
        ),
        (
            "entropy_production",
            (s.entropy_production, s.entropy_production_err),
            mean_se(&scaled(&|j| j * eps)),
        ),
    ];
    if let Some(across) = across {
        pairs.push(("J_perp", (s.J_perp, s.J_perp_err), mean_se(across)));
    }
    let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
    (pairs.into_iter())
        .filter(|(_, (v, e), (a, ae))| !same(*v, *a) || !same(*e, *ae))
        .map(|(name, (v, e), (a, ae))| {
            format!("{name} {v:e} ± {e:e} is not {a:e} ± {ae:e} from the batches")
        })
        .collect()
}

/// λ₊ + λ₋ + ⟨α⟩ = 0 on average (within the Student-t bound of the batches) and per trajectory
/// (the worst residual of Σ ln stretchings + ∫α + ln(|f(T)|/|f(0)|) within its rounding bound).
fn sum_rule_checks(r: &CurrentReport, checks: &mut Checks) {
    let s = &r.steady;
    let dof = f64::from(r.config.batches) - 1.0;
    checks.within_t(
        dof,
        ("identities", "sum rule: λ₊ + λ₋ + ⟨α⟩ = 0"),
        ((s.sum_rule, s.sum_rule_err), 0.0),
        format!(
            "λ₊ = {}, λ₋ = {}: λ₊ + λ₋ + ⟨α⟩ = ",
            s.lambda_plus, s.lambda_minus
        ),
    );
    let (res, b) = (s.sum_rule_residual, s.sum_rule_residual_bound);
    checks.pass_if(
        res.abs() <= b,
        "identities",
        "sum rule per trajectory: Σ ln stretchings + ∫α dt = −ln(|f(T)|/|f(0)|)",
        format!("worst residual {res:.2e} against its rounding bound {b:.2e}"),
        &[("residual", res), ("bound", b)],
    );
}

/// The order of the table's rotation group whose mirror lines the field may lie on, in degrees
/// between lines: 30° on the triangular lattice, 45° on the square one, none otherwise.
fn mirror_spacing(scene: &SceneSpec) -> Option<u32> {
    match scene {
        SceneSpec::Triangular { .. } => Some(30),
        SceneSpec::Square { .. } => Some(45),
        _ => None,
    }
}

/// No current across E when E lies on a mirror line of the table (the reflection in that line
/// maps the steady state to itself and J⊥ to −J⊥): J⊥ = 0 within the Student-t bound.
fn mirror_check(r: &CurrentReport, checks: &mut Checks) -> Result<(), Error> {
    let name = "no current across a field along a mirror line: J⊥ = 0";
    let Motion::Thermostat { angle, .. } = &r.config.table.motion else {
        return Ok(());
    };
    let on_mirror = match mirror_spacing(&r.config.table.scene) {
        Some(d) => (parse_exact(angle)? / d).is_integer(),
        None => false,
    };
    if !on_mirror {
        checks.add(
            "identities",
            name,
            Verdict::NotApplicable,
            format!("the field at {angle}° lies on no mirror line of this table"),
            &[],
        );
        return Ok(());
    }
    let s = &r.steady;
    checks.within_t(
        f64::from(r.config.batches) - 1.0,
        ("identities", name),
        ((s.J_perp, s.J_perp_err), 0.0),
        format!("field at {angle}°: J⊥ = "),
    );
    Ok(())
}

/// A shadow audit of thermostatted events at the recorded table, field and seed (its own
/// trajectories from the invariant measure, every event replayed at the audit's precision from
/// its exact pre-event state): none outside the error model.
fn audit_check(cfg: &DiffusionConfig, ctx: &Ctx<'_>, checks: &mut Checks) -> Result<(), Error> {
    let name = "shadow audit of thermostatted events at the recorded table and field";
    let Some(n) = ctx.take_or_skip(checks, ("verification", name)) else {
        return Ok(());
    };
    let Motion::Thermostat { field, angle } = &cfg.table.motion else {
        return Ok(());
    };
    let scene = cfg.table.scene.resolve()?;
    let audit = AuditConfig {
        scene: crate::with_scene!(&scene, |s| crate::scenes::Scene::label(s)),
        collisions: n,
        batches: cfg.batches.min(4),
        sample: 1.0,
        reference_bits: ctx.bits,
        seed: cfg.seed,
        motion: MotionInput {
            electric: Some(field.clone()),
            electric_angle: Some(angle.clone()),
            ..Default::default()
        },
        flights: Default::default(),
    };
    let o = ctx.options();
    let a = crate::with_scene!(&scene, |s| crate::verification::shadow_audit::run(
        s, &audit, &o
    ))?;
    let m = &a.summary;
    checks.pass_if(
        m.outside == 0,
        "verification",
        name,
        format!(
            "{} events replayed at {} bits: {} outside the model, {} ambiguous (a tie the \
             reference cannot split)",
            m.audited, ctx.bits, m.outside, m.ambiguous
        ),
        &[
            ("audited", m.audited as f64),
            ("outside", m.outside as f64),
            ("ambiguous", m.ambiguous as f64),
        ],
    );
    Ok(())
}
