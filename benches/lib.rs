//! The benchmarks are the `kernel` and `divider` targets of this package (`cargo bench -p lorentz-gas-benches`).
