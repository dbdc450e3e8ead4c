// The harness's own models, checked without a firmware:
//   node --test tests/pico/
// The panel must refuse a malformed command stream, and the stub ROM must
// round as the RP2040's does.

import { test } from 'node:test';
import assert from 'node:assert/strict';
import { RP2040 } from 'rp2040js';
import { ST7789 } from './st7789.mjs';
import { buildBootrom, bits, f32, bigToF32 } from './bootrom.mjs';

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
