//! The thermostat kernel on decoded states: the lattice stepper's degenerate starts (grazing,
//! near-surface, tangents, rim crossings, corners) flown under a Gaussian-thermostatted field
//! decoded from the last three bytes, E from 10⁻³ to 10 at any angle.
//!
//! For every event: MPFR at 53 bits took the same event to the same bits (every operation of the
//! flight and of the march is correctly rounded in both, `proofs-notes/thermostat-flight.md`);
//! no contact was missed before it — at [`SAMPLES`] − 1 times spread over the flight the exact
//! flight (at [`FLIGHT_BITS`], from the same `f64` state and field) is outside every disk and
//! inside every edge up to the kernel's own bound e₀ on the contact function, and at the event
//! it is on the obstacle reported up to 2e₀ (`proofs-notes/thermostat-audit.md`, the stopping
//! band); after it the state is finite, of speed 1 within the energy band widened by the
//! contact's residual through the reflection (4·2e₀/r²), outside every disk and
//! inside every edge up to the post-event bound plus the contact's e₀, the cell moved across the
//! edge on a crossing and the obstacle met is excluded. A flight without a next event (the
//! creeping limit) ends the input.

use super::curved_walk::{Judge, cell_and_exclusions_after, unit_speed_after, walk};
use super::*;
use crate::kernel::thermostat::Thermostat;
use crate::kernel::thermostat::cell::ThermoEvent;
use crate::scenes::thermostat::CellFields;
use crate::verification::curved::{Curved, CurvedEvent};

/// Most events one input flies.
pub const MAX_THERMO_STEPS: u32 = 4;
/// The flight is checked at this many − 1 interior times.
pub const SAMPLES: u32 = 8;
/// Precision of the exact flight the samples are checked on.
pub const FLIGHT_BITS: u32 = 128;

/// The field of an input from its last three bytes k, a₀, a₁: the strength E = 10^(4k/255 − 3)
/// ∈ [10⁻³, 10] and the angle 2π·(a₀ + 256a₁)/65536 (the bytes 0 give E = 10⁻³ along x).
pub fn decode_electric(data: &[u8]) -> (f64, f64) {
    let n = data.len();
    let byte = |i: usize| if n >= 3 { data[n - 3 + i] } else { 0 };
    let k = f64::from(byte(0));
    let a = f64::from(u16::from_le_bytes([byte(1), byte(2)]));
    (
        10f64.powf(4.0 * k / 255.0 - 3.0),
        std::f64::consts::TAU * a / 65536.0,
    )
}

/// Flies a decoded lattice state under the thermostat (see the module documentation).
///
/// # Errors
/// A decoding failure or the first violation, with the state before the failing event.
pub fn thermostat_kernel(data: &[u8]) -> Result<OracleReport, OracleFailure> {
    let input = decode_scene(data)?;
    let (case, start) = input.start();
    let field = decode_electric(data);
    let steps = input.steps.min(MAX_THERMO_STEPS);
    match input.primitive.scene {
        SceneParams::Triangular { w } => {
            fly_thermostat(&triangular(w)?, case, &start, field, steps)
        }
        SceneParams::Square { r } => fly_thermostat(&square(r)?, case, &start, field, steps),
    }
}

/// The `f64` field of strength `e` along `angle` (radians), and the same field lifted exactly to
/// `bits` (each run of the oracle compares the kernel at one field, the `f64` one).
fn fields(e: f64, angle: f64, bits: u32) -> (CellFields<f64>, CellFields<Float>) {
    let th = Thermostat::new(e, Vec2::new(angle.cos(), angle.sin()));
    let lift = |x: f64| Float::with_val(bits, x);
    let hp = Thermostat {
        strength: lift(th.strength),
        dir: Vec2::new(lift(th.dir.x), lift(th.dir.y)),
    };
    (CellFields::new(th), CellFields::new(hp))
}

/// Flies `start` of `scene` under the field of strength `e` at `angle` radians for up to `steps`
/// events, checking every one.
///
/// # Errors
/// The first violation.
pub fn fly_thermostat<S: Scene>(
    scene: &S,
    case: Option<PrimitiveCase>,
    start: &LatticeState<f64>,
    (e, angle): (f64, f64),
    steps: u32,
) -> Result<OracleReport, OracleFailure> {
    let label = format!("{} E={e:e} at {angle} rad", scene.label());
    let err =
        |e: crate::Error| OracleFailure::new(case, &label, None, e.to_string(), String::new());
    let lat = scene.lattice::<f64>(()).map_err(err)?;
    let lhp = scene.lattice::<Float>(FLIGHT_BITS).map_err(err)?;
    let (f64s, f53) = fields(e, angle, 53);
    let (_, fhp) = fields(e, angle, FLIGHT_BITS);
    let cell = lat.cell();
    let band = energy_band(cell);
    let judge: &mut Judge<'_> = &mut |before, ev, after, rep| {
        let CurvedEvent::Thermostat(ev) = ev else {
            return Err(format!("not a thermostatted event: {:?}", ev.kind()));
        };
        let (th, th_hp) = (f64s.in_cell(&before.cell), fhp.in_cell(&before.cell));
        let slack = no_missed_contact(cell, lhp.cell(), before, th, th_hp, ev)?;
        after_event(cell, band, slack, before, ev, after, rep)
    };
    let motions = (&Curved::Thermostat(f64s.clone()), &Curved::Thermostat(f53));
    let run = (case, label.as_str(), steps);
    walk(scene, &lat, run, start, motions, judge)
}

/// The contact functions of every disk and edge along the exact flight from `s` (at the
/// precision of `hp`, the `f64` state and field lifted exactly) at [`SAMPLES`] − 1 interior times
/// of the event `ev`'s flight and at the event: none below −e₀ before it (e₀ the `f64` kernel's
/// own bound of that contact function there), the obstacle met within 2e₀ of zero at it. Returns
/// the largest e₀ at the event (the post-event check's slack). Each bound adds the start's own
/// offset from its obstacles, the post-event bound.
fn no_missed_contact(
    cell: &ConvexCell<f64>,
    hp: &ConvexCell<Float>,
    s: &LatticeState<f64>,
    th: &Thermostat<f64>,
    th_hp: &Thermostat<Float>,
    ev: &ThermoEvent<f64>,
) -> Result<f64, String> {
    let f = &s.flight;
    let fh = Flight::<Float>::convert_from_f64(FLIGHT_BITS, f);
    let start = th_hp.start(&fh.vel);
    let kinds: Vec<EventKind> = (0..cell.disks.len() as u8)
        .map(EventKind::Collision)
        .chain((0..cell.edges.len() as u8).map(EventKind::Crossing))
        .collect();
    // The kernel takes the start as exact, the obstacle it is on at distance 0; the start itself
    // is off its obstacles by up to the decoder's validity and the post-event bound (kept as an
    // exclusion within it, `arcs::into_domain`), an offset the flight carries along.
    let r = cell
        .disks
        .iter()
        .map(|d| d.radius().to_f64())
        .fold(0.0, f64::max);
    let floor = POST_EVENT_U * U * (1.0 + cell.extent()) * (1.0 + r);
    let mut slack = 0.0f64;
    for i in 1..=SAMPLES {
        let t = ev.time * f64::from(i) / f64::from(SAMPLES);
        let at = start.at(&Float::with_val(FLIGHT_BITS, t));
        let x = Vec2::new(fh.pos.x.clone() + &at.disp.x, fh.pos.y.clone() + &at.disp.y);
        for &k in &kinds {
            let e0 = cell.thermostat_jet(f, th, k, &t).err[0];
            let value = match k {
                EventKind::Collision(m) => {
                    let d = &hp.disks[m as usize];
                    (x.sub(&d.centre).norm2() - d.radius2()).to_f64()
                }
                EventKind::Crossing(j) => {
                    let e = &hp.edges[j as usize];
                    (e.normal.dot(&x) - &e.offset).to_f64()
                }
            };
            if i < SAMPLES && value < -(e0 + floor) {
                return Err(format!(
                    "{k:?} missed before {:?} at t = {t:e} of {:e}: F = {value:e}, e0 = {e0:e}",
                    ev.kind, ev.time
                ));
            }
            if i == SAMPLES {
                slack = slack.max(e0);
                if k == ev.kind && value.abs() > 2.0 * e0 + 64.0 * U + floor {
                    return Err(format!(
                        "{k:?} at t = {t:e} off its obstacle: F = {value:e}, e0 = {e0:e}"
                    ));
                }
            }
        }
    }
    Ok(slack)
}

/// The checks after one event: finite, speed within the energy band, outside every disk and
/// inside every edge up to the post-event bound and the contact's `slack`, the cell and the
/// exclusions the event's.
fn after_event(
    cell: &ConvexCell<f64>,
    band: f64,
    slack: f64,
    before: &LatticeState<f64>,
    ev: &ThermoEvent<f64>,
    after: &LatticeState<f64>,
    rep: &mut OracleReport,
) -> Result<(), String> {
    let fl = &after.flight;
    // A contact a residual δF = |x − c|² − r² off the circle (|δF| ≤ 2e₀ + 64u, checked at the
    // event) reflects the speed² by up to 4|δF|/r²: the straight band plus that.
    let r = cell.smallest_radius();
    let band = band + 4.0 * (2.0 * slack + 64.0 * U) / (r * r * U);
    unit_speed_after(fl, ev.kind, band, rep)?;
    let room = POST_EVENT_U * U * (1.0 + cell.extent()) + 2.0 * slack;
    for (m, disk) in cell.disks.iter().enumerate() {
        let d = fl.pos.sub(&disk.centre).norm2() - disk.radius2();
        if d.is_nan() || d < -room {
            return Err(format!("inside disk {m} after {:?}: {d:e}", ev.kind));
        }
    }
    for k in 0..cell.edges.len() {
        let sig = cell.edge_distance(k, &fl.pos);
        if sig.is_nan() || sig < -room {
            return Err(format!("outside edge {k} after {:?}: {sig:e}", ev.kind));
        }
    }
    cell_and_exclusions_after(cell, before, ev.kind, after, rep)
}
