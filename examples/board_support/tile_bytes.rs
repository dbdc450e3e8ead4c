//! A finished tile as a DMA channel's source, for the firmwares whose HAL
//! takes an `embedded_dma::ReadBuffer` (the Pico's rp2040-hal and the Pico
//! 2's rp235x-hal): the tile buffer, packed into one block of wire bytes,
//! and the block's address and length. One copy of the `unsafe` promises
//! those traits ask for, included by both firmwares.
#![allow(dead_code)]

use crate::st7789_scene::PicoTile;
use embedded_dma::ReadBuffer;
use embedded_graphics::primitives::Rectangle;
use microraster::sink::wire::wire_bytes;

/// A packed tile and its buffer, which the DMA transfer owns while it
/// reads the block.
pub struct TileBytes {
    pub tile: &'static mut PicoTile,
    bytes: (*const u8, usize),
}

impl TileBytes {
    /// Packs the tile that covers `area` of the frame (see
    /// `TileBuffer::pack`) and takes its buffer.
    pub fn new(tile: &'static mut PicoTile, area: &Rectangle) -> Self {
        let bytes = wire_bytes(tile.pack(area));
        Self { tile, bytes }
    }
}

// SAFETY: `bytes` lies within `*tile` (it was made from the tile's packed
// pixels, `2 n` bytes for `n` pixels) and never changes. The buffer is
// `'static` and borrowed exclusively by `self`, so nothing else writes or
// frees it while the DMA channel reads it: the channel's `Transfer` owns
// `self` until it is done, and only then gives the buffer back.
unsafe impl ReadBuffer for TileBytes {
    type Word = u8;

    unsafe fn read_buffer(&self) -> (*const u8, usize) {
        self.bytes
    }
}

// SAFETY: the raw pointer is the only thing that keeps `TileBytes` from
// being `Send`, and it points into the buffer that `self` borrows
// exclusively. Sending it moves that exclusive borrow (on the Pico,
// between the core's thread and the DMA interrupt on the one core,
// through a critical section).
unsafe impl Send for TileBytes {}
