//! A rectangle of grid cells: costmap_2d's update bounds (`updateBounds`), in cell indices.

/// Cells `c0..c1` x `r0..r1` (columns, rows; ends excluded) of a grid.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CellBounds {
    /// First column.
    pub c0: usize,
    /// First row.
    pub r0: usize,
    /// One past the last column.
    pub c1: usize,
    /// One past the last row.
    pub r1: usize,
}

impl CellBounds {
    /// The single cell (c, r).
    pub fn cell(c: usize, r: usize) -> Self {
        Self { c0: c, r0: r, c1: c + 1, r1: r + 1 }
    }

    /// The whole `width` x `height` grid.
    pub fn all(width: usize, height: usize) -> Self {
        Self { c0: 0, r0: 0, c1: width, r1: height }
    }

    /// Whether it holds no cell.
    pub fn is_empty(&self) -> bool {
        self.c0 >= self.c1 || self.r0 >= self.r1
    }

    /// Columns covered.
    pub fn width(&self) -> usize {
        self.c1.saturating_sub(self.c0)
    }

    /// Rows covered.
    pub fn height(&self) -> usize {
        self.r1.saturating_sub(self.r0)
    }

    /// Cells covered.
    pub fn area(&self) -> usize {
        self.width() * self.height()
    }

    /// The smallest bounds holding both.
    pub fn union(self, o: CellBounds) -> CellBounds {
        if self.is_empty() {
            return o;
        }
        if o.is_empty() {
            return self;
        }
        CellBounds { c0: self.c0.min(o.c0), r0: self.r0.min(o.r0), c1: self.c1.max(o.c1), r1: self.r1.max(o.r1) }
    }

    /// Grown by `k` cells on every side, clipped to a `width` x `height` grid.
    pub fn expanded(self, k: usize, width: usize, height: usize) -> CellBounds {
        CellBounds { c0: self.c0.saturating_sub(k), r0: self.r0.saturating_sub(k), c1: self.c1.saturating_add(k).min(width), r1: self.r1.saturating_add(k).min(height) }
    }

    /// Whether `o` lies inside.
    pub fn contains(&self, o: &CellBounds) -> bool {
        o.is_empty() || (o.c0 >= self.c0 && o.r0 >= self.r0 && o.c1 <= self.c1 && o.r1 <= self.r1)
    }
}

/// Bounds that grow as cells are added (empty at first).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct DirtyBounds(Option<CellBounds>);

impl DirtyBounds {
    /// Adds cell (c, r).
    pub fn touch(&mut self, c: usize, r: usize) {
        self.add(CellBounds::cell(c, r));
    }

    /// Adds the rectangle `b`.
    pub fn add(&mut self, b: CellBounds) {
        if b.is_empty() {
            return;
        }
        self.0 = Some(match self.0 {
            Some(a) => a.union(b),
            None => b,
        });
    }

    /// The bounds so far, emptied.
    pub fn take(&mut self) -> Option<CellBounds> {
        self.0.take()
    }

    /// The bounds so far.
    pub fn get(&self) -> Option<CellBounds> {
        self.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_grow_and_clip() {
        let mut d = DirtyBounds::default();
        assert_eq!(d.get(), None);
        d.touch(3, 4);
        d.touch(1, 9);
        let b = d.take().unwrap();
        assert_eq!(b, CellBounds { c0: 1, r0: 4, c1: 4, r1: 10 });
        assert_eq!(d.take(), None);
        assert_eq!(b.expanded(2, 5, 11), CellBounds { c0: 0, r0: 2, c1: 5, r1: 11 });
        assert!(CellBounds::all(5, 11).contains(&b));
        assert!(!b.contains(&CellBounds::all(5, 11)));
        assert_eq!(b.area(), 18);
    }
}
