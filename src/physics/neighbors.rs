//! Who may touch whom: a Verlet neighbour list built by a cell grid (or all pairs, for tests),
//! plus the disks near walls, carrying each contact's tangential spring from one build to the next.
//!
//! The list holds every pair closer than `r_i + r_j + skin` and is rebuilt once any disk may have
//! moved more than half the skin since the last build (by the sum of every step's longest move, which
//! the integrator reports), so no contact is missed in between. Pairs are kept
//! sorted by `(i, j)`, which makes the result independent of the broad phase and lets a rebuild carry
//! tangential springs over by a linear merge: no hashing, no allocation once buffers have grown.

use super::config::BroadPhaseKind;
use super::contact::ContactState;
use super::contact_record::Partner;
use super::material::{effective_mass, effective_radius};
use super::memory_order::{FAR_PLACES, gather};
use super::parallel::{Span, Split, Team};
use super::particles::{InitialContact, Particles};
use super::run_state::{Input, Persist, StateError, StateReason, persist_fields};
use super::walls::{BoxWalls, Periodic, Sides};
use std::ops::Range;
use std::sync::Mutex;

/// A pair `i < j` that may be in contact, with its effective radius and mass (computed once per
/// build, not once per step). Its tangential spring lives in [`Candidates::springs`], apart, so
/// that the step loop writes only springs and leaves the pair records clean in cache.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NeighborPair {
    /// First disk (smaller index).
    pub i: u32,
    /// Second disk.
    pub j: u32,
    /// Effective radius R* (m).
    pub r_star: f64,
    /// Effective mass m* (kg).
    pub m_star: f64,
}

impl NeighborPair {
    fn new(p: &Particles, i: usize, j: usize) -> Self {
        Self {
            i: i as u32,
            j: j as u32,
            r_star: effective_radius(p.r[i], p.r[j]),
            m_star: effective_mass(p.mass[i], p.mass[j]),
        }
    }
}

/// A disk that may touch a wall (its spring lives in [`Candidates::springs`]), with the contact's
/// effective mass: the disk's (kept here, so the step loop needs no fetch of the mass array).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct WallPair {
    /// The disk.
    pub i: u32,
    /// Index of the wall in [`BoxWalls::walls`].
    pub wall: u32,
    /// Effective mass m* (kg).
    pub m_star: f64,
}

/// A list entry with a sort key, for carrying springs over rebuilds.
pub trait Keyed {
    /// The entry's position in the sorted list.
    fn key(&self) -> (u32, u32);
}

impl Keyed for NeighborPair {
    fn key(&self) -> (u32, u32) {
        (self.i, self.j)
    }
}

impl Keyed for WallPair {
    fn key(&self) -> (u32, u32) {
        (self.i, self.wall)
    }
}

/// One sorted candidate list with each entry's contact history: its tangential spring ξ (m) and
/// the contact law's own state `S` (both reset while not in contact), and the buffers of the next
/// build. (Laws without state have `S = ()`, which takes no memory and no work.)
#[derive(Clone, Debug)]
pub struct Candidates<T, S = ()> {
    /// Candidates, sorted by key.
    pub entries: Vec<T>,
    /// Tangential spring of each entry.
    pub springs: Vec<f64>,
    /// The contact law's state of each entry.
    pub states: Vec<S>,
    fresh: Vec<T>,
    fresh_springs: Vec<f64>,
    fresh_states: Vec<S>,
    /// Which build the entries are from (and the histories, but for the steps' own updates):
    /// unique among all lists of the process, 0 for none.
    build: u64,
}

/// The number of the latest build of any candidate list.
static BUILDS: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

impl<T, S> Candidates<T, S> {
    /// Which build the entries are from (the same number: the same entries, whose springs and
    /// states only the steps changed since): unique among all candidate lists of the process; 0
    /// for a list not built by [`NeighborList::rebuild`].
    pub fn build(&self) -> u64 {
        self.build
    }

    /// Draws a new build number (entries built, or histories set from outside the steps).
    fn renumber(&mut self) {
        self.build = BUILDS.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
    }
}

impl<T, S> Default for Candidates<T, S> {
    fn default() -> Self {
        Self {
            entries: Vec::new(),
            springs: Vec::new(),
            states: Vec::new(),
            fresh: Vec::new(),
            fresh_springs: Vec::new(),
            fresh_states: Vec::new(),
            build: 0,
        }
    }
}

/// Fresh entries per unit of the merge that carries histories over.
const MERGE_UNIT: usize = 4096;

/// A run of fresh entries and their histories, to be taken from the old list.
struct FreshRun<'a, T, S> {
    entries: &'a [T],
    springs: &'a mut [f64],
    states: &'a mut [S],
}

impl<T: Sync, S: Send> Split for FreshRun<'_, T, S> {
    fn units(&self) -> usize {
        self.entries.len().div_ceil(MERGE_UNIT)
    }

    fn split_at(self, at: usize) -> (Self, Self) {
        let mid = (at * MERGE_UNIT).min(self.entries.len());
        let (e0, e1) = self.entries.split_at(mid);
        let (sp0, sp1) = self.springs.split_at_mut(mid);
        let (st0, st1) = self.states.split_at_mut(mid);
        (FreshRun { entries: e0, springs: sp0, states: st0 }, FreshRun { entries: e1, springs: sp1, states: st1 })
    }
}

impl<T: Keyed + Sync, S: Copy + Default + Send + Sync> Candidates<T, S> {
    /// Replaces the entries by the freshly collected ones (in `fresh`), carrying the histories of
    /// entries present in both by a linear merge of the two sorted lists, the fresh entries shared
    /// out in runs between the `team`'s threads (each run's merge starts where its first key is
    /// and writes every history of its run: the buffers are only resized, not cleared, so no
    /// thread writes the whole of them). `fresh` holds the old entries afterwards, as scratch.
    fn swap_in_fresh(&mut self, team: &Team) {
        self.fresh_springs.resize(self.fresh.len(), 0.0);
        self.fresh_states.resize(self.fresh.len(), S::default());
        let run = FreshRun { entries: &self.fresh, springs: &mut self.fresh_springs, states: &mut self.fresh_states };
        let (old, springs, states) = (&self.entries, &self.springs, &self.states);
        team.for_each_part(run, &|run: FreshRun<'_, T, S>, _| {
            let Some(first) = run.entries.first() else { return };
            let mut k = old.partition_point(|e| e.key() < first.key());
            for (entry, (spring, state)) in run.entries.iter().zip(run.springs.iter_mut().zip(run.states.iter_mut())) {
                while k < old.len() && old[k].key() < entry.key() {
                    k += 1;
                }
                let kept = k < old.len() && old[k].key() == entry.key();
                (*spring, *state) = if kept { (springs[k], states[k]) } else { (0.0, S::default()) };
            }
        });
        std::mem::swap(&mut self.entries, &mut self.fresh);
        std::mem::swap(&mut self.springs, &mut self.fresh_springs);
        std::mem::swap(&mut self.states, &mut self.fresh_states);
        self.renumber();
    }

    /// Renames the disks of every entry by `rename` and sorts the entries again by key with their
    /// histories, through the buffers of the next build.
    fn renumber_disks(&mut self, rename: impl Fn(&T) -> T)
    where
        T: Copy,
    {
        self.fresh.clear();
        self.fresh.extend(self.entries.iter().map(rename));
        let mut sorted: Vec<u32> = (0..self.fresh.len() as u32).collect();
        sorted.sort_unstable_by_key(|&k| self.fresh[k as usize].key());
        self.entries.clear();
        self.entries.extend(sorted.iter().map(|&k| self.fresh[k as usize]));
        gather(&mut self.springs, &sorted, &mut self.fresh_springs);
        gather(&mut self.states, &sorted, &mut self.fresh_states);
        self.renumber();
    }

    /// Gives the entry of `key`, if there is one, the history `(spring, state)`.
    fn seed(&mut self, key: Option<(u32, u32)>, (spring, state): (f64, S)) {
        if let Some(k) = key.and_then(|key| self.entries.binary_search_by_key(&key, Keyed::key).ok()) {
            (self.springs[k], self.states[k]) = (spring, state);
            self.renumber();
        }
    }
}

/// Verlet list with its build state; `S`: the contact law's per-contact state.
#[derive(Clone, Debug)]
pub struct NeighborList<S = ()> {
    /// Candidate disk pairs, sorted by `(i, j)`.
    pub pairs: Candidates<NeighborPair, S>,
    /// Candidate disk-wall contacts, sorted by `(i, wall)`.
    pub walls: Candidates<WallPair, S>,
    /// Longest distance a disk can have moved since the last build (m): the sum of every step's
    /// longest move, an upper bound that needs no stored positions.
    travel: f64,
    skin: f64,
    broad_phase: BroadPhaseKind,
    grid: CellGrid,
    /// Scratch of the parallel search for wall candidates.
    wall_finds: PartFinds<WallPair>,
}

/// What a search does with a run of disks: given them, a row of scratch and where to put its finds.
type Finder<'a, T> = dyn Fn(Range<usize>, &mut Vec<u32>, &mut Vec<T>) + Sync + 'a;

/// Scratch of a parallel search: each run's row and finds (a clone starts without).
#[derive(Debug)]
struct PartFinds<T>(Vec<Mutex<(Vec<u32>, Vec<T>)>>);

impl<T> Default for PartFinds<T> {
    fn default() -> Self {
        Self(Vec::new())
    }
}

impl<T> Clone for PartFinds<T> {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl<T: Copy + Send> PartFinds<T> {
    /// Puts in `out` (its entries replaced) what `find` finds among the disks `0..disks`, in disk
    /// order: the disks shared out in runs between the `team`'s threads, each run's finds in a
    /// buffer of its own, then joined, each buffer copied to its place by the part of the same
    /// runs (so mostly by the thread that found them, which holds them in its cache).
    fn find(&mut self, disks: usize, team: &Team, out: &mut Vec<T>, find: &Finder<'_, T>) {
        let parts = team.parts();
        self.0.resize_with(self.0.len().max(parts), Default::default);
        if parts <= 1 {
            out.clear();
            let row = &mut self.0[0].get_mut().expect("no panic while held").0;
            return find(0..disks, row, out);
        }
        for buffer in &mut self.0 {
            buffer.get_mut().expect("no panic while held").1.clear();
        }
        let buffers = &self.0;
        team.for_each_part(Span { range: 0..disks, unit: 256 }, &|run: Span, number| {
            let mut buffer = buffers[number].lock().expect("a buffer per run");
            let (row, found) = &mut *buffer;
            find(run.range, row, found);
        });
        let found = |b: &mut Mutex<(Vec<u32>, Vec<T>)>| b.get_mut().expect("no panic while held").1.first().copied();
        let Some(filler) = self.0.iter_mut().find_map(found) else { return out.clear() };
        // Only a longer list than the last writes on this thread: the rest is overwritten in place.
        let total = self.0.iter_mut().map(|b| b.get_mut().expect("no panic while held").1.len()).sum();
        out.resize(total, filler);
        team.for_each_part(Joined { finds: &self.0, out }, &|part: Joined<'_, T>, _| part.copy());
    }
}

/// Buffers of a [`PartFinds`] and their places in the joined list.
struct Joined<'a, T> {
    finds: &'a [Mutex<(Vec<u32>, Vec<T>)>],
    out: &'a mut [T],
}

impl<T: Copy> Joined<'_, T> {
    fn copy(self) {
        let mut rest = self.out;
        for buffer in self.finds {
            let found = &buffer.lock().expect("no panic while held").1;
            let (place, after) = rest.split_at_mut(found.len());
            place.copy_from_slice(found);
            rest = after;
        }
    }
}

impl<T: Send> Split for Joined<'_, T> {
    fn units(&self) -> usize {
        self.finds.len()
    }

    fn split_at(self, at: usize) -> (Self, Self) {
        let (f0, f1) = self.finds.split_at(at);
        let len = f0.iter().map(|b| b.lock().expect("no panic while held").1.len()).sum();
        let (o0, o1) = self.out.split_at_mut(len);
        (Joined { finds: f0, out: o0 }, Joined { finds: f1, out: o1 })
    }
}

impl<S> NeighborList<S> {
    /// Longest distance a disk can have moved since the last build (m), the rounding of its sum
    /// aside.
    pub fn travel(&self) -> f64 {
        self.travel
    }
}

impl<S: Copy + Default + Send + Sync> NeighborList<S> {
    /// An empty list; call [`NeighborList::rebuild`] before use.
    pub fn new(broad_phase: BroadPhaseKind, skin: f64) -> Self {
        Self {
            pairs: Candidates::default(),
            walls: Candidates::default(),
            travel: 0.0,
            skin,
            broad_phase,
            grid: CellGrid::default(),
            wall_finds: PartFinds::default(),
        }
    }

    /// The candidate pairs whose disks are more than [`FAR_PLACES`] places apart.
    pub fn far_pairs(&self) -> usize {
        self.pairs.entries.iter().filter(|p| p.j - p.i > FAR_PLACES).count()
    }

    /// Numbers the disks of the lists afresh: disk `i` becomes disk `new_of_old[i]` (a pair keeps
    /// its smaller index first; its tangential spring and law state read the same either way).
    pub fn renumber_disks(&mut self, new_of_old: &[u32]) {
        let new = |i: u32| new_of_old[i as usize];
        self.pairs.renumber_disks(|p| NeighborPair { i: new(p.i).min(new(p.j)), j: new(p.i).max(new(p.j)), ..*p });
        self.walls.renumber_disks(|w| WallPair { i: new(w.i), ..*w });
    }

    /// Adds a step in which no disk moved farther than `longest` (m); returns whether the list
    /// must be rebuilt: some disk may have moved more than half the skin since the last build
    /// (an infinite or NaN move counts as that).
    pub fn note_step(&mut self, longest: f64) -> bool {
        self.travel += longest;
        self.travel >= 0.5 * self.skin || self.travel.is_nan()
    }

    /// Rebuilds the lists from the current positions, keeping springs of surviving pairs; the
    /// grid's search shared out between the `team`'s threads in runs of disks (the list is the same).
    pub fn rebuild(&mut self, p: &Particles, walls: &BoxWalls, team: &Team) {
        let period = walls.period();
        match self.broad_phase {
            BroadPhaseKind::Grid => self.grid.collect(p, (self.skin, period), &mut self.pairs.fresh, team),
            BroadPhaseKind::AllPairs => all_pairs(p, (self.skin, period), &mut self.pairs.fresh),
        }
        self.pairs.swap_in_fresh(team);
        let skin = self.skin;
        self.wall_finds.find(p.len(), team, &mut self.walls.fresh, &|disks, _, found| {
            for i in disks {
                for (w, wall) in walls.touchable() {
                    // NaN positions are kept as candidates, so a diverging disk is still seen.
                    let overlap = wall.overlap(p.x[i], p.y[i], p.r[i]);
                    if overlap > -skin || overlap.is_nan() {
                        found.push(WallPair { i: i as u32, wall: w as u32, m_star: p.mass[i] });
                    }
                }
            }
        });
        self.walls.swap_in_fresh(team);
        self.travel = 0.0;
    }
}

impl<S: ContactState> NeighborList<S> {
    /// Gives the candidates of `contacts` their tangential springs and law states (a restart's
    /// contact history; call after a build). A contact whose bodies are no candidates (too far
    /// apart to touch, or no such disk or wall) is dropped, as a step would drop it.
    pub fn seed_histories(&mut self, contacts: &[InitialContact]) {
        let key = |a: usize, b: usize| Some((u32::try_from(a).ok()?, u32::try_from(b).ok()?));
        for c in contacts {
            let history = (c.tangential_spring, S::from_number(c.law_state));
            match c.partner {
                Partner::Disk(j) => self.pairs.seed(key(c.disk.min(j), c.disk.max(j)), history),
                Partner::Wall(w) => self.walls.seed(key(c.disk, w), history),
            }
        }
    }
}

/// Whether disks `i` and `j` are closer than `r_i + r_j + skin`, across the sides of `period` (m)
/// to the nearest image.
#[inline]
fn within(p: &Particles, i: usize, j: usize, (skin, period): (f64, Option<f64>)) -> bool {
    let dx = p.x[j] - p.x[i];
    let dx = period.map_or(dx, |width| Periodic::new(width).dx(dx));
    let dy = p.y[j] - p.y[i];
    let reach = p.r[i] + p.r[j] + skin;
    dx * dx + dy * dy < reach * reach
}

fn all_pairs(p: &Particles, reach: (f64, Option<f64>), out: &mut Vec<NeighborPair>) {
    out.clear();
    for i in 0..p.len() {
        for j in i + 1..p.len() {
            if within(p, i, j, reach) {
                out.push(NeighborPair::new(p, i, j));
            }
        }
    }
}

/// Uniform cell grid sized to the current positions (a counting sort of disks into cells): the
/// broad phase of the neighbour list, and of the study's overlap check of placement files. Time and
/// memory are O(N) to build, whatever the positions (cells grow until there are at most ~2 per disk).
#[derive(Clone, Debug, Default)]
pub struct CellGrid {
    cell_of: Vec<u32>,
    start: Vec<u32>,
    members: Vec<u32>,
    fill: Vec<u32>,
    /// Scratch of the search.
    finds: PartFinds<NeighborPair>,
    cols: usize,
    rows: usize,
    /// Whether the columns wrap around (periodic sides).
    wraps: bool,
}

impl CellGrid {
    /// Sorts the disks at `x`, `y` into cells at least `reach` wide (m): any two disks closer than
    /// `reach` are in the same or adjacent cells. Non-finite positions land in an edge cell.
    pub fn build(&mut self, x: &[f64], y: &[f64], reach: f64) {
        self.build_in(x, y, (reach, None));
    }

    /// [`Self::build`], with periodic sides `period` (m) apart when given: the columns then span
    /// `[0, period)`, and the first and last are neighbours.
    fn build_in(&mut self, x: &[f64], y: &[f64], (reach, period): (f64, Option<f64>)) {
        let n = x.len();
        let (xmin, xmax) = min_max(x);
        let (ymin, ymax) = min_max(y);
        // At most ~2 cells per disk so a disk that flew far away cannot blow the grid up (disks
        // beyond are clamped to edge cells).
        let mut cell = if reach > 0.0 && reach.is_finite() { reach } else { f64::MAX };
        let max_cells = (2 * n + 16) as f64;
        let span = |lo: f64, hi: f64, c: f64| (((hi - lo) / c).floor() + 1.0).min(1e9);
        // Periodic columns: as many whole cells as the period holds, at least one.
        let columns = |c: f64| period.map_or(span(xmin, xmax, c), |w| (w / c).floor().clamp(1.0, 1e9));
        while columns(cell) * span(ymin, ymax, cell) > max_cells {
            cell *= 1.5;
        }
        let (cols, rows) = (columns(cell) as usize, span(ymin, ymax, cell) as usize);
        (self.cols, self.rows, self.wraps) = (cols, rows, period.is_some());
        let (x0, column_width) = period.map_or((xmin, cell), |w| (0.0, w / cols as f64));
        let cell_index = |x: f64, y: f64| {
            let c = (((x - x0) / column_width) as usize).min(cols - 1);
            let r = (((y - ymin) / cell) as usize).min(rows - 1);
            r * cols + c
        };
        self.cell_of.clear();
        self.cell_of.extend(x.iter().zip(y).map(|(&x, &y)| cell_index(x, y) as u32));
        self.start.clear();
        self.start.resize(cols * rows + 1, 0);
        for &c in &self.cell_of {
            self.start[c as usize + 1] += 1;
        }
        for c in 0..cols * rows {
            self.start[c + 1] += self.start[c];
        }
        self.members.resize(n, 0);
        self.fill.clone_from(&self.start);
        for (k, &c) in self.cell_of.iter().enumerate() {
            self.members[self.fill[c as usize] as usize] = k as u32;
            self.fill[c as usize] += 1;
        }
    }

    /// The disks `j > i` in disk `i`'s cell and the cells around it (after [`Self::build`]), by cell.
    pub fn neighbours(&self, i: usize) -> impl Iterator<Item = usize> + '_ {
        self.around(i).flatten().map(|&j| j as usize).filter(move |&j| j > i)
    }

    /// The disks of disk `i`'s cell and the cells around it, in three runs: the cells of a row are
    /// consecutive in `members`, so each row's three cells are one slice.
    #[inline]
    fn around(&self, i: usize) -> impl Iterator<Item = &[u32]> + '_ {
        let c = self.cell_of[i] as usize;
        let (ci, ri) = (c % self.cols, c / self.cols);
        let (first, last) = (ci.saturating_sub(1), (ci + 1).min(self.cols - 1));
        (ri.saturating_sub(1)..=(ri + 1).min(self.rows - 1)).map(move |r| {
            let (from, to) = (self.start[r * self.cols + first], self.start[r * self.cols + last + 1]);
            &self.members[from as usize..to as usize]
        })
    }

    /// The cells next to disk `i`'s across periodic sides that [`Self::around`] leaves out: in the
    /// column at the other side, when disk `i`'s is the first or last of three or more, its row and
    /// the rows next to it (with fewer columns, `around` has them all).
    fn across(&self, i: usize) -> impl Iterator<Item = &[u32]> + '_ {
        let (c, cols) = (self.cell_of[i] as usize, self.cols);
        let (ci, ri) = (c % cols, c / cols);
        let other = match ci {
            _ if !self.wraps || cols < 3 => None,
            0 => Some(cols - 1),
            _ if ci == cols - 1 => Some(0),
            _ => None,
        };
        let rows = ri.saturating_sub(1)..=(ri + 1).min(self.rows - 1);
        other.into_iter().flat_map(move |column| {
            rows.clone().map(move |r| {
                let cell = r * cols + column;
                &self.members[self.start[cell] as usize..self.start[cell + 1] as usize]
            })
        })
    }

    /// The neighbour list's candidate pairs: every pair closer than `r_i + r_j + skin` (across
    /// periodic sides `period` apart, when given), sorted; the disks shared out in runs between
    /// the `team`'s threads, whose pairs are joined in disk order.
    fn collect(&mut self, p: &Particles, reach: (f64, Option<f64>), out: &mut Vec<NeighborPair>, team: &Team) {
        if p.is_empty() {
            return out.clear();
        }
        let (skin, period) = reach;
        self.build_in(&p.x, &p.y, (2.0 * p.max_radius() + skin, period));
        let mut finds = std::mem::take(&mut self.finds);
        finds.find(p.len(), team, out, &|disks, row, found| self.pairs_of(p, reach, disks, row, found));
        self.finds = finds;
    }

    /// Appends the candidate pairs `(i, j)` of the disks `i` in `disks` to `out`, sorted.
    fn pairs_of(
        &self,
        p: &Particles,
        reach: (f64, Option<f64>),
        disks: Range<usize>,
        row: &mut Vec<u32>,
        out: &mut Vec<NeighborPair>,
    ) {
        for i in disks {
            row.clear();
            for run in self.around(i).chain(self.across(i)) {
                for &j in run {
                    if j as usize > i && within(p, i, j as usize, reach) {
                        row.push(j);
                    }
                }
            }
            row.sort_unstable();
            out.extend(row.iter().map(|&j| NeighborPair::new(p, i, j as usize)));
        }
    }
}

fn min_max(v: &[f64]) -> (f64, f64) {
    let lo = v.iter().cloned().fold(f64::INFINITY, f64::min);
    let hi = v.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    if lo.is_finite() && hi.is_finite() { (lo, hi) } else { (0.0, 0.0) }
}

persist_fields!(NeighborPair { i, j, r_star, m_star });
persist_fields!(WallPair { i, wall, m_star });

/// The entries and their histories (law states as numbers); a list read back counts as a new
/// build, so that no table kept from before takes it for its own.
impl<T: Persist + Default, S: ContactState> Persist for Candidates<T, S> {
    fn save(&self, out: &mut Vec<u8>) {
        self.entries.save(out);
        self.springs.save(out);
        self.states.iter().map(|s| s.to_number()).collect::<Vec<f64>>().save(out);
    }
    fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError> {
        self.entries.load(input)?;
        self.springs.load(input)?;
        let mut states: Vec<f64> = Vec::new();
        states.load(input)?;
        for (found, expected) in [(self.springs.len(), self.entries.len()), (states.len(), self.entries.len())] {
            if found != expected {
                return Err(input.error(StateReason::Invalid { found: found as u64, expected: expected as u64 }));
            }
        }
        self.states.clear();
        self.states.extend(states.into_iter().map(S::from_number));
        self.renumber();
        Ok(())
    }
}

/// The lists and the travel since their build (the grid and scratch are rebuilt as needed).
impl<S: ContactState> Persist for NeighborList<S> {
    fn save(&self, out: &mut Vec<u8>) {
        self.pairs.save(out);
        self.walls.save(out);
        self.travel.save(out);
    }
    fn load(&mut self, input: &mut Input<'_>) -> Result<(), StateError> {
        self.pairs.load(input)?;
        self.walls.load(input)?;
        self.travel.load(input)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::config::SceneConfig;
    use crate::physics::particles::InitialDisk;
    use crate::physics::placement;

    #[test]
    fn grid_finds_exactly_the_all_pairs_set() {
        let mut scene = SceneConfig::default();
        scene.particles.count = 200;
        scene.particles.radius_max = Some(0.015);
        let disks = placement::generate(&scene).unwrap();
        let p = Particles::new(&disks, 1000.0, 1.0);
        let walls = BoxWalls::new(&scene.domain);
        let mut grid = NeighborList::<()>::new(BroadPhaseKind::Grid, 0.006);
        let mut brute = NeighborList::<()>::new(BroadPhaseKind::AllPairs, 0.006);
        grid.rebuild(&p, &walls, &Team::new(1));
        brute.rebuild(&p, &walls, &Team::new(1));
        assert!(!grid.walls.entries.is_empty());
        assert_eq!(grid.walls.entries, brute.walls.entries);
        assert!(!brute.pairs.entries.is_empty());
        assert_eq!(grid.pairs.entries, brute.pairs.entries);
    }

    /// The grid's and the all-pairs lists of `disks` between periodic sides `width` apart: equal,
    /// with pairs across the sides and no side wall candidates.
    fn periodic_lists_agree(disks: &[InitialDisk], width: f64) {
        let domain = crate::physics::config::DomainConfig { width, periodic_x: true, ..Default::default() };
        let p = Particles::new(disks, 1000.0, 1.0);
        let walls = BoxWalls::new(&domain);
        let mut grid = NeighborList::<()>::new(BroadPhaseKind::Grid, 0.006);
        let mut brute = NeighborList::<()>::new(BroadPhaseKind::AllPairs, 0.006);
        grid.rebuild(&p, &walls, &Team::new(1));
        brute.rebuild(&p, &walls, &Team::new(1));
        let far = |q: &&NeighborPair| (p.x[q.j as usize] - p.x[q.i as usize]).abs() > 0.5 * width;
        assert!(brute.pairs.entries.iter().filter(far).count() > 0, "pairs across the sides");
        assert_eq!(grid.pairs.entries, brute.pairs.entries);
        assert!(grid.walls.entries.iter().all(|w| w.wall == 0), "only the floor: {:?}", grid.walls.entries);
    }

    #[test]
    fn periodic_grid_finds_exactly_the_all_pairs_set_across_the_sides() {
        let mut scene = SceneConfig::default();
        (scene.particles.count, scene.particles.radius_max) = (200, Some(0.012));
        let width = scene.domain.width;
        let mut disks = placement::generate(&scene).unwrap();
        // Half a width over: the disks at the sides of the placement now meet across them.
        for d in &mut disks {
            d.x = (d.x + 0.5 * width) % width;
        }
        periodic_lists_agree(&disks, width);
        // A box of one or two grid columns: a row of three disks, the first and last touching
        // across the sides.
        let row = [0.005, 0.027, 0.045].map(|x| InitialDisk { x, y: 0.01, r: 0.01, ..Default::default() });
        periodic_lists_agree(&row, 0.05);
    }

    #[test]
    fn rebuild_keeps_histories_of_surviving_pairs() {
        let pair = |i, j| NeighborPair { i, j, r_star: 0.0, m_star: 0.0 };
        let mut list = Candidates {
            entries: vec![pair(0, 1), pair(0, 3), pair(2, 3)],
            springs: vec![1.0, 2.0, 3.0],
            states: vec![10_u8, 20, 30],
            fresh: vec![pair(0, 3), pair(1, 2), pair(2, 3)],
            ..Default::default()
        };
        list.swap_in_fresh(&Team::new(1));
        assert_eq!(list.entries, [pair(0, 3), pair(1, 2), pair(2, 3)]);
        assert_eq!(list.springs, [2.0, 0.0, 3.0]);
        assert_eq!(list.states, [20, 0, 30]);
    }

    #[test]
    fn histories_carried_over_in_runs_on_several_threads_land_where_on_one() {
        // Old and fresh lists of some 30 000 pairs sharing about half their keys: the fresh list
        // spans several merge runs, whose starts fall on keys present and absent in the old one.
        let pair = |i: u32, j: u32| NeighborPair { i, j, r_star: 0.0, m_star: 0.0 };
        let keys = |keep: u32| {
            (0..10_000u32).flat_map(move |i| (1..5).filter(move |d| (i + d) % keep != 0).map(move |d| pair(i, i + d)))
        };
        let old: Vec<_> = keys(3).collect();
        let merged = |team: &Team| {
            let mut list = Candidates {
                springs: (0..old.len()).map(|k| k as f64 + 1.0).collect(),
                states: (0..old.len() as u32).collect(),
                entries: old.clone(),
                fresh: keys(2).collect(),
                ..Default::default()
            };
            list.swap_in_fresh(team);
            list
        };
        let one = merged(&Team::new(1));
        let pool = rayon::ThreadPoolBuilder::new().num_threads(3).build().unwrap();
        let three = pool.install(|| merged(&Team::new(3)));
        assert!(one.entries.len() > 3 * MERGE_UNIT);
        assert_eq!((&one.entries, &one.springs, &one.states), (&three.entries, &three.springs, &three.states));
        for (k, entry) in one.entries.iter().enumerate() {
            let before = old.binary_search_by_key(&entry.key(), Keyed::key).ok();
            assert_eq!(one.springs[k], before.map_or(0.0, |b| b as f64 + 1.0), "pair {:?}", entry.key());
            assert_eq!(one.states[k], before.map_or(0, |b| b as u32));
        }
    }

    #[test]
    fn seeded_histories_land_on_their_candidates_in_either_order_and_the_rest_are_dropped() {
        let disks = [0.0, 0.02, 0.2].map(|x| InitialDisk { x: 0.1 + x, y: 0.01, r: 0.01, ..Default::default() });
        let p = Particles::new(&disks, 1000.0, 1.0);
        let walls = BoxWalls::new(&SceneConfig::default().domain);
        type State = <crate::physics::contact::HystereticLinear as crate::physics::ContactLaw>::State;
        let mut list = NeighborList::<State>::new(BroadPhaseKind::Grid, 0.002);
        list.rebuild(&p, &walls, &Team::new(1));
        let contact =
            |disk, partner, tangential_spring| InitialContact { disk, partner, tangential_spring, law_state: 1e-4 };
        list.seed_histories(&[
            contact(1, Partner::Disk(0), 2e-7),
            contact(2, Partner::Wall(0), -3e-7),
            contact(0, Partner::Disk(2), 5.0),
            contact(7, Partner::Wall(0), 5.0),
            contact(0, Partner::Wall(9), 5.0),
        ]);
        assert_eq!(list.pairs.entries.iter().map(Keyed::key).collect::<Vec<_>>(), [(0, 1)]);
        assert_eq!((list.pairs.springs[0], list.pairs.states[0].0), (2e-7, 1e-4));
        let floor = |i| list.walls.entries.iter().position(|w| w.key() == (i, 0)).unwrap();
        assert_eq!(list.walls.springs[floor(2)], -3e-7);
        assert_eq!(list.walls.springs[floor(0)], 0.0);
        assert!(list.walls.springs.iter().chain(&list.pairs.springs).all(|&s| s != 5.0), "no home: dropped");
    }

    #[test]
    fn rebuild_due_once_the_moves_add_up_to_half_the_skin() {
        let mut scene = SceneConfig::default();
        scene.particles.count = 20;
        let p = Particles::new(&placement::generate(&scene).unwrap(), 1000.0, 1.0);
        let walls = BoxWalls::new(&scene.domain);
        let mut list = NeighborList::<()>::new(BroadPhaseKind::Grid, 0.004);
        list.rebuild(&p, &walls, &Team::new(1));
        let steps_until_due = |list: &mut NeighborList<()>, step: f64| (1..).find(|_| list.note_step(step)).unwrap();
        assert_eq!(steps_until_due(&mut list, 0.00025), 8);
        // Due until rebuilt; then counted afresh.
        assert!(list.note_step(0.0));
        list.rebuild(&p, &walls, &Team::new(1));
        assert_eq!(steps_until_due(&mut list, 0.0005), 4);
        list.rebuild(&p, &walls, &Team::new(1));
        assert!(!list.note_step(0.0) && list.note_step(f64::NAN));
    }
}
