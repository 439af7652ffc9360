//! Block-diagonal LU for the iteration matrix of a DAE with a [`super::BlockStructure`]: the
//! matrix is block diagonal over the connected components of the block graph, so only those
//! blocks are stored and each is factored on its own (partial pivoting) — memory and time
//! O(Σ m_k²) and O(Σ m_k³) instead of O(n²) and O(n³). Safe code; `ida/linear.rs` wraps it as a
//! SUNDIALS matrix and linear solver. Buffers are reused, so a warm layout and factorisation
//! allocate nothing.

use super::colouring::Colouring;

/// The diagonal blocks of an iteration matrix (one dense column-major block per connected
/// component of a [`Colouring`]) and their LU factors. The Jacobian is written straight into
/// the blocks ([`Self::set`]), so no `n × n` matrix exists.
#[derive(Clone, Debug, Default)]
pub(crate) struct BlockLu {
    /// Unknowns of component `k`: `index[start[k]..start[k + 1]]` (copied at layout, so a later
    /// change of the structure cannot mismatch the factors).
    index: Vec<usize>,
    start: Vec<usize>,
    /// Component and position within it of each unknown.
    comp: Vec<usize>,
    local: Vec<usize>,
    /// Column-major block (then LU factors) of component k at `lu[off[k]..]`, size m_k².
    lu: Vec<f64>,
    off: Vec<usize>,
    /// Row permutation of each component (local indices), at `piv[start[k]..]`.
    piv: Vec<usize>,
    /// Gathered right-hand side.
    work: Vec<f64>,
}

impl BlockLu {
    /// Lays out zeroed blocks for the components of `col` (n unknowns).
    pub fn layout(&mut self, col: &Colouring, n: usize) {
        self.index.clear();
        self.start.clear();
        self.off.clear();
        self.start.push(0);
        self.comp.resize(n, 0);
        self.local.resize(n, 0);
        let mut size = 0;
        for k in 0..col.n_components() {
            let c = col.component(k);
            for (l, &i) in c.iter().enumerate() {
                self.comp[i] = k;
                self.local[i] = l;
            }
            self.index.extend_from_slice(c);
            self.start.push(self.index.len());
            self.off.push(size);
            size += c.len() * c.len();
        }
        self.lu.clear();
        self.lu.resize(size, 0.0);
        self.piv.clear();
        self.piv.resize(self.index.len(), 0);
        self.work.resize(n, 0.0);
    }

    /// Sets entry (`i`, `j`) of the matrix; both unknowns must be in one component (entries
    /// between components are zero by construction).
    #[inline]
    pub fn set(&mut self, i: usize, j: usize, value: f64) {
        let k = self.comp[j];
        debug_assert_eq!(self.comp[i], k, "entry ({i}, {j}) couples two components");
        let m = self.start[k + 1] - self.start[k];
        self.lu[self.off[k] + self.local[j] * m + self.local[i]] = value;
    }

    /// Adds `values[t]` to entry (`i0 + t`, `j`): the rows must be in `j`'s component and
    /// consecutive in it (as a run of one block's unknowns is), so the run is one slice of
    /// the block's column.
    #[inline]
    pub fn add_run(&mut self, i0: usize, j: usize, values: &[f64]) {
        let k = self.comp[j];
        let m = self.start[k + 1] - self.start[k];
        let base = self.off[k] + self.local[j] * m + self.local[i0];
        for (t, &v) in values.iter().enumerate() {
            debug_assert_eq!(
                self.comp[i0 + t],
                k,
                "entry ({}, {j}) couples two components",
                i0 + t
            );
            debug_assert_eq!(
                self.local[i0 + t],
                self.local[i0] + t,
                "rows not consecutive"
            );
            self.lu[base + t] += v;
        }
    }

    /// Factors every block in place. Returns the global index of the first zero pivot if a
    /// block is singular.
    pub fn factor(&mut self) -> Result<(), usize> {
        for k in 0..self.off.len() {
            let idx = &self.index[self.start[k]..self.start[k + 1]];
            let m = idx.len();
            let lu = &mut self.lu[self.off[k]..self.off[k] + m * m];
            let piv = &mut self.piv[self.start[k]..self.start[k + 1]];
            lu_in_place(lu, m, piv).map_err(|local| idx[local])?;
        }
        Ok(())
    }

    /// Solves `A x = b` in place (`x` holds `b` on entry) with the factors of [`Self::factor`].
    pub fn solve(&mut self, x: &mut [f64]) {
        for k in 0..self.off.len() {
            let idx = &self.index[self.start[k]..self.start[k + 1]];
            let m = idx.len();
            let lu = &self.lu[self.off[k]..self.off[k] + m * m];
            let piv = &self.piv[self.start[k]..self.start[k + 1]];
            let w = &mut self.work[..m];
            for (l, &i) in idx.iter().enumerate() {
                w[l] = x[i];
            }
            lu_solve(lu, m, piv, w);
            for (l, &i) in idx.iter().enumerate() {
                x[i] = w[l];
            }
        }
    }
}

/// LU with partial pivoting of the column-major `m × m` matrix `a` in place (unit lower `L`
/// below the diagonal, `U` on and above); `piv[k]` = row swapped with row k at step k.
/// Err(k) when column k has no non-zero pivot.
fn lu_in_place(a: &mut [f64], m: usize, piv: &mut [usize]) -> Result<(), usize> {
    for k in 0..m {
        let col_k = k * m;
        let p = (k..m)
            .max_by(|&i, &j| a[col_k + i].abs().total_cmp(&a[col_k + j].abs()))
            .unwrap_or(k);
        piv[k] = p;
        if a[col_k + p] == 0.0 {
            return Err(k);
        }
        if p != k {
            for j in 0..m {
                a.swap(j * m + k, j * m + p);
            }
        }
        let inv = 1.0 / a[col_k + k];
        for i in k + 1..m {
            a[col_k + i] *= inv;
        }
        for j in k + 1..m {
            let akj = a[j * m + k];
            if akj != 0.0 {
                let (left, right) = a.split_at_mut(j * m);
                let lcol = &left[col_k..col_k + m];
                let ucol = &mut right[..m];
                for i in k + 1..m {
                    ucol[i] -= lcol[i] * akj;
                }
            }
        }
    }
    Ok(())
}

/// Solves with the factors of [`lu_in_place`], `b` overwritten by `x`. The inner loops run
/// over column slices zipped with `b` (no index arithmetic or bounds check per entry): with
/// indexed loops the block solves took 1.005e9 of billiards16's 4.50e9 instructions, now
/// 0.860e9 (callgrind, BENCHMARKS.md "Where the time goes"). Most of it is the rack's balls
/// touching each other: one component of up to 15 × 13 unknowns, solved densely.
fn lu_solve(a: &[f64], m: usize, piv: &[usize], b: &mut [f64]) {
    let b = &mut b[..m];
    for (k, &p) in piv.iter().enumerate().take(m) {
        b.swap(k, p);
    }
    for (j, col) in a.chunks_exact(m).enumerate().take(m) {
        let bj = b[j];
        if bj != 0.0 {
            let (_, below) = b.split_at_mut(j + 1);
            for (bi, &aij) in below.iter_mut().zip(&col[j + 1..]) {
                *bi -= aij * bj;
            }
        }
    }
    for (j, col) in a.chunks_exact(m).enumerate().take(m).rev() {
        let (above, rest) = b.split_at_mut(j);
        rest[0] /= col[j];
        let bj = rest[0];
        if bj != 0.0 {
            for (bi, &aij) in above.iter_mut().zip(&col[..j]) {
                *bi -= aij * bj;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::BlockStructure;
    use nalgebra::{DMatrix, DVector};

    /// A random block-sparse matrix solved blockwise agrees with nalgebra's dense LU of the
    /// whole matrix to round-off (well-conditioned: diagonally weighted).
    #[test]
    fn blockwise_solve_matches_dense_lu() {
        let mut x: u64 = 0x2545f4914f6cdd1d;
        let mut rnd = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let n = 23;
        let nb = 7;
        let block_of: Vec<usize> = (0..n).map(|i| (i * 5 + 3) % nb).collect();
        let couplings = vec![(0, 1), (1, 2), (4, 5)];
        let mut col = Colouring::with_structure(BlockStructure {
            block_of: block_of.clone(),
            n_blocks: nb,
            couplings: couplings.clone(),
            ..Default::default()
        });
        col.update(n).unwrap();
        let coupled = |a: usize, b: usize| {
            a == b
                || couplings
                    .iter()
                    .any(|&(p, q)| (p, q) == (a, b) || (q, p) == (a, b))
        };
        let mut a = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for j in 0..n {
                if coupled(block_of[i], block_of[j]) {
                    // Small diagonal on some rows forces pivoting.
                    a[(i, j)] = rnd() + if i == j && i % 3 != 0 { 3.0 } else { 0.0 };
                }
            }
        }
        let b = DVector::<f64>::from_fn(n, |_, _| rnd());
        let exact = a.clone().lu().solve(&b).unwrap();
        let mut lu = BlockLu::default();
        let load = |lu: &mut BlockLu, a: &DMatrix<f64>| {
            lu.layout(&col, n);
            for i in 0..n {
                for j in 0..n {
                    if coupled(block_of[i], block_of[j]) {
                        lu.set(i, j, a[(i, j)]);
                    }
                }
            }
        };
        load(&mut lu, &a);
        lu.factor().unwrap();
        let mut xs = b.as_slice().to_vec();
        lu.solve(&mut xs);
        let err = (DVector::from_vec(xs) - &exact).amax();
        assert!(err < 1e-12 * exact.amax().max(1.0), "max error {err:e}");
        // A zero column in a block is reported by its global index.
        let mut sing = a.clone();
        sing.column_mut(5).fill(0.0);
        load(&mut lu, &sing);
        assert_eq!(lu.factor(), Err(5));
    }
}
