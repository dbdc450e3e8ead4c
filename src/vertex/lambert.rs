//! The vertex stage's Lambert fast path (one directional light on a plain
//! material: n·l and the lit colour in integers) and the per-draw
//! constants of its common loop: [`LoopConstants`] on 32-bit cores with a
//! long multiply, [`NarrowRows`] on ARMv6-M, both read through an opaque
//! reference so that the loop loads each where it uses it.

use super::screen::color_word;
use crate::math::FixedMat4;
use crate::mesh::Vec3Fx;

/// One directional light in model space (see
/// [`LightSetup::single_directional`](crate::light::LightSetup::single_directional)).
#[derive(Clone, Copy, Debug)]
pub(super) struct Lambert {
    pub(super) dir: [i32; 3],
    pub(super) color: [u32; 3],
    pub(super) ambient: [u32; 3],
}

impl Lambert {
    pub(super) fn new((dir, color, ambient): ([i32; 3], [u8; 3], [u8; 3])) -> Self {
        Lambert {
            dir,
            color: color.map(u32::from),
            ambient: ambient.map(u32::from),
        }
    }

    /// n·l in 1/256 steps, clamped to `0..=256` ([`shade`](Self::shade)'s).
    #[inline(always)]
    fn ndotl(&self, n: crate::mesh::Vec3Fx) -> u32 {
        let n = [n[0].to_bits(), n[1].to_bits(), n[2].to_bits()];
        // ARMv6-M builds each 64-bit product from four 16-bit ones: a
        // normal within ±1 takes n·l from six 32-bit products instead.
        match crate::math::SPLIT {
            true => ndotl_narrow(n, self.dir).unwrap_or_else(|| self.ndotl_wide(n)),
            false => self.ndotl_wide(n),
        }
    }

    /// [`ndotl`](Self::ndotl) of the normal's bits `n` by 64-bit products.
    #[inline(always)]
    fn ndotl_wide(&self, n: [i32; 3]) -> u32 {
        use crate::math::mul_wide;
        let d =
            mul_wide(n[0], self.dir[0]) + mul_wide(n[1], self.dir[1]) + mul_wide(n[2], self.dir[2]);
        // n·l in 1/256 steps, floored, clamped to [0, 1]. On 32-bit
        // cores from d's upper word, which is 0 exactly when d >> 24 is
        // 0 to 255 (the 64-bit clamp took twice the instructions on
        // the Cortex-M3); 64-bit ones keep the clamp, which measured
        // fewer there.
        if cfg!(target_pointer_width = "64") {
            (d >> 24).clamp(0, 256) as u32
        } else {
            clamp_ndotl_words(d)
        }
    }

    /// Per channel `c`, for the draw's colour `base`: `base[c] ambient[c]
    /// 256 + 32,640` and `base[c] color[c]`, so that [`shade`](Self::shade)'s
    /// `base[c] (ambient[c] 256 + color[c] n·l) + 32,640` is one
    /// multiply-add (the same value: every term is below `2^26`). Once per
    /// draw, for the common loop's constants.
    fn folded(&self, base: [u8; 3]) -> [[u32; 2]; 3] {
        let mut out = [[0; 2]; 3];
        for (c, ch) in out.iter_mut().enumerate() {
            let b = base[c] as u32;
            *ch = [b * self.ambient[c] * 256 + 32_640, b * self.color[c]];
        }
        out
    }

    /// The n·l (`0..=256`) whose colour on `base` has every channel in
    /// `1..=254`, as `[lo, span]`: n·l is such exactly when `n·l - lo <=
    /// span` (wrapping; [`within`]); none unless `gouraud`. Each channel's
    /// `floor((a + k n·l) / 65,280)` (`[a, k]` of [`folded`](Self::folded))
    /// grows with n·l, so the n·l where it is at least 1 are those from
    /// `ceil((65,280 - a) / k)` up, where it is at most 254 those up to
    /// `floor((255 · 65,280 - 1 - a) / k)`: the three channels' meet is
    /// one interval. Per vertex, then, the colour's half of the interior
    /// bit (see [`ScreenVertex::interior`](super::ScreenVertex::interior))
    /// is a subtraction and a compare, not three of each, and a draw that
    /// is not Gouraud shaded (whose vertices' bit nothing reads) gets an
    /// empty interval and the bit clear at the same cost.
    pub(super) fn interior_ndotl(&self, base: [u8; 3], gouraud: bool) -> [u32; 2] {
        interior_ndotl(&self.folded(base), gouraud)
    }

    /// The lit colour of normal `n` on the colour `base`.
    #[inline(always)]
    pub(super) fn shade(&self, n: crate::mesh::Vec3Fx, base: [u8; 3]) -> [u8; 3] {
        self.shade_ndotl(self.ndotl(n), base)
    }

    /// The lit colour for n·l `ndotl` (`0..=256`, [`ndotl`](Self::ndotl))
    /// on `base`: each channel `floor((base (256 ambient + color n·l) +
    /// 32,640) / 65,280)`, at most 255.
    #[inline(always)]
    fn shade_ndotl(&self, ndotl: u32, base: [u8; 3]) -> [u8; 3] {
        let mut out = [0u8; 3];
        for c in 0..3 {
            // At most 2^17.
            let k = self.ambient[c] * 256 + self.color[c] * ndotl;
            let x = base[c] as u32 * k + 32_640;
            // floor(x / 65,280) = floor(floor(x / 256) / 255): ARMv6-M,
            // without a multiply-high, divides by a constant through the
            // library (about a hundred instructions), `div255` in eight.
            out[c] = if cfg!(microraster_narrow_multiply) {
                crate::light::div255(x >> 8).min(255) as u8
            } else if cfg!(target_pointer_width = "32") {
                div65280_sat(x)
            } else {
                (x / 65_280).min(255) as u8
            };
        }
        out
    }
}

/// [`Lambert::interior_ndotl`] from the channels' `[a, k]`
/// ([`Lambert::folded`]): the first n·l with every channel at least 1
/// and the last with every channel at most 254, each by a binary search
/// over `0..=256` (each channel grows with n·l, so each test holds on one
/// end of the range only). Out of line, and called once the loop's
/// constants are made (inlined, the Cortex-M3 kept the matrix's elements
/// on the stack across it); searches rather than a division per channel
/// and end, which took the Cortex-M3's firmware 120 bytes more.
#[inline(never)]
fn interior_ndotl(channels: &[[u32; 2]; 3], gouraud: bool) -> [u32; 2] {
    // Where no vertex carries the bit (a size build's flash).
    if !super::screen::INTERIOR_STARTS {
        return [257, 0];
    }
    const ONE: u32 = 65_280;
    const TOP: u32 = 255 * ONE - 1;
    // Where `a + k n·l` is at least `ONE`: from `lo` on (`257`: nowhere).
    let (mut lo, mut end) = (0u32, 257u32);
    while lo < end {
        let mid = (lo + end) / 2;
        match channels.iter().all(|&[a, k]| a + k * mid >= ONE) {
            true => end = mid,
            false => lo = mid + 1,
        }
    }
    // Where it is at most `TOP`: below `hi` (`0`: nowhere).
    let (mut start, mut hi) = (0u32, 257u32);
    while start < hi {
        let mid = (start + hi) / 2;
        match channels.iter().all(|&[a, k]| a + k * mid <= TOP) {
            true => start = mid + 1,
            false => hi = mid,
        }
    }
    match gouraud && lo < hi {
        true => [lo, hi - 1 - lo],
        // n·l is at most 256: `n·l - 257` wraps above 0.
        false => [257, 0],
    }
}

/// Whether n·l `ndotl` is in the interval `[lo, span]` of
/// [`Lambert::interior_ndotl`].
#[inline(always)]
pub(super) fn within(ndotl: u32, [lo, span]: [u32; 2]) -> bool {
    ndotl.wrapping_sub(lo) <= span
}

/// `floor(x / 65,280)`, at most 255, for `x < 2^31` (the Lambert colour's
/// `x` is below 2^26): the quotient by the multiply-high LLVM makes of it
/// (`floor(x 0x8080_8081 / 2^47)`, exact for every `u32`), its upper word
/// taken as signed (below 2^31 for such `x`, so the shift is the same) so
/// that the clamp to `0..=255` is one `USAT` on ARMv7-M, where the
/// unsigned minimum took a compare, an `IT` and a conditional shift a
/// channel.
#[inline(always)]
pub(super) fn div65280_sat(x: u32) -> u8 {
    div65280_sat_by(x, DIV65280)
}

/// [`div65280_sat`]'s multiplier: `floor(x / 65,280) = floor(x
/// 0x8080_8081 / 2^47)`.
const DIV65280: u32 = 0x8080_8081;

/// [`div65280_sat`] with its multiplier `magic` ([`DIV65280`]) passed in,
/// for the common loop, which reads it from its constants.
#[inline(always)]
pub(super) fn div65280_sat_by(x: u32, magic: u32) -> u8 {
    debug_assert!(x < 1 << 31 && magic == DIV65280);
    let high = ((x as u64 * magic as u64) >> 32) as u32 as i32;
    (high >> 15).clamp(0, 255) as u8
}

/// The Lambert fast path's n·l, `(n·l >> 24).clamp(0, 256)`, in 32-bit
/// products, when every `|n[i]| <= 2^16` and `|l[i]| <= 2^20`; `None`
/// otherwise. With `n[i] = h[i] 2^8 + o[i]` (`|h[i]| <= 2^8`, `0 <= o[i] <
/// 2^8`), `n·l = 2^8 A + B` for `A = Σ h[i] l[i]` and `B = Σ o[i] l[i]`,
/// each below `3 2^28` in magnitude; so `floor(n·l / 2^8) = A + floor(B /
/// 2^8)` fits `i32`, and shifting it by 16 more floors `n·l / 2^24`.
#[inline(always)]
pub(super) fn ndotl_narrow(n: [i32; 3], l: [i32; 3]) -> Option<u32> {
    let within = |v: i32, m: u32| v.unsigned_abs() <= m;
    if !(n.iter().all(|&v| within(v, 1 << 16)) && l.iter().all(|&v| within(v, 1 << 20))) {
        return None;
    }
    let (mut a, mut b) = (0i32, 0i32);
    for i in 0..3 {
        a += (n[i] >> 8) * l[i];
        b += (n[i] & 0xff) * l[i];
    }
    Some(((a + (b >> 8)) >> 16).clamp(0, 256) as u32)
}

/// The n·l of [`ndotl_narrow`]'s sums, unchecked, for ARMv6-M's common
/// loop ([`NarrowRows`]), which checks the light once per draw
/// ([`SPLIT_LIGHT`]) and the normal by one compare ([`split_normal`]):
/// for `-2^17 <= n[i] < 2^17` and the light `l` split once per draw
/// ([`split_light`]: `l[i] = h[i] 2^8 + o[i]`, `0 <= o[i] < 2^8`) from
/// `|l[i]| <= 2^18`, so that the normal is not split per vertex (six
/// instructions a vertex fewer). Then `|h[i]| <= 2^10`, each `|n[i]
/// h[i]| <= 2^27` and `A = Σ n[i] h[i]` within `3 2^27`; `|n[i] o[i]| <
/// 2^25`, `B = Σ n[i] o[i]` within `3 2^25`; so every sum fits `i32`,
/// `n·l = 2^8 A + B`, and `floor(n·l / 2^24) = floor((A + floor(B /
/// 2^8)) / 2^16)`: `ndotl_narrow`'s result.
#[inline(always)]
fn ndotl_split(n: [i32; 3], [h, o]: &[[i32; 3]; 2]) -> u32 {
    debug_assert!(split_normal(n));
    let (mut a, mut b) = (0i32, 0i32);
    for i in 0..3 {
        a += n[i] * h[i];
        b += n[i] * o[i];
    }
    ((a + (b >> 8)) >> 16).clamp(0, 256) as u32
}

/// [`ndotl_split`]'s light: each component of `l` (within
/// [`SPLIT_LIGHT`]) as `h 2^8 + o`, `0 <= o < 2^8`, the `h` first.
fn split_light(l: [i32; 3]) -> [[i32; 3]; 2] {
    debug_assert!(l.iter().all(|&v| v.unsigned_abs() <= SPLIT_LIGHT));
    [l.map(|v| v >> 8), l.map(|v| v & 0xff)]
}

/// The largest light component [`ndotl_split`] takes (checked once per
/// draw by [`NarrowRows::takes`]).
const SPLIT_LIGHT: u32 = 1 << 18;

/// Whether every `n[i]` is in `-2^17..2^17` ([`ndotl_split`]'s normals):
/// each `n[i] + 2^17` below `2^18` as a word, so all three are when
/// their `or` is (two instructions a component on ARMv6-M, where
/// `ndotl_narrow`'s test of the normal and of the light took about 27 a
/// vertex).
#[inline(always)]
fn split_normal(n: [i32; 3]) -> bool {
    split_bits(n) >> 18 == 0
}

/// The `or` of [`split_normal`]'s three offset components.
#[inline(always)]
fn split_bits(n: [i32; 3]) -> u32 {
    let k = 1i32 << 17;
    (n[0].wrapping_add(k) | n[1].wrapping_add(k) | n[2].wrapping_add(k)) as u32
}

/// Whether the vertex stage's common loop reads its per-draw constants
/// from a [`LoopConstants`]: on 32-bit cores with a 32 x 32 -> 64-bit
/// multiply (the Cortex-M3 and M4, RISC-V `rv32im`).
pub(super) const LOOP_CONSTANTS: bool = cfg!(all(
    target_pointer_width = "32",
    not(microraster_narrow_multiply)
));

/// The per-vertex work of the vertex stage's common lit loop: a
/// position's clip coordinates and a normal's Lambert colour, from
/// constants made once per draw. One implementation per way of computing
/// them: [`LoopConstants`] on 32-bit cores with a long multiply,
/// [`NarrowRows`] with its light on ARMv6-M, the bounded matrix with its
/// light and colour on 64-bit hosts; and [`ColorTable`] over any of them.
pub(super) trait LitWork {
    /// The clip coordinates of the position `p` (16.16 bits).
    fn transform(&self, p: [i32; 3]) -> [i32; 4];
    /// [`transform`](Self::transform) as 64-bit words, each within `i32`
    /// (x86-64's loop, see `FixedMat4::transform_point_bounded_wide`).
    #[inline(always)]
    fn transform_wide(&self, p: [i32; 3]) -> [i64; 4] {
        self.transform(p).map(i64::from)
    }
    /// n·l of the normal `n` in 1/256 steps, clamped to `0..=256`
    /// ([`Lambert::ndotl`]'s).
    fn ndotl(&self, n: Vec3Fx) -> u32;
    /// The Lambert colour for n·l `ndotl` (`0..=256`) as a
    /// [`color_word`], with the colour's half
    /// of the interior bit: n·l within the draw's
    /// [`interior_ndotl`](Lambert::interior_ndotl).
    fn word(&self, ndotl: u32) -> u32;
    /// [`word`](Self::word) of the normal `n`'s n·l.
    #[inline(always)]
    fn shade(&self, n: Vec3Fx) -> u32 {
        self.word(self.ndotl(n))
    }
}

impl LitWork for (&NarrowRows, &Lambert) {
    #[inline(always)]
    fn transform(&self, p: [i32; 3]) -> [i32; 4] {
        self.0.transform(p)
    }

    #[inline(always)]
    fn ndotl(&self, n: Vec3Fx) -> u32 {
        self.0.ndotl(self.1, n)
    }

    #[inline(always)]
    fn word(&self, ndotl: u32) -> u32 {
        self.0.word(ndotl)
    }
}

impl LitWork for (&FixedMat4, &Lambert, [u8; 3], [u32; 2]) {
    #[inline(always)]
    fn transform(&self, p: [i32; 3]) -> [i32; 4] {
        self.0.transform_point_bounded(p)
    }

    #[inline(always)]
    fn transform_wide(&self, p: [i32; 3]) -> [i64; 4] {
        self.0.transform_point_bounded_wide(p)
    }

    #[inline(always)]
    fn ndotl(&self, n: Vec3Fx) -> u32 {
        self.1.ndotl(n)
    }

    #[inline(always)]
    fn word(&self, ndotl: u32) -> u32 {
        let color = self.1.shade_ndotl(ndotl, self.2);
        color_word(color, within(ndotl, self.3))
    }
}

/// A draw's Lambert colour words ([`LitWork::word`]) for every n·l,
/// `0..=256`, made once per run of vertices, over the loop's own
/// [`LitWork`] `k` (whose transform and n·l it keeps): per vertex the
/// colour is then one load by n·l, where it took three channels'
/// multiply-adds and quotients by 65,280, their packing and the interval
/// test of the interior bit. Only for runs of at least [`TABLE_MIN`]
/// vertices, which pay for the table's 257 words; 1,028 bytes of stack,
/// within the vertex stage's draw set-up's depth.
pub(super) struct ColorTable<'k, K> {
    k: &'k K,
    words: &'k [u32; 257],
}

impl<'k, K: LitWork> ColorTable<'k, K> {
    /// The table of `k`'s colours, written into the caller's `words`
    /// (built and returned by value, the table took a second copy of
    /// itself on the stack, ARMv6-M's frame 2.4 KB).
    #[inline(always)]
    pub(super) fn new(k: &'k K, words: &'k mut [u32; 257]) -> Self {
        for (n, w) in words.iter_mut().enumerate() {
            *w = k.word(n as u32);
        }
        Self { k, words }
    }
}

impl<K: LitWork> LitWork for ColorTable<'_, K> {
    #[inline(always)]
    fn transform(&self, p: [i32; 3]) -> [i32; 4] {
        self.k.transform(p)
    }

    #[inline(always)]
    fn transform_wide(&self, p: [i32; 3]) -> [i64; 4] {
        self.k.transform_wide(p)
    }

    #[inline(always)]
    fn ndotl(&self, n: Vec3Fx) -> u32 {
        self.k.ndotl(n)
    }

    #[inline(always)]
    fn word(&self, ndotl: u32) -> u32 {
        // n·l is at most 256 (the compiler sees the clamp: no check).
        self.words[ndotl as usize]
    }
}

/// The shortest run of vertices that a [`ColorTable`] is made for: its
/// 257 words cost about as much as the colours of 257 vertices and a
/// little more (each a store besides).
pub(super) const TABLE_MIN: usize = 320;

/// The per-draw constants of the vertex stage's common loop (a bounded
/// matrix, the Lambert fast path, no vertex colours), laid out in the
/// order the loop reads them and read through a reference the compiler
/// cannot see into (`black_box`). The loop has more constants (28) than
/// a Cortex-M3 has registers: held as values, the allocator spilled them
/// to slots of their own and reloaded each with one `LDR` a vertex; read
/// from here, neighbours load together (`LDRD`), the translation's two
/// words straight into a row's accumulator, and the Lambert colour's
/// constants are folded per draw (two per channel where there were
/// three and a multiply more).
#[derive(Clone, Copy, Debug)]
#[cfg_attr(not(any(test, target_pointer_width = "32")), allow(dead_code))]
pub(super) struct LoopConstants {
    /// Per row `r` of the matrix: the low and high words of `m[3][r] 2^16 +
    /// 2^15` (translation and rounding, as in
    /// [`FixedMat4::transform_point_bounded`]), then `m[0][r]`, `m[1][r]`
    /// and `m[2][r]`.
    rows: [[i32; 5]; 4],
    /// The light's direction (as [`Lambert`]'s).
    dir: [i32; 3],
    /// The Lambert colour's factors per channel ([`Lambert::folded`]).
    channels: [[u32; 2]; 3],
    /// [`div65280_sat`]'s multiplier, loaded with the channels' factors
    /// (as a literal the Cortex-M3 rebuilt it, two instructions a vertex).
    magic: u32,
    /// The n·l that may carry the interior bit
    /// ([`Lambert::interior_ndotl`]); none where no vertex carries it
    /// ([`INSIDE`]).
    inside: [[u32; 2]; INSIDE],
}

#[cfg_attr(not(any(test, target_pointer_width = "32")), allow(dead_code))]
impl LoopConstants {
    /// The constants of a draw with matrix `m`, light `l` and colour
    /// `base`, Gouraud shaded or not (`gouraud`: whether its vertices
    /// carry the interior bit).
    pub(super) fn new(m: &FixedMat4, l: &Lambert, base: [u8; 3], gouraud: bool) -> Self {
        // Loops rather than `map`s, here and below: the size profile
        // (the OLED firmware's) keeps a `map` as a loop through a
        // temporary array and a `memcpy`.
        let mut k = Self {
            rows: [[0; 5]; 4],
            dir: l.dir,
            channels: [[0; 2]; 3],
            magic: DIV65280,
            inside: [[0; 2]; INSIDE],
        };
        for (r, row) in k.rows.iter_mut().enumerate() {
            let t = (m.m[3][r] as i64) << 16 | 1 << 15;
            *row = [t as i32, (t >> 32) as i32, m.m[0][r], m.m[1][r], m.m[2][r]];
        }
        k.channels = l.folded(base);
        for b in k.inside.iter_mut() {
            *b = interior_ndotl(&k.channels, gouraud);
        }
        k
    }
}

#[cfg_attr(not(any(test, target_pointer_width = "32")), allow(dead_code))]
impl LitWork for LoopConstants {
    /// [`FixedMat4::transform_point_bounded`] of `p`: the same sums.
    #[inline(always)]
    fn transform(&self, p: [i32; 3]) -> [i32; 4] {
        use crate::math::mul_wide;
        let mut out = [0i32; 4];
        for (o, k) in out.iter_mut().zip(&self.rows) {
            let acc = ((k[1] as i64) << 32 | k[0] as u32 as i64)
                .wrapping_add(mul_wide(k[2], p[0]))
                .wrapping_add(mul_wide(k[3], p[1]))
                .wrapping_add(mul_wide(k[4], p[2]));
            *o = (acc >> 16) as i32;
        }
        out
    }

    /// [`Lambert::ndotl`] of normal `n`: the same n·l.
    #[inline(always)]
    fn ndotl(&self, n: Vec3Fx) -> u32 {
        use crate::math::mul_wide;
        let d = mul_wide(n[0].to_bits(), self.dir[0])
            + mul_wide(n[1].to_bits(), self.dir[1])
            + mul_wide(n[2].to_bits(), self.dir[2]);
        clamp_ndotl_words(d)
    }

    /// [`Lambert::shade_ndotl`] of `ndotl` on the draw's colour: the same
    /// colour.
    #[inline(always)]
    fn word(&self, ndotl: u32) -> u32 {
        let mut out = [0u8; 3];
        for (o, &[a, c]) in out.iter_mut().zip(&self.channels) {
            *o = div65280_sat_by(a + c * ndotl, self.magic);
        }
        color_word(out, within_any(ndotl, &self.inside))
    }
}

/// How many n·l intervals of the interior bit a loop's constants hold:
/// one where vertices carry the bit ([`INTERIOR_STARTS`](super::screen::INTERIOR_STARTS)), none
/// elsewhere. (An interval held and never read moved the Cortex-M4F's
/// loop constants and its register allocation: `demo` 8,000
/// instructions more.)
const INSIDE: usize = super::screen::INTERIOR_STARTS as usize;

/// [`within`] the interval of `inside`, if any (without one, never).
#[inline(always)]
fn within_any(ndotl: u32, inside: &[[u32; 2]; INSIDE]) -> bool {
    inside.first().is_some_and(|&b| within(ndotl, b))
}

/// The rows of a [`narrow`](FixedMat4::narrow) matrix for ARMv6-M's
/// common vertex loop, its elements split rather than the point:
/// `FixedMat4::transform_point_narrow` (now the tests' reference) split each coordinate `p[i] =
/// a[i] 2^8 + b[i]` per vertex (six values besides the point, more than
/// Thumb-1's eight low registers held with the matrix: spilled, and each
/// element copied before its `MULS`). Here each element `m = h 2^8 + l`
/// (`0 <= l < 2^8`, `|h| <= 2^8` for `|m| <= 2^16`) is split once per
/// draw, and a row's `Σ m[i] p[i] = 2^8 H + L` for `H = Σ h[i] p[i]` and
/// `L = Σ l[i] p[i]`: with `|p[i]| <= 2^21` each product is below `2^29`
/// in magnitude and each sum below `3 2^29`, exact in `i32`; then the
/// rounding is `transform_point_narrow`'s, `floor((H + floor((L + 2^15) /
/// 2^8)) / 2^8)`, and the same result. Read through an opaque reference
/// (as [`LoopConstants`]), each element is loaded into the register its
/// `MULS` overwrites.
#[derive(Clone, Copy, Debug)]
#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
pub(super) struct NarrowRows {
    /// Per row `r`: `h` of `m[0][r]`, `m[1][r]`, `m[2][r]`, then their
    /// `l`, then the translation and the rounding, `m[3][r] 2^8 + 2^7`
    /// (see [`transform`](Self::transform)).
    rows: [[i32; 7]; 4],
    /// The Lambert colour's factors per channel ([`Lambert::folded`]: one
    /// `MULS` a channel fewer), each `a` with 256 more for
    /// [`div65280_narrow`].
    channels: [[u32; 2]; 3],
    /// The n·l that may carry the interior bit
    /// ([`Lambert::interior_ndotl`]).
    inside: [u32; 2],
    /// The light's direction (as [`Lambert`]'s) split for
    /// [`ndotl_split`] ([`split_light`]): the normal is then not split
    /// per vertex (ARMv6-M `demo` vertex stage 771,577 -> 759,519).
    dir: [[i32; 3]; 2],
}

#[cfg_attr(not(any(test, microraster_narrow_multiply)), allow(dead_code))]
impl NarrowRows {
    /// The rows of `m` ([`fits`](Self::fits)) and the colour constants of
    /// light `l` ([`takes`](Self::takes)) on `base`, for a draw Gouraud
    /// shaded or not (`gouraud`, as
    /// [`LoopConstants::new`]).
    pub(super) fn new(m: &FixedMat4, l: &Lambert, base: [u8; 3], gouraud: bool) -> Self {
        debug_assert!(Self::takes(l));
        let mut k = Self {
            rows: [[0; 7]; 4],
            channels: [[0; 2]; 3],
            inside: [0; 2],
            dir: split_light(l.dir),
        };
        k.channels = l.folded(base);
        k.inside = match super::screen::INTERIOR_STARTS {
            true => interior_ndotl(&k.channels, gouraud),
            false => [257, 0],
        };
        for ch in k.channels.iter_mut() {
            ch[0] += 256;
        }
        for (r, row) in k.rows.iter_mut().enumerate() {
            let e = [m.m[0][r], m.m[1][r], m.m[2][r]];
            *row = [
                e[0] >> 8,
                e[1] >> 8,
                e[2] >> 8,
                e[0] & 0xff,
                e[1] & 0xff,
                e[2] & 0xff,
                m.m[3][r] << 8 | 128,
            ];
        }
        k
    }

    /// Whether the light `l` is within [`SPLIT_LIGHT`], as the rows'
    /// n·l takes it ([`ndotl_split`]): a draw whose light is not (longer
    /// than 4 in the draw's model space, a model matrix that shrinks the
    /// mesh fourfold or more) takes the general loop. Tested once a draw,
    /// where a word or-ed into each normal's test (which sent every vertex
    /// of such a draw to the 64-bit n·l) took two instructions a vertex:
    /// ARMv6-M `demo` vertex stage 749,487 -> 747,437.
    pub(super) fn takes(l: &Lambert) -> bool {
        l.dir.iter().all(|&v| v.unsigned_abs() <= SPLIT_LIGHT)
    }

    /// Whether `m`'s translation is small enough for the rows'
    /// [`transform`](Self::transform), `|m[3][r]| <= 2^20` (every
    /// normalized matrix's: its elements are at most `2^16`), besides
    /// [`FixedMat4::narrow`].
    pub(super) fn fits(m: &FixedMat4) -> bool {
        m.m[3].iter().all(|v| v.unsigned_abs() <= 1 << 20)
    }

    /// `FixedMat4::transform_point_narrow` of `p`, for the matrix this
    /// was made of ([`fits`](Self::fits)) and a point within its narrow
    /// extent: the same point.
    ///
    /// `(l + 2^15) >> 8` is `(l >> 8) + 2^7` (2^15 a multiple of 2^8),
    /// and the translation `t`, added after the last shift, is `t 2^8`
    /// before it: so both are one constant per row, `t 2^8 + 2^7`, added
    /// to `h` (one instruction a row fewer: ARMv6-M `demo` vertex stage
    /// 759,519 -> 751,511). With `|h| <= 3 2^29`,
    /// `|l >> 8| <= 3 2^21` and `|t| <= 2^20` the sum stays below `2^31`
    /// in magnitude.
    #[inline(always)]
    pub(super) fn transform(&self, p: [i32; 3]) -> [i32; 4] {
        let mut out = [0i32; 4];
        for (o, k) in out.iter_mut().zip(&self.rows) {
            let h = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
            let l = k[3] * p[0] + k[4] * p[1] + k[5] * p[2];
            *o = (h + k[6] + (l >> 8)) >> 8;
        }
        out
    }

    /// [`Lambert::ndotl`] of normal `n`, `l` the light this was made
    /// with: the same n·l.
    #[inline(always)]
    pub(super) fn ndotl(&self, l: &Lambert, n: Vec3Fx) -> u32 {
        let n = [n[0].to_bits(), n[1].to_bits(), n[2].to_bits()];
        match split_normal(n) {
            true => ndotl_split(n, &self.dir),
            false => l.ndotl_wide(n),
        }
    }

    /// [`Lambert::shade_ndotl`] of `ndotl` on the draw's colour: the same
    /// colour, as a [`color_word`] with the colour's half of the interior
    /// bit.
    #[inline(always)]
    pub(super) fn word(&self, ndotl: u32) -> u32 {
        let mut out = [0u8; 3];
        for (o, &[a, c]) in out.iter_mut().zip(&self.channels) {
            // Lambert::shade's division on cores without a multiply-high.
            *o = div65280_narrow(a + c * ndotl);
        }
        color_word(out, within(ndotl, self.inside))
    }
}

/// `min(floor((x - 256) / 65,280), 255)` for `256 <= x < 2^32`, by one
/// 32-bit multiply, for ARMv6-M's loop (whose channel constants hold the
/// 256: [`NarrowRows`]): with `y = floor((x - 256) / 256)`, `x >> 8` is
/// `y + 1`, and `z = min(y + 1, 65,280)` gives `floor((z - 1) / 255) = min(
/// floor(y / 255), 255) = min(floor((x - 256) / 65,280), 255)`, which is
/// `(z 257) >> 16` for every `z` in `1..=65,280` (the tests try them
/// all; the product is below `2^24`). `div255` and its clamp took about
/// 19 instructions a channel.
#[inline(always)]
fn div65280_narrow(x: u32) -> u8 {
    debug_assert!(x >= 256);
    let z = (x >> 8).min(65_280);
    ((z * 257) >> 16) as u8
}

/// `(d >> 24).clamp(0, 256)` from `d`'s upper word, which is 0 exactly
/// when `d >> 24` is 0 to 255: the Lambert fast path's n·l on 32-bit cores.
#[inline(always)]
pub(super) fn clamp_ndotl_words(d: i64) -> u32 {
    match (d >> 32) as i32 {
        0 => d as u32 >> 24,
        1.. => 256,
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::{LightSetup, Material};
    use crate::math::{Mat4, Vec3};
    use crate::vertex::MAX_LIGHTS;

    /// n·l's clamp from the upper word is the 64-bit clamp.
    #[test]
    fn ndotl_from_words_is_the_clamp() {
        let mut next = crate::testing::rng();
        let check =
            |d: i64| assert_eq!(clamp_ndotl_words(d), (d >> 24).clamp(0, 256) as u32, "{d}");
        for b in 0..64 {
            let p = 1i64 << b;
            for d in [p, p.wrapping_sub(1), p.wrapping_neg(), p.wrapping_neg() + 1] {
                check(d);
            }
        }
        for d in [
            0,
            -1,
            i64::MIN,
            i64::MAX,
            (256 << 24) - 1,
            256 << 24,
            255 << 24,
        ] {
            check(d);
        }
        for _ in 0..100_000 {
            check(((next(1 << 32) << 32 | next(1 << 32)) as i64) >> next(64));
        }
    }

    /// The saturated quotient by 65,280 of the Lambert colour is the
    /// division's, for every `x` below 2^31 (every 127th value, the ends
    /// of each quotient's range, and the top of the range).
    #[test]
    fn div65280_sat_is_the_clamped_quotient() {
        let check = |x: u32| assert_eq!(div65280_sat(x), (x / 65_280).min(255) as u8, "{x}");
        for x in (0..1u32 << 31).step_by(127) {
            check(x);
        }
        for q in 1..32_896u32 {
            check(q * 65_280);
            check(q * 65_280 - 1);
        }
        for x in (1 << 31) - 1_000..1 << 31 {
            check(x);
        }
    }

    /// ARMv6-M's quotient by 65,280 is the clamped division: every `z`
    /// of its proof, and `x` across the colour's range with every
    /// quotient's ends.
    #[test]
    fn div65280_narrow_is_the_clamped_quotient() {
        for z in 1..=65_280u32 {
            assert_eq!((z * 257) >> 16, (z - 1) / 255, "{z}");
        }
        let check = |x0: u32| {
            let want = (x0 / 65_280).min(255) as u8;
            assert_eq!(div65280_narrow(x0 + 256), want, "{x0}");
        };
        for x0 in (0..1u32 << 26).step_by(61) {
            check(x0);
        }
        for q in 1..1_030u32 {
            check(q * 65_280);
            check(q * 65_280 - 1);
        }
        check(u32::MAX - 256);
    }

    /// The narrow n·l is the 64-bit one wherever it is taken: random and
    /// extreme normals and light directions within its bounds, and just
    /// beyond them (where it declines).
    #[test]
    fn narrow_ndotl_is_the_wide_one() {
        let mut next = crate::testing::rng();
        let wide = |n: [i32; 3], l: [i32; 3]| {
            let d: i64 = (0..3).map(|i| n[i] as i64 * l[i] as i64).sum();
            (d >> 24).clamp(0, 256) as u32
        };
        let ends = [
            -(1 << 16) - 1,
            -(1 << 16),
            -(1 << 16) + 1,
            -256,
            -255,
            -1,
            0,
            1,
            255,
            256,
            (1 << 16) - 1,
            1 << 16,
            (1 << 16) + 1,
        ];
        let lends = [
            -(1 << 20) - 1,
            -(1 << 20),
            -(1 << 16),
            -1,
            0,
            1,
            1 << 16,
            1 << 20,
            (1 << 20) + 1,
        ];
        for &a in &ends {
            for &b in &ends {
                for &c in &ends {
                    for &l in &lends {
                        for l in [[l, l, l], [l, -l, l], [-l, l, 1 << 16]] {
                            let n = [a, b, c];
                            let inside = n.iter().all(|v: &i32| v.unsigned_abs() <= 1 << 16)
                                && l.iter().all(|v: &i32| v.unsigned_abs() <= 1 << 20);
                            assert_eq!(
                                ndotl_narrow(n, l),
                                inside.then(|| wide(n, l)),
                                "{n:?} {l:?}"
                            );
                        }
                    }
                }
            }
        }
        for _ in 0..1_000_000 {
            let mut r = |m: u64| (next(2 * m + 1) as i64 - m as i64) as i32;
            let n = [r(1 << 16), r(1 << 16), r(1 << 16)];
            let l = [r(1 << 20), r(1 << 20), r(1 << 20)];
            assert_eq!(ndotl_narrow(n, l), Some(wide(n, l)), "{n:?} {l:?}");
        }
    }

    /// The split n·l of ARMv6-M's loop is the 64-bit one over its whole
    /// range: the ends of the normal's and the light's, and random ones;
    /// a light beyond its range is not taken (`NarrowRows::takes`).
    #[test]
    fn split_ndotl_is_the_wide_one() {
        let mut next = crate::testing::rng();
        let wide = |n: [i32; 3], l: [i32; 3]| {
            let d: i64 = (0..3).map(|i| n[i] as i64 * l[i] as i64).sum();
            (d >> 24).clamp(0, 256) as u32
        };
        let ends = [
            -(1 << 17),
            -(1 << 17) + 1,
            -257,
            -256,
            -1,
            0,
            1,
            255,
            256,
            (1 << 17) - 1,
        ];
        let lends = [
            -(1 << 18),
            -(1 << 18) + 1,
            -1,
            0,
            1,
            1 << 16,
            (1 << 18) - 1,
            1 << 18,
        ];
        for &a in &ends {
            for &b in &ends {
                for &c in &ends {
                    for &l in &lends {
                        for l in [[l, l, l], [l, -l, l], [-l, l, 1 << 18]] {
                            let n = [a, b, c];
                            assert!(split_normal(n));
                            let s = split_light(l);
                            assert_eq!(ndotl_split(n, &s), wide(n, l), "{n:?} {l:?}");
                        }
                    }
                }
            }
        }
        for bad in [1 << 17, -(1 << 17) - 1, i32::MIN, i32::MAX] {
            for i in 0..3 {
                let mut n = [0; 3];
                n[i] = bad;
                assert!(!split_normal(n), "{n:?}");
            }
        }
        for _ in 0..1_000_000 {
            let mut r = |m: u64| (next(2 * m) as i64 - m as i64) as i32;
            let n = [r(1 << 17), r(1 << 17), r(1 << 17)];
            let l = [r(1 << 18), r(1 << 18), r(1 << 18)];
            assert_eq!(ndotl_split(n, &split_light(l)), wide(n, l), "{n:?} {l:?}");
        }
        for (dir, takes) in [
            ([(1 << 18) + 1, 0, 0], false),
            ([0, -(1 << 18) - 1, 0], false),
            ([1 << 18, 1 << 18, -(1 << 18)], true),
        ] {
            let l = Lambert {
                dir,
                color: [255; 3],
                ambient: [0; 3],
            };
            assert_eq!(NarrowRows::takes(&l), takes, "{dir:?}");
        }
    }

    /// The fast path of one directional light gives the general
    /// lighting's colours, for any normal, colour and light.
    #[test]
    fn lambert_fast_path_matches_the_light_setup() {
        use crate::light::{DirectionalLight, Lighting};
        use embedded_graphics::pixelcolor::Rgb888;
        let mut next = crate::testing::rng();
        for _ in 0..200 {
            let mut f = || next(2001) as f32 / 1000.0 - 1.0;
            let dir = Vec3::new(f(), f(), f() + 0.01);
            let model = Mat4::rotation_y(f() * 3.0) * Mat4::rotation_x(f() * 3.0);
            let mut c = || Rgb888::new(next(256) as u8, next(256) as u8, next(256) as u8);
            let one = [DirectionalLight::new(dir, c())];
            let lighting = Lighting::new(c()).directional(&one);
            let setup: LightSetup<MAX_LIGHTS> =
                LightSetup::new(&lighting, &model, Vec3::new(0.0, 0.0, 5.0)).unwrap();
            let (dir, color, ambient) = setup.single_directional().unwrap();
            let fast = Lambert {
                dir,
                color: color.map(u32::from),
                ambient: ambient.map(u32::from),
            };
            for _ in 0..500 {
                let n = [0; 3]
                    .map(|_| fixed::types::I16F16::from_bits(next(1 << 18) as i32 - (1 << 17)));
                let base = [next(256) as u8, next(256) as u8, next(256) as u8];
                let general = setup.shade(&Material::new(), base, [0; 3], n.map(|v| v.to_bits()));
                assert_eq!(fast.shade(n, base), general, "{n:?} {base:?}");
                let inside = crate::vertex::screen::channels_interior(general);
                let zero = FixedMat4 { m: [[0; 4]; 4] };
                for gouraud in [false, true] {
                    let want = color_word(general, gouraud && inside);
                    let k = LoopConstants::new(&zero, &fast, base, gouraud);
                    assert_eq!(k.shade(n), want, "{n:?} {base:?}");
                    let k = NarrowRows::new(&zero, &fast, base, gouraud);
                    assert_eq!((&k, &fast).shade(n), want, "{n:?} {base:?}");
                    let b = fast.interior_ndotl(base, gouraud);
                    let k = (&zero, &fast, base, b);
                    assert_eq!(k.shade(n), want, "{n:?} {base:?}");
                    let mut words = [0; 257];
                    let t = ColorTable::new(&k, &mut words);
                    assert_eq!(t.shade(n), want, "{n:?} {base:?}");
                }
            }
        }
    }

    /// The n·l interval of the interior bit holds exactly the n·l whose
    /// colour has every channel in `1..=254`: every n·l, for random
    /// lights and colours and their extremes.
    #[test]
    fn interior_ndotl_is_exact() {
        let mut next = crate::testing::rng();
        let ends = [0u8, 1, 2, 127, 128, 253, 254, 255];
        for i in 0..20_000 {
            let mut c = |j: u64| match (i + j) % 3 {
                0 => ends[next(ends.len() as u64) as usize],
                _ => next(256) as u8,
            };
            let l = Lambert {
                dir: [0; 3],
                color: [c(0), c(1), c(2)].map(u32::from),
                ambient: [c(3), c(4), c(5)].map(u32::from),
            };
            let base = [c(6), c(7), c(8)];
            for gouraud in [false, true] {
                let b = l.interior_ndotl(base, gouraud);
                for n in 0..=256 {
                    let inside = crate::vertex::screen::channels_interior(l.shade_ndotl(n, base));
                    assert_eq!(within(n, b), gouraud && inside, "{l:?} {base:?} {n}");
                }
            }
        }
    }

    /// A light that adds nothing, for the transform tests.
    const NO_LIGHT: Lambert = Lambert {
        dir: [0; 3],
        color: [0; 3],
        ambient: [0; 3],
    };

    /// The common loop's rows are the bounded transform: random matrices
    /// of every magnitude (the translation up to the `i32` extremes), and
    /// points within an extent they are bounded for.
    #[test]
    fn loop_constants_transform_as_the_bounded_matrix() {
        let mut next = crate::testing::rng();
        let mut taken = 0;
        let none = NO_LIGHT;
        for _ in 0..50_000 {
            let span = (1i64 << next(32)) - 1;
            let mut e = || (next(2 * span as u64 + 1) as i64 - span) as i32;
            let m = FixedMat4 {
                m: [[0; 4]; 4].map(|c| c.map(|_| e())),
            };
            let extent = 1u32 << next(23);
            if !m.bounded(extent) {
                continue;
            }
            taken += 1;
            let k = LoopConstants::new(&m, &none, [0; 3], true);
            for _ in 0..20 {
                let ext = extent as i64;
                let p = [0; 3].map(|_| (next(2 * ext as u64 + 1) as i64 - ext) as i32);
                assert_eq!(k.transform(p), m.transform_point_bounded(p), "{m:?} {p:?}");
                // x86-64's 64-bit words (`transform_point_bounded_wide`).
                let wide = m.transform_point_bounded(p).map(i64::from);
                assert_eq!(m.transform_point_bounded_wide(p), wide, "{m:?} {p:?}");
            }
        }
        assert!(taken > 5_000, "{taken}");
    }

    /// ARMv6-M's split rows are the narrow transform, hence the bounded
    /// one: random narrow matrices (elements up to `±2^16`, translations
    /// of any size) and points up to the narrow extent `2^21`, the
    /// extremes included.
    #[test]
    fn narrow_rows_transform_as_the_bounded_matrix() {
        let mut next = crate::testing::rng();
        let mut taken = 0;
        let none = NO_LIGHT;
        for i in 0..50_000 {
            let mut e = |span: i64| (next(2 * span as u64 + 1) as i64 - span) as i32;
            let mut m = FixedMat4 { m: [[0; 4]; 4] };
            for c in 0..4 {
                for r in 0..4 {
                    m.m[c][r] = match (c, i % 7) {
                        (3, _) => e((1 << (i % 31)) - 1),
                        (_, 0) => [-(1 << 16), 1 << 16][(r + c) % 2],
                        _ => e(1 << 16),
                    };
                }
            }
            let extent = 1u32 << (i % 22);
            if !(m.bounded(extent) && m.narrow(extent) && NarrowRows::fits(&m)) {
                continue;
            }
            taken += 1;
            let k = NarrowRows::new(&m, &none, [0; 3], true);
            let ext = extent as i64;
            for j in 0..20 {
                let mut c = || match (j + i) % 5 {
                    0 => extent as i32,
                    1 => -(extent as i32),
                    _ => (next(2 * ext as u64 + 1) as i64 - ext) as i32,
                };
                let p = [c(), c(), c()];
                assert_eq!(k.transform(p), m.transform_point_bounded(p), "{m:?} {p:?}");
                assert_eq!(k.transform(p), m.transform_point_narrow(p), "{m:?} {p:?}");
            }
        }
        assert!(taken > 5_000, "{taken}");
    }
}
