//! The broad phase: a uniform grid of cells holding the small bodies, and
//! the list of large bodies that every body checks (docs/simulator.md,
//! "Broad phase").  The reference's cell_of, cell_add and cell_remove.

use super::scene::Scene;

const CELL_INLINE: usize = 4;

/// One grid cell's list of bodies: the first few inline (a cell rarely
/// holds more), the rest in a vector.  Python's list operations: append at
/// the end, remove by moving the last element into the hole.
#[derive(Clone, Default)]
pub struct CellList {
    n: u32,
    inline: [u32; CELL_INLINE],
    more: Vec<u32>,
}

impl CellList {
    /// Number of bodies in the cell.
    #[inline(always)]
    pub fn len(&self) -> usize {
        self.n as usize
    }

    /// The k-th body of the cell, in Python's list order.
    #[inline(always)]
    pub fn get(&self, k: usize) -> u32 {
        if k < CELL_INLINE {
            self.inline[k]
        } else {
            self.more[k - CELL_INLINE]
        }
    }

    #[inline]
    fn push(&mut self, x: u32) {
        let n = self.n as usize;
        if n < CELL_INLINE {
            self.inline[n] = x;
        } else {
            self.more.push(x);
        }
        self.n += 1;
    }

    /// Python's cell_remove: the last element moves into the hole.
    #[inline]
    fn remove(&mut self, x: u32) {
        let n = self.n as usize;
        let k = (0..n).position(|k| self.get(k) == x).expect("a body is in its cell");
        let last = if n > CELL_INLINE { self.more.pop().expect("n > inline") } else { self.inline[n - 1] };
        if k < n - 1 {
            if k < CELL_INLINE {
                self.inline[k] = last;
            } else {
                self.more[k - CELL_INLINE] = last;
            }
        }
        self.n -= 1;
    }
}

/// The cells (row after row, `nx` per row) and the large bodies.
pub struct Grid {
    cells: Vec<CellList>,
    nx: i64,
    /// the bodies outside the grid (walls), by index in the scene
    pub large: Vec<u32>,
}

impl Grid {
    /// The empty grid of a scene, with its large bodies listed.
    pub fn new(s: &Scene) -> Grid {
        let large = s.bodies.iter().filter(|b| b.large).map(|b| b.idx).collect();
        Grid { cells: vec![CellList::default(); (s.nx * s.ny) as usize], nx: s.nx, large }
    }

    /// The cell (jx, jy); both within the grid.
    #[inline(always)]
    pub fn cell(&self, jx: i64, jy: i64) -> &CellList {
        &self.cells[(jy * self.nx + jx) as usize]
    }

    /// Put body b into cell (cx, cy).
    pub fn add(&mut self, b: u32, cx: i32, cy: i32) {
        let k = (i64::from(cy) * self.nx + i64::from(cx)) as usize;
        self.cells[k].push(b);
    }

    /// Take body b out of cell (cx, cy).
    pub fn remove(&mut self, b: u32, cx: i32, cy: i32) {
        let k = (i64::from(cy) * self.nx + i64::from(cx)) as usize;
        self.cells[k].remove(b);
    }
}

/// The cell of a point, clamped to the grid (border cells reach to infinity).
pub fn cell_of(s: &Scene, x: f64, y: f64) -> (i32, i32) {
    let fx = ((x - s.x0) / s.cw).floor();
    let fy = ((y - s.y0) / s.ch).floor();
    let ix = if fx < 0.0 { 0 } else if fx > (s.nx - 1) as f64 { s.nx - 1 } else { fx as i64 };
    let iy = if fy < 0.0 { 0 } else if fy > (s.ny - 1) as f64 { s.ny - 1 } else { fy as i64 };
    (ix as i32, iy as i32)
}

#[cfg(test)]
mod tests {
    use super::{CellList, CELL_INLINE};

    #[test]
    fn cell_list_is_a_python_list_with_last_into_the_hole() {
        // xorshift64*: reproducible numbers without a dependency
        let mut state = 777u64;
        let mut next = || {
            state ^= state >> 12;
            state ^= state << 25;
            state ^= state >> 27;
            state.wrapping_mul(0x2545_f491_4f6c_dd1d)
        };
        let mut cell = CellList::default();
        let mut model: Vec<u32> = Vec::new();
        let mut fresh = 0u32;
        for _ in 0..50_000 {
            if model.is_empty() || (model.len() < 3 * CELL_INLINE && next() % 2 == 0) {
                cell.push(fresh);
                model.push(fresh);
                fresh += 1;
            } else {
                let x = model[(next() % model.len() as u64) as usize];
                cell.remove(x);
                let k = model.iter().position(|&o| o == x).unwrap();
                let last = model.pop().unwrap();
                if k < model.len() {
                    model[k] = last;
                }
            }
            assert_eq!(cell.len(), model.len());
            for (k, &x) in model.iter().enumerate() {
                assert_eq!(cell.get(k), x);
            }
        }
    }
}
