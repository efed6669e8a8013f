//! Contact forces of one step: disk pairs in blocks, with the disk-wall contacts in between.
//!
//! Disk pairs are taken in blocks of `BLOCK` (128) neighbour-list candidates, each in three stages:
//! 1. **narrow phase**: which candidates touch. Their geometry, radii and relative velocities are
//!    copied into a small table, one array per quantity (branching on contact in short lists only,
//!    see `TouchingPairs::collect`). In short lists each block keeps its touching pairs' rows (which
//!    pairs, their disks, radii, `R*` and `m*`) from step to step: a block whose pairs touch as at
//!    the previous step (most blocks of a settling pile) only gathers positions and
//!    velocities (`TouchingPairs::gather_unchanged`; the springs are kept with the rows). The
//!    same touching test decides: for its pairs in contact, in stage 2's geometry loop; for its
//!    pairs apart, in the gather: at every step for the few nearly touching, for the others only
//!    once the disks may have moved far enough for them to touch;
//! 2. **forces**: distance, unit normal, overlap, the law's stiffness and damping, the tangential
//!    spring with its Coulomb limit, and the resulting force and torques, for every touching pair of
//!    the block, in branch-free loops over the table that the compiler vectorises. Their three
//!    square roots and two divisions per contact are the most expensive operations of a step done
//!    one contact at a time: the divide/square-root unit does two (SSE2) or four (AVX2) of them for
//!    the price of one. They depend on one another within a contact (distance, then overlap, then
//!    stiffness, then damping), so the work is split into three loops (geometry, the law's
//!    coefficients, the resolved forces), each short enough that the CPU overlaps many contacts'
//!    chains. On x86-64 CPUs with AVX2 the
//!    loops run in copies compiled for AVX2; both copies do the same IEEE operations in the same
//!    order, so results are bit-identical;
//! 3. **scatter**: the forces and torques are added to both disks, pair after pair in list order, so
//!    that every sum is always added up in the same order (determinism).
//!
//! Disk-wall contacts go through the same table and stages (the narrow phase puts the wall's normal
//! and the overlap in place of the geometry loop's), each disk's between the blocks, once no later
//! block can touch the disk (see [`TouchingPairs::contacts`]).
//!
//! One file per stage: [`table`] (the table), [`blocks`] (the one-thread block loop),
//! [`narrow_phase`] (stage 1) with [`kept_rows`] (what a block keeps from step to step), [`stages`]
//! (stage 2), [`scatter`] (stage 3), [`walls`] (disk-wall contacts) and [`parts`] (the parallel
//! path). `super::contact_list` evaluates one contact at a
//! time with the same functions and is the readable reference for what the stages compute.

mod blocks;
mod kept_rows;
mod narrow_phase;
mod parts;
mod scatter;
mod stages;
mod table;
#[cfg(test)]
mod tests;
mod walls;

pub use parts::contacts_in_parts;
pub(super) use stages::{relative_motion, unit_normal_and_overlap};
pub use table::{ContactParameters, TouchingPairs};
