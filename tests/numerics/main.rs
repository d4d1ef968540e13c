//! The numerical-correctness suite: the kernel's properties per scalar type, bit-for-bit
//! agreement of every path (MPFR-53, generic f64, SIMD), hard cases, physics identities, scenes,
//! certified trajectories, the fuzz oracle, shadowing and the shadow audits.
//!
//! One test binary with one module per topic (one link of the library with static GMP/MPFR
//! instead of one per file); helpers shared by every binary are in `tests/common`.

#[path = "../common/mod.rs"]
mod common;

/// The items a property module at scalar type `$t` (context `$ctx`) works with: `T`, `ctx()`, its
/// unit roundoff `u()`, and `lift`, an `f64` flight lifted exactly with its velocity normalised at
/// the working precision. `Flight` and `Real` must be in scope.
macro_rules! at_precision {
    ($t:ty, $ctx:expr) => {
        type T = $t;
        fn ctx() -> <T as Real>::Ctx {
            $ctx
        }
        fn u() -> f64 {
            <T as Real>::unit_roundoff(ctx())
        }
        fn lift(f: &Flight<f64>) -> Flight<T> {
            let mut g = Flight::<T>::convert_from_f64(ctx(), f);
            g.normalise_speed();
            g
        }
    };
}

mod arc_audit;
mod arc_engine;
mod arc_shadowing;
mod arc_tangency_band;
mod arc_tangent;
mod bit_for_bit;
mod cell_engine;
mod certified;
mod checkpoints;
mod choice;
mod cycles;
mod engine;
mod field;
mod fuzz_oracle;
mod fuzz_regressions_arc;
mod fuzz_thermostat;
mod hard_cases;
mod kernel_properties;
mod lattice_cycles;
mod long_flight;
mod long_flight_audit;
mod long_flight_triangular;
mod physics;
mod scene_diffusion;
mod scenes;
mod shadowing;
mod square;
mod table_field;
mod tables;
mod thermo_audit;
mod thermo_shadowing;
mod ties;
mod trajectory;
mod verification;
