//! The stack probe's panel: a `TileTransfer` that does what the boards'
//! `Panel`s do with a finished tile, short of the SPI and DMA driver calls
//! (the tile's window commands, `TileBuffer::pack` and `wire_bytes`), and
//! instead of sending the bytes folds them into a checksum at once. So its
//! transfers complete as they start, and a frame's checksum, FNV-1a over
//! every tile's window commands and wire bytes in order, tells whether the
//! firmware's frame equals the host's. No std: shared by the probe firmware
//! (`examples/stack_probe.rs`) and its test (`tests/qemu_stack.rs`).

use core::borrow::BorrowMut;
use embedded_graphics::prelude::Point;
use embedded_graphics::primitives::Rectangle;
use microraster::prelude::TileTransfer;
use microraster::sink::wire::{wire_bytes, Window};

use crate::st7789_scene::PicoTile;

/// The animation times the probe draws, in microseconds: the test renders
/// the same ones on the host.
pub const FRAME_TIMES: [u64; 4] = [0, 1_000_000, 2_500_000, 5_200_000];

/// The most stack the Pico 2 and ESP32-C3 firmwares may take, start-up and
/// frames, in bytes: the test holds the probe's peaks to it. The RP2040
/// firmware's measured peak is 15,924 B (rp2040js); 24 KiB leaves room for
/// a board's own `main` and drivers, within the RP2350's 512 KiB and the
/// ESP32-C3's 320 KiB beside 66 and 75 KB of statics.
pub const STACK_BUDGET: usize = 24 * 1024;

/// FNV-1a's offset basis (32-bit).
const FNV_OFFSET: u32 = 0x811c_9dc5;
/// FNV-1a's prime (32-bit).
const FNV_PRIME: u32 = 0x0100_0193;

/// Why a tile was refused.
#[derive(Debug, PartialEq, Eq)]
pub enum ChecksumError {
    /// A tile was started while another was in flight.
    Busy,
    /// The tile's window lies outside the panel's addresses.
    Window,
}

/// A panel that checksums what the board would send.
pub struct ChecksumPanel<B> {
    hash: u32,
    tiles: u32,
    in_flight: Option<B>,
    /// Whether the bytes are folded into the checksum: not by a panel
    /// that only packs them ([`packing_only`](Self::packing_only)).
    checksum: bool,
}

impl<B> ChecksumPanel<B> {
    /// A panel before its first frame.
    pub const fn new() -> Self {
        Self {
            hash: FNV_OFFSET,
            tiles: 0,
            in_flight: None,
            checksum: true,
        }
    }

    /// A panel that does with each tile what a board does short of
    /// sending it (its window commands, `pack`, `wire_bytes`) and no more:
    /// no checksum, the probe's own work, so that a frame drawn into it
    /// counts the instructions of the boards' frame code.
    #[allow(dead_code)] // The host's test checksums every frame.
    pub const fn packing_only() -> Self {
        let mut panel = Self::new();
        panel.checksum = false;
        panel
    }

    /// The checksum and tile count of the bytes since the last call, and a
    /// fresh start for the next frame.
    pub fn take(&mut self) -> (u32, u32) {
        let out = (self.hash, self.tiles);
        self.hash = FNV_OFFSET;
        self.tiles = 0;
        out
    }

    fn fold(&mut self, bytes: &[u8]) {
        if !self.checksum {
            // What the board would send, kept from the optimiser.
            core::hint::black_box(bytes);
            return;
        }
        for &b in bytes {
            self.hash = (self.hash ^ u32::from(b)).wrapping_mul(FNV_PRIME);
        }
    }
}

impl<B: BorrowMut<PicoTile>> TileTransfer<B> for ChecksumPanel<B> {
    type Error = ChecksumError;

    fn start(&mut self, area: &Rectangle, mut tile: B) -> Result<(), (ChecksumError, B)> {
        if self.in_flight.is_some() {
            return Err((ChecksumError::Busy, tile));
        }
        // As the boards: the window at the panel's top-left corner.
        let Some(window) = Window::new(area, Point::zero()) else {
            return Err((ChecksumError::Window, tile));
        };
        for (command, parameters) in window.commands() {
            self.fold(&[command]);
            self.fold(parameters);
        }
        let (address, len) = wire_bytes(tile.borrow_mut().pack(area));
        // SAFETY: `wire_bytes` gives the address and length in bytes of
        // the packed pixels, which lie in the tile buffer that `tile`
        // borrows; nothing writes it while this shared slice lives.
        let bytes = unsafe { core::slice::from_raw_parts(address, len) };
        self.fold(bytes);
        self.tiles += 1;
        self.in_flight = Some(tile);
        Ok(())
    }

    fn wait(&mut self) -> (B, Result<(), ChecksumError>) {
        match self.in_flight.take() {
            Some(tile) => (tile, Ok(())),
            // `render_double_buffered` waits only after a successful start.
            None => unreachable!("TileTransfer::wait without a tile in flight"),
        }
    }
}
