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
/// than two share it (docs/performance.md).
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

/// Most parts a section is cut into, and most threads a team has.
const MAX_PARTS: usize = 64;

/// Parts of a team of two threads, and of sections of few units.
const FEW_PARTS: usize = 2 * PARTS_PER_THREAD;

/// The threads one simulation shares its steps' work with.
///
/// Each parallel section of a step (the integrator's pass, the contact blocks, the per-disk sums,
/// the neighbour search) is cut into the team's number of parts, in one region of consecutive parts
/// per thread: every section's units are in disk order, so a thread's region holds about the same
/// disks in every section. Each thread does its own region's parts first, from its front, then
/// takes the parts left in other regions from their backs. So each disk's data stays in the cache
/// of the thread that last wrote it, except near where threads meet. That matters most where the
/// cores share no cache: parts claimed in any order would fetch most of a step's data from the
/// other core (results/bench/performance.md has the figures).
///
/// Helpers are tasks of the current rayon pool that stay between sections, spinning, until the
/// simulation ends or no section has come for `HELPER_PATIENCE`; so a step's three or four
/// sections cost no wake-up of a sleeping thread (tens of microseconds each, a large share of a
/// step of a few hundred microseconds). A helper that no idle thread takes up leaves its region to the others: the
/// simulation's own thread never waits for a thread busy elsewhere. Which thread does a part never
/// changes its result.
pub struct Team {
    threads: usize,
    parts: usize,
    shared: Arc<Shared>,
}

/// Parts per thread a section is cut into when a team has more than one thread (see [`part_end`]):
/// parts that take longer (more contacts) are made up for by others, as threads claim parts while
/// any is left; more parts shorten the wait for the last one and cost a claim each.
const PARTS_PER_THREAD: usize = 6;

/// Units before the end of part `k` of a section of `units` units cut into `parts` parts in
/// `regions` regions of consecutive parts (equal shares of the units). Within a region each part
/// takes half of what the region has left, the last all the rest: a region's parts shrink towards
/// its back, where other threads take them once they are done with their own.
fn part_end(units: usize, parts: usize, regions: usize, k: usize) -> usize {
    let region = (0..regions).rev().find(|&r| parts * r / regions <= k).unwrap_or(0);
    let (first, next) = (parts * region / regions, parts * (region + 1) / regions);
    let (start, end) = (units * region / regions, units * (region + 1) / regions);
    if k + 1 >= next {
        return end;
    }
    let fraction = 1.0 - 0.5_f64.powi((k + 1 - first) as i32);
    (start + ((end - start) as f64 * fraction).round() as usize).min(end)
}

/// How long a helper spins without a part to do before it hands its thread back to the pool.
const HELPER_PATIENCE: Duration = Duration::from_millis(2);

/// A value alone on its cache line, so that threads writing one do not slow those reading another.
#[derive(Default)]
#[repr(align(64))]
struct Line<T>(T);

/// What the simulation's thread and its helpers share.
struct Shared {
    /// Per region: the current section, its next part from the front and its end: see [`pack`].
    regions: [Line<AtomicU64>; MAX_PARTS],
    /// Regions the team's sections have (its threads).
    region_count: usize,
    /// The last section whose regions are all stored.
    published: Line<AtomicU64>,
    /// Parts of the current section done.
    done: Line<AtomicUsize>,
    /// The current section's work (a `*const &(dyn Fn(usize) + Sync)`), valid from the store of
    /// its regions until all its parts are done.
    job: AtomicPtr<()>,
    /// The helpers' slots taken (bit `s`: the helper of region `s`; region 0 is the simulation's).
    helpers: AtomicU64,
    /// Set when the simulation ends.
    closed: AtomicBool,
    /// The first panic of a part on a helper, handed on by the simulation's thread.
    panic: Mutex<Option<Box<dyn Any + Send>>>,
}

/// Bits of a region's [`Shared::regions`] word for its front and its end (the rest count
/// sections, so that a claim of a finished section's part can never succeed).
const PART_BITS: u32 = 12;

/// `section · 2²⁴ + front · 2¹² + end`: parts `front..end` of the region are unclaimed.
fn pack(section: u64, front: usize, end: usize) -> u64 {
    (section << (2 * PART_BITS)) | ((front as u64) << PART_BITS) | end as u64
}

/// The section, front and end of a [`pack`]ed region.
fn unpack(word: u64) -> (u64, usize, usize) {
    let mask = (1 << PART_BITS) - 1;
    (word >> (2 * PART_BITS), ((word >> PART_BITS) & mask) as usize, (word & mask) as usize)
}

impl Shared {
    fn new(region_count: usize) -> Self {
        Self {
            regions: std::array::from_fn(|_| Line::default()),
            region_count,
            published: Line::default(),
            done: Line::default(),
            job: AtomicPtr::default(),
            helpers: AtomicU64::default(),
            closed: AtomicBool::default(),
            panic: Mutex::default(),
        }
    }

    /// Claims the front (`FRONT`) or back part of region `r`, if any is left in a section up to
    /// `latest`.
    fn claim_in<const FRONT: bool>(&self, r: usize, latest: u64) -> Option<usize> {
        let region = &self.regions[r].0;
        let mut word = region.load(Ordering::Acquire);
        loop {
            let (section, front, end) = unpack(word);
            if front >= end || section > latest {
                return None;
            }
            let (claimed, part) =
                if FRONT { (pack(section, front + 1, end), front) } else { (pack(section, front, end - 1), end - 1) };
            match region.compare_exchange_weak(word, claimed, Ordering::AcqRel, Ordering::Acquire) {
                Ok(_) => return Some(part),
                Err(now) => word = now,
            }
        }
    }

    /// The next part for the thread of region `own`: its own region's front, else another's back.
    /// Only parts of published sections are taken from other regions, so that a thread never
    /// takes another's part while its own region of the same section is being stored.
    fn claim_part(&self, own: usize) -> Option<usize> {
        let (n, latest) = (self.region_count, self.published.0.load(Ordering::Acquire));
        if own < n
            && let Some(k) = self.claim_in::<true>(own, u64::MAX)
        {
            return Some(k);
        }
        (1..n).find_map(|d| self.claim_in::<false>((own + d) % n, latest))
    }

    /// Does part `k` of the current section (claimed by this thread), keeping a panic for the
    /// simulation's thread to hand on once every part is done.
    fn do_part(&self, k: usize, job: &(dyn Fn(usize) + Sync)) {
        if let Err(panic) = std::panic::catch_unwind(AssertUnwindSafe(|| job(k))) {
            self.panic.lock().unwrap_or_else(|e| e.into_inner()).get_or_insert(panic);
        }
        self.done.0.fetch_add(1, Ordering::Release);
    }

    /// The life of the helper of region `own`: parts as they come, until the simulation ends or
    /// none has come for [`HELPER_PATIENCE`].
    fn help(&self, own: usize) {
        let mut idle_since = Instant::now();
        let mut spins = 0_u32;
        while !self.closed.load(Ordering::Relaxed) {
            if let Some(k) = self.claim_part(own) {
                #[allow(unsafe_code)]
                // SAFETY: `job` was stored before the regions of its section (release, read by the
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
        self.helpers.fetch_and(!(1 << own), Ordering::AcqRel);
    }
}

impl Team {
    /// A team of `threads` threads (at most 64), the simulation's own included (1: everything on it).
    pub fn new(threads: usize) -> Self {
        let threads = threads.clamp(1, MAX_PARTS);
        let parts = if threads == 1 { 1 } else { (threads * PARTS_PER_THREAD).min(MAX_PARTS) };
        Self { threads, parts, shared: Arc::new(Shared::new(threads)) }
    }

    /// Parts each section is cut into.
    pub fn parts(&self) -> usize {
        self.parts
    }

    /// Runs `work` on `whole` cut into the team's parts (fewer if it has fewer units), each part
    /// with its number (the parts in order: part 0 holds the first units; see `part_end`).
    pub fn for_each_part<V: Split>(&self, whole: V, work: &(impl Fn(V, usize) + Sync)) {
        let units = whole.units();
        let parts = self.parts.min(units).max(1);
        if parts == 1 {
            work(whole, 0);
            return;
        }
        if parts <= FEW_PARTS {
            self.share::<V, FEW_PARTS>(whole, units, parts, work);
        } else {
            self.share::<V, MAX_PARTS>(whole, units, parts, work);
        }
    }

    /// [`Self::for_each_part`] of `units` units in `parts` parts, at most `N` (the parts wait in
    /// `N` slots: a section of a few parts does not move or clear a slot for each of 64).
    fn share<V: Split, const N: usize>(&self, whole: V, units: usize, parts: usize, work: &(impl Fn(V, usize) + Sync)) {
        let regions = self.threads.min(parts);
        let slots: [Mutex<Option<V>>; N] = std::array::from_fn(|_| Mutex::new(None));
        let (mut rest, mut taken) = (whole, 0);
        for (k, slot) in slots.iter().enumerate().take(parts - 1) {
            let end = part_end(units, parts, regions, k).max(taken);
            let (part, after) = rest.split_at(end - taken);
            *slot.lock().expect("not shared yet") = Some(part);
            (rest, taken) = (after, end);
        }
        *slots[parts - 1].lock().expect("not shared yet") = Some(rest);
        let job = |k: usize| {
            let part = slots[k].lock().expect("no panic while held").take().expect("each part claimed once");
            work(part, k);
        };
        self.run(parts, regions, &job);
    }

    /// Runs a section of `parts` parts in `regions` regions: publishes `job`, calls helpers, does
    /// parts until none is left, waits for those claimed by helpers, and hands on the first panic.
    fn run(&self, parts: usize, regions: usize, job: &(dyn Fn(usize) + Sync)) {
        let s = &*self.shared;
        let erased: *const &(dyn Fn(usize) + Sync) = &job;
        s.job.store(erased as *mut (), Ordering::Relaxed);
        s.done.0.store(0, Ordering::Relaxed);
        let section = unpack(s.regions[0].0.load(Ordering::Relaxed)).0 + 1;
        for (r, region) in s.regions[..self.threads].iter().enumerate() {
            let (first, next) = if r < regions { (parts * r / regions, parts * (r + 1) / regions) } else { (0, 0) };
            region.0.store(pack(section, first, next), Ordering::Release);
        }
        s.published.0.store(section, Ordering::Release);
        self.call_helpers(regions - 1);
        while let Some(k) = s.claim_part(0) {
            s.do_part(k, job);
        }
        while s.done.0.load(Ordering::Acquire) < parts {
            std::hint::spin_loop();
        }
        if let Some(panic) = s.panic.lock().unwrap_or_else(|e| e.into_inner()).take() {
            std::panic::resume_unwind(panic);
        }
    }

    /// Calls helpers for regions `1..=wanted` that have none (no more than the pool has other
    /// threads).
    fn call_helpers(&self, wanted: usize) {
        let wanted = wanted.min(rayon::current_num_threads().saturating_sub(1));
        let taken = self.shared.helpers.load(Ordering::Acquire);
        for own in (1..=wanted).filter(|r| taken & (1 << r) == 0) {
            self.shared.helpers.fetch_or(1 << own, Ordering::AcqRel);
            let shared = Arc::clone(&self.shared);
            rayon::spawn(move || shared.help(own));
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
    fn each_thread_takes_its_regions_parts_from_the_front_then_others_from_the_back() {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let team = Team::new(2);
        let (parts, second) = (team.parts(), team.parts() / 2);
        for _ in 0..20 {
            let order = Mutex::new(Vec::new());
            let mut seen = vec![0; 1000];
            let main = pool.install(|| {
                team.for_each_part(Units(&mut seen, 0), &|_: Units, k| {
                    order.lock().unwrap().push((std::thread::current().id(), k));
                    let start = Instant::now();
                    while start.elapsed() < Duration::from_micros(50) {}
                });
                std::thread::current().id()
            });
            let order = order.into_inner().unwrap();
            assert_eq!(order.len(), parts);
            for (mine, front, back) in [(true, 0..second, second..parts), (false, second..parts, 0..second)] {
                let done: Vec<usize> = order.iter().filter(|(t, _)| (*t == main) == mine).map(|(_, k)| *k).collect();
                let own: Vec<usize> = done.iter().copied().filter(|k| front.contains(k)).collect();
                let taken: Vec<usize> = done.iter().copied().filter(|k| back.contains(k)).collect();
                // Its own region's first parts in order, then the other's last parts, last first.
                assert!(own.iter().copied().eq(front.start..front.start + own.len()), "{done:?} ({mine})");
                assert!(taken.iter().copied().eq((back.end - taken.len()..back.end).rev()), "{done:?} ({mine})");
                assert!(done.iter().take(own.len()).all(|k| front.contains(k)), "own parts first: {done:?}");
            }
        }
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
    fn parts_shrink_towards_each_regions_back_and_cover_every_unit() {
        let ends: Vec<_> = (0..6).map(|k| part_end(1000, 6, 2, k)).collect();
        assert_eq!(ends, [250, 375, 500, 750, 875, 1000]);
        assert_eq!((0..5).map(|k| part_end(10, 5, 2, k)).collect::<Vec<_>>(), [3, 5, 8, 9, 10]);
        assert_eq!((0..3).map(|k| part_end(7, 3, 1, k)).collect::<Vec<_>>(), [4, 5, 7]);
        assert_eq!((0..4).map(|k| part_end(3, 4, 4, k)).collect::<Vec<_>>(), [0, 1, 2, 3]);
    }
}
