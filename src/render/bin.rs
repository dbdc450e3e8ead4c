//! Bins: per tile, a chain of fixed-size chunks of triangle indices.

/// Slots per chunk of the bin pool: `CHUNK - 1` triangle indices and the
/// index of the tile's next chunk. Small, because a tile wastes half a
/// chunk on average and a chunk an eighth of its slots on the link.
pub const CHUNK: usize = 8;

/// The tail of a tile that has no chunk yet. `EMPTY % CHUNK == CHUNK - 1`,
/// so it reads as a full chunk and the tile's first entry allocates one.
const EMPTY: u16 = u16::MAX;
/// The end of the free-chunk list.
const NO_CHUNK: u16 = u16::MAX;
const _: () = assert!(CHUNK.is_power_of_two() && CHUNK >= 2 && EMPTY as usize % CHUNK == CHUNK - 1);

/// The slot of chunk `c` that links to the next chunk.
#[inline(always)]
fn link(c: u16) -> usize {
    c as usize * CHUNK + CHUNK - 1
}

/// The bins of a frame: the pool and the per-tile tables, which every pass
/// of the frame uses in turn ([`pass`](Self::pass)), and how many tiles
/// the current pass holds.
pub(super) struct Bins<'w> {
    pool: &'w mut [u16],
    heads: &'w mut [u16],
    tails: &'w mut [u16],
    held: usize,
    /// The most slots a pass has taken from the pool.
    peak: usize,
}

impl<'w> Bins<'w> {
    /// Bins over `pool`, for passes of at most `heads.len()` tiles
    /// (`tails` as long), holding no tile until a pass is binned.
    pub(super) fn new(pool: &'w mut [u16], heads: &'w mut [u16], tails: &'w mut [u16]) -> Self {
        Self {
            pool,
            heads,
            tails,
            held: 0,
            peak: 0,
        }
    }

    /// Empties the pool and calls `bin` to fill it for a pass of `tiles`
    /// tiles (at most as many as the tile tables hold); afterwards the
    /// bins hold the tiles the pass kept.
    pub(super) fn pass(&mut self, tiles: usize, bin: impl FnOnce(&mut Pass<'_>)) {
        let n = tiles.min(self.tails.len());
        let mut pass = Pass::new(self.pool, &mut self.heads[..n], &mut self.tails[..n]);
        bin(&mut pass);
        self.held = pass.tiles();
        // Chunks are taken in order before any is reused: `fresh` is the
        // pass's high-water mark.
        self.peak = self.peak.max(pass.fresh as usize * CHUNK);
    }

    /// The most pool slots any pass so far has taken (whole chunks).
    pub(super) fn peak(&self) -> usize {
        self.peak
    }

    /// The number of tiles the last pass holds.
    pub(super) fn tiles(&self) -> usize {
        self.held
    }

    /// Whether tile `k` of the last pass holds no triangle (`iter(k)`
    /// empty): a tile is given a chunk only with its first entry. Its tail
    /// alone, without [`iter`](Self::iter)'s set-up (about 45 instructions
    /// on the Cortex-M3, for each tile the frame's tile stream looks at).
    /// In builds optimised for size, `iter(k)`'s (the tail alone let LTO
    /// inline the tile stream into the OLED firmware's `main`: 240 bytes
    /// more).
    #[inline(always)]
    pub(super) fn is_empty(&self, k: usize) -> bool {
        if cfg!(microraster_size) {
            return self.iter(k).is_empty();
        }
        let empty = match self.tails.get(k) {
            Some(&tail) if k < self.held => tail == EMPTY,
            _ => true,
        };
        debug_assert_eq!(empty, self.iter(k).is_empty());
        empty
    }

    /// The triangles of tile `k` of the last pass, in submission order.
    pub(super) fn iter(&self, k: usize) -> BinIter<'_> {
        let tail = if k < self.held { self.tails[k] } else { EMPTY };
        let (first, end) = if tail == EMPTY {
            (0, 0)
        } else {
            (self.heads[k] as usize * CHUNK, tail as usize)
        };
        // The first slot of the bin's last chunk (`end` may be that
        // chunk's link slot: the chunk is full).
        let last = end.saturating_sub(1) & !(CHUNK - 1);
        let mut iter = BinIter {
            pool: self.pool,
            run: [].iter(),
            next: end,
            last,
            end,
        };
        iter.enter(first);
        iter
    }
}

/// The bins of one pass being filled: per tile, a chain of chunks of the
/// pool holding triangle indices in submission order.
pub(super) struct Pass<'p> {
    pool: &'p mut [u16],
    heads: &'p mut [u16],
    /// Per tile the pass still holds (a prefix of the pass's tiles: the
    /// pass gives up tiles from its end when the pool runs dry), the slot
    /// its next entry goes to.
    tails: &'p mut [u16],
    /// Chunks `fresh..chunks` have never been used.
    fresh: u16,
    chunks: u16,
    /// Chunks given back, linked through their last slot.
    free: u16,
}

impl<'p> Pass<'p> {
    fn new(pool: &'p mut [u16], heads: &'p mut [u16], tails: &'p mut [u16]) -> Self {
        tails.fill(EMPTY);
        Self {
            // At most 65,535 / CHUNK chunks: every slot index fits `u16`
            // below `EMPTY`.
            chunks: (pool.len() / CHUNK) as u16,
            pool,
            heads,
            tails,
            fresh: 0,
            free: NO_CHUNK,
        }
    }

    /// The number of tiles the pass holds.
    pub(super) fn tiles(&self) -> usize {
        self.tails.len()
    }

    /// Appends triangle `t` to the bin of tile `k` of the pass, unless the
    /// pass does not hold that tile.
    #[inline(always)]
    pub(super) fn push(&mut self, k: usize, t: u16) {
        let Some(tail) = self.tails.get_mut(k) else {
            return;
        };
        let slot = *tail as usize;
        // The next slot's index tested, not the slot's: it is the tail
        // stored (the Cortex-M3 had complemented the slot for the test).
        let next = slot + 1;
        if next & (CHUNK - 1) != 0 {
            // The tail through the reference taken for the test, not
            // indexed again after the store to the pool (which the
            // compiler could not tell apart from the tables: the
            // Cortex-M3 reloaded them and tested the index again).
            // A slot below a chunk's link lies in the pool.
            if let Some(p) = self.pool.get_mut(slot) {
                *p = t;
                *tail = next as u16;
            }
            return;
        }
        self.push_new(k, slot as u16, t);
    }

    /// Appends triangle `t` to the bin of tile `k`, whose chunk is full
    /// (or which has none; its tail is `tail`), in a new chunk
    /// ([`grow`](Self::grow)); `false`
    /// when the pass gave up tile `k`. Out of line in builds optimised
    /// for size (the OLED firmware 120 B smaller); elsewhere inlined: a
    /// tile's chunk fills every `CHUNK - 1` entries, and the call cost
    /// the Cortex-M3's `demo` frame 4,000 instructions of binning.
    #[cfg_attr(microraster_size, cold, inline(never))]
    #[cfg_attr(not(microraster_size), inline(always))]
    fn push_new(&mut self, k: usize, tail: u16, t: u16) -> bool {
        let Some(slot) = self.grow(k, tail) else {
            return false;
        };
        self.pool[slot] = t;
        self.tails[k] = slot as u16 + 1;
        true
    }

    /// Appends triangle `t` to the bins of tiles `ks` of the pass, those
    /// the pass holds: [`push`](Self::push) for each, with the tables in
    /// registers rather than reread from the pass for every tile (a row
    /// of a triangle's tiles in row-major order).
    #[inline(always)]
    pub(super) fn push_run(&mut self, ks: core::ops::Range<usize>, t: u16) {
        let mut k = ks.start;
        loop {
            let end = ks.end.min(self.tails.len());
            let (pool, tails) = (&mut *self.pool, &mut *self.tails);
            let (full, tail) = loop {
                if k >= end {
                    return;
                }
                let slot = tails[k] as usize;
                let next = slot + 1;
                if next & (CHUNK - 1) == 0 {
                    break (k, slot as u16);
                }
                pool[slot] = t;
                tails[k] = next as u16;
                k += 1;
            };
            // A new chunk, or the pass gave up tile `k` (and every later
            // one: tiles go from the end).
            if !self.push_new(full, tail, t) {
                return;
            }
            k = full + 1;
        }
    }

    /// Links a new chunk to tile `k`, whose chunk is full (or which has
    /// none), and returns the chunk's first slot. `tail` is the tile's
    /// tail, which the caller has just read: passed rather than read
    /// again with its bounds check. When the pool is
    /// exhausted, the pass gives up its last tile, whose chunks go back to
    /// the pool, until a chunk is found; `None` when tile `k` itself had to
    /// go.
    ///
    /// Out of line; where not optimised for size, a chunk never used
    /// before (every chunk of a pass that does not run dry: its only case)
    /// is linked here and the rest is a function of its own, so that this
    /// one saves and loads few registers (about 30 instructions a new
    /// chunk the Cortex-M3 spent on the whole function's prologue and
    /// loads).
    #[cold]
    #[inline(never)]
    fn grow(&mut self, k: usize, tail: u16) -> Option<usize> {
        if !cfg!(microraster_size) && self.fresh < self.chunks {
            // `k` is held, and a tail lies in the pool: neither `get`
            // fails (and none would take a chunk). Its tail is the
            // caller's, which has just read it.
            let c = self.fresh;
            debug_assert_eq!(self.tails.get(k), Some(&tail));
            let at = match tail {
                EMPTY => self.heads.get_mut(k),
                _ => self.pool.get_mut(tail as usize),
            };
            *at? = c;
            self.fresh += 1;
            return Some(c as usize * CHUNK);
        }
        self.grow_apart(k)
    }

    /// [`grow`](Self::grow)'s general case: a chunk from the free list, or
    /// the pass's last tiles given up until one is found.
    #[cold]
    #[cfg_attr(microraster_size, inline(always))]
    #[cfg_attr(not(microraster_size), inline(never))]
    fn grow_apart(&mut self, k: usize) -> Option<usize> {
        loop {
            if let Some(c) = self.alloc() {
                let tail = self.tails[k];
                if tail == EMPTY {
                    self.heads[k] = c;
                } else {
                    self.pool[tail as usize] = c;
                }
                return Some(c as usize * CHUNK);
            }
            // `k` is held, so there is a last tile.
            let last = self.tails.len() - 1;
            self.release(last);
            let tails = core::mem::take(&mut self.tails);
            self.tails = &mut tails[..last];
            if last == k {
                return None;
            }
        }
    }

    fn alloc(&mut self) -> Option<u16> {
        if self.fresh < self.chunks {
            self.fresh += 1;
            Some(self.fresh - 1)
        } else if self.free != NO_CHUNK {
            let c = self.free;
            self.free = self.pool[link(c)];
            Some(c)
        } else {
            None
        }
    }

    /// Gives the chunks of tile `k` back to the pool.
    fn release(&mut self, k: usize) {
        let tail = self.tails[k];
        if tail == EMPTY {
            return;
        }
        let mut c = self.heads[k];
        loop {
            // The chunk holding the tail is the last; its link slot holds
            // no link.
            let last = tail as usize / CHUNK == c as usize;
            let next = self.pool[link(c)];
            self.pool[link(c)] = self.free;
            self.free = c;
            if last {
                break;
            }
            c = next;
        }
        self.tails[k] = EMPTY;
    }
}

/// The triangle indices of one bin: a chunk's entries at a time, through
/// a slice iterator, so that an entry costs the tile loop a pointer
/// compare and a load rather than a test for the chunk's link slot and a
/// bounds check.
pub(super) struct BinIter<'a> {
    pool: &'a [u16],
    /// The current chunk's entries not yet visited.
    run: core::slice::Iter<'a, u16>,
    /// The slot after them: the chunk's link, or `end`.
    next: usize,
    /// The first slot of the bin's last chunk.
    last: usize,
    /// The slot after the bin's last entry.
    end: usize,
}

impl BinIter<'_> {
    /// Enters the chunk whose first slot is `first`: its entries up to
    /// its link slot, or up to `end` in the bin's last chunk.
    #[inline(always)]
    fn enter(&mut self, first: usize) {
        let stop = if first == self.last {
            self.end
        } else {
            first + CHUNK - 1
        };
        if let Some(run) = self.pool.get(first..stop) {
            (self.run, self.next) = (run.iter(), stop);
        }
    }

    /// A bin holding no triangle.
    pub(super) fn empty() -> Self {
        BinIter {
            pool: &[],
            run: [].iter(),
            next: 0,
            last: 0,
            end: 0,
        }
    }

    /// Whether the bin holds no triangle.
    pub(super) fn is_empty(&self) -> bool {
        self.run.len() == 0 && self.next == self.end
    }

    /// Moves to the next chunk of the bin; `false` at its end.
    #[inline(always)]
    fn follow(&mut self) -> bool {
        if self.next == self.end {
            return false;
        }
        match self.pool.get(self.next) {
            Some(&c) => {
                self.next = self.end;
                self.enter(c as usize * CHUNK);
                true
            }
            None => false,
        }
    }
}

impl Iterator for BinIter<'_> {
    type Item = usize;

    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        loop {
            if let Some(&t) = self.run.next() {
                return Some(t as usize);
            }
            if !self.follow() {
                return None;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bins against a plain list per tile: random appends into pools of
    /// every small size. A tile the pass still holds at the end must hold
    /// exactly its triangles, in order; the tiles given up are the last.
    #[test]
    fn bins_keep_every_held_tile_complete_and_in_order() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move |m: usize| {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x % m as u64) as usize
        };
        let mut gave_up = 0;
        for round in 0..3_000 {
            let tiles = 1 + next(12);
            let pool_len = 1 + next(if round % 2 == 0 { 40 } else { 400 });
            let mut pool = [0u16; 400];
            let (mut heads, mut tails) = ([0u16; 12], [0u16; 12]);
            let mut bins = Bins::new(&mut pool[..pool_len], &mut heads, &mut tails);
            let mut expected: [heapless::Vec<u16, 256>; 12] = Default::default();
            bins.pass(tiles, |pass| {
                for t in 0..next(200) as u16 {
                    // A triangle touches one to four consecutive tiles,
                    // some beyond the pass.
                    let first = next(tiles + 2);
                    let ks = first..first + 1 + next(4);
                    if round % 3 == 0 {
                        pass.push_run(ks.clone(), t);
                    } else {
                        for k in ks.clone() {
                            pass.push(k, t);
                        }
                    }
                    for k in ks {
                        if let Some(e) = expected.get_mut(k).filter(|_| k < tiles) {
                            e.push(t).unwrap();
                        }
                    }
                }
            });
            let held = bins.tiles();
            gave_up += (held < tiles) as u32;
            for (k, e) in expected.iter().enumerate().take(held) {
                assert!(
                    bins.iter(k).map(|t| t as u16).eq(e.iter().copied()),
                    "round {round} tile {k}"
                );
            }
        }
        assert!(gave_up > 100, "the test should exhaust pools: {gave_up}");
    }
}
