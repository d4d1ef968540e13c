//! The batches of a run under the thermostat summarised: means and standard errors over batches.

use serde::{Deserialize, Serialize};

use super::tangent::pair_summary;
use super::track::{ANGLE_BINS, Batch};
use super::{CurrentReport, WARM_UP_SHARE, grid, mean_of, slope};
use crate::engine::metadata::RunMeta;
use crate::estimators::diffusion::{DiffusionConfig, Window, time_unit};
use crate::kernel::thermostat::Thermostat;
use crate::scenes::Scene;
use crate::statistics::mean_se;

/// The diffusion tensor about the drift over one window, each component with its standard error
/// over batches: half the slopes of the lag covariances ⟨ΔaΔb⟩ − ⟨Δa⟩⟨Δb⟩.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct DriftTensor {
    /// D_xx.
    pub D_xx: f64,
    /// Its standard error.
    pub D_xx_err: f64,
    /// D_yy.
    pub D_yy: f64,
    /// Its standard error.
    pub D_yy_err: f64,
    /// D_xy (symmetric).
    pub D_xy: f64,
    /// Its standard error.
    pub D_xy_err: f64,
    /// Along the field, ê·D·ê.
    pub D_parallel: f64,
    /// Its standard error.
    pub D_parallel_err: f64,
    /// Across it, ê⊥·D·ê⊥.
    pub D_perp: f64,
    /// Its standard error.
    pub D_perp_err: f64,
}

/// The numbers of the steady state under the thermostat, each with its standard error over
/// batches: what a run reports and a sweep over E keeps of each point.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[allow(non_snake_case)]
pub struct Steady {
    /// J_x = ⟨v_x⟩ in the steady state.
    pub J_x: f64,
    /// Its standard error over the batches.
    pub J_x_err: f64,
    /// J_y.
    pub J_y: f64,
    /// Its standard error over the batches.
    pub J_y_err: f64,
    /// ê·J, the current along the field.
    pub J_parallel: f64,
    /// Its standard error over the batches.
    pub J_parallel_err: f64,
    /// ê⊥·J (ê⊥ = ê turned by +90°), the current across it (0 where a mirror of the table
    /// contains E).
    pub J_perp: f64,
    /// Its standard error over the batches.
    pub J_perp_err: f64,
    /// J_parallel/ε: the mobility, which tends to D as ε → 0 (the Einstein relation).
    pub mobility: f64,
    /// Its standard error over the batches.
    pub mobility_err: f64,
    /// E·J = ⟨α⟩, the entropy production (the mean phase-space contraction rate).
    pub entropy_production: f64,
    /// Its standard error over the batches.
    pub entropy_production_err: f64,
    /// λ₊, the positive Lyapunov exponent of the flow (per unit time).
    pub lambda_plus: f64,
    /// Its standard error over the batches.
    pub lambda_plus_err: f64,
    /// λ₋, the negative one (the third is 0, along the flow).
    pub lambda_minus: f64,
    /// Its standard error over the batches.
    pub lambda_minus_err: f64,
    /// λ₊ + λ₋ + ⟨α⟩ over the pair's own stretch (to its last collision) per batch: the sum
    /// rule says 0, but for ln(|f(T)|/|f(0)|)/T ≤ ln(1 + ε²)/(2T).
    pub sum_rule: f64,
    /// Its standard error over the batches.
    pub sum_rule_err: f64,
    /// The largest |Σ ln stretchings + ∫α + ln(|f(T)|/|f(0)|)| of a batch: the sum rule per
    /// trajectory, 0 but for rounding.
    pub sum_rule_residual: f64,
    /// The rounding bound of that batch's residual (`proofs-notes/thermostat-lyapunov.md`).
    pub sum_rule_residual_bound: f64,
    /// The Kaplan–Yorke dimension of the attractor of the flow, 2 + λ₊/|λ₋| (per batch).
    pub kaplan_yorke: f64,
    /// Its standard error over the batches.
    pub kaplan_yorke_err: f64,
    /// The diffusion tensor about the drift over the fit window.
    pub diffusion: DriftTensor,
    /// Mean time between collisions in the steady state: the inverse of the collision rate
    /// averaged over batches of equal duration.
    pub mean_free_time: f64,
    /// Its standard error over the batches.
    pub mean_free_time_err: f64,
}

/// One batch's tensor over `win`: [xx, yy, xy, along, across].
fn tensor_of(b: &Batch, lags: &[usize], tau: f64, win: &Window, e: [f64; 2]) -> [f64; 5] {
    let var = |m: &[f64; 5], u: [f64; 2]| {
        let cxx = m[0] - m[3] * m[3];
        let cyy = m[1] - m[4] * m[4];
        let cxy = m[2] - m[3] * m[4];
        u[0] * u[0] * cxx + 2.0 * u[0] * u[1] * cxy + u[1] * u[1] * cyy
    };
    let half = |f: &dyn Fn(&[f64; 5]) -> f64| slope(b, lags, tau, win, f) / 2.0;
    [
        half(&|m| var(m, [1.0, 0.0])),
        half(&|m| var(m, [0.0, 1.0])),
        half(&|m| m[2] - m[3] * m[4]),
        half(&|m| var(m, e)),
        half(&|m| var(m, [-e[1], e[0]])),
    ]
}

/// The tensor over `win` from every batch.
fn tensor(batches: &[Batch], lags: &[usize], tau: f64, win: &Window, e: [f64; 2]) -> DriftTensor {
    let per: Vec<[f64; 5]> = batches
        .iter()
        .map(|b| tensor_of(b, lags, tau, win, e))
        .collect();
    let stat = |k: usize| mean_se(&per.iter().map(|t| t[k]).collect::<Vec<_>>());
    let ((xx, xx_e), (yy, yy_e), (xy, xy_e)) = (stat(0), stat(1), stat(2));
    let ((par, par_e), (perp, perp_e)) = (stat(3), stat(4));
    DriftTensor {
        D_xx: xx,
        D_xx_err: xx_e,
        D_yy: yy,
        D_yy_err: yy_e,
        D_xy: xy,
        D_xy_err: xy_e,
        D_parallel: par,
        D_parallel_err: par_e,
        D_perp: perp,
        D_perp_err: perp_e,
    }
}

/// The velocity angle's density per radian by bin, with its standard error over batches.
fn angle_density(batches: &[Batch]) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let width = std::f64::consts::TAU / ANGLE_BINS as f64;
    let centres = (0..ANGLE_BINS)
        .map(|k| -std::f64::consts::PI + (k as f64 + 0.5) * width)
        .collect();
    let (density, err) = (0..ANGLE_BINS)
        .map(|k| {
            let per: Vec<f64> = batches
                .iter()
                .map(|b| b.angles[k] as f64 / (b.angles.iter().sum::<u64>().max(1) as f64 * width))
                .collect();
            mean_se(&per)
        })
        .unzip();
    (centres, density, err)
}

/// The steady state's numbers over `batches` under the field `world` (doubles), the tensor over
/// the fit window `win` of `lags` (time unit `tau`).
fn steady(
    world: &Thermostat<f64>,
    batches: &[Batch],
    (lags, tau, win): (&[usize], f64, &Window),
) -> Steady {
    let e = [world.dir.x, world.dir.y];
    let eps = world.strength;
    let per = |f: &dyn Fn(&Batch) -> f64| batches.iter().map(f).collect::<Vec<f64>>();
    let along = per(&|b| along_across(e, b)[0]);
    let across = per(&|b| along_across(e, b)[1]);
    let rate = mean_of(&per(&|b| b.collisions as f64 / b.time));
    let (j_x, j_y) = (
        mean_of(&per(&|b| b.current[0])),
        mean_of(&per(&|b| b.current[1])),
    );
    let (j_par, j_perp) = (mean_of(&along), mean_of(&across));
    let mobility = mean_of(&along.iter().map(|j| j / eps).collect::<Vec<_>>());
    let production = mean_of(&along.iter().map(|j| j * eps).collect::<Vec<_>>());
    let mean_free_time = 1.0 / rate.value;
    let lyapunov = pair_summary(&batches.iter().map(|b| b.pair).collect::<Vec<_>>());
    Steady {
        J_x: j_x.value,
        J_x_err: j_x.err,
        J_y: j_y.value,
        J_y_err: j_y.err,
        J_parallel: j_par.value,
        J_parallel_err: j_par.err,
        J_perp: j_perp.value,
        J_perp_err: j_perp.err,
        mobility: mobility.value,
        mobility_err: mobility.err,
        entropy_production: production.value,
        entropy_production_err: production.err,
        lambda_plus: lyapunov.plus.value,
        lambda_plus_err: lyapunov.plus.err,
        lambda_minus: lyapunov.minus.value,
        lambda_minus_err: lyapunov.minus.err,
        sum_rule: lyapunov.sum_rule.value,
        sum_rule_err: lyapunov.sum_rule.err,
        sum_rule_residual: lyapunov.residual.0,
        sum_rule_residual_bound: lyapunov.residual.1,
        kaplan_yorke: lyapunov.kaplan_yorke.value,
        kaplan_yorke_err: lyapunov.kaplan_yorke.err,
        diffusion: tensor(batches, lags, tau, win, e),
        mean_free_time,
        mean_free_time_err: rate.err * mean_free_time * mean_free_time,
    }
}

/// A batch's current along E and across it (ê⊥ = ê turned by +90°), `e` = ê.
pub(super) fn along_across(e: [f64; 2], b: &Batch) -> [f64; 2] {
    [
        e[0] * b.current[0] + e[1] * b.current[1],
        -e[1] * b.current[0] + e[0] * b.current[1],
    ]
}

/// The report of `batches`, run on `scene` under the field `world` (doubles) in `seconds`.
pub(super) fn summarise<S: Scene>(
    scene: &S,
    cfg: &DiffusionConfig,
    world: &Thermostat<f64>,
    batches: &[Batch],
    (seconds, meta): (f64, RunMeta),
) -> CurrentReport {
    let e = [world.dir.x, world.dir.y];
    let eps = world.strength;
    let tau = time_unit(scene);
    let lags = cfg.lags();
    let per = |f: &dyn Fn(&Batch) -> f64| batches.iter().map(f).collect::<Vec<f64>>();
    let along = per(&|b| along_across(e, b)[0]);
    let across = per(&|b| along_across(e, b)[1]);
    let (angle_bins, angle_density, angle_density_err) = angle_density(batches);
    let collisions = batches.iter().map(|b| b.collisions).sum();
    let (spacing, _, samples) = grid(scene, cfg);
    let duration = samples as f64 * spacing;
    CurrentReport {
        scene: scene.label(),
        electric: eps,
        direction: e,
        steady: steady(world, batches, (&lags, tau, &cfg.window)),
        diffusion_check: tensor(batches, &lags, tau, &cfg.check_window, e),
        angle_bins,
        angle_density,
        angle_density_err,
        mean_free_time_no_field: scene.mean_free_path(),
        window: cfg.window,
        check_window: cfg.check_window,
        tau,
        warm_up: duration / WARM_UP_SHARE,
        measured_time: duration,
        collisions,
        seconds,
        collisions_per_second: collisions as f64 / seconds.max(f64::MIN_POSITIVE),
        batch_J_parallel: along,
        batch_J_perp: across,
        config: cfg.clone(),
        meta,
    }
}
