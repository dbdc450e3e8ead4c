//! The Hilbert curve as an order of cells: the cell at a step of the curve
//! and back, and the same over a grid of any size (only the grid's cells
//! counted), which the renderer uses to visit tiles along the curve. The
//! curve is the state machine of the [parent module](super), so cells and
//! pixels are visited in the same order.

use super::{entry, I, MAX_ORDER, NEXT, QUAD};

/// The cell `(x, y)` of the `index`-th step along the Hilbert curve of a
/// `2^order` square, from the state machine's tables (the same order the
/// traversal visits pixels in). Used to visit tiles in Hilbert order.
pub const fn index_to_cell(order: u32, index: u32) -> (u32, u32) {
    let (mut x, mut y) = (0u32, 0u32);
    let mut state = I;
    let mut level = order;
    while level > 0 {
        level -= 1;
        let k = (index >> (2 * level)) & 3;
        let q = entry(QUAD, state, k);
        x |= (q as u32 & 1) << level;
        y |= ((q as u32 >> 1) & 1) << level;
        state = entry(NEXT, state, k);
    }
    (x, y)
}

/// The position along the Hilbert curve of a `2^order` square of the cell
/// `(x, y)`: the inverse of [`index_to_cell`].
pub const fn cell_to_index(order: u32, x: u32, y: u32) -> u32 {
    let mut index = 0u32;
    let mut state = I;
    let mut level = order;
    while level > 0 {
        level -= 1;
        let q = (((x >> level) & 1) | (((y >> level) & 1) << 1)) as u8;
        // The step k whose quadrant is q, in this state.
        let mut k = 0;
        while k < 3 && entry(QUAD, state, k) != q {
            k += 1;
        }
        index = (index << 2) | k;
        state = entry(NEXT, state, k);
    }
    index
}

/// The number of cells of a `cols x rows` grid inside the `side`-sided
/// square at `(x, y)`.
const fn cells_in(x: u32, y: u32, side: u32, cols: u32, rows: u32) -> u32 {
    let w = if x + side < cols {
        side
    } else {
        cols.saturating_sub(x)
    };
    let h = if y + side < rows {
        side
    } else {
        rows.saturating_sub(y)
    };
    w * h
}

/// The position of cell `(x, y)` of a `cols x rows` grid when only the
/// grid's cells are visited, in the order of the Hilbert curve over the
/// smallest power-of-two square holding the grid: the number of grid cells
/// the curve passes before it. `O(log side)`: at every level, the grid
/// cells of the quadrants visited before the cell's own are counted as
/// rectangles.
///
/// ```
/// use microraster::raster::hilbert::{cell_at_rank, rank_in_grid};
/// // A 3 x 2 grid (in a 4 x 4 curve): (0,0) (1,0) (1,1) (0,1) (2,1) (2,0).
/// assert_eq!(rank_in_grid(3, 2, 2, 0), 5);
/// assert_eq!(cell_at_rank(3, 2, 4), (2, 1));
/// ```
pub const fn rank_in_grid(cols: u32, rows: u32, x: u32, y: u32) -> u32 {
    let mut level = order_for(cols, rows);
    let (mut bx, mut by, mut rank) = (0u32, 0u32, 0u32);
    let mut state = I;
    while level > 0 {
        level -= 1;
        let half = 1u32 << level;
        let q = (((x >> level) & 1) | (((y >> level) & 1) << 1)) as u8;
        let mut k = 0;
        while k < 4 {
            let qk = entry(QUAD, state, k);
            let (qx, qy) = (bx + (qk as u32 & 1) * half, by + (qk as u32 >> 1) * half);
            if qk == q || k == 3 {
                bx = qx;
                by = qy;
                state = entry(NEXT, state, k);
                break;
            }
            rank += cells_in(qx, qy, half, cols, rows);
            k += 1;
        }
    }
    rank
}

/// The cell at position `rank` of the Hilbert-order visit of a
/// `cols x rows` grid: the inverse of [`rank_in_grid`] for
/// `rank < cols * rows`.
pub const fn cell_at_rank(cols: u32, rows: u32, rank: u32) -> (u32, u32) {
    let mut level = order_for(cols, rows);
    let (mut bx, mut by, mut rank) = (0u32, 0u32, rank);
    let mut state = I;
    while level > 0 {
        level -= 1;
        let half = 1u32 << level;
        let mut k = 0;
        while k < 4 {
            let qk = entry(QUAD, state, k);
            let (qx, qy) = (bx + (qk as u32 & 1) * half, by + (qk as u32 >> 1) * half);
            let n = cells_in(qx, qy, half, cols, rows);
            if rank < n || k == 3 {
                bx = qx;
                by = qy;
                state = entry(NEXT, state, k);
                break;
            }
            rank -= n;
            k += 1;
        }
    }
    (bx, by)
}

/// The order (`log2` of the side) of the smallest power-of-two square that
/// holds a `w x h` rectangle.
pub const fn order_for(w: u32, h: u32) -> u32 {
    let side = if w > h { w } else { h };
    let mut order = 0;
    while (1u32 << order) < side && order < MAX_ORDER {
        order += 1;
    }
    order
}
