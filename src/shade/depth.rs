//! The depth test: the comparison of a fragment against the depth buffer,
//! known at compile time for the default `LessEqual` or decided per pixel,
//! and the 16-bit depth of an interpolated one.

/// The depth comparison of a fragment against the depth buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, Hash)]
pub enum DepthTest {
    /// Always passes (no depth test).
    Always,
    /// Passes when nearer.
    Less,
    /// Passes when nearer or equal: later triangles win ties (default).
    #[default]
    LessEqual,
    /// Passes when equal.
    Equal,
    /// Passes when farther or equal.
    GreaterEqual,
    /// Passes when farther.
    Greater,
    /// Never passes.
    Never,
}

impl DepthTest {
    /// Whether a fragment at depth `new` passes against the stored `old`
    /// (the fragment-shader path tests at run time; the flat and Gouraud
    /// paths have the test monomorphized).
    #[inline(always)]
    pub fn passes(self, new: u16, old: u16) -> bool {
        match self {
            DepthTest::Always => true,
            DepthTest::Less => new < old,
            DepthTest::LessEqual => new <= old,
            DepthTest::Equal => new == old,
            DepthTest::GreaterEqual => new >= old,
            DepthTest::Greater => new > old,
            DepthTest::Never => false,
        }
    }
}

/// A depth comparison in the span loop: [`DLessEqual`], the default,
/// compiled into its own loops, or any [`DepthTest`] decided per pixel (one
/// more loop for all the others, rather than a copy of every loop per
/// comparison: each copy costs kilobytes of flash).
pub(crate) trait DepthFn: Copy {
    /// The comparison for `test` (a type that is one comparison ignores it).
    fn new(test: DepthTest) -> Self;
    /// Whether a fragment at depth `new` passes against the stored `old`.
    fn pass(self, new: u16, old: u16) -> bool;
    /// The depth to store after testing `new` against `old` with depth
    /// writes on: `if pass(new, old) { new } else { old }`, written as the
    /// min, max or plain value it always equals, so the span loops need no
    /// branch or conditional store.
    fn merge(self, new: u16, old: u16) -> u16;
}

/// `LessEqual`, the default comparison, known at compile time.
#[derive(Clone, Copy, Debug)]
pub(crate) struct DLessEqual;

impl DepthFn for DLessEqual {
    #[inline(always)]
    fn new(_: DepthTest) -> Self {
        Self
    }
    #[inline(always)]
    fn pass(self, n: u16, o: u16) -> bool {
        n <= o
    }
    #[inline(always)]
    fn merge(self, n: u16, o: u16) -> u16 {
        n.min(o)
    }
}

impl DepthFn for DepthTest {
    #[inline(always)]
    fn new(test: DepthTest) -> Self {
        test
    }
    #[inline(always)]
    fn pass(self, n: u16, o: u16) -> bool {
        self.passes(n, o)
    }
    #[inline(always)]
    fn merge(self, n: u16, o: u16) -> u16 {
        match self {
            DepthTest::Always => n,
            DepthTest::Less | DepthTest::LessEqual => n.min(o),
            DepthTest::GreaterEqual | DepthTest::Greater => n.max(o),
            DepthTest::Equal | DepthTest::Never => o,
        }
    }
}

/// The 16-bit depth of an interpolated depth `z` held as `z << 2`
/// (`Z_FRAC = 14`): the integer part `(z >> 14) as u16` is then the upper
/// half of the `u32`, and stepping `z << 2` by `gz << 2` with wrapping
/// arithmetic keeps exactly the bits that matter. Taking the upper half
/// with an arithmetic shift lets x86 pack eight of them with one
/// signed-saturating instruction.
#[inline(always)]
pub(crate) fn depth16(z: u32) -> u16 {
    ((z as i32) >> 16) as u16
}
