//! The LM3S6965's interrupt vectors, all bound to cortex-m-rt's
//! `DefaultHandler`: the firmwares enable no interrupt. Without its
//! `device` feature, cortex-m-rt would place a table of 240 interrupts,
//! 960 bytes of flash for a chip that has 44 (the Stellaris LM3S6965
//! data sheet, "Interrupts": GPIO port A, IRQ 0, to the hibernation
//! module, IRQ 43); this one takes 176. `build.rs` turns on the
//! `microraster_lm3s6965` cfg and writes the `device.x` that cortex-m-rt's
//! linker script then includes.

/// The interrupt handlers of the vector table, after the exceptions.
#[link_section = ".vector_table.interrupts"]
#[no_mangle]
#[used]
static __INTERRUPTS: [unsafe extern "C" fn(); 44] = [DefaultHandler; 44];

extern "C" {
    /// cortex-m-rt's default handler (`DefaultHandler_`, or the
    /// firmware's own `#[exception] fn DefaultHandler`).
    fn DefaultHandler();
}
