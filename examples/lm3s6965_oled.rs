//! Firmware for the TI Stellaris LM3S6965EVB: renders a lit, rotating torus
//! knot in 16 grey levels with microraster and streams every finished
//! 32x32 tile over SSI0 (SPI) to the board's SSD0323 128x64 OLED.
//!
//! ```text
//! cargo run --release --example lm3s6965_oled --target thumbv7m-none-eabi
//! ```
//!
//! runs it in QEMU (`scripts/qemu-lm3s6965.sh` is the cargo runner; with a
//! desktop, QEMU shows the OLED). Built with `MICRORASTER_OLED_FRAMES=N` in
//! the environment it stops after N frames, prints `done` and idles, which is
//! how the end-to-end test takes the panel's picture.
//!
//! Each frame's line ends with the peak stack since boot, measured by
//! painting the free RAM at start-up (`examples/stack_gauge/mod.rs`).
//!
//! With `--features assets` it shows `examples/assets/rocket.obj` instead,
//! converted into flash-resident arrays by `build.rs` at build time.
//!
//! On a host build this file is only a stub that says how to build it.

#![cfg_attr(target_os = "none", no_std)]
#![cfg_attr(target_os = "none", no_main)]

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!(
        "lm3s6965_oled is firmware: cargo run --release --example lm3s6965_oled --target thumbv7m-none-eabi"
    );
}

#[cfg(target_os = "none")]
mod oled_scene;
#[cfg(target_os = "none")]
mod stack_gauge;
// The LM3S6965's own interrupt table (cortex-m-rt's `device` feature).
#[cfg(microraster_lm3s6965)]
mod lm3s6965_vectors;

#[cfg(target_os = "none")]
mod firmware {
    use crate::oled_scene::*;
    use cortex_m_rt::entry;
    use cortex_m_semihosting::{debug, hio};
    use embedded_graphics::pixelcolor::{Gray4, GrayColor};
    use embedded_graphics::prelude::*;
    use embedded_graphics::primitives::Rectangle;
    use microraster::prelude::*;
    use static_cell::ConstStaticCell;

    // Built in place in RAM (.bss), never moved through the stack: together
    // they are about 28 KiB of the board's 64 KiB.
    #[cfg(not(feature = "assets"))]
    static KNOT: ConstStaticCell<KnotData> = ConstStaticCell::new(KnotData::new());
    static WORKSPACE: ConstStaticCell<OledWorkspace> = ConstStaticCell::new(OledWorkspace::new());

    /// Memory-mapped registers of the LM3S6965 (datasheet addresses).
    mod reg {
        pub const RCGC1: usize = 0x400F_E104;
        pub const RCGC2: usize = 0x400F_E108;
        pub const GPIO_A: usize = 0x4000_4000;
        pub const GPIO_C: usize = 0x4000_6000;
        pub const GPIO_D: usize = 0x4000_7000;
        pub const GPIO_DIR: usize = 0x400;
        pub const GPIO_AFSEL: usize = 0x420;
        pub const GPIO_DEN: usize = 0x51C;
        pub const SSI0: usize = 0x4000_8000;
        pub const SSI_CR0: usize = 0x00;
        pub const SSI_CR1: usize = 0x04;
        pub const SSI_DR: usize = 0x08;
        pub const SSI_SR: usize = 0x0C;
        pub const SSI_CPSR: usize = 0x10;
        pub const SR_TNF: u32 = 1 << 1;
        pub const SR_RNE: u32 = 1 << 2;
        pub const SR_BSY: u32 = 1 << 4;

        pub fn write(addr: usize, value: u32) {
            // SAFETY: `addr` is one of the word-aligned peripheral registers
            // above, which no Rust object aliases; a volatile store is how
            // the hardware is told anything.
            unsafe { core::ptr::write_volatile(addr as *mut u32, value) }
        }

        pub fn read(addr: usize) -> u32 {
            // SAFETY: as for `write`.
            unsafe { core::ptr::read_volatile(addr as *const u32) }
        }

        pub fn set_bits(addr: usize, bits: u32) {
            write(addr, read(addr) | bits);
        }

        /// Sets one GPIO pin through the address-masked data register.
        pub fn gpio_pin(port: usize, pin: u32, high: bool) {
            write(port + ((1 << pin) << 2), if high { 1 << pin } else { 0 });
        }
    }

    /// The SSD0323 on SSI0, with D/C on PC7.
    struct Oled;

    /// The initialisation sequence of the board's OSRAM 128x64 panel, as in
    /// TI's board driver: window, contrast, current range, remap (horizontal
    /// address increment), start line, offset, normal mode, multiplex ratio,
    /// phase length, row period, clock, VSL, VCOMH, VP, grey-scale table,
    /// DC-DC on, display on.
    const INIT: &[u8] = &[
        0x15, 0x00, 0x3F, 0x75, 0x00, 0x3F, 0x81, 0x33, 0x85, 0xA0, 0x52, 0xA1, 0x00, 0xA2, 0x40,
        0xA4, 0xA8, 0x3F, 0xB1, 0x22, 0xB2, 0x46, 0xB3, 0xF1, 0xBF, 0x0D, 0xBE, 0x02, 0xBC, 0x10,
        0xB8, 0x01, 0x11, 0x22, 0x32, 0x43, 0x54, 0x65, 0x76, 0xAD, 0x03, 0xAF,
    ];

    impl Oled {
        fn init() -> Self {
            use reg::*;
            // Clocks: SSI0, and GPIO ports A, C and D.
            set_bits(RCGC1, 1 << 4);
            set_bits(RCGC2, (1 << 0) | (1 << 2) | (1 << 3));
            for _ in 0..16 {
                cortex_m::asm::nop();
            }
            // PA2 clock, PA3 frame select, PA5 transmit: the SSI function.
            let ssi_pins = (1 << 2) | (1 << 3) | (1 << 5);
            set_bits(GPIO_A + GPIO_AFSEL, ssi_pins);
            set_bits(GPIO_A + GPIO_DEN, ssi_pins);
            // PC7 is D/C, PC6 enables the panel's +15 V supply.
            set_bits(GPIO_C + GPIO_DIR, (1 << 7) | (1 << 6));
            set_bits(GPIO_C + GPIO_DEN, (1 << 7) | (1 << 6));
            gpio_pin(GPIO_C, 6, true);
            // PD0 selects the OLED rather than the SD card on the shared bus.
            set_bits(GPIO_D + GPIO_DIR, 1);
            set_bits(GPIO_D + GPIO_DEN, 1);
            gpio_pin(GPIO_D, 0, true);
            // SSI0: master, Freescale SPI mode 3, 8-bit frames.
            write(SSI0 + SSI_CR1, 0);
            write(SSI0 + SSI_CPSR, 2);
            write(SSI0 + SSI_CR0, (1 << 7) | (1 << 6) | 7);
            write(SSI0 + SSI_CR1, 1 << 1);
            let mut oled = Oled;
            oled.command(INIT);
            oled
        }

        fn send(&mut self, byte: u8) {
            use reg::*;
            while read(SSI0 + SSI_SR) & SR_TNF == 0 {}
            write(SSI0 + SSI_DR, byte as u32);
            // Transmit-only: drain what the bus clocked in, or the FIFO fills.
            while read(SSI0 + SSI_SR) & SR_RNE != 0 {
                let _ = read(SSI0 + SSI_DR);
            }
        }

        /// Switches D/C once the bytes sent so far have left the shifter.
        fn data_mode(&mut self, data: bool) {
            use reg::*;
            while read(SSI0 + SSI_SR) & SR_BSY != 0 {
                let _ = read(SSI0 + SSI_DR);
            }
            gpio_pin(GPIO_C, 7, data);
        }

        fn command(&mut self, bytes: &[u8]) {
            self.data_mode(false);
            for &b in bytes {
                self.send(b);
            }
        }
    }

    impl OriginDimensions for Oled {
        fn size(&self) -> Size {
            Size::new(WIDTH, HEIGHT)
        }
    }

    impl DrawTarget for Oled {
        type Color = Gray4;
        type Error = core::convert::Infallible;

        /// Single pixels: the panel cannot be read, so the other pixel of
        /// the byte is written black. microraster only uses
        /// `fill_contiguous`.
        fn draw_iter<I: IntoIterator<Item = Pixel<Gray4>>>(
            &mut self,
            pixels: I,
        ) -> Result<(), Self::Error> {
            for Pixel(p, c) in pixels {
                if p.x < 0 || p.y < 0 || p.x >= WIDTH as i32 || p.y >= HEIGHT as i32 {
                    continue;
                }
                let col = (p.x / 2) as u8;
                self.command(&[0x15, col, col, 0x75, p.y as u8, p.y as u8]);
                self.data_mode(true);
                let v = c.luma();
                self.send(if p.x % 2 == 0 { v << 4 } else { v });
            }
            Ok(())
        }

        /// One window command pair and `w * h / 2` data bytes, two pixels per
        /// byte with the left pixel in the high nibble.
        fn fill_contiguous<I: IntoIterator<Item = Gray4>>(
            &mut self,
            area: &Rectangle,
            colors: I,
        ) -> Result<(), Self::Error> {
            let (x, y) = (area.top_left.x, area.top_left.y);
            let (w, h) = (area.size.width as i32, area.size.height as i32);
            let inside = x >= 0 && y >= 0 && x + w <= WIDTH as i32 && y + h <= HEIGHT as i32;
            if !inside || x % 2 != 0 || w % 2 != 0 || w == 0 || h == 0 {
                return self.draw_iter(area.points().zip(colors).map(|(p, c)| Pixel(p, c)));
            }
            self.command(&[
                0x15,
                (x / 2) as u8,
                ((x + w) / 2 - 1) as u8,
                0x75,
                y as u8,
                (y + h - 1) as u8,
            ]);
            self.data_mode(true);
            let mut it = colors.into_iter();
            while let (Some(a), Some(b)) = (it.next(), it.next()) {
                self.send((a.luma() << 4) | b.luma());
            }
            Ok(())
        }
    }

    #[entry]
    fn main() -> ! {
        // Everything below `main`'s frame, so that each frame's line can say
        // how deep the stack has gone since boot.
        crate::stack_gauge::paint();
        // The imported rocket (`--features assets`), in flash since the
        // build; or the knot, generated into RAM.
        #[cfg(feature = "assets")]
        let (meshes, camera) = (rocket::meshes(), rocket::camera());
        #[cfg(not(feature = "assets"))]
        let (mesh, camera) = {
            let Some(knot) = KNOT.try_take() else { halt() };
            knot.generate();
            (knot.mesh(), camera())
        };
        let Some(workspace) = WORKSPACE.try_take() else {
            halt()
        };
        let mut renderer = OledRenderer::new(config());
        let mut oled = Oled::init();
        let frames: Option<u32> =
            option_env!("MICRORASTER_OLED_FRAMES").and_then(|s| s.parse().ok());

        let mut frame = 0;
        loop {
            #[cfg(feature = "assets")]
            let draws = rocket::draws(&meshes, frame);
            #[cfg(not(feature = "assets"))]
            let draws = [draw(&mesh, frame)];
            let scene = Scene::new(camera, &draws).light(light());
            let mut line = Line::new();
            line.str("frame ").num(frame);
            match renderer.render(workspace, &scene, &mut oled) {
                Ok(s) => {
                    line.str(": ").num(s.drawn).str(" of ").num(s.triangles_in);
                    line.str(" triangles drawn, ").num(s.pixels_shaded);
                    line.str(" pixels shaded, ")
                        .num(s.tiles)
                        .str(" tiles; peak stack ");
                    line.num(crate::stack_gauge::peak() as u32).str(" B of ");
                    line.num(crate::stack_gauge::room() as u32).str(" B free");
                    line.print();
                }
                Err(_) => {
                    line.str(": render error").print();
                    debug::exit(debug::EXIT_FAILURE);
                }
            }
            frame += 1;
            if Some(frame) == frames {
                Line::new().str("done").print();
                loop {
                    cortex_m::asm::wfi();
                }
            }
        }
    }

    /// One line of output, built without `core::fmt`: the firmware prints
    /// only text and unsigned numbers, and formatting machinery (with the
    /// panic handler's message formatting) took about 7 KB of its flash.
    struct Line {
        buf: [u8; 128],
        len: usize,
    }

    impl Line {
        fn new() -> Self {
            Line {
                buf: [0; 128],
                len: 0,
            }
        }

        /// Appends `s` (cut at the buffer's end).
        fn str(&mut self, s: &str) -> &mut Self {
            self.bytes(s.as_bytes())
        }

        /// Appends `bytes` (cut at the buffer's end).
        #[inline(never)]
        fn bytes(&mut self, bytes: &[u8]) -> &mut Self {
            for &b in bytes {
                if let Some(slot) = self.buf.get_mut(self.len) {
                    *slot = b;
                    self.len += 1;
                }
            }
            self
        }

        /// Appends `n` in decimal.
        #[inline(never)]
        fn num(&mut self, mut n: u32) -> &mut Self {
            let mut digits = [0u8; 10];
            let mut k = digits.len();
            loop {
                k -= 1;
                digits[k] = b'0' + (n % 10) as u8;
                n /= 10;
                if n == 0 {
                    break;
                }
            }
            self.bytes(digits.get(k..).unwrap_or(&[]))
        }

        /// Writes the line and a newline to the host's stdout.
        #[inline(never)]
        fn print(&mut self) {
            self.str("\n");
            if let Ok(mut out) = hio::hstdout() {
                let _ = out.write_all(&self.buf[..self.len]);
            }
        }
    }

    /// Prints where the panic happened (not its message, which would link
    /// `core::fmt`) and ends the QEMU run with a failure.
    #[panic_handler]
    fn panic(info: &core::panic::PanicInfo) -> ! {
        let mut line = Line::new();
        line.str("panicked");
        if let Some(at) = info.location() {
            line.str(" at ").str(at.file()).str(":").num(at.line());
        }
        line.print();
        halt()
    }

    /// Ends the QEMU run with a failure. `main` takes its statics with
    /// `try_take` and halts here if one was taken already (it never is:
    /// `main` runs once): `take` would panic with a message and a
    /// location in `static_cell`'s source, over 150 B of flash.
    fn halt() -> ! {
        loop {
            debug::exit(debug::EXIT_FAILURE);
        }
    }
}
