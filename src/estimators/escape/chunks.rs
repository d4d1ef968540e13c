//! What an escape-rate run keeps so that a kill loses at most one checkpoint interval: each
//! batch's particles in consecutive chunks (their lifetimes and events), appended to the run's
//! [`Journal`] at the interval and when the batch ends. A particle lives for at most t_max, so
//! nothing is saved in flight: a resumed batch draws again (and discards) the starts of the
//! particles already followed — the starts are the only use of its random stream — and goes on
//! with the next, to the uninterrupted bits.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use rand::Rng;

use super::{EscapeConfig, Lifetime};
use crate::Error;
use crate::engine::metadata::RunMeta;
use crate::engine::options::StopFlag;
use crate::engine::resume::Journal;
use crate::scenes::strip::Strip;

/// Kind of the records of an escape checkpoint.
const CHECKPOINT_KIND: &str = "escape particles";

/// Particles `from` … `from + lifetimes.len() − 1` of batch `task`.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Chunk {
    /// The batch: width index × batches per width + batch.
    pub(super) task: u32,
    /// Its first particle.
    pub(super) from: u64,
    /// Their lifetimes, in order.
    pub(super) lifetimes: Vec<Lifetime>,
    /// Events they took.
    pub(super) events: u64,
}

/// A batch's particles so far: their lifetimes and events.
#[derive(Debug, Clone, Default)]
pub(super) struct Done {
    pub(super) lifetimes: Vec<Lifetime>,
    pub(super) events: u64,
}

/// The journal of an escape run (or none) and the particles it held at the start, by batch.
pub(super) struct Chunks {
    journal: Option<Journal<Chunk>>,
    every: Duration,
    found: BTreeMap<u32, Done>,
}

impl Chunks {
    /// Opens the journal at `path` (if any) of `cfg`: its chunks, checked to continue each other
    /// batch by batch, with particle counts within `quota(task)` and lifetimes within
    /// `t_max(task)`.
    pub(super) fn open(
        path: Option<&Path>,
        cfg: &EscapeConfig,
        tasks: u32,
        quota: impl Fn(u32) -> u64,
        t_max: impl Fn(u32) -> f64,
        every: Duration,
    ) -> Result<Self, Error> {
        let mut c = Chunks {
            journal: None,
            every,
            found: BTreeMap::new(),
        };
        let Some(p) = path else {
            return Ok(c);
        };
        let meta = RunMeta::new(Some(cfg.seed), Some(tasks as u64), "f64", None);
        let (journal, chunks) = Journal::<Chunk>::open(p, CHECKPOINT_KIND, cfg, Some(meta))?;
        for k in chunks {
            let done = c.found.entry(k.task).or_default();
            let end = k.from + k.lifetimes.len() as u64;
            let sane = k.task < tasks
                && k.from == done.lifetimes.len() as u64
                && end <= quota(k.task)
                && k.lifetimes
                    .iter()
                    .all(|l| l.time >= 0.0 && l.time <= t_max(k.task));
            if !sane {
                return Err(Error::malformed(
                    p,
                    format!(
                        "the chunk of batch {} from particle {} does not continue that batch: an \
                         edited or foreign checkpoint (use another file)",
                        k.task, k.from
                    ),
                ));
            }
            done.lifetimes.extend(k.lifetimes);
            done.events += k.events;
        }
        c.journal = Some(journal);
        Ok(c)
    }

    /// The particles of batch `task` already followed.
    fn found(&self, task: u32) -> Done {
        self.found.get(&task).cloned().unwrap_or_default()
    }

    /// Particles already followed, over all batches.
    pub(super) fn particles_done(&self) -> u64 {
        self.found.values().map(|d| d.lifetimes.len() as u64).sum()
    }

    /// Follows the particles of batch `task` from the random stream `rng` in `strip`, up to `n`
    /// of them with cut-off `t_max`, continuing after those already kept (whose starts are drawn
    /// again, not followed) and keeping new ones at the interval and at the end. A requested
    /// `stop`, looked at before each particle, keeps the particles followed and ends the batch
    /// with [`Error::Interrupted`].
    pub(super) fn follow(
        &self,
        (task, strip): (u32, &Strip),
        mut rng: impl Rng,
        (n, t_max): (u64, f64),
        progress: &(dyn Fn(u64) + Sync),
        stop: Option<&StopFlag>,
    ) -> Result<Done, Error> {
        let mut done = self.found(task);
        for _ in 0..done.lifetimes.len() {
            strip.sample(&mut rng);
        }
        let (mut saved, mut last) = ((done.lifetimes.len(), done.events), Instant::now());
        for _ in done.lifetimes.len() as u64..n {
            if stop.is_some_and(StopFlag::requested) {
                self.save(task, &done, &mut saved, &mut last, true)?;
                return Err(Error::Interrupted);
            }
            let s = strip.sample(&mut rng);
            let o = strip.follow(s, t_max)?;
            done.events += o.events;
            done.lifetimes.push(Lifetime {
                time: o.time,
                absorbed: o.exit.is_some(),
            });
            progress(1);
            self.save(task, &done, &mut saved, &mut last, false)?;
        }
        self.save(task, &done, &mut saved, &mut last, true)?;
        Ok(done)
    }

    /// Appends batch `task`'s particles since `saved` (of `done`) if the interval has passed
    /// since `last` or `finished`, and moves `saved` and `last` on.
    fn save(
        &self,
        task: u32,
        done: &Done,
        saved: &mut (usize, u64),
        last: &mut Instant,
        finished: bool,
    ) -> Result<(), Error> {
        let Some(j) = &self.journal else {
            return Ok(());
        };
        if !finished && last.elapsed() < self.every {
            return Ok(());
        }
        if done.lifetimes.len() > saved.0 {
            j.append(&Chunk {
                task,
                from: saved.0 as u64,
                lifetimes: done.lifetimes[saved.0..].to_vec(),
                events: done.events - saved.1,
            })?;
        }
        *saved = (done.lifetimes.len(), done.events);
        *last = Instant::now();
        Ok(())
    }
}
