//! The box cut into vertical columns, each a list of its disks sorted by height: what a falling or
//! rolling disk can touch is a few entries near one height in a few columns, found by bisection.

/// Columns of equal width across the box; each holds `(y, disk)` sorted by `y`.
pub struct Columns {
    width: f64,
    lists: Vec<Vec<(f64, u32)>>,
}

impl Columns {
    /// Columns at least `cell` wide (at most `most` of them) across a box `box_width` wide.
    pub fn new(box_width: f64, cell: f64, most: usize) -> Self {
        let count = ((box_width / cell).floor() as usize).clamp(1, most.max(1));
        Self { width: box_width / count as f64, lists: vec![Vec::new(); count] }
    }

    fn column(&self, x: f64) -> usize {
        ((x.max(0.0) / self.width) as usize).min(self.lists.len() - 1)
    }

    /// The columns that hold centres between `left` and `right` (m).
    pub fn span(&self, left: f64, right: f64) -> std::ops::RangeInclusive<usize> {
        self.column(left)..=self.column(right)
    }

    /// Adds disk `k` with its centre at (`x`, `y`).
    pub fn insert(&mut self, x: f64, y: f64, k: u32) {
        let column = self.column(x);
        let list = &mut self.lists[column];
        let at = list.partition_point(|e| e.0 <= y);
        list.insert(at, (y, k));
    }

    /// The disks of `column` with centres at or below `y`, highest first, as `(y, disk)`.
    pub fn below(&self, column: usize, y: f64) -> impl Iterator<Item = (f64, u32)> + '_ {
        let list = &self.lists[column];
        list[..list.partition_point(|e| e.0 <= y)].iter().rev().copied()
    }

    /// The disks with centres in `[left, right] × [bottom, top]`.
    pub fn within(&self, [left, right, bottom, top]: [f64; 4]) -> impl Iterator<Item = u32> + '_ {
        self.span(left, right).flat_map(move |c| {
            let list = &self.lists[c];
            let (a, b) = (list.partition_point(|e| e.0 < bottom), list.partition_point(|e| e.0 <= top));
            list[a..b].iter().map(|e| e.1)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::Columns;

    #[test]
    fn columns_find_disks_by_place_and_height() {
        let mut columns = Columns::new(1.0, 0.3, 100);
        for (k, (x, y)) in [(0.1, 0.5), (0.1, 0.2), (0.5, 0.4), (0.9, 0.1), (0.15, 0.9)].into_iter().enumerate() {
            columns.insert(x, y, k as u32);
        }
        assert_eq!(columns.span(0.0, 1.0), 0..=2, "three columns of 1/3 m");
        let below: Vec<u32> = columns.below(0, 0.6).map(|e| e.1).collect();
        assert_eq!(below, [0, 1], "highest first, the disk above left out");
        let mut found: Vec<u32> = columns.within([0.0, 0.6, 0.15, 0.5]).collect();
        found.sort_unstable();
        assert_eq!(found, [0, 1, 2]);
    }
}
