//! The broad phase: a uniform grid of cells holding the small bodies, the
//! large fixed bodies that do not move listed in the cells their boxes
//! cover (walls), and the list of the other large bodies that every body
//! checks (docs/simulator.md, "Broad phase").  The reference's cell_of,
//! cell_add, cell_remove, place_large, unplace_large, walls_in, large_near.

use super::motion::point_at;
use super::queue::prefetch;
use super::scene::Scene;

const CELL_INLINE: usize = 3;
/// Room for [`Grid::inline_ids`]: the inline bodies of 3x3 cells.
pub const INLINE_IDS: usize = 9 * CELL_INLINE;

/// The bit of [`CellList`]'s `n` that says a wall is listed in the cell's
/// 3x3 block (its `Grid::wnear` count is not zero); the bits below count
/// the bodies.
const WALLS_NEAR: u32 = 1 << 31;

/// One grid cell's list of bodies: the first few inline (a cell 1.15
/// times the largest body wide rarely holds more), the rest in the grid's `more` list of
/// the cell.  16 bytes, so that a row of a 3x3 block is one or two cache
/// lines (at 10^5 disks the 3 x 10^5 cells do not fit the cache; a
/// 48-byte cell with a vector of its own would take twice as many lines,
/// and `walls_near` kept apart a line more).  Python's list operations: append at
/// the end, remove by moving the last element into the hole.
#[derive(Clone, Copy, Default)]
#[repr(C, align(16))]
pub struct CellList {
    /// number of bodies, and the WALLS_NEAR bit
    n: u32,
    inline: [u32; CELL_INLINE],
}

impl CellList {
    /// Number of bodies in the cell.
    #[inline(always)]
    fn count(&self) -> usize {
        (self.n & !WALLS_NEAR) as usize
    }
}

/// A cell's bodies as the broad phase reads them ([`Grid::cell`]).
#[derive(Clone, Copy)]
pub struct Cell<'a> {
    grid: &'a Grid,
    /// the cell's index
    k: usize,
}

impl Cell<'_> {
    /// Number of bodies in the cell.
    #[inline(always)]
    pub fn len(&self) -> usize {
        self.grid.cells[self.k].count()
    }

    /// The k-th body of the cell, in Python's list order.
    #[inline(always)]
    pub fn get(&self, k: usize) -> u32 {
        if k < CELL_INLINE {
            self.grid.cells[self.k].inline[k]
        } else {
            // indexed here only: a reference to the cell's overflow list
            // taken before would let the compiler read it ahead, a cache
            // line of another array for every cell
            self.grid.more[self.k][k - CELL_INLINE]
        }
    }
}

/// The cells (row after row, `nx` per row), the walls listed per cell and
/// the large bodies not placed in cells.
pub struct Grid {
    cells: Vec<CellList>,
    /// per cell, its bodies past the first CELL_INLINE
    more: Vec<Vec<u32>>,
    nx: i64,
    ny: i64,
    /// per cell, the placed large bodies (fixed, not moving) whose box covers it
    walls: Vec<Vec<u32>>,
    /// per cell, the entries of the walls' lists in its 3x3 block (0: no
    /// wall near; the cell's WALLS_NEAR bit says which)
    wnear: Vec<u32>,
    /// the large bodies outside the cells (moving or movable), by index in the scene
    pub large: Vec<u32>,
}

impl Grid {
    /// The empty grid of a scene (its large bodies are placed by [`place_large`]).
    pub fn new(s: &Scene) -> Grid {
        let n = (s.nx * s.ny) as usize;
        let mut cells = Vec::with_capacity(n);
        super::huge::advise(&cells);
        cells.resize(n, CellList::default());
        Grid {
            cells,
            more: vec![Vec::new(); n],
            nx: s.nx,
            ny: s.ny,
            walls: vec![Vec::new(); n],
            wnear: vec![0; n],
            large: Vec::new(),
        }
    }

    /// Whether any wall is listed in the 3x3 block of cell (cx, cy).
    #[inline(always)]
    pub fn walls_near(&self, cx: i64, cy: i64) -> bool {
        self.cells[(cy * self.nx + cx) as usize].n & WALLS_NEAR != 0
    }

    /// A wall entry into (add) or out of the list of cell (jx, jy): counted
    /// in every cell whose 3x3 block holds it.
    fn count_wall(&mut self, jx: i64, jy: i64, add: bool) {
        for y in (jy - 1).max(0)..=(jy + 1).min(self.ny - 1) {
            for x in (jx - 1).max(0)..=(jx + 1).min(self.nx - 1) {
                let k = (y * self.nx + x) as usize;
                let c = &mut self.wnear[k];
                if add {
                    *c += 1;
                } else {
                    *c -= 1;
                }
                let cell = &mut self.cells[k];
                cell.n = if *c != 0 { cell.n | WALLS_NEAR } else { cell.n & !WALLS_NEAR };
            }
        }
    }

    /// The cell (jx, jy); both within the grid.
    #[inline(always)]
    pub fn cell(&self, jx: i64, jy: i64) -> Cell<'_> {
        Cell { grid: self, k: (jy * self.nx + jx) as usize }
    }

    /// The bodies of the cells x0..=x1, y0..=y1 (all within the grid; none
    /// when x1 < x0 or y1 < y0) into `out`, in the order of a walk of the
    /// rows, their cells and each cell's list ([`Grid::cell`]); their
    /// number, or None when they might not fit (then `out` holds a part).
    #[inline(always)]
    pub fn gather(&self, x0: i64, x1: i64, y0: i64, y1: i64, out: &mut [u32]) -> Option<usize> {
        if x1 < x0 || y1 < y0 {
            return Some(0);
        }
        // exclusive ranges and a row slice of the width: the inclusive
        // ones cost a check of their end and of overflow per row
        let (width, nx) = ((x1 - x0 + 1) as usize, self.nx as usize);
        let mut lo = y0 as usize * nx + x0 as usize;
        let mut n = 0;
        for _ in y0..y1 + 1 {
            for c in lo..lo + width {
                let cell = &self.cells[c];
                if n + CELL_INLINE > out.len() {
                    return None;
                }
                // all three inline words (those past the count are
                // overwritten next or never read): no loop over the count
                out[n..n + CELL_INLINE].copy_from_slice(&cell.inline);
                let count = cell.count();
                if count > CELL_INLINE {
                    if n + count > out.len() {
                        return None;
                    }
                    out[n + CELL_INLINE..n + count].copy_from_slice(&self.more[c]);
                }
                n += count;
            }
            lo += nx;
        }
        Some(n)
    }

    /// Bytes of the cells' lists (what the broad phase reads at random).
    pub fn cell_bytes(&self) -> usize {
        self.cells.len() * std::mem::size_of::<CellList>()
    }

    /// Have the cells of the 3x3 block around (cx, cy) fetched (clamped to
    /// the grid).  A hint only: nothing is read.
    #[inline(always)]
    pub fn prefetch_block(&self, cx: i64, cy: i64) {
        self.prefetch_cells(cx - 1, cx + 1, cy - 1, cy + 1);
    }

    /// Have the cells from column xa to xb and row ya to yb (either order,
    /// at most three of each, clamped to the grid) fetched: a row's first
    /// and last cell, three cells of 16 bytes lying in one or two lines.
    /// A hint only: nothing is read.
    #[inline(always)]
    pub fn prefetch_cells(&self, xa: i64, xb: i64, ya: i64, yb: i64) {
        let (x0, x1) = (xa.min(xb).max(0), xa.max(xb).min(self.nx - 1));
        let (y0, y1) = (ya.min(yb).max(0), ya.max(yb).min(self.ny - 1));
        if x0 > x1 {
            return;
        }
        let cells = self.cells.as_ptr();
        for y in y0..=y1 {
            // wrapping: the address of a hint, never dereferenced
            let row = cells.wrapping_add((y * self.nx) as usize);
            prefetch(row.wrapping_add(x0 as usize));
            prefetch(row.wrapping_add(x1 as usize));
        }
    }

    /// The bodies held inline (the first CELL_INLINE of each) in the cells
    /// x_lo..=x_hi, y_lo..=y_hi (clamped to the grid; at most 3x3) into
    /// `out`, in the order of the cells; their number: which bodies to fetch
    /// ahead of predicting against them.  Each cell's inline words are
    /// copied whole and the count moves on by their number (a loop over a
    /// cell's 0 to 3 bodies mispredicted its exit at nearly every cell).
    #[inline(always)]
    pub fn inline_ids(&self, x_lo: i64, x_hi: i64, y_lo: i64, y_hi: i64, out: &mut [u32; INLINE_IDS]) -> usize {
        let (x0, x1) = (x_lo.max(0), x_hi.min(self.nx - 1));
        let (y0, y1) = (y_lo.max(0), y_hi.min(self.ny - 1));
        if x0 > x1 || y0 > y1 {
            return 0;
        }
        debug_assert!(x1 - x0 < 3 && y1 - y0 < 3, "a block of at most 3x3 cells");
        let (width, nx) = ((x1 - x0 + 1) as usize, self.nx as usize);
        let mut lo = y0 as usize * nx + x0 as usize;
        let mut n = 0;
        for _ in y0..y1 + 1 {
            for cell in &self.cells[lo..lo + width] {
                out[n..n + CELL_INLINE].copy_from_slice(&cell.inline);
                n += cell.count().min(CELL_INLINE);
            }
            lo += nx;
        }
        n
    }

    /// Put body b into cell (cx, cy).
    pub fn add(&mut self, b: u32, cx: i32, cy: i32) {
        self.push(((i64::from(cy) * self.nx) + i64::from(cx)) as usize, b);
    }

    /// Take body b out of cell (cx, cy).
    pub fn remove(&mut self, b: u32, cx: i32, cy: i32) {
        self.pull(((i64::from(cy) * self.nx) + i64::from(cx)) as usize, b);
    }

    /// Python's append to the list of cell c.
    #[inline]
    fn push(&mut self, c: usize, x: u32) {
        let n = self.cells[c].count();
        if n < CELL_INLINE {
            self.cells[c].inline[n] = x;
        } else {
            self.more[c].push(x);
        }
        self.cells[c].n += 1;
    }

    /// Python's cell_remove from the list of cell c: the last element moves
    /// into the hole (the overflow list is read only when the cell has one).
    #[inline]
    fn pull(&mut self, c: usize, x: u32) {
        let n = self.cells[c].count();
        let at = |g: &Grid, k: usize| if k < CELL_INLINE { g.cells[c].inline[k] } else { g.more[c][k - CELL_INLINE] };
        let k = (0..n).position(|k| at(self, k) == x).expect("a body is in its cell");
        let last = if n > CELL_INLINE { self.more[c].pop().expect("n > inline") } else { self.cells[c].inline[n - 1] };
        if k < n - 1 {
            if k < CELL_INLINE {
                self.cells[c].inline[k] = last;
            } else {
                self.more[c][k - CELL_INLINE] = last;
            }
        }
        self.cells[c].n -= 1;
    }

    /// Take large body b (its placed cells `wcells`, None: in `large`) out
    /// of the grid (the reference's unplace_large).
    pub fn unplace_large(&mut self, b: u32, wcells: Option<[i32; 4]>) {
        let Some([i0, i1, j0, j1]) = wcells else {
            let at = self.large.iter().position(|&o| o == b).expect("a large body is listed");
            self.large.remove(at);
            return;
        };
        for jy in i64::from(j0)..=i64::from(j1) {
            for jx in i64::from(i0)..=i64::from(i1) {
                let list = &mut self.walls[(jy * self.nx + jx) as usize];
                let at = list.iter().position(|&o| o == b).expect("a wall is listed in its cells");
                list.remove(at);
                self.count_wall(jx, jy, false);
            }
        }
    }

    /// Append to out the placed large bodies listed in the cells x_lo..=x_hi,
    /// y_lo..=y_hi (clamped to the grid), but b (the caller sorts and
    /// removes repeats: the reference's marks).
    pub fn walls_in(&self, b: usize, x_lo: i64, x_hi: i64, y_lo: i64, y_hi: i64, out: &mut Vec<u32>) {
        for jy in y_lo.max(0)..=y_hi.min(self.ny - 1) {
            for jx in x_lo.max(0)..=x_hi.min(self.nx - 1) {
                for &o in &self.walls[(jy * self.nx + jx) as usize] {
                    if o as usize != b {
                        out.push(o);
                    }
                }
            }
        }
    }

    /// The large bodies b (in cell (cx, cy)) predicts against: those placed
    /// in its 3x3 cells and every one in `large`, each once, but b, in index
    /// order.
    pub fn large_near(&self, b: usize, cx: i32, cy: i32) -> Vec<u32> {
        let (cx, cy) = (i64::from(cx), i64::from(cy));
        let mut out = Vec::new();
        if self.walls_near(cx, cy) {
            self.walls_in(b, cx - 1, cx + 1, cy - 1, cy + 1, &mut out);
        }
        out.extend(self.large.iter().copied().filter(|&o| o as usize != b));
        out.sort_unstable();
        out.dedup();
        out
    }
}

/// Put large body bi of the scene into the grid: into the walls of every
/// cell its box covers when it is fixed and does not move (v = a = 0; the
/// box of a polygon that does not turn from its vertices at its time, else
/// its centre +- bound; the cells from cell_of(box's low corner) to
/// cell_of(its high corner)), else into `large` (the reference's place_large).
pub fn place_large(grid: &mut Grid, s: &mut Scene, bi: usize) {
    let b = &s.bodies[bi];
    if !(b.fixed && b.vx == 0.0 && b.vy == 0.0 && b.ax == 0.0 && b.ay == 0.0) {
        grid.large.push(b.idx);
        return;
    }
    let (x0, x1, y0, y1);
    if b.polygon && b.om == 0.0 {
        let (mut lx, mut ly) = point_at(b, Some(&s.verts[b.vert(0)]), b.tb);
        let (mut hx, mut hy) = (lx, ly);
        for k in 0..b.nverts() {
            let (x, y) = point_at(b, Some(&s.verts[b.vert(k)]), b.tb);
            // Python's min(x0, x), max(x1, x), ...
            if x < lx {
                lx = x;
            }
            if x > hx {
                hx = x;
            }
            if y < ly {
                ly = y;
            }
            if y > hy {
                hy = y;
            }
        }
        (x0, x1, y0, y1) = (lx, hx, ly, hy);
    } else {
        (x0, x1, y0, y1) = (b.px - b.bound, b.px + b.bound, b.py - b.bound, b.py + b.bound);
    }
    let (i0, j0) = cell_of(s, x0, y0);
    let (i1, j1) = cell_of(s, x1, y1);
    let idx = b.idx;
    s.bodies[bi].wcells = Some([i0, i1, j0, j1]);
    for jy in i64::from(j0)..=i64::from(j1) {
        for jx in i64::from(i0)..=i64::from(i1) {
            grid.walls[(jy * grid.nx + jx) as usize].push(idx);
            grid.count_wall(jx, jy, true);
        }
    }
}

/// The cell of a point, clamped to the grid (border cells reach to infinity).
pub fn cell_of(s: &Scene, x: f64, y: f64) -> (i32, i32) {
    let fx = ((x - s.x0) / s.cw).floor();
    let fy = ((y - s.y0) / s.ch).floor();
    let ix = if fx < 0.0 {
        0
    } else if fx > (s.nx - 1) as f64 {
        s.nx - 1
    } else {
        fx as i64
    };
    let iy = if fy < 0.0 {
        0
    } else if fy > (s.ny - 1) as f64 {
        s.ny - 1
    } else {
        fy as i64
    };
    (ix as i32, iy as i32)
}

#[cfg(test)]
mod tests {
    use super::{CellList, Grid, CELL_INLINE, INLINE_IDS, WALLS_NEAR};

    /// A grid of nx x ny empty cells, no walls, no large bodies.
    fn empty_grid(nx: i64, ny: i64) -> Grid {
        let n = (nx * ny) as usize;
        Grid {
            cells: vec![CellList::default(); n],
            more: vec![Vec::new(); n],
            nx,
            ny,
            walls: vec![Vec::new(); n],
            wnear: vec![0; n],
            large: Vec::new(),
        }
    }

    /// Marsaglia's xorshift64* from seed: the tests' reproducible numbers.
    fn xorshift(seed: u64) -> impl FnMut() -> u64 {
        let mut state = seed;
        move || {
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            state.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
    }

    #[test]
    fn cell_list_is_a_python_list_with_last_into_the_hole() {
        // xorshift64*: reproducible numbers without a dependency
        let mut next = xorshift(777);
        // a grid of one row of three cells; the middle one is exercised
        let mut grid = empty_grid(3, 1);
        let mut model: Vec<u32> = Vec::new();
        let mut fresh = 0u32;
        for _ in 0..50_000 {
            // the walls' bit comes and goes: it never changes the list
            if next().is_multiple_of(7) {
                grid.cells[1].n ^= WALLS_NEAR;
            }
            if model.is_empty() || (model.len() < 3 * CELL_INLINE && next().is_multiple_of(2)) {
                grid.add(fresh, 1, 0);
                model.push(fresh);
                fresh += 1;
            } else {
                let x = model[(next() % model.len() as u64) as usize];
                grid.remove(x, 1, 0);
                let k = model.iter().position(|&o| o == x).unwrap();
                let last = model.pop().unwrap();
                if k < model.len() {
                    model[k] = last;
                }
            }
            let cell = grid.cell(1, 0);
            assert_eq!(cell.len(), model.len());
            assert_eq!(grid.more[1].len(), model.len().saturating_sub(CELL_INLINE));
            for (k, &x) in model.iter().enumerate() {
                assert_eq!(cell.get(k), x);
            }
            assert!(grid.cell(0, 0).len() == 0 && grid.cell(2, 0).len() == 0);
        }
    }

    #[test]
    fn inline_ids_are_the_first_bodies_of_each_cell_in_order() {
        let (nx, ny) = (4i64, 4i64);
        let n = (nx * ny) as usize;
        let mut grid = empty_grid(nx, ny);
        // 0 to 5 bodies a cell (some past the inline ones), walls near some
        let mut fresh = 0u32;
        for k in 0..n {
            for _ in 0..(k * 7) % 6 {
                grid.add(fresh, (k % 4) as i32, (k / 4) as i32);
                fresh += 1;
            }
            if k % 3 == 0 {
                grid.cells[k].n ^= WALLS_NEAR;
            }
        }
        for (cx, cy) in [(0i64, 0i64), (1, 1), (2, 2), (3, 3), (1, 3), (3, 0)] {
            for (x_lo, x_hi, y_lo, y_hi) in
                [(cx - 1, cx + 1, cy - 1, cy + 1), (cx, cx, cy - 1, cy + 1), (cx - 1, cx + 1, cy, cy)]
            {
                let mut want = Vec::new();
                for jy in y_lo.max(0)..=y_hi.min(ny - 1) {
                    for jx in x_lo.max(0)..=x_hi.min(nx - 1) {
                        let cell = grid.cell(jx, jy);
                        for k in 0..cell.len().min(CELL_INLINE) {
                            want.push(cell.get(k));
                        }
                    }
                }
                let mut out = [u32::MAX; INLINE_IDS];
                let m = grid.inline_ids(x_lo, x_hi, y_lo, y_hi, &mut out);
                assert_eq!(&out[..m], &want[..], "block {x_lo}..={x_hi} x {y_lo}..={y_hi}");
            }
        }
    }

    #[test]
    fn gather_walks_the_block_as_the_cells_do() {
        let mut next = xorshift(4242);
        let (nx, ny) = (5i64, 4i64);
        let n = (nx * ny) as usize;
        let mut grid = empty_grid(nx, ny);
        let mut fresh = 0u32;
        let (mut fitted, mut spilled, mut overflowed) = (0, 0, 0);
        for round in 0..2000 {
            // up to 7 bodies in a cell (some past the inline ones), some taken out
            let (cx, cy) = ((next() % nx as u64) as i32, (next() % ny as u64) as i32);
            if grid.cell(i64::from(cx), i64::from(cy)).len() < 7 && !next().is_multiple_of(3) {
                grid.add(fresh, cx, cy);
                fresh += 1;
            } else if grid.cell(i64::from(cx), i64::from(cy)).len() > 0 {
                let o = grid.cell(i64::from(cx), i64::from(cy)).get(0);
                grid.remove(o, cx, cy);
            }
            if round % 2 == 1 {
                grid.cells[(next() % n as u64) as usize].n ^= WALLS_NEAR;
            }
            let (x0, y0) = ((next() % nx as u64) as i64, (next() % ny as u64) as i64);
            let (x1, y1) = (x0 - 1 + (next() % 4) as i64, y0 - 1 + (next() % 4) as i64);
            let (x1, y1) = (x1.min(nx - 1), y1.min(ny - 1));
            let mut walked = Vec::new();
            for jy in y0..=y1 {
                for jx in x0..=x1 {
                    let cell = grid.cell(jx, jy);
                    for k in 0..cell.len() {
                        walked.push(cell.get(k));
                    }
                }
            }
            let mut out = [u32::MAX; 24];
            match grid.gather(x0, x1, y0, y1, &mut out) {
                Some(m) => {
                    assert_eq!(&out[..m], &walked[..]);
                    fitted += 1;
                    if m > CELL_INLINE && (y0..=y1).any(|jy| (x0..=x1).any(|jx| grid.cell(jx, jy).len() > CELL_INLINE))
                    {
                        spilled += 1;
                    }
                }
                // None only when the bodies, or a cell's inline words, might not fit
                None => {
                    assert!(walked.len() + CELL_INLINE > out.len(), "{} bodies", walked.len());
                    overflowed += 1;
                }
            }
        }
        // every case came up: blocks that fit, cells past their inline words, blocks that did not fit
        assert!(fitted > 100 && spilled > 100 && overflowed > 100, "{fitted} {spilled} {overflowed}");
    }
}
