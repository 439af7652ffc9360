//! Block LU for the iteration matrix of a DAE with a [`super::BlockStructure`]: the matrix is
//! block diagonal over the connected components of the block graph, so only those blocks are
//! stored and each is factored on its own — memory and time O(Σ m_k²) and O(Σ m_k³) instead of
//! O(n²) and O(n³). A component is factored
//!
//! - **densely** (partial pivoting over the whole component) when it is small or its blocks are
//!   densely coupled: one joint tree, two balls touching, a closed loop;
//! - **block-sparse** when that needs fewer operations (piles, stacks, a rack of balls: each
//!   block couples with a few others): the blocks are eliminated in a greedy minimum-fill order
//!   (weighted by block size), only the blocks of `L + U` including the fill are stored, each
//!   diagonal block is factored with partial pivoting inside it, and the off-diagonal blocks
//!   follow by triangular solves and Schur updates. The choice is made per component from the
//!   operation counts of both (`SPARSE_GAIN`), when the structure changes.
//!
//! Pivoting inside a diagonal block only is safe for the iteration matrices of mechanical
//! systems (`c_j·M` and `c_j·I` on the diagonal, contact stiffness coupling bodies weakly
//! against `c_j²·M` at the step sizes that resolve a contact), but not for every matrix: a
//! component whose diagonal block is singular, or whose `L` blocks grow beyond
//! `MAX_L_GROWTH` (a pivot much smaller than an entry below it in another block), is
//! factored densely instead, from a copy of its entries, until the structure changes.
//!
//! Safe code; `ida/linear.rs` wraps it as a SUNDIALS matrix and linear solver. Buffers are
//! reused, so a warm layout and factorisation allocate nothing.

use super::colouring::Colouring;

/// A component is factored block-sparse when its operation count is below the dense one
/// divided by this factor (the sparse path's per-block bookkeeping and shorter inner loops
/// cost more per operation than the dense loops; measured by
/// `tests::sparse_and_dense_factor_times`, ignored, see BENCHMARKS.md "Linear algebra").
const SPARSE_GAIN: f64 = 3.0;

/// Largest entry of an `L` block accepted from pivoting inside the diagonal block: threshold
/// partial pivoting as sparse direct solvers use it (a pivot at least 1e-3 of the largest entry
/// in its column); beyond, the component is factored densely.
const MAX_L_GROWTH: f64 = 1e3;

/// The diagonal blocks of an iteration matrix (one per connected component of a
/// [`Colouring`]) and their LU factors. The Jacobian is written straight into the blocks
/// ([`Self::set`], [`Self::add_run`]), so no `n × n` matrix exists.
#[derive(Clone, Debug, Default)]
pub(crate) struct BlockLu {
    /// Unknowns of component `k`: `index[start[k]..start[k + 1]]`, in its local order (copied at
    /// layout, so a later change of the structure cannot mismatch the factors).
    index: Vec<usize>,
    start: Vec<usize>,
    /// Component and position within it (local order) of each unknown.
    comp: Vec<usize>,
    local: Vec<usize>,
    /// Dense components: column-major block (then LU factors) of component k at
    /// `lu[off[k]..]`, size m_k² (0 for sparse components).
    lu: Vec<f64>,
    off: Vec<usize>,
    /// Row permutation of each component (local indices), at `piv[start[k]..]`.
    piv: Vec<usize>,
    /// Sparse component of component k (`usize::MAX`: dense).
    kind: Vec<usize>,
    /// The sparse components (a pool: entries beyond `n_sparse` keep their buffers).
    sparse: Vec<SparseComp>,
    n_sparse: usize,
    /// Gathered right-hand side.
    work: Vec<f64>,
    /// Runs of consecutive unknowns of component k (`runs[run_start[k]..run_start[k + 1]]`):
    /// `(global first, local first, length)`, so that the right-hand side is gathered and
    /// scattered by slice copies (a free body's block is two runs, its positions and its
    /// velocities) instead of entry by entry.
    runs: Vec<(usize, usize, usize)>,
    run_start: Vec<usize>,
    /// Layout scratch: blocks by component, block → local block index, ordering scratch.
    comp_blocks: Vec<usize>,
    comp_block_start: Vec<usize>,
    scratch: OrderScratch,
    /// A layout exists for `laid_n` unknowns.
    laid_n: Option<usize>,
    /// Replaces [`SPARSE_GAIN`] (tests: 0 forces the block-sparse path, infinity the dense).
    gain: Option<f64>,
}

/// One component factored block-sparse. Blocks are numbered by their elimination position
/// `p`; block `p` holds the local unknowns `bstart[p]..bstart[p + 1]`. Every stored block is
/// column-major.
#[derive(Clone, Debug, Default)]
struct SparseComp {
    bstart: Vec<usize>,
    /// Elimination position of each local unknown.
    bpos: Vec<usize>,
    /// Offset of the diagonal block `p` in `vals`.
    diag: Vec<usize>,
    /// Later neighbours of `p` (including fill), ascending: `nbr[nstart[p]..nstart[p + 1]]`,
    /// with the offsets of the `L` block `(q, p)` and the `U` block `(p, q)`.
    nbr: Vec<usize>,
    nstart: Vec<usize>,
    l_off: Vec<usize>,
    u_off: Vec<usize>,
    /// Schur update targets of step `p`: the offset of block `(q_a, q_b)` for the neighbours
    /// `a, b` of `p`, row-major over `(a, b)` from `ustart[p]`.
    upd: Vec<usize>,
    ustart: Vec<usize>,
    /// The entries (then the factors) and a copy of the entries for the dense fallback.
    vals: Vec<f64>,
    orig: Vec<f64>,
    /// The dense fallback: factored densely until the structure changes.
    dense: bool,
    dense_lu: Vec<f64>,
    /// Row permutations of the diagonal blocks (local indices within each block), or of the
    /// whole component when dense.
    piv: Vec<usize>,
    /// The L and U blocks of one step, copied for its Schur updates.
    lbuf: Vec<f64>,
    ubuf: Vec<f64>,
}

/// Buffers of the minimum-fill ordering.
#[derive(Clone, Debug, Default)]
struct OrderScratch {
    /// Block adjacency (with fill) of the component being ordered, `nb × nb`.
    adj: Vec<bool>,
    size: Vec<usize>,
    cost: Vec<usize>,
    done: Vec<bool>,
    /// Elimination order (local block indices) and position of each local block in it (also
    /// the bucket cursors of `BlockLu::layout` before the components are ordered).
    order: Vec<usize>,
    pos: Vec<usize>,
    nbrs: Vec<usize>,
    local_of_block: Vec<usize>,
}

impl BlockLu {
    /// A block LU that chooses dense or block-sparse per component, or (`dense`:
    /// `IdaOptions::dense_lu`, for comparisons) factors every component densely.
    pub(super) fn new(dense: bool) -> Self {
        BlockLu {
            gain: dense.then_some(f64::INFINITY),
            ..Default::default()
        }
    }

    /// Lays out zeroed blocks for the components of `col` (n unknowns). `rebuilt`: the colouring
    /// changed since the last layout (else only the entries are zeroed, and the ordering, the
    /// choice of dense or sparse and a dense fallback are kept).
    pub(super) fn layout(&mut self, col: &Colouring, n: usize, rebuilt: bool) {
        if !rebuilt && self.laid_n == Some(n) {
            self.lu.fill(0.0);
            for sc in &mut self.sparse[..self.n_sparse] {
                sc.vals.fill(0.0);
            }
            return;
        }
        self.laid_n = Some(n);
        self.index.clear();
        self.start.clear();
        self.off.clear();
        self.kind.clear();
        self.n_sparse = 0;
        self.start.push(0);
        self.comp.resize(n, 0);
        self.local.resize(n, 0);
        // Blocks of each component (non-empty ones).
        let n_comp = col.n_components();
        let nb = col.n_blocks();
        self.comp_block_start.clear();
        self.comp_block_start.resize(n_comp + 1, 0);
        for b in 0..nb {
            if !col.members(b).is_empty() {
                self.comp_block_start[col.component_of_block(b) + 1] += 1;
            }
        }
        for k in 0..n_comp {
            self.comp_block_start[k + 1] += self.comp_block_start[k];
        }
        self.comp_blocks.clear();
        self.comp_blocks.resize(self.comp_block_start[n_comp], 0);
        self.scratch.pos.clear();
        self.scratch
            .pos
            .extend_from_slice(&self.comp_block_start[..n_comp]);
        for b in 0..nb {
            if !col.members(b).is_empty() {
                let k = col.component_of_block(b);
                self.comp_blocks[self.scratch.pos[k]] = b;
                self.scratch.pos[k] += 1;
            }
        }
        self.scratch.local_of_block.resize(nb, 0);
        let mut size = 0;
        for k in 0..n_comp {
            let blocks = &self.comp_blocks[self.comp_block_start[k]..self.comp_block_start[k + 1]];
            let c = col.component(k);
            let gain = self.gain.unwrap_or(SPARSE_GAIN);
            let sparse = blocks.len() >= 3
                && order_blocks(col, blocks, &mut self.scratch) * gain < dense_flops(c.len());
            if sparse {
                if self.n_sparse == self.sparse.len() {
                    self.sparse.push(SparseComp::default());
                }
                let sc = &mut self.sparse[self.n_sparse];
                let first = self.index.len();
                sc.symbolic(col, blocks, &self.scratch, &mut self.index);
                for (l, &i) in self.index[first..].iter().enumerate() {
                    self.comp[i] = k;
                    self.local[i] = l;
                }
                self.kind.push(self.n_sparse);
                self.n_sparse += 1;
                self.off.push(size);
            } else {
                for (l, &i) in c.iter().enumerate() {
                    self.comp[i] = k;
                    self.local[i] = l;
                }
                self.index.extend_from_slice(c);
                self.kind.push(usize::MAX);
                self.off.push(size);
                size += c.len() * c.len();
            }
            self.start.push(self.index.len());
        }
        self.lu.clear();
        self.lu.resize(size, 0.0);
        self.piv.clear();
        self.piv.resize(self.index.len(), 0);
        self.work.resize(n, 0.0);
        self.runs.clear();
        self.run_start.clear();
        self.run_start.push(0);
        for k in 0..self.start.len() - 1 {
            let idx = &self.index[self.start[k]..self.start[k + 1]];
            let first = self.runs.len();
            for (l, &i) in idx.iter().enumerate() {
                match self.runs[first..].last_mut() {
                    Some((g, _, len)) if *g + *len == i => *len += 1,
                    _ => self.runs.push((i, l, 1)),
                }
            }
            self.run_start.push(self.runs.len());
        }
    }

    /// Number of components factored block-sparse in the current layout.
    #[cfg(test)]
    fn n_sparse(&self) -> usize {
        self.n_sparse
    }

    /// The entry (`i`, `j`) of the matrix, as a slot of the storage; both unknowns must be in
    /// one component (entries between components are zero by construction), and for a sparse
    /// component in blocks coupled by the structure. `None` for an entry outside the layout.
    #[inline]
    fn slot(&mut self, i: usize, j: usize) -> Option<&mut f64> {
        let k = self.comp[j];
        debug_assert_eq!(self.comp[i], k, "entry ({i}, {j}) couples two components");
        let s = self.kind[k];
        if s == usize::MAX {
            let m = self.start[k + 1] - self.start[k];
            return self
                .lu
                .get_mut(self.off[k] + self.local[j] * m + self.local[i]);
        }
        let sc = &mut self.sparse[s];
        let at = sc.offset(self.local[i], self.local[j]);
        debug_assert!(at.is_some(), "entry ({i}, {j}) outside the block pattern");
        sc.vals.get_mut(at?)
    }

    /// Sets entry (`i`, `j`) of the matrix; both unknowns must be in one component (entries
    /// between components are zero by construction).
    #[inline]
    pub(super) fn set(&mut self, i: usize, j: usize, value: f64) {
        if let Some(e) = self.slot(i, j) {
            *e = value;
        }
    }

    /// Adds `values[t]` to entry (`i0 + t`, `j`): the rows must be in `j`'s component and
    /// consecutive in one of its blocks (as a run of one block's unknowns is), so the run is one
    /// slice of a stored column.
    #[inline]
    pub(super) fn add_run(&mut self, i0: usize, j: usize, values: &[f64]) {
        let k = self.comp[j];
        for t in 0..values.len() {
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
        }
        let s = self.kind[k];
        let (store, base) = if s == usize::MAX {
            let m = self.start[k + 1] - self.start[k];
            (
                &mut self.lu,
                self.off[k] + self.local[j] * m + self.local[i0],
            )
        } else {
            let sc = &mut self.sparse[s];
            let Some(base) = sc.offset(self.local[i0], self.local[j]) else {
                debug_assert!(false, "entry ({i0}, {j}) outside the block pattern");
                return;
            };
            (&mut sc.vals, base)
        };
        if let Some(dst) = store.get_mut(base..base + values.len()) {
            for (d, &v) in dst.iter_mut().zip(values) {
                *d += v;
            }
        }
    }

    /// The entries as laid out and written (call before [`Self::factor`]), into `out`: the
    /// dense components, then the block-sparse ones, in storage order.
    pub(super) fn entries(&self, out: &mut Vec<f64>) {
        out.clear();
        out.extend_from_slice(&self.lu);
        for sc in &self.sparse[..self.n_sparse] {
            out.extend_from_slice(&sc.vals);
        }
    }

    /// Sets the entries to `a + s·b`, both taken by [`Self::entries`] in the current layout.
    /// `false` (nothing written) if their lengths do not match the layout.
    pub(super) fn set_entries(&mut self, a: &[f64], b: &[f64], s: f64) -> bool {
        let total = self.lu.len()
            + self.sparse[..self.n_sparse]
                .iter()
                .map(|sc| sc.vals.len())
                .sum::<usize>();
        if a.len() != total || b.len() != total {
            return false;
        }
        let stores = std::iter::once(&mut self.lu).chain(
            self.sparse[..self.n_sparse]
                .iter_mut()
                .map(|sc| &mut sc.vals),
        );
        let mut at = 0;
        for store in stores {
            let m = store.len();
            for ((d, &x), &y) in store.iter_mut().zip(&a[at..at + m]).zip(&b[at..at + m]) {
                *d = x + s * y;
            }
            at += m;
        }
        true
    }

    /// Factors every component in place. Returns the global index of the first zero pivot if a
    /// component is singular.
    pub(super) fn factor(&mut self) -> Result<(), usize> {
        for k in 0..self.off.len() {
            let idx = &self.index[self.start[k]..self.start[k + 1]];
            let m = idx.len();
            let piv = &mut self.piv[self.start[k]..self.start[k + 1]];
            let s = self.kind[k];
            if s == usize::MAX {
                let lu = &mut self.lu[self.off[k]..self.off[k] + m * m];
                lu_in_place(lu, m, piv).map_err(|local| idx[local])?;
            } else {
                self.sparse[s].factor(m).map_err(|local| idx[local])?;
            }
        }
        Ok(())
    }

    /// Solves `A x = b` in place (`x` holds `b` on entry) with the factors of [`Self::factor`].
    pub(super) fn solve(&mut self, x: &mut [f64]) {
        for k in 0..self.off.len() {
            let idx = &self.index[self.start[k]..self.start[k + 1]];
            let m = idx.len();
            let w = &mut self.work[..m];
            let runs = &self.runs[self.run_start[k]..self.run_start[k + 1]];
            for &(g, l, len) in runs {
                w[l..l + len].copy_from_slice(&x[g..g + len]);
            }
            let s = self.kind[k];
            if s == usize::MAX {
                let lu = &self.lu[self.off[k]..self.off[k] + m * m];
                let piv = &self.piv[self.start[k]..self.start[k + 1]];
                lu_solve(lu, m, piv, w);
            } else {
                self.sparse[s].solve(m, w);
            }
            for &(g, l, len) in runs {
                x[g..g + len].copy_from_slice(&w[l..l + len]);
            }
        }
    }
}

/// Orders the blocks of one component (`blocks`, global block numbers; `m` unknowns) for
/// block elimination by greedy minimum fill: the next block is the one whose remaining
/// neighbours have the fewest unknowns, and eliminating it couples those neighbours with each
/// other. Leaves the order, the positions and the filled adjacency in `sc` and returns the operation count of
/// the block elimination in that order.
fn order_blocks(col: &Colouring, blocks: &[usize], sc: &mut OrderScratch) -> f64 {
    let nb = blocks.len();
    for (l, &b) in blocks.iter().enumerate() {
        sc.local_of_block[b] = l;
    }
    sc.adj.clear();
    sc.adj.resize(nb * nb, false);
    sc.size.clear();
    sc.size.extend(blocks.iter().map(|&b| col.members(b).len()));
    for (l, &b) in blocks.iter().enumerate() {
        for &o in col.neighbours(b) {
            if !col.members(o).is_empty() && o != b {
                let lo = sc.local_of_block[o];
                sc.adj[l * nb + lo] = true;
                sc.adj[lo * nb + l] = true;
            }
        }
    }
    sc.cost.clear();
    sc.cost.extend((0..nb).map(|a| {
        (0..nb)
            .filter(|&b| sc.adj[a * nb + b])
            .map(|b| sc.size[b])
            .sum::<usize>()
    }));
    sc.done.clear();
    sc.done.resize(nb, false);
    sc.order.clear();
    let mut flops = 0.0;
    for _ in 0..nb {
        let Some(v) = (0..nb)
            .filter(|&a| !sc.done[a])
            .min_by_key(|&a| (sc.cost[a], a))
        else {
            break;
        };
        sc.order.push(v);
        sc.done[v] = true;
        sc.nbrs.clear();
        sc.nbrs
            .extend((0..nb).filter(|&u| !sc.done[u] && sc.adj[v * nb + u]));
        let s = sc.size[v] as f64;
        let sn: f64 = sc.nbrs.iter().map(|&u| sc.size[u] as f64).sum();
        // Diagonal LU, the two triangular solves of its row and column, the Schur update.
        flops += 2.0 / 3.0 * s * s * s + 2.0 * s * s * sn + 2.0 * s * sn * sn;
        for &u in &sc.nbrs {
            sc.cost[u] -= sc.size[v];
        }
        for ai in 0..sc.nbrs.len() {
            for bi in 0..sc.nbrs.len() {
                let (a, b) = (sc.nbrs[ai], sc.nbrs[bi]);
                if a != b && !sc.adj[a * nb + b] {
                    sc.adj[a * nb + b] = true;
                    sc.cost[a] += sc.size[b];
                }
            }
        }
    }
    sc.pos.clear();
    sc.pos.resize(nb, 0);
    for (p, &v) in sc.order.iter().enumerate() {
        sc.pos[v] = p;
    }
    flops
}

/// Operations of the dense LU of an `m × m` matrix.
fn dense_flops(m: usize) -> f64 {
    2.0 / 3.0 * (m as f64).powi(3)
}

impl SparseComp {
    /// The symbolic factorisation from the ordering in `sc` (its filled adjacency): block
    /// positions, the pattern of `L + U`, the Schur update targets; appends the component's
    /// unknowns in local (elimination) order to `index`.
    fn symbolic(
        &mut self,
        col: &Colouring,
        blocks: &[usize],
        sc: &OrderScratch,
        index: &mut Vec<usize>,
    ) {
        let nb = blocks.len();
        let pos_of = &sc.pos;
        self.bstart.clear();
        self.bstart.push(0);
        self.bpos.clear();
        for (p, &v) in sc.order.iter().enumerate() {
            let members = col.members(blocks[v]);
            index.extend_from_slice(members);
            self.bpos.extend(std::iter::repeat_n(p, members.len()));
            self.bstart.push(self.bpos.len());
        }
        // Pattern: the later neighbours of each block in the filled adjacency.
        self.nbr.clear();
        self.nstart.clear();
        self.nstart.push(0);
        for &v in &sc.order {
            let p = pos_of[v];
            let first = self.nbr.len();
            self.nbr.extend(
                (0..nb)
                    .filter(|&u| sc.adj[v * nb + u] && pos_of[u] > p)
                    .map(|u| pos_of[u]),
            );
            self.nbr[first..].sort_unstable();
            self.nstart.push(self.nbr.len());
        }
        // Offsets: the diagonal block, then the L and U blocks of each step.
        let mut at = 0;
        self.diag.clear();
        self.l_off.clear();
        self.u_off.clear();
        let bs = &self.bstart;
        for p in 0..nb {
            let s = bs[p + 1] - bs[p];
            self.diag.push(at);
            at += s * s;
            for &q in &self.nbr[self.nstart[p]..self.nstart[p + 1]] {
                let sq = bs[q + 1] - bs[q];
                self.l_off.push(at);
                at += sq * s;
                self.u_off.push(at);
                at += s * sq;
            }
        }
        self.vals.clear();
        self.vals.resize(at, 0.0);
        self.orig.clear();
        self.orig.resize(at, 0.0);
        // Schur targets: block (q_a, q_b) for each pair of later neighbours of p.
        self.upd.clear();
        self.ustart.clear();
        for p in 0..nb {
            self.ustart.push(self.upd.len());
            let nbrs = &self.nbr[self.nstart[p]..self.nstart[p + 1]];
            for &qa in nbrs {
                for &qb in nbrs {
                    let target = self.block_offset(qa, qb);
                    debug_assert!(target.is_some(), "fill block ({qa}, {qb}) missing");
                    self.upd.push(target.unwrap_or(usize::MAX));
                }
            }
        }
        self.ustart.push(self.upd.len());
        self.dense = false;
        self.piv.clear();
        self.piv.resize(self.bpos.len(), 0);
    }

    /// Offset in `vals` of the stored block (row block `p`, column block `q`).
    fn block_offset(&self, p: usize, q: usize) -> Option<usize> {
        use std::cmp::Ordering;
        match p.cmp(&q) {
            Ordering::Equal => Some(self.diag[p]),
            // L block (p, q), stored with the later neighbours of q.
            Ordering::Greater => {
                let r = self.nstart[q]..self.nstart[q + 1];
                let t = self.nbr[r.clone()].binary_search(&p).ok()?;
                Some(self.l_off[r.start + t])
            }
            Ordering::Less => {
                let r = self.nstart[p]..self.nstart[p + 1];
                let t = self.nbr[r.clone()].binary_search(&q).ok()?;
                Some(self.u_off[r.start + t])
            }
        }
    }

    /// Offset in `vals` of the entry of local row `li` and local column `lj`.
    #[inline]
    fn offset(&self, li: usize, lj: usize) -> Option<usize> {
        let (p, q) = (self.bpos[li], self.bpos[lj]);
        let rows = self.bstart[p + 1] - self.bstart[p];
        let base = self.block_offset(p, q)?;
        Some(base + (lj - self.bstart[q]) * rows + (li - self.bstart[p]))
    }

    /// Block elimination in place (or the dense fallback); `Err(local index)` of a zero pivot.
    fn factor(&mut self, m: usize) -> Result<(), usize> {
        if !self.dense {
            self.orig.copy_from_slice(&self.vals);
            match self.eliminate() {
                Ok(()) => return Ok(()),
                // A singular diagonal block or a poor pivot: dense from here on.
                Err(_) => self.dense = true,
            }
            self.vals.copy_from_slice(&self.orig);
        }
        self.dense_lu.clear();
        self.dense_lu.resize(m * m, 0.0);
        let nb = self.bstart.len() - 1;
        for p in 0..nb {
            for q in 0..nb {
                let Some(off) = self.block_offset(p, q) else {
                    continue;
                };
                let (r0, r1) = (self.bstart[p], self.bstart[p + 1]);
                let (c0, c1) = (self.bstart[q], self.bstart[q + 1]);
                let rows = r1 - r0;
                for c in c0..c1 {
                    let src = &self.vals[off + (c - c0) * rows..off + (c - c0 + 1) * rows];
                    self.dense_lu[c * m + r0..c * m + r1].copy_from_slice(src);
                }
            }
        }
        lu_in_place(&mut self.dense_lu, m, &mut self.piv)
    }

    /// The block-sparse elimination; `Err(())` when a diagonal block is singular or an `L`
    /// block grows beyond [`MAX_L_GROWTH`].
    fn eliminate(&mut self) -> Result<(), ()> {
        let nb = self.bstart.len() - 1;
        for p in 0..nb {
            let s = self.bstart[p + 1] - self.bstart[p];
            let d0 = self.diag[p];
            let (b0, b1) = (self.bstart[p], self.bstart[p + 1]);
            lu_in_place(&mut self.vals[d0..d0 + s * s], s, &mut self.piv[b0..b1])
                .map_err(|_| ())?;
            let (nb0, nb1) = (self.nstart[p], self.nstart[p + 1]);
            self.lbuf.clear();
            self.ubuf.clear();
            for t in nb0..nb1 {
                let q = self.nbr[t];
                let sq = self.bstart[q + 1] - self.bstart[q];
                // U block (p, q) = L_pp⁻¹ P_p A_pq, column by column.
                let (head, tail) = self.vals.split_at_mut(self.u_off[t]);
                let d = &head[d0..d0 + s * s];
                let piv = &self.piv[b0..b1];
                let u = &mut tail[..s * sq];
                for colv in u.chunks_exact_mut(s) {
                    for (k, &pk) in piv.iter().enumerate() {
                        colv.swap(k, pk);
                    }
                    unit_lower_solve(d, s, colv);
                }
                self.ubuf.extend_from_slice(u);
                // L block (q, p) = A_qp U_pp⁻¹: X U = A, column by column.
                let (head, tail) = self.vals.split_at_mut(self.l_off[t]);
                let d = &head[d0..d0 + s * s];
                let l = &mut tail[..sq * s];
                for c in 0..s {
                    for k in 0..c {
                        let ukc = d[c * s + k];
                        if ukc != 0.0 {
                            let (done, rest) = l.split_at_mut(c * sq);
                            let xk = &done[k * sq..(k + 1) * sq];
                            for (lc, &xv) in rest[..sq].iter_mut().zip(xk) {
                                *lc -= xv * ukc;
                            }
                        }
                    }
                    // The factors keep U's diagonal as reciprocals (`lu_in_place`).
                    let inv = d[c * s + c];
                    for lc in &mut l[c * sq..(c + 1) * sq] {
                        *lc *= inv;
                    }
                }
                if l.iter()
                    .any(|x| x.abs().partial_cmp(&MAX_L_GROWTH) != Some(std::cmp::Ordering::Less))
                {
                    return Err(());
                }
                self.lbuf.extend_from_slice(l);
            }
            // Schur updates: block (q_a, q_b) -= L_{q_a p} U_{p q_b}.
            let deg = nb1 - nb0;
            let mut la = 0;
            for a in 0..deg {
                let qa = self.nbr[nb0 + a];
                let sa = self.bstart[qa + 1] - self.bstart[qa];
                let lblk = &self.lbuf[la..la + sa * s];
                la += sa * s;
                let mut ub = 0;
                for b in 0..deg {
                    let qb = self.nbr[nb0 + b];
                    let sb = self.bstart[qb + 1] - self.bstart[qb];
                    let ublk = &self.ubuf[ub..ub + s * sb];
                    ub += s * sb;
                    let off = self.upd[self.ustart[p] + a * deg + b];
                    let Some(target) = self.vals.get_mut(off..off + sa * sb) else {
                        return Err(());
                    };
                    for (tcol, ucol) in target.chunks_exact_mut(sa).zip(ublk.chunks_exact(s)) {
                        for (lcol, &u) in lblk.chunks_exact(sa).zip(ucol) {
                            if u != 0.0 {
                                for (t, &lv) in tcol.iter_mut().zip(lcol) {
                                    *t -= lv * u;
                                }
                            }
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// Solves with the factors of [`Self::factor`], `w` (the component's right-hand side in
    /// local order) overwritten by the solution.
    fn solve(&self, m: usize, w: &mut [f64]) {
        if self.dense {
            lu_solve(&self.dense_lu, m, &self.piv, w);
            return;
        }
        let nb = self.bstart.len() - 1;
        // Forward: z_p = L_pp⁻¹ P_p b_p, then b_q -= L_qp z_p.
        for p in 0..nb {
            let (b0, b1) = (self.bstart[p], self.bstart[p + 1]);
            let s = b1 - b0;
            let d = &self.vals[self.diag[p]..self.diag[p] + s * s];
            let (head, tail) = w.split_at_mut(b1);
            let z = &mut head[b0..];
            for (k, &pk) in self.piv[b0..b1].iter().enumerate() {
                z.swap(k, pk);
            }
            unit_lower_solve(d, s, z);
            for t in self.nstart[p]..self.nstart[p + 1] {
                let q = self.nbr[t];
                let (q0, q1) = (self.bstart[q] - b1, self.bstart[q + 1] - b1);
                let sq = q1 - q0;
                let l = &self.vals[self.l_off[t]..self.l_off[t] + sq * s];
                let bq = &mut tail[q0..q1];
                for (lcol, &zc) in l.chunks_exact(sq).zip(z.iter()) {
                    if zc != 0.0 {
                        for (bi, &lv) in bq.iter_mut().zip(lcol) {
                            *bi -= lv * zc;
                        }
                    }
                }
            }
        }
        // Backward: x_p = U_pp⁻¹ (z_p − Σ U_pq x_q).
        for p in (0..nb).rev() {
            let (b0, b1) = (self.bstart[p], self.bstart[p + 1]);
            let s = b1 - b0;
            let (head, tail) = w.split_at_mut(b1);
            let z = &mut head[b0..];
            for t in self.nstart[p]..self.nstart[p + 1] {
                let q = self.nbr[t];
                let (q0, q1) = (self.bstart[q] - b1, self.bstart[q + 1] - b1);
                let u = &self.vals[self.u_off[t]..self.u_off[t] + s * (q1 - q0)];
                for (ucol, &xq) in u.chunks_exact(s).zip(&tail[q0..q1]) {
                    if xq != 0.0 {
                        for (zi, &uv) in z.iter_mut().zip(ucol) {
                            *zi -= uv * xq;
                        }
                    }
                }
            }
            upper_solve(&self.vals[self.diag[p]..self.diag[p] + s * s], s, z);
        }
    }
}

/// Calls `$f::<$m, J>($a, $b)` for J = 0, 1, …, 25 (columns beyond `$m` return at once):
/// the column index a constant in each call, so that the fixed-size kernels' loops have
/// fixed bounds and unroll. Sizes up to 26 ([`lu_solve`]).
macro_rules! each_column {
    ($m:ident, $f:ident, $a:expr, $b:expr) => {
        each_column!(@ $m, $f, $a, $b; 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25)
    };
    (@ $m:ident, $f:ident, $a:expr, $b:expr; $($j:literal)*) => {
        $( $f::<$m, $j>($a, $b); )*
    };
}

/// [`each_column!`] with `?` after each call (a step that fails ends the caller).
macro_rules! each_column_try {
    ($m:ident, $f:ident, $a:expr, $b:expr) => {
        each_column_try!(@ $m, $f, $a, $b; 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25)
    };
    (@ $m:ident, $f:ident, $a:expr, $b:expr; $($j:literal)*) => {
        $( $f::<$m, $j>($a, $b)?; )*
    };
}

/// [`each_column!`] from J = 25 down to 0.
macro_rules! each_column_rev {
    ($m:ident, $f:ident, $a:expr, $b:expr) => {
        each_column!(@ $m, $f, $a, $b; 25 24 23 22 21 20 19 18 17 16 15 14 13 12 11 10 9 8 7 6 5 4 3 2 1 0)
    };
}

/// LU with partial pivoting of the column-major `m × m` matrix `a` in place (unit lower `L`
/// below the diagonal, `U` above it and **the reciprocals of `U`'s diagonal on it**);
/// `piv[k]` = row swapped with row k at step k. Err(k) when column k has no non-zero pivot.
///
/// Why reciprocals: the back substitution is a chain of dependent operations (each `x_j`
/// waits for the updates of the ones after it), and a division's latency is three to four
/// times a multiplication's; with `1/u_jj` at hand the 13 × 13 solves that dominate contact
/// scenes (several per step, one factorisation) multiply instead (BENCHMARKS.md "U's
/// diagonal as reciprocals"). The factorisation computes `1/u_kk` anyway, to scale the column
/// below it.
///
/// Sizes 13 and 26 (see [`lu_solve`]) take [`lu_in_place_fixed`].
fn lu_in_place(a: &mut [f64], m: usize, piv: &mut [usize]) -> Result<(), usize> {
    match m {
        13 => lu_in_place_fixed::<13>(a, piv),
        26 => lu_in_place_fixed::<26>(a, piv),
        _ => lu_in_place_general(a, m, piv),
    }
}

/// The loops of [`lu_in_place`] for any size.
fn lu_in_place_general(a: &mut [f64], m: usize, piv: &mut [usize]) -> Result<(), usize> {
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
        a[col_k + k] = inv;
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

/// [`lu_in_place`] for an `M × M` matrix, its columns as `[f64; M]` arrays and its steps
/// unrolled ([`factor_column`] with the step a constant, from [`each_column_try`]); the same
/// operations in the same order (the pivot is the last of equal largest magnitudes, as
/// `Iterator::max_by` picks it there). billiards16's factorisations took 5,470 instructions
/// each with the step a loop variable, 3,440 so (BENCHMARKS.md "Unrolled block kernels").
fn lu_in_place_fixed<const M: usize>(a: &mut [f64], piv: &mut [usize]) -> Result<(), usize> {
    // `each_column_try!` expands 26 steps: a larger M would leave the rest unfactored.
    const { assert!(M <= 26) };
    let a = &mut a[..M * M];
    let piv = &mut piv[..M];
    each_column_try!(M, factor_column, a, piv);
    Ok(())
}

/// Step `K` of [`lu_in_place_fixed`]: the pivot of column `K`, the row swap, `L`'s column and
/// the update of the columns right of it; with `K` a constant every loop has fixed bounds.
#[inline(always)]
fn factor_column<const M: usize, const K: usize>(
    a: &mut [f64],
    piv: &mut [usize],
) -> Result<(), usize> {
    if K >= M {
        return Ok(());
    }
    let (left, right) = a.split_at_mut((K + 1) * M);
    let Ok(ck) = <&mut [f64; M]>::try_from(&mut left[K * M..]) else {
        return Err(K);
    };
    let mut p = K;
    for i in K + 1..M {
        if ck[p].abs().total_cmp(&ck[i].abs()) != std::cmp::Ordering::Greater {
            p = i;
        }
    }
    piv[K] = p;
    if ck[p] == 0.0 {
        return Err(K);
    }
    if p != K {
        for col in left.chunks_exact_mut(M).chain(right.chunks_exact_mut(M)) {
            col.swap(K, p);
        }
    }
    let Ok(ck) = <&mut [f64; M]>::try_from(&mut left[K * M..]) else {
        return Err(K);
    };
    let inv = 1.0 / ck[K];
    ck[K] = inv;
    for x in &mut ck[K + 1..] {
        *x *= inv;
    }
    let lcol: &[f64; M] = ck;
    for ucol in right.chunks_exact_mut(M) {
        let Ok(ucol) = <&mut [f64; M]>::try_from(ucol) else {
            continue;
        };
        let akj = ucol[K];
        if akj != 0.0 {
            for i in K + 1..M {
                ucol[i] -= lcol[i] * akj;
            }
        }
    }
    Ok(())
}

/// Solves with the factors of [`lu_in_place`], `b` overwritten by `x`. The inner loops run
/// over column slices zipped with `b` (no index arithmetic or bounds check per entry): with
/// indexed loops the block solves took 1.005e9 of billiards16's 4.50e9 instructions, now
/// 0.860e9 (callgrind, BENCHMARKS.md "Where the time goes").
///
/// A free body's block (13 unknowns) and two bodies in contact (26) are what nearly every
/// contact scene solves with, several times per step: for them [`lu_solve_fixed`] runs the
/// same operations in the same order (so the same bits) with the size a constant.
fn lu_solve(a: &[f64], m: usize, piv: &[usize], b: &mut [f64]) {
    match m {
        13 => lu_solve_fixed::<13>(a, piv, b),
        26 => lu_solve_fixed::<26>(a, piv, b),
        _ => lu_solve_general(a, m, piv, b),
    }
}

/// The loops of [`lu_solve`] for any size.
fn lu_solve_general(a: &[f64], m: usize, piv: &[usize], b: &mut [f64]) {
    let b = &mut b[..m];
    for (k, &p) in piv.iter().enumerate().take(m) {
        b.swap(k, p);
    }
    unit_lower_solve(a, m, b);
    upper_solve(a, m, b);
}

/// [`lu_solve`] for `M × M` factors, every loop unrolled: each column's update is a call of
/// [`lower_column`] and [`upper_column`] with the column index a constant (`J`, from
/// [`each_column`]), so both triangles become straight-line code without loop bookkeeping.
/// The same operations in the same order as [`lu_solve_general`] (so the same bits). The
/// loops with the columns as `[f64; M]` arrays spent ~1,250 instructions on a 13 × 13 solve
/// in billiards16 (BENCHMARKS.md "Fixed-size LU kernels"); unrolled, billiards16's block
/// solves take 670 on average instead of 1,350 (BENCHMARKS.md "Unrolled block kernels").
fn lu_solve_fixed<const M: usize>(a: &[f64], piv: &[usize], b: &mut [f64]) {
    // `each_column!` expands 26 columns: a larger M would skip the rest.
    const { assert!(M <= 26) };
    let a = &a[..M * M];
    let Ok(b) = <&mut [f64; M]>::try_from(&mut b[..M]) else {
        return;
    };
    for (k, &p) in piv.iter().enumerate().take(M) {
        b.swap(k, p);
    }
    each_column!(M, lower_column, a, b);
    each_column_rev!(M, upper_column, a, b);
}

/// Column `J` of the column-major `M × M` factors `a` (`None` beyond `M`).
#[inline(always)]
fn column<const M: usize, const J: usize>(a: &[f64]) -> Option<&[f64; M]> {
    if J >= M {
        return None;
    }
    <&[f64; M]>::try_from(&a[J * M..(J + 1) * M]).ok()
}

/// `b[J+1..] -= a[.., J] · b[J]` (the unit lower triangle's column `J`).
#[inline(always)]
fn lower_column<const M: usize, const J: usize>(a: &[f64], b: &mut [f64; M]) {
    let Some(col) = column::<M, J>(a) else {
        return;
    };
    let bj = b[J];
    if bj != 0.0 {
        for i in J + 1..M {
            b[i] -= col[i] * bj;
        }
    }
}

/// `b[J] *= 1/u_JJ; b[..J] -= a[..J, J] · b[J]` (the upper triangle's column `J`, its
/// diagonal held as a reciprocal).
#[inline(always)]
fn upper_column<const M: usize, const J: usize>(a: &[f64], b: &mut [f64; M]) {
    let Some(col) = column::<M, J>(a) else {
        return;
    };
    b[J] *= col[J];
    let bj = b[J];
    if bj != 0.0 {
        for i in 0..J {
            b[i] -= col[i] * bj;
        }
    }
}

/// `b ← L⁻¹ b` with the unit lower triangle of the column-major `m × m` factors `a`.
fn unit_lower_solve(a: &[f64], m: usize, b: &mut [f64]) {
    let b = &mut b[..m];
    for (j, col) in a.chunks_exact(m).enumerate().take(m) {
        let bj = b[j];
        if bj != 0.0 {
            let (_, below) = b.split_at_mut(j + 1);
            for (bi, &aij) in below.iter_mut().zip(&col[j + 1..]) {
                *bi -= aij * bj;
            }
        }
    }
}

/// `b ← U⁻¹ b` with the upper triangle of the column-major `m × m` factors `a` (its diagonal
/// held as reciprocals, [`lu_in_place`]).
fn upper_solve(a: &[f64], m: usize, b: &mut [f64]) {
    let b = &mut b[..m];
    for (j, col) in a.chunks_exact(m).enumerate().take(m).rev() {
        let (above, rest) = b.split_at_mut(j);
        rest[0] *= col[j];
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

    /// The fixed-size kernels (13 and 26 unknowns) give the general loops' factors, pivots,
    /// solutions and zero-pivot index to the last bit: they promise the same operations in the
    /// same order. Matrices with ties of magnitude in a pivot column (the last one is taken),
    /// exact zeros (skipped updates), small diagonals (row swaps) and a singular column.
    #[test]
    fn fixed_size_kernels_match_the_general_loops_bit_for_bit() {
        let mut rnd = crate::test_rng::uniform(0x9e3779b97f4a7c15);
        for m in [13usize, 26] {
            for trial in 0..20 {
                let mut a: Vec<f64> = (0..m * m)
                    .map(|e| {
                        let (i, j) = (e % m, e / m);
                        let v = rnd();
                        match (i * 7 + j * 3 + trial) % 5 {
                            0 => 0.0,
                            1 => 0.25,
                            _ if i == j && i % 4 == 0 => v * 1e-9,
                            _ => v,
                        }
                    })
                    .collect();
                if trial % 7 == 6 {
                    // A zero column: both must report the same step.
                    let c = trial % m;
                    a[c * m..(c + 1) * m].fill(0.0);
                }
                let b: Vec<f64> = (0..m)
                    .map(|i| if i % 6 == 0 { 0.0 } else { rnd() })
                    .collect();
                let (mut fa, mut ga) = (a.clone(), a.clone());
                let (mut fp, mut gp) = (vec![0; m], vec![0; m]);
                let fr = lu_in_place(&mut fa, m, &mut fp);
                let gr = lu_in_place_general(&mut ga, m, &mut gp);
                assert_eq!(fr, gr, "m {m} trial {trial}");
                assert_eq!(fp, gp, "m {m} trial {trial}");
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&fa), bits(&ga), "factors, m {m} trial {trial}");
                if fr.is_ok() {
                    let (mut fx, mut gx) = (b.clone(), b.clone());
                    lu_solve(&fa, m, &fp, &mut fx);
                    lu_solve_general(&ga, m, &gp, &mut gx);
                    assert_eq!(bits(&fx), bits(&gx), "solution, m {m} trial {trial}");
                    assert!(fx.iter().all(|v| v.is_finite()));
                }
            }
        }
    }

    /// A random block-sparse matrix solved blockwise agrees with nalgebra's dense LU of the
    /// whole matrix to round-off (well-conditioned: diagonally weighted).
    #[test]
    fn blockwise_solve_matches_dense_lu() {
        let mut rnd = crate::test_rng::uniform(0x2545f4914f6cdd1d);
        let n = 23;
        let nb = 7;
        let block_of: Vec<usize> = (0..n).map(|i| (i * 5 + 3) % nb).collect();
        let couplings = vec![(0, 1), (1, 2), (4, 5)];
        // Small diagonal on some rows forces pivoting.
        let (a, col) = structured(&block_of, nb, &couplings, |i, j| {
            rnd() + if i == j && i % 3 != 0 { 3.0 } else { 0.0 }
        });
        let coupled = |i: usize, j: usize| col_coupled(&couplings, block_of[i], block_of[j]);
        let b = DVector::<f64>::from_fn(n, |_, _| rnd());
        let exact = a.clone().lu().solve(&b).unwrap();
        let mut lu = BlockLu::default();
        let load = |lu: &mut BlockLu, a: &DMatrix<f64>| {
            lu.layout(&col, n, true);
            for i in 0..n {
                for j in 0..n {
                    if coupled(i, j) {
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

    /// Blocks `a` and `b` are coupled (or the same).
    fn col_coupled(couplings: &[(usize, usize)], a: usize, b: usize) -> bool {
        a == b
            || couplings
                .iter()
                .any(|&(p, q)| (p, q) == (a, b) || (q, p) == (a, b))
    }

    /// The colouring of the structure (`block_of`, `nb` blocks, `couplings`) and a matrix with
    /// `entry(i, j)` where the blocks of `i` and `j` are coupled, zero elsewhere.
    fn structured(
        block_of: &[usize],
        nb: usize,
        couplings: &[(usize, usize)],
        mut entry: impl FnMut(usize, usize) -> f64,
    ) -> (DMatrix<f64>, Colouring) {
        let n = block_of.len();
        let mut col = Colouring::with_structure(BlockStructure {
            block_of: block_of.to_vec(),
            n_blocks: nb,
            couplings: couplings.to_vec(),
            ..Default::default()
        });
        col.update(n).unwrap();
        let mut a = DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for j in 0..n {
                if col_coupled(couplings, block_of[i], block_of[j]) {
                    a[(i, j)] = entry(i, j);
                }
            }
        }
        (a, col)
    }

    /// A random matrix on the block pattern of `couplings` (block `b` has `sizes[b]` unknowns,
    /// interleaved as a real system's are), diagonally weighted by `diag` on the rows of block
    /// rows; returns the matrix, its block structure and the colouring.
    fn pattern(
        sizes: &[usize],
        couplings: &[(usize, usize)],
        diag: f64,
        seed: u64,
    ) -> (DMatrix<f64>, Colouring, Vec<usize>) {
        let mut rnd = crate::test_rng::uniform(seed);
        // Unknowns of the blocks interleaved (block of unknown i round-robin over the blocks
        // that still have unknowns), so that a block's unknowns are not consecutive.
        let mut left = sizes.to_vec();
        let mut block_of = Vec::new();
        while left.iter().any(|&l| l > 0) {
            for (b, l) in left.iter_mut().enumerate() {
                if *l > 0 {
                    block_of.push(b);
                    *l -= 1;
                }
            }
        }
        let (a, col) = structured(&block_of, sizes.len(), couplings, |i, j| {
            rnd() + if i == j { diag } else { 0.0 }
        });
        (a, col, block_of)
    }

    /// Loads `a` (entries on the pattern only, by columns in runs where rows are consecutive
    /// in their block) into a fresh layout, factors and solves `a x = b`; returns the largest
    /// error against nalgebra's dense LU relative to the solution and the layout.
    fn solve_both(a: &DMatrix<f64>, col: &Colouring) -> (f64, BlockLu) {
        let n = a.nrows();
        let mut lu = BlockLu::default();
        lu.layout(col, n, true);
        for j in 0..n {
            for i in 0..n {
                if a[(i, j)] != 0.0 {
                    if i % 2 == 0 {
                        lu.set(i, j, a[(i, j)]);
                    } else {
                        lu.add_run(i, j, &[a[(i, j)]]);
                    }
                }
            }
        }
        lu.factor().unwrap();
        let b = DVector::<f64>::from_fn(n, |i, _| ((i * 7919) % 13) as f64 - 6.0);
        let exact = a.clone().lu().solve(&b).unwrap();
        let mut xs = b.as_slice().to_vec();
        lu.solve(&mut xs);
        let err = (DVector::from_vec(xs) - &exact).amax() / exact.amax().max(1.0);
        (err, lu)
    }

    /// The couplings of a triangular rack of 15 balls (5 rows; each ball touches its row
    /// neighbour and the two below it).
    fn rack_of_15() -> Vec<(usize, usize)> {
        let mut rack = Vec::new();
        let id = |r: usize, c: usize| r * (r + 1) / 2 + c;
        for r in 0..5 {
            for c in 0..=r {
                if c < r {
                    rack.push((id(r, c), id(r, c + 1)));
                }
                if r < 4 {
                    rack.push((id(r, c), id(r + 1, c)));
                    rack.push((id(r, c), id(r + 1, c + 1)));
                }
            }
        }
        rack
    }

    /// A triangular rack of 15 balls (13 unknowns each, couplings between touching balls) and a
    /// stack of 10 bodies (a chain) are factored block-sparse and agree with nalgebra's dense LU
    /// to round-off (the matrices are diagonally weighted, as an iteration matrix with
    /// `c_j·M` on its diagonal is, condition ~1e2: 1e-12 is ~1e4 roundings).
    #[test]
    fn sparse_components_match_dense_lu() {
        let rack = rack_of_15();
        let chain: Vec<_> = (0..9).map(|b| (b, b + 1)).collect();
        let mixed_sizes: Vec<usize> = (0..10).map(|b| [13, 6, 1, 7][b % 4]).collect();
        for (name, sizes, couplings) in [
            ("rack", vec![13; 15], rack),
            ("stack", vec![13; 10], chain.clone()),
            ("mixed stack", mixed_sizes, chain),
        ] {
            for seed in 1..4u64 {
                let (a, col, _) = pattern(
                    &sizes,
                    &couplings,
                    4.0,
                    seed.wrapping_mul(0x9e3779b97f4a7c15),
                );
                let (err, lu) = solve_both(&a, &col);
                assert_eq!(lu.n_sparse(), 1, "{name}: not factored block-sparse");
                assert!(err < 1e-12, "{name}, seed {seed}: error {err:e}");
                // A second Jacobian on the same structure reuses the layout, and loading,
                // factoring and solving allocate nothing (the unit tests count allocations
                // per thread, `counting_alloc`).
                let mut lu = lu;
                let mut x = vec![1.0; a.nrows()];
                let before = crate::counting_alloc::allocs();
                lu.layout(&col, a.nrows(), false);
                assert!(lu.sparse[0].vals.iter().all(|&v| v == 0.0));
                for (i, j) in (0..a.nrows()).flat_map(|i| (0..a.nrows()).map(move |j| (i, j))) {
                    if a[(i, j)] != 0.0 {
                        lu.set(i, j, a[(i, j)]);
                    }
                }
                lu.factor().unwrap();
                lu.solve(&mut x);
                assert_eq!(
                    crate::counting_alloc::allocs() - before,
                    0,
                    "{name}: allocations"
                );
            }
        }
    }

    /// The parts of an iteration matrix kept by `entries` and recombined by `set_entries`
    /// (`ida/linear.rs` forms the matrix at a new `c_j` so): `A + s·B` loaded that way solves
    /// as nalgebra's dense LU of `A + s·B` does, to round-off, on a block-sparse rack and a
    /// dense pair of blocks, and the recombination allocates nothing.
    #[test]
    fn entries_recombine_to_the_matrix_of_a_new_c_j() {
        for (sizes, couplings) in [(vec![13; 15], rack_of_15()), (vec![6, 7], vec![(0, 1)])] {
            let (a, col, _) = pattern(&sizes, &couplings, 4.0, 11);
            let (b, _, _) = pattern(&sizes, &couplings, 9.0, 12);
            let n = a.nrows();
            let mut lu = BlockLu::default();
            let load = |lu: &mut BlockLu, m: &DMatrix<f64>| {
                lu.layout(&col, n, false);
                for (i, j) in (0..n).flat_map(|i| (0..n).map(move |j| (i, j))) {
                    if m[(i, j)] != 0.0 {
                        lu.set(i, j, m[(i, j)]);
                    }
                }
            };
            lu.layout(&col, n, true);
            let (mut ea, mut eb) = (vec![], vec![]);
            load(&mut lu, &a);
            lu.entries(&mut ea);
            load(&mut lu, &b);
            lu.entries(&mut eb);
            let s = 2.5e3;
            let rhs = DVector::<f64>::from_fn(n, |i, _| ((i * 7919) % 13) as f64 - 6.0);
            let mut xs = rhs.as_slice().to_vec();
            // A first factorisation sizes the buffers; the second allocates nothing.
            for round in 0..2 {
                xs.copy_from_slice(rhs.as_slice());
                let before = crate::counting_alloc::allocs();
                assert!(lu.set_entries(&ea, &eb, s));
                lu.factor().unwrap();
                lu.solve(&mut xs);
                let allocated = crate::counting_alloc::allocs() - before;
                assert!(round == 0 || allocated == 0, "{allocated} allocations");
            }
            let exact = (&a + &b * s).lu().solve(&rhs).unwrap();
            let err = (DVector::from_vec(xs) - &exact).amax() / exact.amax();
            assert!(err < 1e-12, "{} blocks: error {err:e}", sizes.len());
            assert!(
                !lu.set_entries(&ea[1..], &eb[1..], s),
                "a wrong length is refused"
            );
        }
    }

    /// Pivoting inside diagonal blocks fails where a diagonal block is singular when it is
    /// eliminated (a saddle point: its own entries are zero, as an algebraic constraint's are) or its
    /// pivots are tiny against the entries below them: the component is then factored densely
    /// and still solves to round-off; a singular component reports its zero column.
    #[test]
    fn sparse_falls_back_to_dense_where_block_pivots_fail() {
        let chain: Vec<_> = (0..5).map(|b| (b, b + 1)).collect();
        let sizes = vec![4; 6];
        let (mut a, col, block_of) = pattern(&sizes, &chain, 4.0, 77);
        let n = a.nrows();
        for i in 0..n {
            for j in 0..n {
                // Block 0 ends the chain and is eliminated first, so its block is still zero
                // then (a block eliminated later has received Schur updates).
                if block_of[i] == 0 && block_of[j] == 0 {
                    a[(i, j)] = 0.0;
                }
            }
        }
        let (err, lu) = solve_both(&a, &col);
        assert_eq!(lu.n_sparse(), 1);
        assert!(lu.sparse[0].dense, "expected the dense fallback");
        assert!(err < 1e-11, "error {err:e}");
        // Tiny pivots in block 0 against O(1) entries below: L would grow by 1e8.
        let (mut a, col, block_of) = pattern(&sizes, &chain, 4.0, 78);
        for i in 0..n {
            for j in 0..n {
                if block_of[i] == 0 && block_of[j] == 0 {
                    a[(i, j)] *= 1e-8;
                }
            }
        }
        let (err, lu) = solve_both(&a, &col);
        assert!(lu.sparse[0].dense, "expected the dense fallback");
        assert!(err < 1e-9, "error {err:e}");
        // A zero column: singular, reported by its global index.
        let (mut a, col, _) = pattern(&sizes, &chain, 4.0, 79);
        a.column_mut(9).fill(0.0);
        let mut lu = BlockLu::default();
        lu.layout(&col, n, true);
        for j in 0..n {
            for i in 0..n {
                if a[(i, j)] != 0.0 {
                    lu.set(i, j, a[(i, j)]);
                }
            }
        }
        assert_eq!(lu.factor(), Err(9));
    }

    /// Calibration of [`SPARSE_GAIN`]: wall time of the dense and the block-sparse
    /// factorisation and solve of the rack, stacks and square piles of 13-unknown blocks
    /// (`cargo test --release -p modia3d-core sparse_and_dense_factor_times -- --ignored
    /// --nocapture`).
    #[test]
    #[ignore]
    fn sparse_and_dense_factor_times() {
        use std::time::Instant;
        let grid = |w: usize| {
            let mut c = Vec::new();
            for r in 0..w {
                for k in 0..w {
                    if k + 1 < w {
                        c.push((r * w + k, r * w + k + 1));
                    }
                    if r + 1 < w {
                        c.push((r * w + k, (r + 1) * w + k));
                    }
                }
            }
            c
        };
        println!(
            "| pattern | blocks | unknowns | operations dense / block-sparse | dense factor + solve [µs] | block-sparse [µs] | time dense / block-sparse | chosen |"
        );
        println!("|---|---:|---:|---:|---:|---:|---:|---|");
        for (name, nb, couplings) in [
            ("chain 3", 3, (0..2).map(|b| (b, b + 1)).collect::<Vec<_>>()),
            ("chain 4", 4, (0..3).map(|b| (b, b + 1)).collect()),
            ("chain 10", 10, (0..9).map(|b| (b, b + 1)).collect()),
            ("grid 2x2", 4, grid(2)),
            ("grid 3x3", 9, grid(3)),
            ("grid 4x4", 16, grid(4)),
            ("grid 6x6", 36, grid(6)),
            ("grid 8x8", 64, grid(8)),
            ("chain 30", 30, (0..29).map(|b| (b, b + 1)).collect()),
        ] {
            let (a, col, _) = pattern(&vec![13; nb], &couplings, 4.0, 5);
            let n = a.nrows();
            let blocks: Vec<usize> = (0..nb).collect();
            let mut sc = OrderScratch::default();
            sc.local_of_block.resize(nb, 0);
            let flop_ratio = dense_flops(n) / order_blocks(&col, &blocks, &mut sc);
            let time = |force_dense: bool| {
                let mut lu = BlockLu {
                    gain: Some(if force_dense { f64::INFINITY } else { 0.0 }),
                    ..Default::default()
                };
                lu.layout(&col, n, true);
                for j in 0..n {
                    for i in 0..n {
                        if a[(i, j)] != 0.0 {
                            lu.set(i, j, a[(i, j)]);
                        }
                    }
                }
                let loaded = lu.clone();
                let reps = 20_000_000 / (n * n * n).max(1) + 3;
                let mut best = f64::INFINITY;
                let mut x = vec![1.0; n];
                for _ in 0..5 {
                    let t0 = Instant::now();
                    for _ in 0..reps {
                        lu.clone_from(&loaded);
                        lu.factor().unwrap();
                        lu.solve(&mut x);
                    }
                    best = best.min(t0.elapsed().as_secs_f64() / reps as f64);
                }
                (best, lu.n_sparse())
            };
            let (dense, _) = time(true);
            let (sparse, _) = time(false);
            let chosen = flop_ratio > SPARSE_GAIN;
            println!(
                "| {name} | {nb} | {n} | {flop_ratio:.1} | {:.1} | {:.1} | {:.2} | {} |",
                dense * 1e6,
                sparse * 1e6,
                dense / sparse,
                if chosen { "block-sparse" } else { "dense" }
            );
        }
    }
}
