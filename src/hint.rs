//! Branch hints for the optimiser.

/// Marks the path that calls it as rarely taken: a call of a `#[cold]`
/// function gives its branch the weights of an unlikely one (as
/// `core::hint::cold_path` does, stable only from Rust 1.95, after the
/// crate's minimum 1.93), and then is inlined: no instruction.
#[cold]
#[inline]
pub(crate) fn cold() {}
