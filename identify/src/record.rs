//! One record of a fit: input, measured output and warm-up.

/// One record of a fit: the model's input, the measured output, and a
/// warm-up.
///
/// Each record is simulated from the model's initial state (a fresh copy
/// of the model, with the record's own values of any per-record
/// parameters), so records need not start or end at rest.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Record<'a> {
    /// The input, `stride · y.len()` samples (see [`FitOptions::stride`](crate::FitOptions::stride)).
    pub x: &'a [f64],
    /// The measured output.
    pub y: &'a [f64],
    /// Leading output samples that are simulated but not compared (the
    /// model settles from its initial state); `skip < y.len()`.
    pub skip: usize,
}

impl<'a> Record<'a> {
    /// The whole record `(x, y)`, nothing skipped.
    pub fn new(x: &'a [f64], y: &'a [f64]) -> Self {
        Self { x, y, skip: 0 }
    }

    /// The output samples compared: `y.len() − skip`.
    pub(crate) fn scored(&self) -> usize {
        self.y.len().saturating_sub(self.skip)
    }

    /// The scored samples among the input samples `offset..offset + len`
    /// for the stride `stride` (≥ 1): `(i, q)` where input sample
    /// `offset + i` is output sample `q` (`skip ≤ q < y.len()`), in order.
    /// One division per call, none per sample.
    pub(crate) fn scored_in(
        &self,
        stride: usize,
        offset: usize,
        len: usize,
    ) -> impl Iterator<Item = (usize, usize)> {
        // input sample `q · stride` lies in the range iff
        // `⌈offset/stride⌉ ≤ q < ⌈(offset + len)/stride⌉`
        let first = offset.div_ceil(stride).max(self.skip);
        let end = (offset + len).div_ceil(stride).min(self.y.len());
        (first..end).map(move |q| (q * stride - offset, q))
    }
}
