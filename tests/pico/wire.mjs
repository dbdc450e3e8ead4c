// The SPI wire of the emulated RP2040: how long a byte takes, and how DMA
// is paced by it.
//
// rp2040js's SPI (PL022) has the real 8-entry TX FIFO in front of a
// shifter but shifts a byte out at once; `attachWire` makes each byte take
// 8 SPI clocks at the baud rate the firmware set (SSPCPSR and SSPCR0.SCR
// against clk_peri), so the wire takes the time it takes on a Pico, and
// hands each byte to `onByte` when its last bit is clocked.
//
// DMA. rp2040js 1.4.1's DMA channels honour the data request they are
// paced by (CTRLn.TREQ_SEL): a channel moves a word only while its DREQ is
// asserted, and the SPI asserts DREQ_SPIn_TX while its TX FIFO has room and
// withdraws it when the FIFO is full, after every push and pull. A channel
// feeding SSPDR therefore fills the FIFO, stops, and moves one byte each
// time the shifter takes one: it is paced by the byte time modelled here,
// as on a Pico. What it does not model: the DMA's own bus cycles (a
// transfer takes no time, and never stalls the core's accesses to SRAM or
// the APB bridge: at 62.5 MHz one byte every 16 system clocks, a load and a
// store of the DMA, contention the real chip hides almost entirely), and
// DREQ as a counter (the real DMA counts requests; rp2040js reads the
// level after every change, which comes to the same for a FIFO). That the
// pacing works is checked without a firmware (models.test.mjs) and in
// every run: a write to a full TX FIFO, which the PL022 drops, fails the
// run instead of losing a byte.

/**
 * Models the wire of `mcu.spi[index]`: 8 SPI clocks a byte, 8-bit frames
 * only. `onByte(value)` sees each byte when it has been clocked out;
 * `fail(message)` is called on what a Pico would get wrong. Returns the
 * running totals: `busyCycles`, the system-clock cycles the SPI has been
 * sending, and `bytes`, the bytes sent.
 */
export function attachWire(mcu, index, { onByte, fail }) {
  const spi = mcu.spi[index];
  const wire = { busyCycles: 0, bytes: 0 };
  let value = 0;
  const done = mcu.clock.createAlarm(() => {
    wire.bytes++;
    onByte(value);
    // Frees the shifter: the next byte of the FIFO starts, and the FIFO's
    // room raises DREQ again.
    spi.completeTransmit(0);
  });
  spi.onTransmit = (v) => {
    if (spi.dataBits !== 8) fail(`SPI${index} sends ${spi.dataBits}-bit words, not bytes`);
    const hz = spi.clockFrequency;
    if (!(hz > 0)) fail(`SPI${index} transmits with no clock`);
    const ns = (8 * 1e9) / hz;
    wire.busyCycles += (ns * mcu.clkSys) / 1e9;
    value = v;
    done.schedule(ns);
  };
  const write = spi.writeUint32.bind(spi);
  spi.writeUint32 = (offset, v) => {
    if (offset === 0x008 && spi.txFIFO.full) {
      // SSPDR. The core waits for TNF and a paced DMA channel for DREQ;
      // anything else loses the byte.
      fail(`a write of 0x${(v & 0xff).toString(16)} to SPI${index}'s full TX FIFO: the byte is lost`);
    }
    write(offset, v);
  };
  return wire;
}
