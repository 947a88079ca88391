//! The run's time series kept in memory, bounded: every `stride`-th row, the
//! stride doubling (and every other kept row dropped) whenever the buffer is full, so a run
//! of any length keeps between half and all of [`MAX_POINTS`] points per signal. A
//! [`crate::run::RowSink`] gets every row.

/// Points kept per signal at most.
pub const MAX_POINTS: usize = 8_192;

/// Columns of decimated samples.
pub struct PlotBuffer {
    columns: Vec<Vec<f64>>,
    stride: usize,
    /// Rows offered since the last kept one.
    since_kept: usize,
    cap: usize,
}

impl PlotBuffer {
    /// A buffer for `columns` signals, at most [`MAX_POINTS`] points each.
    pub fn new(columns: usize) -> Self {
        Self::with_cap(columns, MAX_POINTS)
    }

    fn with_cap(columns: usize, cap: usize) -> Self {
        let cap = cap.max(2) & !1;
        Self {
            columns: (0..columns).map(|_| Vec::with_capacity(cap)).collect(),
            stride: 1,
            since_kept: 0,
            cap,
        }
    }

    /// Offers one row (one value per column); keeps it if it falls on the stride.
    pub fn push(&mut self, row: &[f64]) {
        if self.since_kept > 0 {
            self.since_kept = (self.since_kept + 1) % self.stride;
            return;
        }
        // Full: keep every other point. The kept rows were 0, s, …, (cap − 1)s; this row,
        // cap·s, falls on the new stride 2s.
        if self.columns.first().is_some_and(|c| c.len() == self.cap) {
            for c in &mut self.columns {
                let mut k = 0;
                c.retain(|_| {
                    k += 1;
                    k % 2 == 1
                });
            }
            self.stride *= 2;
        }
        for (c, x) in self.columns.iter_mut().zip(row) {
            c.push(*x);
        }
        self.since_kept = 1 % self.stride;
    }

    /// Column `k`'s kept points.
    pub fn column(&self, k: usize) -> &[f64] {
        &self.columns[k]
    }

    /// Every column's kept points.
    pub fn columns(&self) -> &[Vec<f64>] {
        &self.columns
    }

    /// Rows between two kept points.
    pub fn stride(&self) -> usize {
        self.stride
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kept_rows_are_evenly_spaced_and_memory_is_bounded() {
        for n in [5usize, 16, 17, 100, 1_000, 12_345] {
            let mut b = PlotBuffer::with_cap(2, 16);
            for k in 0..n {
                b.push(&[k as f64, -(k as f64)]);
            }
            let t = b.column(0);
            assert!(
                t.len() <= 16 && (n < 8 || t.len() >= 8),
                "n {n}: {}",
                t.len()
            );
            assert_eq!(t[0], 0.0);
            for w in t.windows(2) {
                assert_eq!(w[1] - w[0], b.stride() as f64, "n {n}: {t:?}");
            }
            assert!((n - 1) as f64 - t[t.len() - 1] < b.stride() as f64);
            assert!(b.column(1).iter().zip(t).all(|(a, b)| *a == -b));
        }
    }
}
