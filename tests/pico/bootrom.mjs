// A small RP2040 boot ROM for rp2040js, generated at start-up: no
// third-party binary is needed or committed.
//
// What it holds (RP2040 datasheet, section 2.8, "Bootrom"):
// - a vector table at 0 whose reset handler, written in Thumb below, does
//   what boot2 does in the end: VTOR = 0x10000100 (the firmware's vector
//   table, after the 256 bytes of boot2), then SP and PC from it. rp2040js
//   reads XIP flash without the SSI being set up, so boot2 is not run;
// - the 'Mu' magic and the ROM version at 0x10, the function and data table
//   pointers at 0x14 and 0x16, and `rom_table_lookup` at 0x18;
// - the public functions a Rust firmware uses (rp2040-hal's intrinsics look
//   them up before each call) and the soft-float table of the data table.
//
// Each function is a two-instruction stub, `bkpt #n; bx lr`: the `bkpt`
// traps into JavaScript, which computes the result into r0 (and r1) and
// charges an estimate of the real routine's cycles; then `bx lr` returns.
// A lookup of anything the stub does not provide, or a call of a table entry
// it does not implement, is an error that ends the run: the firmware never
// gets a wrong answer silently.
//
// The arithmetic is the real ROM's as documented: correctly rounded IEEE
// single precision for + - * / and sqrt, and the float-to-integer
// conversions round towards -Infinity (not towards zero as Rust's `as`
// does) and clamp. That is what rp2040-hal's `__aeabi_f2iz` (`f32 as i32`)
// calls, so a firmware that casts a negative fraction gets here what it
// gets on a Pico.

const ROM_VERSION = 3; // RP2040-B2, what Picos ship with
const SP_TOP = 0x20042000;
const FIRMWARE_VECTORS = 0x10000100;

const f32buf = new DataView(new ArrayBuffer(4));
/** The f32 whose bits are `u`, as a JS number. */
export function f32(u) {
  f32buf.setUint32(0, u >>> 0, true);
  return f32buf.getFloat32(0, true);
}
/** The bits of `x` rounded to f32. */
export function bits(x) {
  f32buf.setFloat32(0, x, true);
  return f32buf.getUint32(0, true);
}

/** floor(x) clamped to [lo, hi]; NaN gives 0. */
function floorClamp(x, lo, hi) {
  if (Number.isNaN(x)) return 0;
  const f = Math.floor(x);
  return f < lo ? lo : f > hi ? hi : f;
}

/** The BigInt `v` rounded to the nearest f32 (ties to even), exactly:
 * converting through a double would round twice. */
export function bigToF32(v) {
  if (v === 0n) return 0;
  const neg = v < 0n;
  let m = neg ? -v : v;
  const len = m.toString(2).length;
  let x;
  if (len <= 24) {
    x = Number(m);
  } else {
    const shift = BigInt(len - 24);
    let top = m >> shift;
    const rest = m - (top << shift);
    const half = 1n << (shift - 1n);
    if (rest > half || (rest === half && (top & 1n) === 1n)) top += 1n;
    x = Number(top) * 2 ** (len - 24); // exact: top <= 2^24
  }
  return neg ? -x : x;
}

function splitI64(v) {
  const u = BigInt.asUintN(64, v);
  return [Number(u & 0xffffffffn), Number(u >> 32n)];
}
function joinI64(lo, hi) {
  return BigInt.asIntN(64, (BigInt(hi >>> 0) << 32n) | BigInt(lo >>> 0));
}
function joinU64(lo, hi) {
  return (BigInt(hi >>> 0) << 32n) | BigInt(lo >>> 0);
}

const I32_MIN = -(2 ** 31);
const I32_MAX = 2 ** 31 - 1;
const U32_MAX = 2 ** 32 - 1;
const I64_MIN = -(2n ** 63n);
const I64_MAX = 2n ** 63n - 1n;

function floorBig(x, lo, hi) {
  if (Number.isNaN(x)) return 0n;
  if (x === Infinity) return hi;
  if (x === -Infinity) return lo;
  const f = BigInt(Math.floor(x)); // x is an f32: exact in a double
  return f < lo ? lo : f > hi ? hi : f;
}

// The soft-float table (datasheet table "Bootrom soft float table"), by
// byte offset. `cycles` is a nominal charge per call, of the order of the
// datasheet's averages; the emulator does not run the real routines.
const SOFT_FLOAT = {
  0x00: { name: 'fadd', cycles: 70, fn: (r) => [bits(f32(r[0]) + f32(r[1]))] },
  0x04: { name: 'fsub', cycles: 70, fn: (r) => [bits(f32(r[0]) - f32(r[1]))] },
  0x08: { name: 'fmul', cycles: 55, fn: (r) => [bits(f32(r[0]) * f32(r[1]))] },
  0x0c: { name: 'fdiv', cycles: 75, fn: (r) => [bits(f32(r[0]) / f32(r[1]))] },
  0x18: {
    name: 'fsqrt',
    cycles: 80,
    fn: (r) => [bits(f32(r[0]) < 0 ? -Infinity : Math.sqrt(f32(r[0])))],
  },
  0x1c: {
    name: 'float_to_int',
    cycles: 25,
    fn: (r) => [floorClamp(f32(r[0]), I32_MIN, I32_MAX) >>> 0],
  },
  0x20: {
    name: 'float_to_fix',
    cycles: 25,
    fn: (r) => [floorClamp(f32(r[0]) * 2 ** (r[1] | 0), I32_MIN, I32_MAX) >>> 0],
  },
  0x24: { name: 'float_to_uint', cycles: 25, fn: (r) => [floorClamp(f32(r[0]), 0, U32_MAX) >>> 0] },
  0x28: {
    name: 'float_to_ufix',
    cycles: 25,
    fn: (r) => [floorClamp(f32(r[0]) * 2 ** (r[1] | 0), 0, U32_MAX) >>> 0],
  },
  0x2c: { name: 'int_to_float', cycles: 25, fn: (r) => [bits(r[0] | 0)] },
  0x30: { name: 'fix_to_float', cycles: 25, fn: (r) => [bits((r[0] | 0) / 2 ** (r[1] | 0))] },
  0x34: { name: 'uint_to_float', cycles: 25, fn: (r) => [bits(r[0] >>> 0)] },
  0x38: { name: 'ufix_to_float', cycles: 25, fn: (r) => [bits((r[0] >>> 0) / 2 ** (r[1] | 0))] },
  0x3c: { name: 'fcos', cycles: 0 },
  0x40: { name: 'fsin', cycles: 0 },
  0x44: { name: 'ftan', cycles: 0 },
  0x4c: { name: 'fexp', cycles: 0 },
  0x50: { name: 'fln', cycles: 0 },
  0x54: {
    name: 'fcmp',
    cycles: 25,
    fn: (r) => {
      const a = f32(r[0]);
      const b = f32(r[1]);
      return [a < b ? 0xffffffff : a > b ? 1 : 0];
    },
  },
  0x58: { name: 'fatan2', cycles: 0 },
  0x5c: { name: 'int64_to_float', cycles: 35, fn: (r) => [bits(bigToF32(joinI64(r[0], r[1])))] },
  0x60: { name: 'fix64_to_float', cycles: 0 },
  0x64: { name: 'uint64_to_float', cycles: 35, fn: (r) => [bits(bigToF32(joinU64(r[0], r[1])))] },
  0x68: { name: 'ufix64_to_float', cycles: 0 },
  0x6c: {
    name: 'float_to_int64',
    cycles: 40,
    fn: (r) => splitI64(floorBig(f32(r[0]), I64_MIN, I64_MAX)),
  },
  0x70: { name: 'float_to_fix64', cycles: 0 },
  0x74: {
    name: 'float_to_uint64',
    cycles: 40,
    fn: (r) => splitI64(floorBig(f32(r[0]), 0n, 2n ** 64n - 1n)),
  },
  0x78: { name: 'float_to_ufix64', cycles: 0 },
  0x7c: { name: 'float_to_double', cycles: 0 },
};
const SOFT_FLOAT_ENTRIES = 0x80 / 4;

/** Two ASCII characters as a table code, as the ROM stores them. */
const code = (s) => s.charCodeAt(0) | (s.charCodeAt(1) << 8);

// The function table. Memory functions charge about what the real ROM's
// unrolled loops take: a word per cycle and a half, a byte per three.
const FUNCTIONS = {
  P3: { name: 'popcount32', cycles: 20, fn: (r) => [popcount(r[0])] },
  R3: { name: 'reverse32', cycles: 20, fn: (r) => [reverse(r[0])] },
  L3: { name: 'clz32', cycles: 15, fn: (r) => [Math.clz32(r[0])] },
  T3: { name: 'ctz32', cycles: 15, fn: (r) => [r[0] === 0 ? 32 : 31 - Math.clz32(r[0] & -r[0])] },
  MS: { name: 'memset', mem: 'set', perWord: 0 },
  S4: { name: 'memset4', mem: 'set', perWord: 1 },
  MC: { name: 'memcpy', mem: 'copy', perWord: 0 },
  C4: { name: 'memcpy44', mem: 'copy', perWord: 1 },
};

function popcount(v) {
  let n = 0;
  for (let x = v >>> 0; x; x &= x - 1) n++;
  return n;
}
function reverse(v) {
  let r = 0;
  for (let i = 0; i < 32; i++) r = (r << 1) | ((v >>> i) & 1);
  return r >>> 0;
}

/**
 * Builds the ROM and returns `{ image, onBreak }`: `image` for
 * `rp2040.loadBootrom`, and the `bkpt` handler to install as
 * `rp2040.onBreak` once the firmware is loaded. `hooks.fail(message)` ends
 * the run; `hooks.charge(cycles)` adds the cycles a stub routine stands for.
 */
export function buildBootrom(mcu, hooks) {
  const rom = new Uint8Array(16 * 1024);
  const view = new DataView(rom.buffer);
  const h16 = (addr, v) => view.setUint16(addr, v, true);
  const w32 = (addr, v) => view.setUint32(addr, v >>> 0, true);

  const traps = []; // bkpt number -> { name, run(regs) }
  let next = 0x200; // code grows from here
  const stub = (trap) => {
    const addr = next;
    const n = traps.length;
    if (n > 0xfe) throw new Error('too many ROM traps');
    traps.push(trap);
    h16(addr, 0xbe00 | n); // bkpt #n
    h16(addr + 2, 0x4770); // bx lr
    next += 4;
    return addr | 1; // a Thumb function pointer
  };

  // Vector table: SP, reset, then NMI and HardFault as traps that fail.
  const fault = (what) => stub({ name: what, run: () => hooks.fail(`the core took a ${what}`) });
  w32(0x00, SP_TOP);
  w32(0x04, 0x100 | 1);
  w32(0x08, fault('NMI'));
  w32(0x0c, fault('HardFault'));

  // Magic, version.
  rom[0x10] = 0x4d; // 'M'
  rom[0x11] = 0x75; // 'u'
  rom[0x12] = 0x01;
  rom[0x13] = ROM_VERSION;

  // Reset handler at 0x100, Thumb:
  //   ldr r0, =0x10000100 ; ldr r1, =0xe000ed08 ; str r0, [r1]
  //   ldr r1, [r0] ; msr msp, r1 ; ldr r1, [r0, #4] ; bx r1
  // with its two literals at 0x110 and 0x114.
  const reset = [
    0x4803, // ldr r0, [pc, #12]  (0x100 + 4 + 12 = 0x110)
    0x4904, // ldr r1, [pc, #16]  (0x104 + 16 = 0x114)
    0x6008, // str r0, [r1]
    0x6801, // ldr r1, [r0]
    0xf381, 0x8808, // msr msp, r1
    0x6841, // ldr r1, [r0, #4]
    0x4708, // bx r1
  ];
  reset.forEach((op, i) => h16(0x100 + 2 * i, op));
  w32(0x110, FIRMWARE_VECTORS);
  w32(0x114, 0xe000ed08); // VTOR

  // rom_table_lookup(table, code): walks the (code, pointer) table.
  const lookup = stub({
    name: 'rom_table_lookup',
    cycles: 30,
    run: (r) => {
      const table = r[0] >>> 0;
      const wanted = r[1] & 0xffff;
      for (let a = table; a + 3 < rom.length; a += 4) {
        const c = view.getUint16(a, true);
        if (c === 0) break;
        if (c === wanted) return [view.getUint16(a + 2, true)];
      }
      const name = String.fromCharCode(wanted & 0xff, wanted >> 8);
      return hooks.fail(`rom_table_lookup: the stub ROM has no '${name}' in the table at 0x${table.toString(16)}`);
    },
  });

  // The soft-float table: one stub per entry.
  const sfTable = next;
  next += SOFT_FLOAT_ENTRIES * 4;
  for (let i = 0; i < SOFT_FLOAT_ENTRIES; i++) {
    const e = SOFT_FLOAT[i * 4];
    const name = e ? e.name : `soft-float entry 0x${(i * 4).toString(16)}`;
    const trap = e && e.fn
      ? { name, cycles: e.cycles, run: e.fn }
      : { name, run: () => hooks.fail(`the firmware called the ROM's ${name}, which the stub does not implement`) };
    w32(sfTable + i * 4, stub(trap));
  }

  // The function table.
  const funcEntries = [];
  for (const [c, f] of Object.entries(FUNCTIONS)) {
    let run = f.fn;
    if (f.mem) run = memFunction(mcu, f, hooks);
    funcEntries.push([code(c), stub({ name: f.name, cycles: f.cycles ?? 0, run })]);
  }
  const funcTable = next;
  for (const [c, p] of funcEntries) {
    h16(next, c);
    h16(next + 2, p);
    next += 4;
  }
  w32(next, 0);
  next += 4;

  // The data table: the soft-float table only (no 'SD': rp2040-hal routes
  // no double to the ROM without its `rom-v2-intrinsics` feature).
  const dataTable = next;
  h16(next, code('SF'));
  h16(next + 2, sfTable);
  w32(next + 4, 0);
  next += 8;

  h16(0x14, funcTable);
  h16(0x16, dataTable);
  h16(0x18, lookup);

  if (next > rom.length) throw new Error('ROM overflow');
  const calls = new Map(); // name -> count, for the report

  return {
    image: new Uint32Array(rom.buffer),
    calls,
    onBreak(n) {
      const trap = traps[n];
      if (!trap) {
        hooks.fail(`bkpt #${n} at 0x${((mcu.core.PC - 2) >>> 0).toString(16)} (not a ROM stub)`);
        return;
      }
      calls.set(trap.name, (calls.get(trap.name) ?? 0) + 1);
      const regs = mcu.core.registers;
      const out = trap.run([regs[0] >>> 0, regs[1] >>> 0, regs[2] >>> 0, regs[3] >>> 0]);
      if (!out) return;
      regs[0] = out[0] >>> 0;
      if (out.length > 1) regs[1] = out[1] >>> 0;
      if (trap.cycles) hooks.charge(trap.cycles);
    },
  };
}

/** memset / memset4 / memcpy / memcpy44 on the emulated memory. */
function memFunction(mcu, f, hooks) {
  return (r) => {
    const [dst, src, n] = r;
    if (f.perWord && dst & 3) hooks.fail(`${f.name} to 0x${dst.toString(16)}, not word-aligned`);
    if (f.mem === 'set') {
      for (let i = 0; i < n; i++) mcu.writeUint8(dst + i, src & 0xff);
    } else {
      if (f.perWord && src & 3) hooks.fail(`${f.name} from 0x${src.toString(16)}, not word-aligned`);
      for (let i = 0; i < n; i++) mcu.writeUint8(dst + i, mcu.readUint8(src + i));
    }
    hooks.charge(10 + (f.perWord ? Math.ceil((n * 3) / 8) : n * 3));
    return [dst];
  };
}
