//! One simulation on several threads, with results that do not depend on how many.
//!
//! The work of a step is cut into fixed units (runs of disks, blocks of neighbour-list candidates)
//! whose results never depend on which thread computes them: per-unit partial sums are combined in
//! unit order, per-candidate forces are stored per candidate, and each disk's forces are added up
//! in neighbour-list order (see `contact_sums`). The threads only decide which units run where, so
//! a run's bits are the same on 1, 2 or 16 threads (tests/engine_threads.rs).

use std::any::Any;
use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicU64, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// Disks from which a run uses the threads it is given: below, one thread does the work faster
/// than two share it (measured on 2 cores: see docs/performance.md).
pub const PARALLEL_MIN_DISKS: usize = 8_000;

/// How many threads one simulation may use, and from what size on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Threads {
    /// Threads the run may use; 1: the serial path.
    pub count: usize,
    /// Fewest disks for which more than one thread is used (tests lower it to check small scenes).
    pub min_disks: usize,
}

impl Default for Threads {
    fn default() -> Self {
        Self::new(1)
    }
}

impl Threads {
    /// `count` threads (at least one) for scenes of [`PARALLEL_MIN_DISKS`] disks or more.
    pub fn new(count: usize) -> Self {
        Self { count: count.max(1), min_disks: PARALLEL_MIN_DISKS }
    }

    /// Threads a scene of `disks` disks runs on.
    #[inline]
    pub fn used_for(&self, disks: usize) -> usize {
        if disks >= self.min_disks { self.count.max(1) } else { 1 }
    }
}

/// Work that can be cut at unit boundaries into two independent halves.
pub trait Split: Sized + Send {
    /// Units of work it holds.
    fn units(&self) -> usize;
    /// The first `at` units and the rest.
    fn split_at(self, at: usize) -> (Self, Self);
}

/// Most parts a section is cut into.
const MAX_PARTS: usize = 64;

/// The threads one simulation shares its steps' work with.
///
/// Each parallel section of a step (the integrator's pass, the contact blocks, the per-disk sums,
/// the neighbour search) is cut into the team's number of parts, and each part is claimed by
/// whichever thread comes first: the simulation's own, or one of up to `threads − 1` helpers. Helpers
/// are tasks of the current rayon pool that stay between sections, spinning, until the simulation
/// ends or no section has come for [`HELPER_PATIENCE`]; so a step's three or four sections cost no
/// wake-up of a sleeping thread (tens of microseconds each, on a 40 000-disk step of 300 µs).
/// A helper that no idle thread takes up leaves the simulation's own thread to do every part: it
/// never waits for a thread busy elsewhere. Which thread does a part never changes its result.
pub struct Team {
    threads: usize,
    parts: usize,
    shared: Arc<Shared>,
}

/// Parts per thread a section is cut into when a team has more than one thread (see [`cut_point`]):
/// parts that take longer (more contacts) are made up for by others, as threads claim parts while
/// any is left. On 2 threads the last parts are a 64th of the section each: at 40 000 disks the
/// run's own thread spent 5 % of its time waiting for the other's last part with 3 per thread,
/// 2.7 % with 5, 1.7 % with 8 (`perf`).
const PARTS_PER_THREAD: usize = 6;

/// Units before part `k` of a section of `units` units cut into `parts` parts for `threads`
/// threads. In rounds of one part per thread, the first round takes half the units, each later
/// round half of what is left, the last round all the rest: the parts claimed last, while the
/// other threads finish theirs, are the short ones. (Equal parts if `parts` is not a whole number
/// of rounds.)
fn cut_point(units: usize, parts: usize, threads: usize, k: usize) -> usize {
    if k >= parts {
        return units;
    }
    if threads < 2 || !parts.is_multiple_of(threads) {
        return units * k / parts;
    }
    let (round, place, rounds) = (k / threads, k % threads, parts / threads);
    let before = 0.5_f64.powi(round as i32);
    let share = if round + 1 == rounds { before } else { 0.5 * before };
    let fraction = (1.0 - before) + share * place as f64 / threads as f64;
    ((units as f64 * fraction).round() as usize).min(units)
}

/// How long a helper spins without a part to do before it hands its thread back to the pool.
const HELPER_PATIENCE: Duration = Duration::from_millis(2);

/// What the simulation's thread and its helpers share.
#[derive(Default)]
struct Shared {
    /// The current section and its next unclaimed part: see [`pack`].
    claim: AtomicU64,
    /// Parts of the current section done.
    done: AtomicUsize,
    /// The current section's work (a `*const &(dyn Fn(usize) + Sync)`), valid from the store of
    /// its `claim` until all its parts are done.
    job: AtomicPtr<()>,
    /// Helpers called and not yet gone.
    helpers: AtomicUsize,
    /// Set when the simulation ends.
    closed: AtomicBool,
    /// The first panic of a part on a helper, handed on by the simulation's thread.
    panic: Mutex<Option<Box<dyn Any + Send>>>,
}

/// Bits of [`Shared::claim`] for the parts and the next part of a section (the rest count
/// sections, so that a claim of a finished section's part can never succeed).
const PART_BITS: u32 = 12;

/// `section · 2²⁴ + parts · 2¹² + next`.
fn pack(section: u64, parts: usize, next: usize) -> u64 {
    (section << (2 * PART_BITS)) | ((parts as u64) << PART_BITS) | next as u64
}

/// The section, its parts and its next unclaimed part of a [`pack`]ed claim.
fn unpack(claim: u64) -> (u64, usize, usize) {
    let mask = (1 << PART_BITS) - 1;
    (claim >> (2 * PART_BITS), ((claim >> PART_BITS) & mask) as usize, (claim & mask) as usize)
}

impl Shared {
    /// Claims the next part of the current section, if any is left.
    fn claim_part(&self) -> Option<usize> {
        let mut claim = self.claim.load(Ordering::Acquire);
        loop {
            let (section, parts, next) = unpack(claim);
            if next >= parts {
                return None;
            }
            let claimed = pack(section, parts, next + 1);
            match self.claim.compare_exchange_weak(claim, claimed, Ordering::AcqRel, Ordering::Acquire) {
                Ok(_) => return Some(next),
                Err(now) => claim = now,
            }
        }
    }

    /// Does part `k` of the current section (claimed by this thread), keeping a panic for the
    /// simulation's thread to hand on once every part is done.
    fn do_part(&self, k: usize, job: &(dyn Fn(usize) + Sync)) {
        if let Err(panic) = std::panic::catch_unwind(AssertUnwindSafe(|| job(k))) {
            self.panic.lock().unwrap_or_else(|e| e.into_inner()).get_or_insert(panic);
        }
        self.done.fetch_add(1, Ordering::Release);
    }

    /// A helper's life: parts as they come, until the simulation ends or none has come for
    /// [`HELPER_PATIENCE`].
    fn help(&self) {
        let mut idle_since = Instant::now();
        let mut spins = 0_u32;
        while !self.closed.load(Ordering::Relaxed) {
            if let Some(k) = self.claim_part() {
                #[allow(unsafe_code)]
                // SAFETY: `job` was stored before the claim of its section (release, read by the
                // claim's acquire), and stays valid until all the section's parts are done, which
                // the simulation's thread waits for; this part is not done yet.
                let job = unsafe { *(self.job.load(Ordering::Relaxed) as *const &(dyn Fn(usize) + Sync)) };
                self.do_part(k, job);
                (idle_since, spins) = (Instant::now(), 0);
                continue;
            }
            spins += 1;
            if spins.is_multiple_of(256) && idle_since.elapsed() > HELPER_PATIENCE {
                break;
            }
            std::hint::spin_loop();
        }
        self.helpers.fetch_sub(1, Ordering::AcqRel);
    }
}

impl Team {
    /// A team of `threads` threads, the simulation's own included (1: everything on it).
    pub fn new(threads: usize) -> Self {
        let threads = threads.max(1);
        let parts = if threads == 1 { 1 } else { (threads * PARTS_PER_THREAD).min(MAX_PARTS) };
        Self { threads, parts, shared: Arc::default() }
    }

    /// Parts each section is cut into.
    pub fn parts(&self) -> usize {
        self.parts
    }

    /// Runs `work` on `whole` cut into the team's parts of about equal units (fewer if it has fewer
    /// units), each part with its number (the parts in order: part 0 holds the first units).
    pub fn for_each_part<V: Split>(&self, whole: V, work: &(impl Fn(V, usize) + Sync)) {
        let units = whole.units();
        let parts = self.parts.min(units).max(1);
        if parts == 1 {
            work(whole, 0);
            return;
        }
        let slots: [Mutex<Option<V>>; MAX_PARTS] = std::array::from_fn(|_| Mutex::new(None));
        let (mut rest, mut taken) = (whole, 0);
        for (k, slot) in slots.iter().enumerate().take(parts - 1) {
            let end = cut_point(units, parts, self.threads, k + 1).max(taken);
            let (part, after) = rest.split_at(end - taken);
            *slot.lock().expect("not shared yet") = Some(part);
            (rest, taken) = (after, end);
        }
        *slots[parts - 1].lock().expect("not shared yet") = Some(rest);
        let job = |k: usize| {
            let part = slots[k].lock().expect("no panic while held").take().expect("each part claimed once");
            work(part, k);
        };
        self.run(parts, &job);
    }

    /// Runs a section of `parts` parts: publishes `job`, calls helpers, does parts until none is
    /// left, waits for those claimed by helpers, and hands on the first panic of any.
    fn run(&self, parts: usize, job: &(dyn Fn(usize) + Sync)) {
        let s = &*self.shared;
        let erased: *const &(dyn Fn(usize) + Sync) = &job;
        s.job.store(erased as *mut (), Ordering::Relaxed);
        s.done.store(0, Ordering::Relaxed);
        let section = unpack(s.claim.load(Ordering::Relaxed)).0 + 1;
        s.claim.store(pack(section, parts, 0), Ordering::Release);
        self.call_helpers(self.threads.min(parts) - 1);
        while let Some(k) = s.claim_part() {
            s.do_part(k, job);
        }
        while s.done.load(Ordering::Acquire) < parts {
            std::hint::spin_loop();
        }
        if let Some(panic) = s.panic.lock().unwrap_or_else(|e| e.into_inner()).take() {
            std::panic::resume_unwind(panic);
        }
    }

    /// Calls helpers until `wanted` are about (no more than the pool has other threads).
    fn call_helpers(&self, wanted: usize) {
        let wanted = wanted.min(rayon::current_num_threads().saturating_sub(1));
        while self.shared.helpers.load(Ordering::Acquire) < wanted {
            self.shared.helpers.fetch_add(1, Ordering::AcqRel);
            let shared = Arc::clone(&self.shared);
            rayon::spawn(move || shared.help());
        }
    }
}

impl Drop for Team {
    fn drop(&mut self) {
        self.shared.closed.store(true, Ordering::Relaxed);
    }
}

/// A range of indices (disks) cut in units of `unit`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Span {
    /// The indices.
    pub range: std::ops::Range<usize>,
    /// Indices per unit.
    pub unit: usize,
}

impl Split for Span {
    fn units(&self) -> usize {
        self.range.len().div_ceil(self.unit)
    }

    fn split_at(self, at: usize) -> (Self, Self) {
        let mid = (self.range.start + at * self.unit).min(self.range.end);
        (Span { range: self.range.start..mid, unit: self.unit }, Span { range: mid..self.range.end, unit: self.unit })
    }
}

/// Splits a slice at unit `at` of `unit` elements (at its end if shorter).
pub fn split_slice<T>(slice: &mut [T], at: usize, unit: usize) -> (&mut [T], &mut [T]) {
    let mid = (at * unit).min(slice.len());
    slice.split_at_mut(mid)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Units<'a>(&'a mut [usize], usize);
    impl Split for Units<'_> {
        fn units(&self) -> usize {
            self.0.len()
        }
        fn split_at(self, at: usize) -> (Self, Self) {
            let (a, b) = self.0.split_at_mut(at);
            (Units(a, self.1), Units(b, self.1 + at))
        }
    }

    #[test]
    fn every_unit_is_done_once_whatever_the_parts() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
        for threads in 1..12 {
            let team = Team::new(threads);
            let parts = team.parts().min(37);
            assert!(parts >= threads.min(37) && (threads == 1 || parts > threads.min(9)), "{threads} threads");
            let mut seen = vec![0; 37];
            let numbers = std::sync::Mutex::new(Vec::new());
            pool.install(|| {
                team.for_each_part(Units(&mut seen, 0), &|u: Units, number| {
                    for (k, s) in u.0.iter_mut().enumerate() {
                        *s += u.1 + k + 1;
                    }
                    numbers.lock().unwrap().push(number);
                })
            });
            assert_eq!(seen, (1..38).collect::<Vec<_>>(), "{threads} threads");
            let mut numbers = numbers.into_inner().unwrap();
            numbers.sort_unstable();
            assert_eq!(numbers, (0..parts).collect::<Vec<_>>());
        }
        assert_eq!(Threads { count: 3, min_disks: 10 }.used_for(9), 1);
        assert_eq!(Threads { count: 3, min_disks: 10 }.used_for(10), 3);
    }

    #[test]
    fn a_panic_in_any_part_reaches_the_caller_after_every_part_is_done() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let team = Team::new(2);
        for bad in 0..team.parts() {
            let done = std::sync::atomic::AtomicUsize::new(0);
            let mut seen = vec![0; 40];
            let outcome = std::panic::catch_unwind(AssertUnwindSafe(|| {
                pool.install(|| {
                    team.for_each_part(Units(&mut seen, 0), &|_: Units, number| {
                        done.fetch_add(1, Ordering::SeqCst);
                        assert!(number != bad, "part {number} fails");
                    })
                })
            }));
            let message = outcome.expect_err("the panic is handed on");
            assert_eq!(
                message.downcast_ref::<String>().map(String::as_str),
                Some(format!("part {bad} fails").as_str())
            );
            assert_eq!(done.load(Ordering::SeqCst), team.parts());
        }
        // The team goes on working after a panic.
        let mut seen = vec![0; 40];
        pool.install(|| team.for_each_part(Units(&mut seen, 0), &|u: Units, _| u.0.iter_mut().for_each(|s| *s += 1)));
        assert!(seen.iter().all(|&s| s == 1));
    }

    #[test]
    fn parts_shrink_round_by_round_and_cover_every_unit() {
        let ends: Vec<_> = (0..=6).map(|k| cut_point(1000, 6, 2, k)).collect();
        assert_eq!(ends, [0, 250, 500, 625, 750, 875, 1000]);
        assert_eq!((0..=5).map(|k| cut_point(10, 5, 2, k)).collect::<Vec<_>>(), [0, 2, 4, 6, 8, 10]);
        assert_eq!((0..=3).map(|k| cut_point(7, 3, 1, k)).collect::<Vec<_>>(), [0, 2, 4, 7]);
    }
}
