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
    /// The core's count of instructions executed, where it has one
    /// ([`with_counter`](Self::with_counter)).
    counter: Option<fn() -> u64>,
    /// The instructions the checksum took since the last
    /// [`take_spent`](Self::take_spent), by `counter`: the probe's own
    /// work, which a board spends on its SPI transfer instead.
    spent: u64,
}

impl<B> ChecksumPanel<B> {
    /// A panel before its first frame.
    pub const fn new() -> Self {
        Self {
            hash: FNV_OFFSET,
            tiles: 0,
            in_flight: None,
            counter: None,
            spent: 0,
        }
    }

    /// A panel that counts the instructions of its checksum by `counter`,
    /// the core's count of instructions executed.
    #[allow(dead_code)] // The host's test and the Arm probe count none.
    pub const fn with_counter(counter: fn() -> u64) -> Self {
        let mut panel = Self::new();
        panel.counter = Some(counter);
        panel
    }

    /// The instructions the checksum took since the last call (none
    /// without a counter).
    #[allow(dead_code)] // The host's test counts none.
    pub fn take_spent(&mut self) -> u64 {
        core::mem::take(&mut self.spent)
    }

    /// The checksum and tile count of the bytes since the last call, and a
    /// fresh start for the next frame.
    pub fn take(&mut self) -> (u32, u32) {
        let out = (self.hash, self.tiles);
        self.hash = FNV_OFFSET;
        self.tiles = 0;
        out
    }

    /// The counter's value, where there is one.
    fn count(&self) -> Option<u64> {
        self.counter.map(|count| count())
    }

    /// Adds what the checksum took since the counter read `before`.
    fn spend(&mut self, before: Option<u64>) {
        if let (Some(count), Some(before)) = (self.counter, before) {
            self.spent += count().wrapping_sub(before);
        }
    }

    fn fold(&mut self, bytes: &[u8]) {
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
        let before = self.count();
        for (command, parameters) in window.commands() {
            self.fold(&[command]);
            self.fold(parameters);
        }
        self.spend(before);
        let (address, len) = wire_bytes(tile.borrow_mut().pack(area));
        // SAFETY: `wire_bytes` gives the address and length in bytes of
        // the packed pixels, which lie in the tile buffer that `tile`
        // borrows; nothing writes it while this shared slice lives.
        let bytes = unsafe { core::slice::from_raw_parts(address, len) };
        let before = self.count();
        self.fold(bytes);
        self.spend(before);
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
