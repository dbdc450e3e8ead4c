// The harness's own models, checked without a firmware:
//   node --test tests/pico/
// The panel must refuse a malformed command stream, the stub ROM must
// round as the RP2040's does, and a DMA channel feeding the SPI must be
// paced by the wire's byte time.

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { RP2040, ConsoleLogger, LogLevel } from 'rp2040js';
import { ST7789 } from './st7789.mjs';
import { buildBootrom, bits, f32, bigToF32 } from './bootrom.mjs';
import { attachWire } from './wire.mjs';

const MS = 1e6;

/** A panel at time `t` (ns), started as mipidsi starts it, and a way to
 * send it commands. */
function panel() {
  let t = 0;
  const p = new ST7789(() => t);
  const send = (cmd, ...data) => {
    p.byte(cmd, false, false);
    for (const d of data) p.byte(d, true, false);
  };
  const wait = (ms) => (t += ms * MS);
  p.reset(false);
  wait(0.01);
  p.reset(true);
  wait(150);
  send(0x11); // SLPOUT
  wait(10);
  send(0x36, 0x00); // MADCTL
  send(0x21); // INVON
  send(0x3a, 0x55); // COLMOD
  send(0x13); // NORON
  send(0x29); // DISPON
  return { p, send, wait };
}

test('a well-formed stream draws a window', () => {
  const { p, send } = panel();
  send(0x2a, 0, 10, 0, 11); // CASET 10..11
  send(0x2b, 0, 20, 0, 20); // RASET 20..20
  send(0x2c, 0xf8, 0x00, 0x07, 0xe0); // red, green
  assert.ok(p.windowFilled());
  const pic = p.picture();
  assert.equal(pic.readUInt16BE(2 * (20 * 240 + 10)), 0xf800);
  assert.equal(pic.readUInt16BE(2 * (20 * 240 + 11)), 0x07e0);
});

test('malformed streams are refused', () => {
  const cases = [
    [/unknown command 0xb2/, ({ send }) => send(0xb2, 0x0c)],
    [/past the end of the window/, ({ send }) => {
      send(0x2a, 0, 0, 0, 0);
      send(0x2b, 0, 0, 0, 0);
      send(0x2c, 1, 2, 3, 4);
    }],
    [/CASET 0..240 outside/, ({ send }) => send(0x2a, 0, 0, 0, 240)],
    [/RASET takes 4 parameter bytes, got 2/, ({ send }) => {
      send(0x2b, 0, 0);
      send(0x2c);
    }],
    [/COLMOD 0x66/, ({ send }) => send(0x3a, 0x66)],
    [/in the middle of a pixel/, ({ send }) => {
      send(0x2c, 0xff);
      send(0x00);
    }],
    [/MADCTL 0x60/, ({ send }) => send(0x36, 0x60)],
    [/too soon after/, ({ send }) => {
      send(0x11);
      send(0x29);
    }],
    [/CS high/, ({ p }) => p.byte(0x2c, false, true)],
    [/sent during the reset/, ({ p }) => {
      p.reset(false);
      p.byte(0x00, false, false);
    }],
  ];
  for (const [error, stream] of cases) {
    const s = panel();
    assert.throws(() => stream(s), error);
  }
  // RAMWR before COLMOD 0x55: the panel is in 18-bit mode after a reset;
  // and data before any command.
  let t = 0;
  const p = new ST7789(() => t);
  t = 200 * MS;
  assert.throws(() => p.byte(0x12, true, false), /without a command/);
  assert.throws(() => p.byte(0x2c, false, false), /COLMOD 0x66, not 16 bits/);
});

test('without INVON the IPS panel shows the picture inverted', () => {
  const { p, send } = panel();
  send(0x20); // INVOFF
  send(0x2a, 0, 0, 0, 0);
  send(0x2b, 0, 0, 0, 0);
  send(0x2c, 0x12, 0x34);
  assert.equal(p.picture().readUInt16BE(0), 0x1234 ^ 0xffff);
});

test('the stub ROM converts floats as the RP2040 ROM does', () => {
  const mcu = new RP2040();
  const rom = buildBootrom(mcu, { fail: (m) => assert.fail(m), charge: () => {} });
  mcu.loadBootrom(rom.image);
  // Through the ROM's own tables, as rp2040-hal finds them.
  const view = new DataView(rom.image.buffer);
  assert.equal(view.getUint16(0x10, true), 0x754d); // 'Mu'
  const dataTable = view.getUint16(0x16, true);
  const lookup = view.getUint16(0x18, true);
  assert.equal(lookup & 1, 1, 'a Thumb function pointer');
  const call = (fnAddr, ...args) => {
    args.forEach((a, i) => (mcu.core.registers[i] = a >>> 0));
    const n = view.getUint16(fnAddr & ~1, true) & 0xff; // the bkpt's number
    rom.onBreak(n);
    return mcu.core.registers[0];
  };
  const sf = call(lookup, dataTable, 0x4653); // 'SF'
  const entry = (offset) => view.getUint32(sf + offset, true);
  const toInt = (x) => call(entry(0x1c), bits(x)) | 0;
  assert.equal(toInt(-0.5), -1, 'towards -infinity, not towards zero');
  assert.equal(toInt(-2.0), -2);
  assert.equal(toInt(2.75), 2);
  assert.equal(toInt(-1e10), -(2 ** 31), 'clamped');
  assert.equal(toInt(1e10), 2 ** 31 - 1, 'clamped');
  assert.equal(f32(call(entry(0x08), bits(0.1), bits(3))), Math.fround(Math.fround(0.1) * 3));
  assert.equal(f32(call(entry(0x0c), bits(1), bits(3))), Math.fround(1 / 3));
  // 2^60 + 2^36 + 1 is above the halfway point between two f32s: a double
  // would round it down to the halfway point, and f32 then to even.
  assert.equal(bigToF32(2n ** 60n + 2n ** 36n + 1n), 2 ** 60 + 2 ** 37);
  assert.equal(bigToF32(2n ** 60n + 2n ** 36n), 2 ** 60);
});

/**
 * SPI1 as rp2040-hal sets it up at 62.5 MHz, with the harness's wire, and
 * DMA channel 0 started on `n` bytes from SRAM to SSPDR, paced by
 * `treq`. Returns what the test reads back.
 */
function dmaToSpi(n, treq) {
  const mcu = new RP2040();
  mcu.logger = new ConsoleLogger(LogLevel.Error, true);
  const sent = [];
  const wire = attachWire(mcu, 1, {
    fail: (m) => assert.fail(m),
    onByte: (v) => sent.push([mcu.clock.nanos, v]),
  });
  // From the 125 MHz clk_peri: prescale 2, SCR 0, 8-bit frames, mode 3,
  // TX DMA on, enabled.
  const SPI1 = 0x40040000;
  mcu.writeUint32(SPI1 + 0x10, 2); // SSPCPSR
  mcu.writeUint32(SPI1 + 0x00, 7 | (1 << 6) | (1 << 7)); // SSPCR0
  mcu.writeUint32(SPI1 + 0x24, 1 << 1); // SSPDMACR: TXDMAE
  mcu.writeUint32(SPI1 + 0x04, 1 << 1); // SSPCR1: SSE
  const src = 0x20001000;
  for (let i = 0; i < n; i++) mcu.writeUint8(src + i, (i * 37 + 5) & 0xff);
  // As rp2040-hal's single_buffer transfer configures a channel.
  const DMA = 0x50000000;
  mcu.writeUint32(DMA + 0x00, src); // READ_ADDR
  mcu.writeUint32(DMA + 0x04, SPI1 + 0x08); // WRITE_ADDR: SSPDR
  mcu.writeUint32(DMA + 0x08, n); // TRANS_COUNT
  // CTRL_TRIG: EN, byte transfers, INCR_READ, TREQ_SEL, chained to itself
  // (no chaining); the write starts the channel.
  mcu.writeUint32(DMA + 0x0c, 1 | (1 << 4) | (treq << 15));
  return {
    mcu,
    sent,
    wire,
    dmaBusy: () => (mcu.readUint32(DMA + 0x0c) >>> 24) & 1,
    spiBusy: () => (mcu.readUint32(SPI1 + 0x0c) >>> 4) & 1, // SSPSR.BSY
  };
}

test('DMA into SPI1 goes at the wire\'s pace: paced by TX DREQ, a byte every 8 SPI clocks', () => {
  const N = 100;
  const { mcu, sent, wire, dmaBusy, spiBusy } = dmaToSpi(N, 18); // DREQ_SPI1_TX
  assert.equal(dmaBusy(), 1);
  // 62.5 MHz: a byte is 128 ns, 16 cycles at 125 MHz.
  const byteNs = 128;
  let dmaDoneAt = null;
  let queuedAtDone = null;
  for (let t = 0; t < (N + 4) * byteNs; t += 8) {
    mcu.clock.tick(8);
    if (dmaDoneAt === null && !dmaBusy()) {
      dmaDoneAt = mcu.clock.nanos;
      queuedAtDone = N - sent.length;
      // The channel is done when it has written its last byte into the
      // FIFO: the SPI is still sending.
      assert.equal(spiBusy(), 1, 'the SPI still busy when the DMA is done');
    }
  }
  assert.equal(sent.length, N, 'every byte sent, none lost to a full FIFO');
  sent.forEach(([at, v], i) => {
    assert.equal(v, (i * 37 + 5) & 0xff, `byte ${i}`);
    assert.equal(at, (i + 1) * byteNs, `byte ${i} on the wire at the byte time`);
  });
  assert.equal(Math.round(wire.busyCycles), N * 16);
  // Done as the last byte entered the FIFO, with the shifter's byte and a
  // full FIFO behind it: 9 bytes still to go.
  assert.equal(queuedAtDone, 9);
  assert.equal(dmaDoneAt, (N - 9) * byteNs);
  assert.equal(spiBusy(), 0);
});

test('an unpaced DMA channel overruns the SPI FIFO, and the wire says so', () => {
  // TREQ_SEL 0x3f: as fast as the DMA can go.
  assert.throws(() => dmaToSpi(100, 0x3f).mcu.clock.tick(1), /full TX FIFO: the byte is lost/);
});
