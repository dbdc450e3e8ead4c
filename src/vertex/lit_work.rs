//! The per-draw work of the vertex stage's common lit loop (a bounded
//! matrix, the Lambert fast path on the mesh's normals, no vertex
//! colours; `DrawSetup::screen_vertices`): what the loop computes per
//! vertex ([`LitWork`]: the clip coordinates and the Lambert colour word)
//! from constants made once per draw, one implementation per kind of
//! core. On 32-bit cores with a long multiply [`LoopConstants`] (the
//! matrix's rows with their translation and rounding, the light, the
//! colour folded per channel), on ARMv6-M [`NarrowRows`] (the matrix's
//! elements and the light split into 8-bit halves, for 32-bit products
//! only), on 64-bit hosts the bounded matrix and the [`Lambert`] light
//! themselves; each read through an opaque reference, so that the loop
//! loads each constant where it uses it rather than spilling them all.
//!
//! Over any of them a [`ColorTable`]: a draw's Lambert colour depends on
//! the vertex through n·l alone, which is an integer in `0..=256`, so the
//! draw's 257 colour words (three channels' multiply-adds and quotients by
//! 65,280, their packing and the interior bit's interval test) can be made
//! once and looked up per vertex by n·l. The table pays from about as
//! many vertices as it has words: it is made for runs of at least
//! [`TABLE_MIN`] vertices (not in size builds, where it would be a second
//! copy of the loop). It costs 1,028 bytes of stack (2,048 on ARMv7-M,
//! indexed by n·l saturated to 9 bits: `SAT_INDEX`) in the draw's
//! frame, which on ARMv6-M lies on the 48 KiB frame's deepest path (the
//! vertex stage): the table is written into the caller's array, never
//! returned by value.

use super::lambert::{
    clamp_ndotl_words, div65280_narrow, div65280_sat_by, interior_ndotl, ndotl_split, split_light,
    split_normal, within, Lambert, DIV65280, SPLIT_LIGHT,
};
use super::screen::color_word;
use crate::math::FixedMat4;
use crate::mesh::Vec3Fx;

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
    /// n·l of the normal `n` in 1/256 steps, clamped or not: where it is
    /// not (64-bit hosts' loop, [`ndotl_steps`](Lambert::ndotl_steps)),
    /// clamped to `0..=256` it is [`ndotl`](Self::ndotl).
    #[inline(always)]
    fn ndotl_steps(&self, n: Vec3Fx) -> i64 {
        self.ndotl(n) as i64
    }
    /// The index of the normal `n` in a [`ColorTable`] of
    /// [`TABLE_WORDS`] words: its [`ndotl`](Self::ndotl), or where the
    /// table is longer ([`SAT_INDEX`]) and the work allows it n·l
    /// saturated to the table instead of clamped to 256 (whose words from
    /// 256 on are all n·l 256's).
    #[inline(always)]
    fn table_index(&self, n: Vec3Fx) -> usize {
        self.ndotl(n) as usize
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

    #[inline(always)]
    fn ndotl_steps(&self, n: Vec3Fx) -> i64 {
        self.1.ndotl_steps(n)
    }
}

/// A draw's Lambert colour words ([`LitWork::word`]) for every n·l,
/// `0..=256`, made once per run of vertices, over the loop's own
/// [`LitWork`] `k` (whose transform and n·l it keeps): per vertex the
/// colour is then one load by n·l, where it took three channels'
/// multiply-adds and quotients by 65,280, their packing and the interval
/// test of the interior bit. Only for runs of at least [`TABLE_MIN`]
/// vertices, which pay for the table's 257 words; 1,028 bytes of stack
/// (2,048 where [`SAT_INDEX`]), within the vertex stage's draw set-up's
/// depth.
pub(super) struct ColorTable<'k, K> {
    k: &'k K,
    words: &'k [u32; TABLE_WORDS],
}

/// The words of a [`ColorTable`]: n·l's 257, or where the loop indexes
/// the table by n·l saturated to 9 bits ([`SAT_INDEX`]) 512, the last
/// 255 n·l 256's.
pub(super) const TABLE_WORDS: usize = if SAT_INDEX { 512 } else { 257 };

/// Whether a [`ColorTable`] over [`LoopConstants`] is indexed by the upper
/// word of n·l's sum saturated to `0..=511` (one `USAT` on ARMv7-M) rather
/// than clamped to `0..=256` (five instructions: a compare, an `IT`, a
/// conditional move and a `BIC`), for 255 words more on the stack (1,020
/// bytes) and their stores per table: on the Arm cores with a long
/// multiply (not ARMv6-M, whose frame RAM is short and which indexes by
/// its own n·l), and in the tests. `demo` vertex stage: Cortex-M3 261,421
/// -> 253,940, M4F 243,158 -> 239,553 (`rock` frame M3 2,473,638 ->
/// 2,466,309, M4F 2,477,546 -> 2,474,017); the M3's peak stack 14,588 ->
/// 15,604 bytes (the table is then on the deepest path).
pub(super) const SAT_INDEX: bool = cfg!(any(
    test,
    all(target_arch = "arm", not(microraster_narrow_multiply))
));

impl<'k, K: LitWork> ColorTable<'k, K> {
    /// The table of `k`'s colours, written into the caller's `words`
    /// (built and returned by value, the table took a second copy of
    /// itself on the stack, ARMv6-M's frame 2.4 KB).
    #[inline(always)]
    pub(super) fn new(k: &'k K, words: &'k mut [u32; TABLE_WORDS]) -> Self {
        let (lit, rest) = words.split_at_mut(257);
        for (n, w) in lit.iter_mut().enumerate() {
            *w = k.word(n as u32);
        }
        // n·l beyond 256 is 256 (`SAT_INDEX`'s tail).
        rest.fill(lit[256]);
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

    #[inline(always)]
    fn shade(&self, n: Vec3Fx) -> u32 {
        // Within the table (the compiler sees the clamp: no check).
        self.words[self.k.table_index(n)]
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
/// three and a multiply more). In this order (`repr(C)`), the light's
/// direction first: the table loop loads it with one `LDM` from the
/// struct's address itself, where at the end (where the compiler had put
/// it) it took an `ADD` for the address each vertex (Cortex-M3 `demo`
/// vertex stage 273,361 -> 271,356).
#[derive(Clone, Copy, Debug)]
#[repr(C)]
#[cfg_attr(not(any(test, target_pointer_width = "32")), allow(dead_code))]
pub(super) struct LoopConstants {
    /// The light's direction (as [`Lambert`]'s), times 2^8 where n·l is
    /// the upper word of its sum ([`HIGH_NDOTL`]).
    dir: [i32; 3],
    /// Per row `r` of the matrix: the low and high words of `m[3][r] 2^16 +
    /// 2^15` (translation and rounding, as in
    /// [`FixedMat4::transform_point_bounded`]), then `m[0][r]`, `m[1][r]`
    /// and `m[2][r]`.
    rows: [[i32; 5]; 4],
    /// The Lambert colour's factors per channel ([`Lambert::folded`]).
    channels: [[u32; 2]; 3],
    /// [`div65280_sat`](super::lambert::div65280_sat)'s multiplier, loaded with the channels' factors
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
    ///
    /// Inlined on RV32: out of line there (as the inliner chose from
    /// `b54a8eb` on) its 192 B frame lay on the frame's deepest path, the
    /// ESP32-C3's peak stack 7,004 -> 7,168 B.
    #[cfg_attr(target_arch = "riscv32", inline(always))]
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
        if HIGH_NDOTL {
            debug_assert!(Self::takes(l));
            for d in k.dir.iter_mut() {
                *d <<= 8;
            }
        }
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

    /// `Σ n[i] dir[i]` of the normal `n`: n·l before its clamp, whose
    /// upper word is n·l where [`HIGH_NDOTL`] (both
    /// [`ndotl`](LitWork::ndotl) and [`table_index`](LitWork::table_index)
    /// take it, one sum written once).
    #[inline(always)]
    fn ndotl_sum(&self, n: Vec3Fx) -> i64 {
        use crate::math::mul_wide;
        mul_wide(n[0].to_bits(), self.dir[0])
            + mul_wide(n[1].to_bits(), self.dir[1])
            + mul_wide(n[2].to_bits(), self.dir[2])
    }

    /// Whether the light `l` is within [`HIGH_LIGHT`] where n·l is the
    /// upper word of the sum ([`HIGH_NDOTL`]); a draw whose light is not
    /// (longer than 64 in the draw's model space) takes the general loop.
    pub(super) fn takes(l: &Lambert) -> bool {
        !HIGH_NDOTL || l.dir.iter().all(|&v| v.unsigned_abs() <= HIGH_LIGHT)
    }
}

/// Whether the common lit loop of this target takes the light `l`: its
/// per-draw work bounds the light on ARMv6-M ([`NarrowRows::takes`]: the
/// split n·l) and where n·l is an upper word ([`LoopConstants::takes`]).
/// A draw whose light it does not take goes through the general loop.
#[inline(always)]
pub(super) fn loop_takes(l: &Lambert) -> bool {
    (!crate::math::SPLIT || NarrowRows::takes(l)) && (!LOOP_CONSTANTS || LoopConstants::takes(l))
}

/// Whether [`LoopConstants`] hold the light's direction times 2^8, so
/// that n·l in 1/256 steps, `floor(Σ n[i] l[i] / 2^24)`, is the upper
/// word of `Σ n[i] (l[i] 2^8)` (exact: each product below `2^61` in
/// magnitude for `|l[i]| <= 2^22`, [`HIGH_LIGHT`]), clamped to `0..=256`
/// as a word: on ARMv7-M, where the clamp from both words
/// ([`clamp_ndotl_words`]) took six instructions, this one five (M3
/// `demo` vertex stage 275,829 -> 274,119, M4F 255,409 -> 251,703).
const HIGH_NDOTL: bool = cfg!(any(test, target_arch = "arm"));

/// The largest light component [`LoopConstants`] take where n·l is an
/// upper word ([`HIGH_NDOTL`]).
const HIGH_LIGHT: u32 = 1 << 22;

#[cfg_attr(not(any(test, target_pointer_width = "32")), allow(dead_code))]
impl LitWork for LoopConstants {
    /// [`FixedMat4::transform_point_bounded`] of `p`: the same sums.
    #[inline(always)]
    fn transform(&self, p: [i32; 3]) -> [i32; 4] {
        use crate::math::mul_wide;
        let row = |k: &[i32; 5]| {
            let acc = ((k[1] as i64) << 32 | k[0] as u32 as i64)
                .wrapping_add(mul_wide(k[2], p[0]))
                .wrapping_add(mul_wide(k[3], p[1]))
                .wrapping_add(mul_wide(k[4], p[2]));
            (acc >> 16) as i32
        };
        if PAIRED_ROWS {
            // z and w first, through an opaque pair (a store and a load
            // of two words): the scheduler cannot carry their sums into
            // x's and y's. In this form only (see `PAIRED_ROWS`).
            let first = core::hint::black_box([row(&self.rows[2]), row(&self.rows[3])]);
            let mut out = [0i32; 4];
            out[2] = first[0];
            out[3] = first[1];
            // By index, as measured (the form matters here).
            #[allow(clippy::needless_range_loop)]
            for r in 0..2 {
                out[r] = row(&self.rows[r]);
            }
            return out;
        }
        let mut out = [0i32; 4];
        for (o, k) in out.iter_mut().zip(&self.rows) {
            *o = row(k);
        }
        out
    }

    /// [`Lambert::ndotl`] of normal `n`: the same n·l.
    #[inline(always)]
    fn ndotl(&self, n: Vec3Fx) -> u32 {
        let d = self.ndotl_sum(n);
        match HIGH_NDOTL {
            true => {
                // Written as `clamp(0, 256)`, the Cortex-M3 took eight
                // instructions (two compares, two conditional moves).
                let h = (d >> 32) as i32;
                ((h & !(h >> 31)) as u32).min(256)
            }
            false => clamp_ndotl_words(d),
        }
    }

    /// n·l's upper word saturated to `0..=511` where [`SAT_INDEX`] (and
    /// n·l is that word, [`HIGH_NDOTL`]): one `USAT`.
    #[inline(always)]
    fn table_index(&self, n: Vec3Fx) -> usize {
        if !(SAT_INDEX && HIGH_NDOTL) {
            return self.ndotl(n) as usize;
        }
        let h = (self.ndotl_sum(n) >> 32) as i32;
        // Not `clamp(0, 511)`: in the loop that took seven instructions
        // (an unsigned minimum, then a sign test), this form one `USAT`.
        (h.max(0) as u32).min(TABLE_WORDS as u32 - 1) as usize
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

/// Whether [`LoopConstants::transform`] makes the rows in two pairs, z
/// and w first, passed through `black_box` before x and y: on ARMv7E-M,
/// whose scheduler otherwise sums the four rows at once (eight
/// accumulator registers) and spills a row's constant and the loop's
/// offset to the stack each vertex (the Cortex-M3 sums them one by one).
/// M4F vertex stage `demo` 246,429 -> 244,405 instructions, `rock`
/// 233,007 -> 231,045 (four-scene build). Fragile: z and w are the only
/// pair that paid (x and y first 252,825, x and z 248,897, y and z
/// 254,897, x and w 250,439, y and w 248,439), and only as written (x and
/// y returned in one array expression, 258,993); neither a barrier
/// between rows (`black_box(())`: the sums sank below it, 291,353) nor a
/// row order alone paid (every order 246,439 or more). On the Pico 2's
/// Cortex-M33 (`microraster_armv8m`) and the ESP32-C3's RV32IMC too:
/// frame 0 of the boards' scene 2,176,400 -> 2,175,350 and 2,576,467 ->
/// 2,556,595 instructions.
const PAIRED_ROWS: bool = cfg!(any(
    microraster_armv7em,
    microraster_armv8m,
    target_arch = "riscv32"
));

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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vertex::lambert::tests::each_lit_case;

    /// Every way of the loop's per-draw work gives the Lambert colour as
    /// a colour word, with its half of the interior bit where the draw is
    /// Gouraud shaded: the constants of 32-bit cores, ARMv6-M's split
    /// rows, the bounded matrix with its light, and the colour table over
    /// them.
    #[test]
    fn lit_work_gives_the_lambert_color_words() {
        each_lit_case(|fast, n, base, general| {
            let inside = crate::vertex::screen::channels_interior(general);
            let zero = FixedMat4 { m: [[0; 4]; 4] };
            for gouraud in [false, true] {
                let want = color_word(general, gouraud && inside);
                let k = LoopConstants::new(&zero, fast, base, gouraud);
                assert_eq!(k.shade(n), want, "{n:?} {base:?}");
                let k = NarrowRows::new(&zero, fast, base, gouraud);
                assert_eq!((&k, fast).shade(n), want, "{n:?} {base:?}");
                let b = fast.interior_ndotl(base, gouraud);
                let k = (&zero, fast, base, b);
                assert_eq!(k.shade(n), want, "{n:?} {base:?}");
                let mut words = [0; TABLE_WORDS];
                let t = ColorTable::new(&k, &mut words);
                assert_eq!(t.shade(n), want, "{n:?} {base:?}");
                let k = LoopConstants::new(&zero, fast, base, gouraud);
                let t = ColorTable::new(&k, &mut words);
                assert_eq!(t.shade(n), want, "{n:?} {base:?}");
            }
        });
    }

    /// The n·l of 32-bit cores' constants, the upper word of the sum with
    /// the light times 2^8, is the 64-bit clamp for any normal and any
    /// light they take (the extremes, and random ones); a longer light is
    /// not taken.
    #[test]
    fn loop_constants_ndotl_is_the_wide_one() {
        let mut next = crate::testing::rng();
        let wide = |n: [i32; 3], l: [i32; 3]| {
            let d: i64 = (0..3).map(|i| n[i] as i64 * l[i] as i64).sum();
            (d >> 24).clamp(0, 256) as u32
        };
        let zero = FixedMat4 { m: [[0; 4]; 4] };
        let m = HIGH_LIGHT as i32;
        let ends = [
            i32::MIN,
            -m,
            -m + 1,
            -(1 << 16),
            -1,
            0,
            1,
            1 << 16,
            m - 1,
            m,
            i32::MAX,
        ];
        let check = |n: [i32; 3], dir: [i32; 3]| {
            let l = Lambert { dir, ..NO_LIGHT };
            let takes = dir.iter().all(|&v| v.unsigned_abs() <= HIGH_LIGHT);
            assert_eq!(LoopConstants::takes(&l), takes, "{dir:?}");
            if takes {
                let k = LoopConstants::new(&zero, &l, [0; 3], true);
                let nf = n.map(fixed::types::I16F16::from_bits);
                assert_eq!(k.ndotl(nf), wide(n, dir), "{n:?} {dir:?}");
            }
        };
        for &a in &ends {
            for &b in &ends {
                for &c in &ends {
                    check([a, b, c], [c, a, b]);
                    check([a, b, c], [m, -m, m]);
                    check([m, -m, m], [a, b, c]);
                }
            }
        }
        for _ in 0..200_000 {
            let mut r = |s: u32| (next(1 << 32) as u32 as i32) >> next(s as u64 + 1);
            let n = [r(31), r(31), r(31)];
            let dir = [r(31), r(31), r(31)].map(|v| v >> 9);
            check(n, dir);
        }
    }

    /// ARMv6-M's rows take a light within the split n·l's range only.
    #[test]
    fn narrow_rows_take_lights_within_the_split_range() {
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
