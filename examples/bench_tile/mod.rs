//! The tile size and bin pool of the benchmark renderers
//! (`examples/common/scenes/` on the host, `examples/icount_scenes/` on
//! Cortex-M), chosen at build time for a study of the tile size:
//!
//! * `MICRORASTER_BENCH_TILE=WxH` (e.g. `64x32`): the tiles, 32x32
//!   without it;
//! * `MICRORASTER_BENCH_BINS=N`: the workspaces' bin entries, each
//!   scene's own count without it.
//!
//! Without either, every benchmark builds the renderer and workspaces it
//! always counted, so the counts are the same. `const fn`s, so that a bad
//! value stops the build rather than a run.
#![allow(dead_code)]

/// Parses a decimal number made of `s[from..to]`; panics (at build time)
/// on anything else.
const fn number(s: &[u8], from: usize, to: usize) -> usize {
    assert!(from < to, "a number is missing");
    let (mut i, mut n) = (from, 0usize);
    while i < to {
        let d = s[i];
        assert!(d.is_ascii_digit(), "not a decimal number");
        n = n * 10 + (d - b'0') as usize;
        i += 1;
    }
    n
}

/// The tile `(width, height)` named by `spec` (`WxH`), or 32x32.
pub const fn tile(spec: Option<&str>) -> (usize, usize) {
    let s = match spec {
        Some(s) => s.as_bytes(),
        None => return (32, 32),
    };
    let mut x = 0;
    while x < s.len() && s[x] != b'x' {
        x += 1;
    }
    assert!(x < s.len(), "MICRORASTER_BENCH_TILE is WxH, e.g. 64x32");
    let (w, h) = (number(s, 0, x), number(s, x + 1, s.len()));
    assert!(w > 0 && h > 0, "a tile is at least 1x1");
    (w, h)
}

/// The bin entries named by `spec`, or `default`.
pub const fn bins(spec: Option<&str>, default: usize) -> usize {
    match spec {
        Some(s) => number(s.as_bytes(), 0, s.len()),
        None => default,
    }
}

/// The tile size of this build: `MICRORASTER_BENCH_TILE`, or 32x32.
pub const TILE: (usize, usize) = tile(option_env!("MICRORASTER_BENCH_TILE"));
/// The tile width.
pub const TILE_W: usize = TILE.0;
/// The tile height.
pub const TILE_H: usize = TILE.1;

/// The tiles of a `width x height` frame: what a workspace needs to bin
/// them all in one pass (80 for 320x240 in 32x32 tiles).
pub const fn tiles(width: u32, height: u32) -> usize {
    (width as usize).div_ceil(TILE_W) * (height as usize).div_ceil(TILE_H)
}

/// A workspace's bin entries: `MICRORASTER_BENCH_BINS`, or `default`.
pub const fn bin_entries(default: usize) -> usize {
    bins(option_env!("MICRORASTER_BENCH_BINS"), default)
}
