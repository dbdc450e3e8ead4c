// A model of a 240x240 ST7789 panel on a 4-line SPI bus: it decodes the
// command stream (the D/CX pin tells a command byte from a data byte, CSX
// must be low) into the panel's memory, and refuses what a panel would not
// do what the firmware means by: an unknown command, a command with the
// wrong number of parameters, pixels outside the window or before the
// pixel format is 16 bits, a command during a reset or too soon after one
// (ST7789V datasheet: 5 ms after a reset or SLPOUT, 120 ms before SLPOUT
// after a reset).
//
// The panel is an IPS one, which shows colours right only with INVON
// (mipidsi's `ColorInversion::Inverted`): without it the picture is shown
// inverted, and the model shows it so.

export const WIDTH = 240;
export const HEIGHT = 240;
/** The controller's memory: 240 columns by 320 rows. */
const MEM_ROWS = 320;

// Commands: name and number of parameter bytes (null: RAMWR, any number).
const COMMANDS = {
  0x00: ['NOP', 0],
  0x01: ['SWRESET', 0],
  0x10: ['SLPIN', 0],
  0x11: ['SLPOUT', 0],
  0x12: ['PTLON', 0],
  0x13: ['NORON', 0],
  0x20: ['INVOFF', 0],
  0x21: ['INVON', 0],
  0x28: ['DISPOFF', 0],
  0x29: ['DISPON', 0],
  0x2a: ['CASET', 4],
  0x2b: ['RASET', 4],
  0x2c: ['RAMWR', null],
  0x33: ['VSCRDEF', 6],
  0x34: ['TEOFF', 0],
  0x35: ['TEON', 1],
  0x36: ['MADCTL', 1],
  0x37: ['VSCSAD', 2],
  0x3a: ['COLMOD', 1],
};

const MS = 1e6; // nanoseconds

export class ST7789 {
  /** `now()` gives the emulated time in nanoseconds. */
  constructor(now) {
    this.now = now;
    this.mem = new Uint16Array(WIDTH * MEM_ROWS);
    this.commands = []; // the log: [time, name, params] for every command
    this.pixelsWritten = 0;
    this.inReset = false;
    this.onPixel = null;
    this.powerOn();
  }

  powerOn() {
    this.sleeping = true;
    this.displayOn = false;
    this.inverted = false;
    this.colmod = 0x66; // 18 bits per pixel after reset
    this.madctl = 0;
    this.xs = 0;
    this.xe = WIDTH - 1;
    this.ys = 0;
    this.ye = MEM_ROWS - 1;
    this.cmd = null;
    this.params = [];
    this.quietUntil = this.now() + 120 * MS; // no SLPOUT before
    this.busyUntil = this.now() + 5 * MS; // no command at all before
  }

  fail(message) {
    const last = this.commands.slice(-4).map((c) => c[1]).join(', ');
    throw new Error(`ST7789: ${message} (after ${last || 'no command'})`);
  }

  /** RESX changes: low resets the panel; the reset takes effect when it rises. */
  reset(level) {
    if (!level) {
      this.inReset = true;
      this.resetAt = this.now();
    } else if (this.inReset) {
      this.inReset = false;
      if (this.now() - this.resetAt < 10_000) {
        this.fail(`a reset pulse of ${this.now() - this.resetAt} ns (at least 10 us)`);
      }
      this.finishCommand();
      this.powerOn();
      this.commands.push([this.now(), 'RESET', []]);
    }
  }

  /** One byte off the wire, with D/CX (`dc`) and CSX (`cs`) as they were. */
  byte(value, dc, cs) {
    if (cs) this.fail(`byte 0x${value.toString(16)} sent with CS high`);
    if (this.inReset) this.fail(`byte 0x${value.toString(16)} sent during the reset`);
    if (!dc) {
      this.finishCommand();
      this.startCommand(value);
    } else {
      if (this.cmd === null) this.fail(`data byte 0x${value.toString(16)} without a command`);
      if (this.cmd === 0x2c) this.pixelByte(value);
      else {
        this.params.push(value);
        if (this.params.length > COMMANDS[this.cmd][1]) {
          this.fail(`${COMMANDS[this.cmd][0]} takes ${COMMANDS[this.cmd][1]} parameter bytes, got more`);
        }
        if (this.params.length === COMMANDS[this.cmd][1]) this.finishCommand();
      }
    }
  }

  startCommand(value) {
    const c = COMMANDS[value];
    if (!c) this.fail(`unknown command 0x${value.toString(16)}`);
    const t = this.now();
    if (t < this.busyUntil) {
      this.fail(`${c[0]} ${((this.busyUntil - t) / 1e3).toFixed(0)} us too soon after the last reset or SLPOUT`);
    }
    if (value === 0x11 && t < this.quietUntil) {
      this.fail(`SLPOUT ${((this.quietUntil - t) / 1e3).toFixed(0)} us too soon after a reset`);
    }
    this.cmd = value;
    this.params = [];
    this.cmdAt = t;
    if (value === 0x2c) {
      if (this.colmod !== 0x55 && (this.colmod & 0x0f) !== 0x05) {
        this.fail(`RAMWR with COLMOD 0x${this.colmod.toString(16)}, not 16 bits per pixel`);
      }
      this.x = this.xs;
      this.y = this.ys;
      this.half = null;
      this.ramwrPixels = 0;
    }
    if (c[1] === 0) this.finishCommand();
  }

  /** Ends the current command (a new command byte ends a RAMWR). */
  finishCommand() {
    const cmd = this.cmd;
    if (cmd === null) return;
    const [name, count] = COMMANDS[cmd];
    const p = this.params;
    this.cmd = null;
    if (cmd === 0x2c) {
      if (this.half !== null) this.fail('RAMWR ended in the middle of a pixel');
      this.commands.push([this.cmdAt, name, [this.ramwrPixels]]);
      return;
    }
    if (p.length !== count) this.fail(`${name} takes ${count} parameter bytes, got ${p.length}`);
    this.commands.push([this.cmdAt, name, p]);
    const t = this.now();
    switch (cmd) {
      case 0x01: // SWRESET
        this.powerOn();
        break;
      case 0x10:
        this.sleeping = true;
        this.busyUntil = t + 5 * MS;
        break;
      case 0x11:
        this.sleeping = false;
        this.busyUntil = t + 5 * MS;
        break;
      case 0x20:
        this.inverted = false;
        break;
      case 0x21:
        this.inverted = true;
        break;
      case 0x28:
        this.displayOn = false;
        break;
      case 0x29:
        this.displayOn = true;
        break;
      case 0x2a: {
        this.xs = (p[0] << 8) | p[1];
        this.xe = (p[2] << 8) | p[3];
        if (this.xs > this.xe || this.xe >= WIDTH) {
          this.fail(`CASET ${this.xs}..${this.xe} outside the panel's 0..${WIDTH - 1}`);
        }
        break;
      }
      case 0x2b: {
        this.ys = (p[0] << 8) | p[1];
        this.ye = (p[2] << 8) | p[3];
        if (this.ys > this.ye || this.ye >= HEIGHT) {
          this.fail(`RASET ${this.ys}..${this.ye} outside the panel's 0..${HEIGHT - 1}`);
        }
        break;
      }
      case 0x36:
        // Only the orientation a 240x240 panel shows unshifted: no row or
        // column exchange or mirroring; RGB or BGR order.
        if (p[0] & ~0x0c) this.fail(`MADCTL 0x${p[0].toString(16)}: a rotation or mirroring the model does not show`);
        this.madctl = p[0];
        break;
      case 0x3a:
        this.colmod = p[0];
        if ((p[0] & 0x0f) !== 0x05) this.fail(`COLMOD 0x${p[0].toString(16)}: the firmware sends Rgb565, 0x55`);
        break;
      default:
        break;
    }
  }

  pixelByte(value) {
    if (this.half === null) {
      this.half = value;
      return;
    }
    if (this.y > this.ye) {
      this.fail(`RAMWR past the end of the window ${this.xs}..${this.xe} x ${this.ys}..${this.ye}`);
    }
    this.mem[this.y * WIDTH + this.x] = (this.half << 8) | value;
    this.half = null;
    this.ramwrPixels++;
    this.pixelsWritten++;
    if (this.onPixel) this.onPixel(this.y * WIDTH + this.x);
    if (this.x === this.xe) {
      this.x = this.xs;
      this.y++;
    } else this.x++;
  }

  /** Whether the last pixel written was the last of the current window. */
  windowFilled() {
    return this.cmd === 0x2c && this.half === null && this.y > this.ye;
  }

  /** What the panel shows: big-endian Rgb565, 240x240. */
  picture() {
    if (!this.displayOn) this.fail('the display is off');
    if (this.sleeping) this.fail('the panel is asleep');
    const out = Buffer.alloc(WIDTH * HEIGHT * 2);
    const bgr = this.madctl & 0x08;
    for (let i = 0; i < WIDTH * HEIGHT; i++) {
      let v = this.mem[i];
      if (!this.inverted) v = ~v & 0xffff; // an IPS panel without INVON
      if (bgr) v = ((v & 0x1f) << 11) | (v & 0x07e0) | (v >> 11);
      out.writeUInt16BE(v, 2 * i);
    }
    return out;
  }
}
