//! The range table: every dispatch's slice of its constraint array, one
//! [`Range`] every [`UNIFORM_STRIDE`] bytes, read through a dynamic offset.

use crate::data::Range;
use crate::kernels::UNIFORM_STRIDE;
use pleat::solver::parallel::ColoredConstraints;

/// The ranges of every dispatch, 256 bytes apart, built before upload.
#[derive(Default)]
pub(super) struct RangeTable(Vec<Range>);

impl RangeTable {
    /// Adds a slice and returns its dynamic offset and count.
    pub(super) fn push(&mut self, first: u32, count: u32) -> (u32, u32) {
        self.0.push(Range { first, count });
        (
            (self.0.len() as u64 - 1) as u32 * UNIFORM_STRIDE as u32,
            count,
        )
    }

    pub(super) fn colours<C>(&mut self, set: &ColoredConstraints<C>) -> Vec<(u32, u32)> {
        set.colors()
            .iter()
            .filter(|r| !r.is_empty())
            .map(|r| self.push(r.start as u32, r.len() as u32))
            .collect()
    }

    /// The slice at dynamic offset `offset`.
    pub(super) fn at(&self, offset: u32) -> Range {
        self.0[(offset as u64 / UNIFORM_STRIDE) as usize]
    }

    pub(super) fn bytes(&self) -> Vec<u8> {
        let mut bytes = vec![0u8; self.0.len().max(1) * UNIFORM_STRIDE as usize];
        for (k, r) in self.0.iter().enumerate() {
            let at = k * UNIFORM_STRIDE as usize;
            bytes[at..at + size_of::<Range>()].copy_from_slice(bytemuck::bytes_of(r));
        }
        bytes
    }
}
