//! A table the crate does not ship, run through the library's own estimators: the square lattice
//! of unit spacing with disks of radius 2/5 at the corners and 1/5 at the centres of the squares
//! (two radii in one cell), written as data in `examples/tables/two-radius-square.toml`.
//!
//! ```sh
//! cargo run --release --example custom_scene [TABLE.toml]
//! ```
//!
//! A periodic table of disks is its lattice and the disks of one cell
//! ([`TableSpec`]); [`PeriodicTable`] validates it exactly (overlaps, radii, the horizon) and is a
//! [`Scene`] like the crate's own. It is one [`Table`] (geometry and motion) of the one
//! [`DiffusionConfig`], and everything else comes with it:
//!
//! * D by the Einstein formula with its standard error over independent batches
//!   ([`transport::run`]: on a table without a field, the Einstein estimator on any scene), with
//!   the table's exact identities measured — the mean free path against
//!   Santaló's π|Q|/|∂Q|, the mean crossing time against π|Q|/L — each within the 4σ-equivalent
//!   Student-t bound;
//! * the per-event shadow audit of the run's own events (a sample replayed in MPFR and judged
//!   against the f64 error model): no event may fall outside the model.
//!
//! The program exits with status 1 if any of these checks fails.

use lorentz_gas::Error;
use lorentz_gas::engine::options::{AuditSpec, RunOptions};
use lorentz_gas::estimators::diffusion::DiffusionConfig;
use lorentz_gas::estimators::transport::{self, Transport};
use lorentz_gas::scenes::Scene;
use lorentz_gas::scenes::spec::{Motion, SceneSpec, Table};
use lorentz_gas::scenes::table::PeriodicTable;
use lorentz_gas::scenes::table::spec::TableSpec;

fn main() -> Result<(), Error> {
    let path = std::env::args().nth(1).unwrap_or_else(|| {
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/examples/tables/two-radius-square.toml"
        )
        .into()
    });
    let spec = TableSpec::read(path.as_ref())?;
    let table = PeriodicTable::new(&spec)?;
    let cfg = DiffusionConfig {
        collisions: 32_000_000,
        batches: 16,
        seed: 7,
        ..DiffusionConfig::on(Table {
            scene: SceneSpec::Table(spec),
            motion: Motion::Straight,
        })
    };
    let options = RunOptions {
        audit: Some(AuditSpec::new(1e-3, 256)?),
        ..RunOptions::default()
    };
    let Transport::Table(r) = transport::run(&cfg, &options)? else {
        return Err(Error::Failed(
            "a table without a field runs the table's estimator".into(),
        ));
    };
    println!("{} (finite horizon: {})", r.scene, table.finite_horizon());
    println!(
        "D = {:.6} ± {:.6} from {} batches of {} collisions (check window: {:.6} ± {:.6})",
        r.D,
        r.D_err,
        cfg.batches,
        cfg.collisions / cfg.batches as u64,
        r.D_check,
        r.D_check_err
    );
    let mut fails = Vec::new();
    for i in &r.identities {
        println!(
            "{:<24} {:.6} ± {:.6}   exact {:.6}   ({:+.2} sigma; bound ±{:.2})",
            i.name, i.measured, i.err, i.exact, i.t, i.bound
        );
        if !i.agrees {
            fails.push(format!(
                "{} is {:+.2} sigma from its closed form",
                i.name, i.t
            ));
        }
    }
    let audit = r
        .audit
        .as_ref()
        .ok_or_else(|| Error::Failed("no audit".into()))?;
    println!(
        "shadow audit: {} events replayed at 256 bits, {} outside the error model, {} ambiguous",
        audit.audited, audit.outside, audit.ambiguous
    );
    if audit.outside > 0 || audit.audited == 0 {
        fails.push(format!(
            "{} of {} audited events outside the model",
            audit.outside, audit.audited
        ));
    }
    if !(r.D > 0.0 && r.D_err > 0.0 && r.D_err < 0.05 * r.D) {
        fails.push(format!(
            "D = {} ± {} is not a resolved positive value",
            r.D, r.D_err
        ));
    }
    if fails.is_empty() {
        println!("PASS");
        Ok(())
    } else {
        eprintln!("FAIL: {}", fails.join("; "));
        std::process::exit(1);
    }
}
