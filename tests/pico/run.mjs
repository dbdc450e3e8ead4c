// Runs the Raspberry Pi Pico firmware `examples/rp2040_st7789.rs` in
// rp2040js with the stub boot ROM (bootrom.mjs) and an ST7789 on SPI1
// (st7789.mjs), until it has drawn the frames asked for.
//
//   node tests/pico/run.mjs ELF [--frames N] [--out DIR] [--max-cycles C] [--serial] [--frame-us N]
//   node tests/pico/run.mjs ELF --bench [--max-cycles C]
//   ... [--profile FILE]
//
// Writes DIR/frame_NNN.rgb565 (what the panel shows after frame N:
// 240x240 big-endian Rgb565) and DIR/report.json, and prints a line per
// frame and the peak stack. Exits with status 1 and a message on the first
// thing a panel or a Pico would not do (see st7789.mjs, bootrom.mjs,
// wire.mjs).
//
// The wiring is the firmware's: SCK GP10, TX GP11 (SPI1), CS GP9, DC GP8,
// RES GP12, backlight GP13.
//
// `--serial` sets the firmware's flash byte `MICRORASTER_PICO_SERIAL` to 1
// in the image it loads: the firmware then waits for each tile to leave
// the wire before it draws the next, instead of drawing it while DMA sends
// the previous one. That run's idle wire is the render alone.
//
// `--frame-us N` sets the firmware's flash word `MICRORASTER_PICO_FRAME_US`:
// frame k then shows the animation at k N microseconds, whatever the
// frames took, so that a run with `--serial` and one without draw the same
// frames and their cycles compare exactly.
//
// `--bench` runs the benchmark firmware `examples/rp2040_bench.rs` instead,
// which renders scenes into a `NullSink` and marks each frame with `bkpt`s
// of its own (see that file): the harness charges the cycles from a
// frame's start mark to its end mark to the frame, prints a line per frame
// (with its `FrameStats`, as the host's `examples/count.rs` prints them)
// and a table of cycles per frame for each scene and size, against the
// time the frame's Rgb565 pixels would take on SPI at 62.5 MHz (16
// system-clock cycles a byte at 125 MHz), until the firmware says it is
// done.
//
// Timing. rp2040js charges each instruction its Cortex-M0+ cycles (and a
// few for peripheral accesses) and keeps the clock by them; nothing is
// charged for XIP cache misses, and the ROM's routines cost the nominal
// figures of bootrom.mjs. The SPI takes 8 SPI clocks a byte at the baud
// rate the firmware set, and a DMA channel that feeds it is paced by its
// TX DREQ, so by that byte time (wire.mjs), so the firmware waits for the
// wire as on a Pico. For every frame the report has, in system-clock
// cycles:
//   period: from the end of the previous frame's last pixel to the end of
//           this one's (frame 0: from the end of the panel's set-up);
//   spi:    how long the SPI was sending in that period (transfer);
//   idle:   period - spi, when the wire was idle. With `--serial` (the
//           firmware renders a tile, then sends it, tile after tile) the
//           render time. Without, the firmware sends the tiles it has
//           drawn by DMA while it renders the next: the period is the
//           overlapped frame and idle what the overlap did not hide.
//
// `--profile FILE` charges every cycle after the first frame (with
// `--bench`, every cycle) to the function whose code
// holds the PC (the ELF's function symbols; cycles the core spends
// asleep to `(asleep)`, the stub ROM's routines to `(boot ROM)`), and
// writes a table of the functions by cycles to FILE, names as mangled.

import { readFileSync, writeFileSync, mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { RP2040, ConsoleLogger, LogLevel } from 'rp2040js';
import { buildBootrom } from './bootrom.mjs';
import { ST7789, WIDTH, HEIGHT } from './st7789.mjs';
import { attachWire } from './wire.mjs';

const PIN_DC = 8;
const PIN_CS = 9;
const PIN_RES = 12;
const SPI = 1;
/** The firmware's flash byte that `--serial` sets. */
const SERIAL = 'MICRORASTER_PICO_SERIAL';
/** The firmware's flash word that `--frame-us` sets. */
const FRAME_US = 'MICRORASTER_PICO_FRAME_US';

function parseArgs(argv) {
  const args = {
    frames: 1,
    out: null,
    maxCycles: null,
    elf: null,
    serial: false,
    frameUs: 0,
    bench: false,
    profile: null,
  };
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === '--frames') args.frames = Number(argv[++i]);
    else if (a === '--out') args.out = argv[++i];
    else if (a === '--max-cycles') args.maxCycles = Number(argv[++i]);
    else if (a === '--serial') args.serial = true;
    else if (a === '--frame-us') args.frameUs = Number(argv[++i]);
    else if (a === '--bench') args.bench = true;
    else if (a === '--profile') args.profile = argv[++i];
    else if (!args.elf && !a.startsWith('--')) args.elf = a;
    else throw new Error(`unknown argument ${a}`);
  }
  if (!args.elf || !(args.frames >= 1) || !(Number.isInteger(args.frameUs) && args.frameUs >= 0 && args.frameUs < 2 ** 32)) {
    throw new Error(
      'usage: node run.mjs ELF [--frames N] [--out DIR] [--max-cycles C] [--serial] [--frame-us N], or node run.mjs ELF --bench [--max-cycles C]',
    );
  }
  return args;
}

/**
 * Every entry of the ELF's symbol table (`.symtab`) at `path`:
 * `{ name, value, size, info }`.
 */
function elfSymbolTable(path) {
  const elf = readFileSync(path);
  const shoff = elf.readUInt32LE(32);
  const shentsize = elf.readUInt16LE(46);
  const shnum = elf.readUInt16LE(48);
  const section = (i) => {
    const sh = shoff + i * shentsize;
    return {
      type: elf.readUInt32LE(sh + 4),
      offset: elf.readUInt32LE(sh + 16),
      size: elf.readUInt32LE(sh + 20),
      link: elf.readUInt32LE(sh + 24),
      entsize: elf.readUInt32LE(sh + 36),
    };
  };
  const out = [];
  for (let i = 0; i < shnum; i++) {
    const symtab = section(i);
    if (symtab.type !== 2) continue; // SHT_SYMTAB
    const strtab = section(symtab.link);
    for (let off = symtab.offset; off < symtab.offset + symtab.size; off += symtab.entsize) {
      const nameStart = strtab.offset + elf.readUInt32LE(off);
      out.push({
        name: elf.toString('latin1', nameStart, elf.indexOf(0, nameStart)),
        value: elf.readUInt32LE(off + 4),
        size: elf.readUInt32LE(off + 8),
        info: elf.readUInt8(off + 12),
      });
    }
  }
  return out;
}

/**
 * The value of each of `names` in the ELF's symbol table, by name; a
 * missing one is an error.
 */
function elfSymbols(path, names) {
  const found = {};
  for (const sym of elfSymbolTable(path)) {
    if (names.includes(sym.name)) found[sym.name] = sym.value;
  }
  for (const n of names) {
    if (!(n in found)) throw new Error(`${path} has no symbol ${n}`);
  }
  return found;
}

/** The function symbols of the ELF at `path`: sorted `{ start, end, name }`. */
function elfFunctions(path) {
  const out = [];
  for (const { name, value, size, info } of elfSymbolTable(path)) {
    if ((info & 0xf) !== 2) continue; // STT_FUNC
    const start = (value & ~1) >>> 0;
    out.push({ start, end: start + size, name });
  }
  // A function without a size (hand-written assembly, such as a HAL's
  // intrinsics) ends where the next one starts.
  out.sort((a, b) => a.start - b.start);
  out.forEach((f, i) => {
    if (f.end === f.start) f.end = out[i + 1]?.start ?? f.start + 1;
  });
  return out;
}

/** The cycles charged to each PC, summed by function into a table. */
function profileTable(byPc, functions, asleep) {
  const totals = new Map();
  const find = (pc) => {
    let lo = 0;
    let hi = functions.length - 1;
    while (lo <= hi) {
      const mid = (lo + hi) >> 1;
      const f = functions[mid];
      if (pc < f.start) hi = mid - 1;
      else if (pc >= f.end) lo = mid + 1;
      else return f.name;
    }
    return pc < 0x4000 ? '(boot ROM)' : `(0x${pc.toString(16)})`;
  };
  for (const [pc, c] of byPc) {
    const name = find(pc);
    totals.set(name, (totals.get(name) ?? 0) + c);
  }
  if (asleep) totals.set('(asleep)', asleep);
  const all = [...totals.values()].reduce((a, b) => a + b, 0);
  const rows = [...totals].sort((a, b) => b[1] - a[1]);
  const lines = [`total ${Math.round(all)} cycles`];
  for (const [name, c] of rows) {
    lines.push(`${Math.round(c).toString().padStart(11)} ${((100 * c) / all).toFixed(2).padStart(6)} %  ${name}`);
  }
  return lines.join('\n') + '\n';
}

// The peak stack, measured as on the QEMU boards (examples/stack_gauge):
// the RAM between the statics' end and the top of the stack is painted
// with a pattern before reset, and after the last frame the lowest word no
// longer holding it marks how deep the stack went. cortex-m-rt puts the
// stack at the top of RAM (`_stack_start`) growing down to `_stack_end`;
// nothing else writes that range (no heap). A lower bound, like every
// painted measurement: stack reserved but never written goes unseen.
const PAINT = 0xc5acce55;
const RAM_START = 0x20000000;

function paintStack(mcu, bottom, top) {
  for (let a = bottom; a < top; a += 4) mcu.sramView.setUint32(a - RAM_START, PAINT, true);
}

function peakStack(mcu, bottom, top) {
  let a = bottom;
  while (a < top && mcu.sramView.getUint32(a - RAM_START, true) === PAINT) a += 4;
  return top - a;
}

/** Copies the ELF's loadable segments to flash, by physical (load) address. */
function loadElf(mcu, path) {
  const elf = readFileSync(path);
  if (elf.readUInt32BE(0) !== 0x7f454c46 || elf[4] !== 1 || elf[5] !== 1 || elf.readUInt16LE(18) !== 40) {
    throw new Error(`${path} is not a 32-bit little-endian Arm ELF`);
  }
  const phoff = elf.readUInt32LE(28);
  const phentsize = elf.readUInt16LE(42);
  const phnum = elf.readUInt16LE(44);
  let bytes = 0;
  for (let i = 0; i < phnum; i++) {
    const ph = phoff + i * phentsize;
    const type = elf.readUInt32LE(ph);
    const offset = elf.readUInt32LE(ph + 4);
    const paddr = elf.readUInt32LE(ph + 12);
    const filesz = elf.readUInt32LE(ph + 16);
    if (type !== 1 || filesz === 0) continue; // PT_LOAD with contents
    if (paddr < 0x10000000 || paddr + filesz > 0x10000000 + mcu.flash.length) {
      throw new Error(`segment at 0x${paddr.toString(16)} is not in flash`);
    }
    mcu.flash.set(elf.subarray(offset, offset + filesz), paddr - 0x10000000);
    bytes += filesz;
  }
  if (bytes === 0) throw new Error(`${path} has nothing to load`);
  return bytes;
}

/** The SPI clock of the Pico firmware, for the frames' transfer times. */
const BENCH_SPI_HZ = 62.5e6;
const BENCH_SCENES = ['demo', 'rock'];
/** `FrameStats`' fields, in the order the firmware sends them. */
const FRAME_STATS = [
  'triangles_in', 'culled', 'rejected', 'clipped', 'drawn', 'pixels_shaded', 'tiles', 'bin_passes',
  'rescanned_tiles', 'draws_culled', 'clusters_culled', 'vertices', 'vertex_slots', 'tile_pairs',
  'peak_bin_entries', 'peak_tiles_per_pass',
];

/** The benchmark firmware's marks (`examples/rp2040_bench.rs`). */
class Bench {
  constructor(mcu, cyclesNow, romCycles, fail) {
    Object.assign(this, { mcu, cyclesNow, romCycles, fail });
    this.frames = [];
    this.open = null; // the frame under way
    this.done = false;
  }

  onBreak(n) {
    const r = this.mcu.core.registers;
    const now = this.cyclesNow();
    if (n === 0x60) {
      if (this.open) this.fail('a frame started inside another');
      const scene = BENCH_SCENES[r[0]] ?? this.fail(`unknown scene ${r[0]}`);
      this.open = { scene, width: r[1], height: r[2], start: now, rom0: this.romCycles() };
    } else if (n === 0x61) {
      if (!this.open || this.open.cycles !== undefined) this.fail('a frame ended that had not started');
      this.open.cycles = Math.round(now - this.open.start);
      this.open.rom = this.romCycles() - this.open.rom0;
    } else if (n === 0x62) {
      const f = this.open;
      if (!f || f.cycles === undefined) this.fail('statistics outside a frame');
      const at = r[0] >>> 0;
      f.stats = FRAME_STATS.map((k, i) => `${k}=${this.mcu.readUint32(at + 4 * i)}`).join(' ');
      this.frames.push(f);
      this.open = null;
      console.log(`${f.scene} ${f.width}x${f.height}: ${f.cycles} cycles (ROM stubs ${f.rom}); ${f.stats}`);
    } else if (n === 0x6f) {
      if (this.open) this.fail('done inside a frame');
      this.done = true;
    } else if (n === 0x6e) {
      this.fail(`the benchmark firmware failed with code ${r[0]} (examples/rp2040_bench.rs)`);
    } else {
      this.fail(`bkpt #0x${n.toString(16)} in flash: not a benchmark mark`);
    }
  }

  /** The table: per scene and size, cycles per frame against the SPI. */
  print(clkSys) {
    const groups = new Map();
    for (const f of this.frames) {
      const key = `${f.scene} ${f.width}x${f.height}`;
      if (!groups.has(key)) groups.set(key, []);
      groups.get(key).push(f);
    }
    const sep = (n) => Math.round(n).toLocaleString('en-US');
    let spread = 0;
    console.log(`\n| Scene | Size | Cycles per frame | ms at ${clkSys / 1e6} MHz | fps | SPI frame (cycles, ms) | x SPI |`);
    console.log('|---|---|---:|---:|---:|---:|---:|');
    for (const [, fs] of groups) {
      // The frames of a scene and size are the same frame: the same
      // statistics, and cycles within a few of each other (the mean is
      // shown).
      const f = fs[0];
      const all = fs.map((g) => g.cycles);
      const [lo, hi] = [Math.min(...all), Math.max(...all)];
      if (fs.some((g) => g.stats !== f.stats) || hi - lo > hi / 1000) {
        this.fail(`${f.scene} ${f.width}x${f.height}: the same frame took ${lo} to ${hi} cycles, or differs`);
      }
      const cycles = all.reduce((x, y) => x + y, 0) / all.length;
      spread = Math.max(spread, hi - lo);
      const ms = (cycles / clkSys) * 1e3;
      // Rgb565: 2 bytes a pixel, 8 SPI clocks a byte.
      const spi = ((f.width * f.height * 2 * 8) / BENCH_SPI_HZ) * clkSys;
      const spiMs = (spi / clkSys) * 1e3;
      console.log(
        `| \`${f.scene}\` | ${f.width}x${f.height} | ${sep(cycles)} | ${ms.toFixed(1)} | ${(1e3 / ms).toFixed(1)} | ` +
          `${sep(spi)} (${spiMs.toFixed(2)} ms) | ${(cycles / spi).toFixed(1)}x |`,
      );
    }
    console.log(
      `(${this.frames.length} frames; the frames of a scene and size had the same FrameStats ` +
        `and differed by at most ${spread} cycles)`,
    );
  }
}

function main() {
  const args = parseArgs(process.argv.slice(2));
  const mcu = new RP2040();
  // The default logger throws on errors; warnings (unimplemented
  // peripherals the firmware does not use) are only noise here.
  mcu.logger = new ConsoleLogger(LogLevel.Error, true);

  let cycles = 0; // system-clock cycles since reset
  let charged = 0; // cycles a ROM stub stands for, not yet on the clock
  const fail = (message) => {
    throw new Error(message);
  };
  let romCycles = 0; // of them, in the current frame, for the report
  const charge = (c) => {
    charged += c;
    romCycles += c;
  };
  const rom = buildBootrom(mcu, { fail, charge });
  // The ROM first: loadBootrom resets the chip, which erases the flash.
  mcu.loadBootrom(rom.image);
  const flashBytes = loadElf(mcu, args.elf);
  if (args.serial) {
    // A byte of .rodata, in flash: its link address is its load address.
    const { [SERIAL]: at } = elfSymbols(args.elf, [SERIAL]);
    if (at < 0x10000000 || at >= 0x10000000 + mcu.flash.length) {
      throw new Error(`${SERIAL} at 0x${at.toString(16)} is not in flash`);
    }
    if (mcu.flash[at - 0x10000000] !== 0) throw new Error(`${SERIAL} is not 0 in the image`);
    mcu.flash[at - 0x10000000] = 1;
  }
  if (args.frameUs) {
    // A word of .rodata, in flash: frame k is drawn at k * N microseconds.
    const { [FRAME_US]: at } = elfSymbols(args.elf, [FRAME_US]);
    if (at < 0x10000000 || at + 4 > 0x10000000 + mcu.flash.length || at % 4) {
      throw new Error(`${FRAME_US} at 0x${at.toString(16)} is not a word in flash`);
    }
    const word = new DataView(mcu.flash.buffer, mcu.flash.byteOffset + at - 0x10000000, 4);
    if (word.getUint32(0, true) !== 0) throw new Error(`${FRAME_US} is not 0 in the image`);
    word.setUint32(0, args.frameUs, true);
  }
  const stack = elfSymbols(args.elf, ['_stack_start', '_stack_end']);
  if (stack._stack_end % 4 || stack._stack_start % 4 || stack._stack_end >= stack._stack_start) {
    throw new Error(`stack bounds 0x${stack._stack_end.toString(16)}..0x${stack._stack_start.toString(16)}`);
  }
  paintStack(mcu, stack._stack_end, stack._stack_start);
  mcu.core.reset();
  // A `bkpt` in the ROM is a stub's; in flash, a benchmark mark (`--bench`).
  const bench = args.bench ? new Bench(mcu, () => cycles + charged, () => romCycles, fail) : null;
  mcu.onBreak = (n) => {
    const at = (mcu.core.PC - 2) >>> 0;
    if (bench && at >= 0x10000000 && at < 0x11000000) bench.onBreak(n);
    else rom.onBreak(n);
  };

  const clock = mcu.clock;
  const nsPerCycle = () => 1e9 / mcu.clkSys;

  // The panel and its pins.
  const panel = new ST7789(() => clock.nanos);
  const pin = (n) => mcu.gpio[n].outputValue;
  mcu.gpio[PIN_RES].addListener(() => {
    if (mcu.gpio[PIN_RES].outputEnable) panel.reset(pin(PIN_RES));
  });

  // The animation time the firmware read: the timer's low word, read last
  // before a frame's first byte.
  const timer = mcu.peripherals[0x40054];
  const timerRead = timer.readUint32.bind(timer);
  let lastTimeUs = null;
  timer.readUint32 = (offset) => {
    const v = timerRead(offset);
    if (offset === 0x28 || offset === 0x0c) lastTimeUs = v; // TIMERAWL, TIMELR
    return v;
  };

  // SPI1: a byte takes 8 SPI clocks (wire.mjs, which also says how DMA is
  // paced by it); the panel sees it when its last bit is clocked, with DC
  // and CS as they are then.
  const spi = mcu.spi[SPI];
  const wire = attachWire(mcu, SPI, {
    fail,
    onByte: (value) => {
      panel.byte(value, pin(PIN_DC), pin(PIN_CS));
      afterByte();
    },
  });

  // Frames: a frame is done when every pixel of the panel has been written
  // since the previous one was.
  const frames = [];
  const covered = new Uint8Array(WIDTH * HEIGHT);
  let coveredCount = 0;
  let frameStart = null; // { time_us, cycle } of the frame being sent
  let periodStart = null; // cycle of the end of the last frame (or set-up)
  let periodSpi = 0;
  panel.onPixel = (i) => {
    if (!covered[i]) {
      covered[i] = 1;
      coveredCount++;
    }
  };
  const cyclesNow = () => cycles + charged;
  function afterByte() {
    const last = panel.commands[panel.commands.length - 1];
    if (frameStart === null && last && last[1] === 'CASET' && panel.cmd === null) {
      // The first window of a frame.
      if (periodStart === null) {
        periodStart = cyclesNow();
        periodSpi = wire.busyCycles;
      }
      // The animation time the frame shows: the firmware's last timer
      // reading, or with --frame-us, the frame's index times N.
      const timeUs = args.frameUs ? frames.length * args.frameUs : lastTimeUs;
      frameStart = { time_us: timeUs, cycle: cyclesNow() };
    }
    if (coveredCount === WIDTH * HEIGHT && panel.windowFilled()) {
      const end = cyclesNow();
      const period = Math.round(end - periodStart);
      const spiCycles = Math.round(wire.busyCycles - periodSpi);
      const frame = {
        index: frames.length,
        time_us: frameStart.time_us,
        end_cycle: Math.round(end),
        period_cycles: period,
        spi_cycles: spiCycles,
        idle_cycles: period - spiCycles,
        rom_calls: Object.fromEntries(rom.calls),
        rom_cycles_charged: romCycles,
      };
      rom.calls.clear();
      romCycles = 0;
      frames.push(frame);
      const picture = panel.picture();
      if (args.out) writeFileSync(join(args.out, `frame_${String(frame.index).padStart(3, '0')}.rgb565`), picture);
      const ms = (c) => ((c * nsPerCycle()) / 1e6).toFixed(2);
      console.log(
        `frame ${frame.index}: t = ${frame.time_us} us; ${period} cycles (${ms(period)} ms), ` +
          `SPI ${spiCycles} (${ms(spiCycles)} ms), idle wire ${frame.idle_cycles} (${ms(frame.idle_cycles)} ms)`,
      );
      covered.fill(0);
      coveredCount = 0;
      frameStart = null;
      periodStart = end;
      periodSpi = wire.busyCycles;
    }
  }
  // The set-up's traffic ends the period before frame 0.
  const setupEnd = () => {
    if (periodStart === null) {
      periodStart = cyclesNow();
      periodSpi = wire.busyCycles;
    }
  };
  const panelCommand = panel.finishCommand.bind(panel);
  panel.finishCommand = () => {
    const was = panel.cmd;
    panelCommand();
    if (was === 0x29) setupEnd(); // DISPON
  };

  if (args.out) mkdirSync(args.out, { recursive: true });
  const maxCycles = args.maxCycles ?? (bench ? 2e9 : 200e6 + args.frames * 100e6);
  const started = Date.now();
  // `--profile`: cycles by PC, and asleep, once the first frame is done.
  const byPc = new Map();
  let asleep = 0;
  const profiling = () =>
    args.profile && (bench || frames.length > 0);
  try {
    while (bench ? !bench.done : frames.length < args.frames) {
      const profile = profiling();
      const pc = mcu.core.PC >>> 0;
      // A WFI executed while an enabled interrupt is already pending (it
      // became pending inside a critical section, PRIMASK set) does not
      // sleep on a Cortex-M0+: the ARMv6-M ARM (B1.5.19) wakes the core
      // for any pending interrupt that PRIMASK alone keeps from being
      // taken. rp2040js wakes it only for an interrupt raised while it
      // waits, so the firmware's `wfi` after finding no tile sent (when
      // the DMA finished between its look and the `wfi`) would sleep on.
      if (mcu.core.waiting && (mcu.core.pendingInterrupts & mcu.core.enabledInterrupts)) {
        mcu.core.waiting = false;
      }
      if (mcu.core.waiting) {
        if (!clock.nextAlarm) fail('the core sleeps with nothing to wake it');
        const ns = Math.max(clock.nanosToNextAlarm, 0);
        clock.tick(ns);
        cycles += ns / nsPerCycle();
        if (profile) asleep += ns / nsPerCycle();
      } else {
        const c = mcu.core.executeInstruction();
        cycles += c;
        clock.tick(c * nsPerCycle());
        if (profile) byPc.set(pc, (byPc.get(pc) ?? 0) + c + charged);
      }
      if (charged) {
        cycles += charged;
        clock.tick(charged * nsPerCycle());
        charged = 0;
      }
      if (cycles > maxCycles) {
        fail(
          bench
            ? `the benchmark is not done after ${maxCycles} cycles`
            : `${frames.length} of ${args.frames} frames after ${maxCycles} cycles`,
        );
      }
    }
  } catch (e) {
    const pc = (mcu.core.PC >>> 0).toString(16);
    const log = panel.commands.slice(-6).map((c) => c[1]).join(', ');
    console.error(`pico: ${e.message}\n  at cycle ${Math.round(cycles)}, PC 0x${pc}; last panel commands: ${log}`);
    process.exit(1);
  }
  if (args.profile) writeFileSync(args.profile, profileTable(byPc, elfFunctions(args.elf), asleep));
  if (bench) {
    bench.print(mcu.clkSys);
    console.log(
      `pico: benchmark done in ${Date.now() - started} ms of wall time; peak stack ` +
        `${peakStack(mcu, stack._stack_end, stack._stack_start)} B (painted and read back), ` +
        `statics ${stack._stack_end - RAM_START} B`,
    );
    return;
  }
  const report = {
    elf: args.elf,
    serial: args.serial,
    flash_bytes: flashBytes,
    clk_sys_hz: mcu.clkSys,
    spi_hz: spi.clockFrequency,
    wall_ms: Date.now() - started,
    static_ram_bytes: stack._stack_end - RAM_START,
    peak_stack_bytes: peakStack(mcu, stack._stack_end, stack._stack_start),
    setup: panel.commands.filter((c) => c[1] !== 'CASET' && c[1] !== 'RASET' && c[1] !== 'RAMWR')
      .map((c) => [Math.round(c[0] / 1000), c[1], c[2]]),
    frames,
  };
  if (args.out) writeFileSync(join(args.out, 'report.json'), JSON.stringify(report, null, 1));
  const mode = args.serial ? ' with --serial (each tile on the wire before the next is drawn)' : '';
  console.log(`pico: ${frames.length} frames${mode} in ${report.wall_ms} ms of wall time`);
  console.log(
    `pico: peak stack ${report.peak_stack_bytes} B (painted and read back), ` +
      `statics ${report.static_ram_bytes} B`,
  );
}

main();
