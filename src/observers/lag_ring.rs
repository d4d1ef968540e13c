//! Lag sums on a fixed time grid with every sample a time origin: a ring of the last samples
//! and, per lag (in grid steps), the running sums of what each pair (origin, end) contributes —
//! the moments of the displacement of a run in a magnetic field (with its Lévy area) and of a
//! run under the thermostat (about its drift).

/// The ring of the last samples of `S` numbers and the sums of `M` contributions per lag.
#[derive(Debug, Clone)]
pub struct LagRing<const S: usize, const M: usize> {
    steps: Vec<usize>,
    ring: Vec<[f64; S]>,
    samples: u64,
    sums: Vec<[f64; M]>,
    counts: Vec<u64>,
}

impl<const S: usize, const M: usize> LagRing<S, M> {
    /// The sums at the lags `steps` (grid steps), none taken yet.
    pub fn new(steps: Vec<usize>) -> Self {
        let n = steps.iter().copied().max().unwrap_or(0) + 1;
        LagRing {
            sums: vec![[0.0; M]; steps.len()],
            counts: vec![0; steps.len()],
            steps,
            ring: vec![[0.0; S]; n],
            samples: 0,
        }
    }

    /// The next sample `x`: `pair(origin, x)` added at every lag an origin is that far back.
    #[inline]
    pub fn push(&mut self, x: [f64; S], pair: impl Fn(&[f64; S], &[f64; S]) -> [f64; M]) {
        let n = self.ring.len() as u64;
        let k = self.samples;
        self.ring[(k % n) as usize] = x;
        for (i, &l) in self.steps.iter().enumerate() {
            if k >= l as u64 {
                let origin = self.ring[((k - l as u64) % n) as usize];
                let add = pair(&origin, &x);
                for (s, a) in self.sums[i].iter_mut().zip(add) {
                    *s += a;
                }
                self.counts[i] += 1;
            }
        }
        self.samples += 1;
    }

    /// The means per lag (NaN where a lag was never reached).
    pub fn means(&self) -> Vec<[f64; M]> {
        self.sums
            .iter()
            .zip(&self.counts)
            .map(|(s, &c)| s.map(|v| v / c as f64))
            .collect()
    }
}
