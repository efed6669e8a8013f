//! One simulation on several threads, with results that do not depend on how many.
//!
//! The work of a step is cut into fixed units (runs of disks, blocks of neighbour-list candidates)
//! whose results never depend on which thread computes them: per-unit partial sums are combined in
//! unit order, per-candidate forces are stored per candidate, and each disk's forces are added up
//! in neighbour-list order (see `contact_sums`). The threads only decide which units run where, so
//! a run's bits are the same on 1, 2 or 16 threads (tests/engine_threads.rs).

/// Disks from which a run uses the threads it is given: below, one thread does the work faster
/// than two share it (measured on 2 cores: see docs/performance.md).
pub const PARALLEL_MIN_DISKS: usize = 32_000;

/// How many threads one simulation may use, and from what size on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Threads {
    /// Threads (parts of each step's work); 1: the serial path.
    pub count: usize,
    /// Fewest disks for which more than one part is used (tests lower it to check small scenes).
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

    /// Parts to cut a step's work into for a scene of `disks` disks.
    #[inline]
    pub fn parts(&self, disks: usize) -> usize {
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

/// Runs `work` on `whole` cut into `parts` pieces of about equal units, in parallel on the current
/// rayon pool (the caller's thread takes one piece; idle threads take the others). `work` gets each
/// piece with its number (below `parts`; no two pieces have the same).
pub fn for_each_part<V: Split>(whole: V, parts: usize, work: &(impl Fn(V, usize) + Sync)) {
    part_from(whole, parts, 0, work);
}

fn part_from<V: Split>(whole: V, parts: usize, number: usize, work: &(impl Fn(V, usize) + Sync)) {
    let units = whole.units();
    if parts <= 1 || units <= 1 {
        work(whole, number);
        return;
    }
    let left_parts = parts / 2;
    let (left, right) = whole.split_at(units * left_parts / parts);
    rayon::join(
        || part_from(left, left_parts, number, work),
        || part_from(right, parts - left_parts, number + left_parts, work),
    );
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
        for parts in 1..9 {
            let mut seen = vec![0; 37];
            let numbers = std::sync::Mutex::new(Vec::new());
            for_each_part(Units(&mut seen, 0), parts, &|u: Units, number| {
                for (k, s) in u.0.iter_mut().enumerate() {
                    *s += u.1 + k + 1;
                }
                numbers.lock().unwrap().push(number);
            });
            assert_eq!(seen, (1..38).collect::<Vec<_>>(), "{parts} parts");
            let mut numbers = numbers.into_inner().unwrap();
            numbers.sort_unstable();
            assert_eq!(numbers, (0..parts).collect::<Vec<_>>());
        }
        assert_eq!(Threads { count: 3, min_disks: 10 }.parts(9), 1);
        assert_eq!(Threads { count: 3, min_disks: 10 }.parts(10), 3);
    }
}
