//! The vertex stage's common loop: every vertex of a lit draw transformed,
//! projected and given its Lambert colour in one pass ([`lit_loop`]), the
//! colours from a table of the draw's colours by n·l on long runs
//! ([`ColorTable`]; on 64-bit hosts a table of 64-bit words,
//! `lit_loop_wide`), and the rare vertices it hands to the general path
//! (outside the fast projection's range) out of line. The per-draw set-up
//! that picks it is [`DrawSetup`](super::DrawSetup)'s, the per-draw
//! constants it reads [`lit_work`](super::lit_work)'s.

use super::lit_work::{ColorTable, LitWork, TABLE_MIN, TABLE_WORDS};
use super::screen::COLOR_WORD_INTERIOR;
use super::{ScreenVertex, Viewport};
use crate::mesh::Vec3Fx;
use fixed::types::I16F16;

/// The common case's loop of
/// [`DrawSetup::screen_vertices`](super::DrawSetup::screen_vertices): each
/// vertex's position and its Lambert colour from its normal by `k`, one
/// loop for the three ways of computing them ([`LitWork`]'s
/// implementations: `LoopConstants` on 32-bit cores with a long multiply,
/// `NarrowRows` on ARMv6-M, the bounded matrix on 64-bit hosts). Inlined
/// into each arm, so each arm's constants stay where its `black_box` put
/// them. Whether a vertex gets the interior bit comes with its colour
/// (the draw's n·l interval, empty unless it is Gouraud shaded); on
/// 64-bit hosts the loop is made twice (`DUPLICATE`), and the copy for
/// the other draws (`gouraud` false) makes no test at all.
#[inline(always)]
pub(super) fn lit_loop(
    out: &mut [ScreenVertex],
    positions: &[[I16F16; 3]],
    normals: &[Vec3Fx],
    viewport: &Viewport,
    k: &impl LitWork,
    gouraud: bool,
) {
    // A long run's colours from a table of the draw's colours by n·l,
    // whose words hold the interior bit as the draw has it (none unless
    // Gouraud shaded): one copy of the loop for every draw.
    if COLOR_TABLES && WIDE_LOOP && out.len() >= TABLE_MIN {
        // 64-bit hosts: each word with red and its interior bit copied to
        // the top ([`ScreenVertex::wide_word`]), n·l from -256 on
        // ([`lit_loop_wide`]). The colour words first, then widened, each
        // loop in vector registers (the two as one loop were made one
        // word at a time: about 9,000 instructions a table).
        let mut narrow = [0u32; 257];
        for (n, w) in narrow.iter_mut().enumerate() {
            *w = k.word(n as u32);
        }
        let mut words = [0u64; WIDE_WORDS];
        let (below, lit) = words.split_at_mut(256);
        for (w, &c) in lit.iter_mut().zip(&narrow) {
            *w = ScreenVertex::wide_word(c);
        }
        below.fill(lit[0]);
        return lit_loop_wide(out, positions, normals, viewport, k, &words);
    }
    if COLOR_TABLES && out.len() >= TABLE_MIN {
        let mut words = [0; TABLE_WORDS];
        let table = ColorTable::new(k, &mut words);
        return lit_loop_one::<true>(out, positions, normals, viewport, &table);
    }
    match (DUPLICATE, gouraud) {
        (true, false) => lit_loop_one::<false>(out, positions, normals, viewport, k),
        _ => lit_loop_one::<true>(out, positions, normals, viewport, k),
    }
}

/// Whether [`lit_loop`] looks a long run's colours up in a
/// [`ColorTable`]: everywhere but in builds optimised for size (a second
/// copy of the loop).
const COLOR_TABLES: bool = !cfg!(microraster_size);

/// Whether [`lit_loop`] is made twice, with and without the interior
/// bit: on 64-bit hosts, where flash does not matter. (On the Cortex-M3
/// the second copy took 724 bytes of flash.)
pub(super) const DUPLICATE: bool = cfg!(target_pointer_width = "64");

/// One copy of [`lit_loop`]; without `BIT`, no vertex gets the interior
/// bit.
#[inline(always)]
fn lit_loop_one<const BIT: bool>(
    out: &mut [ScreenVertex],
    positions: &[[I16F16; 3]],
    normals: &[Vec3Fx],
    viewport: &Viewport,
    k: &impl LitWork,
) {
    for (o, (p, nv)) in out.iter_mut().zip(positions.iter().zip(normals)) {
        let p = [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()];
        if WIDE_LOOP {
            // x86-64: the clip coordinates as 64-bit words (not
            // sign-extended again for the projection); a vertex inside
            // the view volume stored here with outcode 0, any other's
            // outcode and projection out of line, each path storing its
            // own vertex (merged before one store, the vertex went
            // through a stack slot: `demo`'s vertex stage 12,000
            // instructions more). The colour inline for both: given `k`,
            // the call kept the loop from holding the matrix (reloaded
            // and sign-extended every vertex: +42,000).
            let pos = k.transform_wide(p);
            let word = lit_word::<BIT>(k, nv);
            match viewport.project_fast_words(&pos) {
                Some((s, z)) => *o = ScreenVertex::with_color_word(s.x, s.y, z, 0, word),
                None => word_rest(viewport, pos.map(|v| v as i32), word, o),
            }
            continue;
        }
        let pos = k.transform(p);
        if crate::math::SPLIT {
            match viewport.project_recip_fast(&pos) {
                Some((s, z)) => {
                    // x first, so that it is not held across the colour
                    // (vertex stage 751,511 -> 749,487).
                    o.set_x(s.x);
                    o.set_lit_word(s.y, z, lit_word::<BIT>(k, nv));
                }
                None => *o = lit_rest::<BIT>(viewport, pos[0], pos[1], pos[2], pos[3], k, nv),
            }
            continue;
        }
        *o = viewport.screen_vertex_word(&pos, true, || lit_word::<BIT>(k, nv));
    }
}

/// [`lit_loop_one`] with a table of the draw's colours (`BIT`) on 64-bit
/// hosts: `words` by n·l from -256 to 256, each a
/// [`ScreenVertex::wide_word`], so that a vertex's y and red and its
/// depth and green and blue are a double shift each
/// ([`ScreenVertex::with_wide_word`]), where the colour word's red was
/// masked and merged. With the index below and the depth's interior test
/// on a rare branch, x86-64's loop takes 106 instructions a vertex where
/// the [`ColorTable`] loop took 113 (`demo` 2,777,612 -> 2,768,859, its
/// vertex stage 246,295 -> 237,530; `rock` -8.5 K, `demo-flat` -8.7 K;
/// `tri4` and `tri100`, whose vertices take the general loop, the same).
#[inline(always)]
fn lit_loop_wide(
    out: &mut [ScreenVertex],
    positions: &[[I16F16; 3]],
    normals: &[Vec3Fx],
    viewport: &Viewport,
    k: &impl LitWork,
    words: &[u64; WIDE_WORDS],
) {
    for (o, (p, nv)) in out.iter_mut().zip(positions.iter().zip(normals)) {
        let p = [p[0].to_bits(), p[1].to_bits(), p[2].to_bits()];
        // As `lit_loop_one`'s `WIDE_LOOP` form.
        let pos = k.transform_wide(p);
        // n·l of a normal within 1 is within `-256..=256`: one unsigned
        // test of it offset by 256, where the clamp to `0..=256` took
        // seven instructions (two a vertex fewer for the table's 256 more
        // words); a longer normal's clamped out of line.
        let i = (k.ndotl_steps(*nv) + 256) as u64;
        let i = match i < WIDE_WORDS as u64 {
            true => i as usize,
            false => wide_index(i),
        };
        let word = words[i];
        match viewport.project_fast_words(&pos) {
            Some((s, z)) => *o = ScreenVertex::with_wide_word(s.x, s.y, z, word),
            None => word_rest(viewport, pos.map(|v| v as i32), word as u32, o),
        }
    }
}

/// The words of [`lit_loop_wide`]'s table: n·l from -256 to 256, the
/// first 256 (n·l below 0) n·l 0's.
const WIDE_WORDS: usize = 513;

/// [`lit_loop_wide`]'s index of n·l `i - 256` (as a word) beyond
/// `-256..=256`, that of n·l clamped to `0..=256`: for normals longer
/// than 1, out of line.
#[cold]
#[inline(never)]
fn wide_index(i: u64) -> usize {
    match (i as i64) < 0 {
        true => 0,
        false => WIDE_WORDS - 1,
    }
}

/// x86-64's vertex that [`Viewport::project_fast_words`] declines, with
/// its colour word: its outcode and projection out of line, stored into
/// `o`.
#[inline(never)]
#[cold]
fn word_rest(viewport: &Viewport, pos: [i32; 4], word: u32, o: &mut ScreenVertex) {
    *o = viewport.screen_vertex_word(&pos, false, || word);
}

/// Whether [`lit_loop_one`] takes its 64-bit form: on 64-bit hosts,
/// whose divisions by `2w` are 64-bit ([`Viewport::project_fast_words`]).
const WIDE_LOOP: bool = cfg!(target_pointer_width = "64");

/// The colour word of the normal `nv` by `k`, its interior bit cleared
/// without `BIT`.
#[inline(always)]
fn lit_word<const BIT: bool>(k: &impl LitWork, nv: &Vec3Fx) -> u32 {
    let word = k.shade(*nv);
    match BIT {
        true => word,
        false => word & !COLOR_WORD_INTERIOR,
    }
}

/// ARMv6-M's vertex that [`Viewport::project_recip_fast`] declines (one
/// outside the view volume, or with `w` beyond its range): the whole
/// vertex out of line, its outcode, projection and colour. The loop's
/// inline path then stores the outcode as the constant 0, where with
/// this path's values merged before the colour it carried the outcode
/// through a stack slot and the projection's results through others:
/// ARMv6-M `demo` vertex stage 799,901 -> 771,577 instructions.
#[inline(never)]
#[cold]
fn lit_rest<const BIT: bool>(
    viewport: &Viewport,
    x: i32,
    y: i32,
    z: i32,
    w: i32,
    k: &impl LitWork,
    nv: &Vec3Fx,
) -> ScreenVertex {
    viewport.screen_vertex_word(&[x, y, z, w], false, || lit_word::<BIT>(k, nv))
}
