//! Distance-2 colouring of a [`BlockStructure`] for the coloured difference-quotient Jacobian
//! (safe code; `ida.rs` only reads the result). All buffers are kept between evaluations, so a
//! warm colouring allocates nothing.

use super::BlockStructure;

/// The blocks of a [`BlockStructure`] in compressed form, with a colour per block such that two
/// blocks of one colour have no residual row in common: neither they nor any of their
/// neighbours are shared (distance-2 colouring).
#[derive(Clone, Debug, Default)]
pub(crate) struct Colouring {
    /// What the system reported (the structure the colouring was built for).
    pub structure: BlockStructure,
    /// What the system reports now: [`Self::refresh`] rebuilds the colouring only when it
    /// differs from `structure` (the contact set changes at events, not at every Jacobian).
    pub next: BlockStructure,
    /// `update` has succeeded for `structure`.
    ready: bool,
    /// Unknowns of block `b`: `members[member_start[b]..member_start[b + 1]]`, ascending.
    members: Vec<usize>,
    member_start: Vec<usize>,
    /// Neighbour blocks of block `b`: `adj[adj_start[b]..adj_start[b + 1]]` (may repeat).
    adj: Vec<usize>,
    adj_start: Vec<usize>,
    /// Blocks of colour `c`: `by_colour[colour_start[c]..colour_start[c + 1]]`.
    by_colour: Vec<usize>,
    colour_start: Vec<usize>,
    /// Largest block size of each colour.
    colour_width: Vec<usize>,
    colour: Vec<usize>,
    order: Vec<usize>,
    stamp: Vec<usize>,
    /// Connected component (over the couplings) of each block, then the unknowns of component
    /// `k`: `comp_members[comp_start[k]..comp_start[k + 1]]`, ascending.
    comp_of: Vec<usize>,
    stack: Vec<usize>,
    comp_members: Vec<usize>,
    comp_start: Vec<usize>,
}

/// Counting sort of `items` by `key` into CSR arrays (`out`, `start` of len `n_keys + 1`),
/// without allocating once the buffers are large enough.
fn bucket(
    n_keys: usize,
    items: impl Iterator<Item = (usize, usize)> + Clone,
    out: &mut Vec<usize>,
    start: &mut Vec<usize>,
) {
    start.clear();
    start.resize(n_keys + 1, 0);
    for (k, _) in items.clone() {
        start[k + 1] += 1;
    }
    for k in 0..n_keys {
        start[k + 1] += start[k];
    }
    out.clear();
    out.resize(start[n_keys], 0);
    // Fill with start[k] as the cursor of key k, then shift the cursors back to the starts.
    for (k, v) in items {
        out[start[k]] = v;
        start[k] += 1;
    }
    for k in (1..=n_keys).rev() {
        start[k] = start[k - 1];
    }
    start[0] = 0;
}

impl Colouring {
    /// A colouring of `structure`, not yet updated.
    #[cfg(test)]
    pub(super) fn with_structure(structure: BlockStructure) -> Self {
        Colouring {
            structure,
            ..Default::default()
        }
    }

    /// Takes `self.next` as the structure and rebuilds the colouring if it differs from the
    /// current one (or none was built yet). Returns whether it rebuilt. Allocation-free once
    /// the buffers have grown.
    pub(super) fn refresh(&mut self, n: usize) -> Result<bool, String> {
        if self.ready && self.next == self.structure {
            return Ok(false);
        }
        std::mem::swap(&mut self.structure, &mut self.next);
        self.update(n)?;
        Ok(true)
    }

    /// Rebuilds the compressed blocks, the adjacency and the colouring from `self.structure`
    /// for a system of `n` unknowns. Errors name what is inconsistent.
    pub(super) fn update(&mut self, n: usize) -> Result<(), String> {
        self.ready = false;
        let s = &self.structure;
        let nb = s.n_blocks;
        if s.block_of.len() != n {
            return Err(format!(
                "jacobian_structure: block_of has length {} but the system has n = {n} unknowns",
                s.block_of.len()
            ));
        }
        if let Some(i) = s.block_of.iter().position(|&b| b >= nb) {
            return Err(format!(
                "jacobian_structure: unknown {i} is in block {} but n_blocks = {nb}",
                s.block_of[i]
            ));
        }
        if let Some(&(a, b)) = s.couplings.iter().find(|&&(a, b)| a >= nb || b >= nb) {
            return Err(format!(
                "jacobian_structure: coupling ({a}, {b}) names a block >= n_blocks = {nb}"
            ));
        }
        if !s.analytic.is_empty() && s.analytic.len() != nb {
            return Err(format!(
                "jacobian_structure: analytic has length {} but n_blocks = {nb}",
                s.analytic.len()
            ));
        }
        bucket(
            nb,
            s.block_of.iter().enumerate().map(|(i, &b)| (b, i)),
            &mut self.members,
            &mut self.member_start,
        );
        let both = s
            .couplings
            .iter()
            .filter(|(a, b)| a != b)
            .flat_map(|&(a, b)| [(a, b), (b, a)]);
        bucket(nb, both, &mut self.adj, &mut self.adj_start);

        // Greedy distance-2 colouring, largest blocks first (they set the cost of a colour).
        self.colour.clear();
        self.colour.resize(nb, usize::MAX);
        self.stamp.clear();
        self.stamp.resize(nb + 1, usize::MAX);
        let mut order = std::mem::take(&mut self.order);
        order.clear();
        order.extend(0..nb);
        // Analytic blocks are not perturbed: size 0 here, so they get no colour.
        let analytic = &self.structure.analytic;
        let size = |b: usize| {
            if analytic.get(b).copied().unwrap_or(false) {
                0
            } else {
                self.member_start[b + 1] - self.member_start[b]
            }
        };
        order.sort_unstable_by_key(|&b| (std::cmp::Reverse(size(b)), b));
        let mut n_colours = 0;
        for &b in &order {
            if size(b) == 0 {
                continue;
            }
            for &nbr in &self.adj[self.adj_start[b]..self.adj_start[b + 1]] {
                for &far in std::iter::once(&nbr)
                    .chain(&self.adj[self.adj_start[nbr]..self.adj_start[nbr + 1]])
                {
                    if far != b && self.colour[far] != usize::MAX {
                        self.stamp[self.colour[far]] = b;
                    }
                }
            }
            // At most nb colours exist, so one of 0..=nb is free.
            let c = (0..=nb).find(|&c| self.stamp[c] != b).unwrap_or(nb);
            self.colour[b] = c;
            n_colours = n_colours.max(c + 1);
        }
        let colour = &self.colour;
        bucket(
            n_colours,
            order
                .iter()
                .filter(|&&b| colour[b] != usize::MAX)
                .map(|&b| (colour[b], b)),
            &mut self.by_colour,
            &mut self.colour_start,
        );
        self.order = order;
        self.colour_width.clear();
        for c in 0..n_colours {
            let w = self.blocks_of_colour(c).iter().map(|&b| size(b)).max();
            self.colour_width.push(w.unwrap_or(0));
        }
        self.components();
        self.ready = true;
        Ok(())
    }

    /// Connected components of the block graph (depth-first over the couplings), and
    /// their unknowns: the iteration matrix is block diagonal over them.
    fn components(&mut self) {
        let nb = self.structure.n_blocks;
        self.comp_of.clear();
        self.comp_of.resize(nb, usize::MAX);
        let mut n_comp = 0;
        for root in 0..nb {
            if self.comp_of[root] != usize::MAX {
                continue;
            }
            self.stack.clear();
            self.stack.push(root);
            self.comp_of[root] = n_comp;
            while let Some(b) = self.stack.pop() {
                for &nbr in &self.adj[self.adj_start[b]..self.adj_start[b + 1]] {
                    if self.comp_of[nbr] == usize::MAX {
                        self.comp_of[nbr] = n_comp;
                        self.stack.push(nbr);
                    }
                }
            }
            n_comp += 1;
        }
        let (comp_of, block_of) = (&self.comp_of, &self.structure.block_of);
        bucket(
            n_comp,
            block_of.iter().enumerate().map(|(i, &b)| (comp_of[b], i)),
            &mut self.comp_members,
            &mut self.comp_start,
        );
    }

    /// Number of connected components.
    pub(super) fn n_components(&self) -> usize {
        self.comp_start.len().saturating_sub(1)
    }
    /// Unknowns of connected component `k`, ascending.
    pub(super) fn component(&self, k: usize) -> &[usize] {
        &self.comp_members[self.comp_start[k]..self.comp_start[k + 1]]
    }

    /// Number of blocks.
    pub(super) fn n_blocks(&self) -> usize {
        self.structure.n_blocks
    }
    /// Connected component of block `b`.
    pub(super) fn component_of_block(&self, b: usize) -> usize {
        self.comp_of[b]
    }

    /// Number of colours.
    pub(super) fn n_colours(&self) -> usize {
        self.colour_width.len()
    }
    /// Largest block size of colour `c` (= residual evaluations it costs).
    pub(super) fn width(&self, c: usize) -> usize {
        self.colour_width[c]
    }
    /// Block `b` is filled by the system ([`BlockStructure::analytic`]).
    pub(super) fn is_analytic(&self, b: usize) -> bool {
        self.structure.analytic.get(b).copied().unwrap_or(false)
    }
    /// Some block is filled by the system.
    pub(super) fn any_analytic(&self) -> bool {
        self.structure.analytic.iter().any(|&a| a)
    }
    /// Residual evaluations per Jacobian.
    #[cfg(test)]
    pub(super) fn cost(&self) -> usize {
        self.colour_width.iter().sum()
    }
    /// Blocks of colour `c`.
    pub(super) fn blocks_of_colour(&self, c: usize) -> &[usize] {
        &self.by_colour[self.colour_start[c]..self.colour_start[c + 1]]
    }
    /// Unknowns (= residual rows) of block `b`.
    pub(super) fn members(&self, b: usize) -> &[usize] {
        &self.members[self.member_start[b]..self.member_start[b + 1]]
    }
    /// Blocks coupled with block `b` (may repeat).
    pub(super) fn neighbours(&self, b: usize) -> &[usize] {
        &self.adj[self.adj_start[b]..self.adj_start[b + 1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn colouring(
        block_of: Vec<usize>,
        n_blocks: usize,
        couplings: Vec<(usize, usize)>,
    ) -> Colouring {
        let n = block_of.len();
        let mut c = Colouring::with_structure(BlockStructure {
            block_of,
            n_blocks,
            couplings,
            ..Default::default()
        });
        c.update(n).unwrap();
        c
    }

    /// The defining property, checked by brute force: for every colour, the row sets
    /// (block ∪ neighbours) of its blocks are disjoint.
    fn assert_valid(c: &Colouring, n: usize) {
        let mut seen = 0;
        for col in 0..c.n_colours() {
            let mut rows = vec![false; n];
            for &b in c.blocks_of_colour(col) {
                seen += 1;
                let mut mine = vec![false; n];
                for blk in std::iter::once(b).chain(c.neighbours(b).iter().copied()) {
                    for &i in c.members(blk) {
                        mine[i] = true;
                    }
                }
                for i in 0..n {
                    assert!(!(mine[i] && rows[i]), "colour {col}: row {i} shared");
                    rows[i] |= mine[i];
                }
            }
            let w = c
                .blocks_of_colour(col)
                .iter()
                .map(|&b| c.members(b).len())
                .max();
            assert_eq!(c.width(col), w.unwrap());
        }
        let non_empty = (0..c.structure.n_blocks)
            .filter(|&b| !c.members(b).is_empty())
            .count();
        assert_eq!(seen, non_empty, "every non-empty block gets one colour");
    }

    #[test]
    fn independent_blocks_share_one_colour() {
        // 4 free bodies of 13 unknowns, no couplings: one colour, 13 evaluations instead of 52.
        let block_of: Vec<usize> = (0..52).map(|i| i / 13).collect();
        let c = colouring(block_of, 4, vec![]);
        assert_eq!(c.n_colours(), 1);
        assert_eq!(c.cost(), 13);
        assert_valid(&c, 52);
    }

    #[test]
    fn a_chain_needs_three_colours() {
        // 0-1-2-3-4-5: distance-2 colouring of a path needs exactly 3 colours.
        let block_of: Vec<usize> = (0..12).map(|i| i / 2).collect();
        let c = colouring(
            block_of,
            6,
            vec![(0, 1), (2, 1), (2, 3), (3, 4), (5, 4), (4, 5)],
        );
        assert_eq!(c.n_colours(), 3);
        assert_valid(&c, 12);
    }

    #[test]
    fn random_structures_are_coloured_validly() {
        // Deterministic pseudo-random graphs (xorshift), blocks of mixed sizes, interleaved.
        let mut next = crate::test_rng::bits(0x9e3779b97f4a7c15);
        let mut rnd = move |m: usize| (next() % m as u64) as usize;
        for _ in 0..200 {
            let nb = 1 + rnd(20);
            let n = nb + rnd(60);
            let block_of: Vec<usize> = (0..n).map(|i| if i < nb { i } else { rnd(nb) }).collect();
            let couplings = (0..rnd(3 * nb)).map(|_| (rnd(nb), rnd(nb))).collect();
            let c = colouring(block_of, nb, couplings);
            assert_valid(&c, n);
            assert!(c.cost() <= n);
        }
    }

    #[test]
    fn analytic_blocks_are_not_coloured_but_separate_their_neighbours() {
        // 0 - 1 - 2 with block 1 analytic: blocks 0 and 2 both write rows of block 1, so
        // they need two colours; block 1 gets none and costs nothing.
        let block_of: Vec<usize> = (0..9).map(|i| i / 3).collect();
        let mut c = Colouring::with_structure(BlockStructure {
            block_of,
            n_blocks: 3,
            couplings: vec![(0, 1), (1, 2)],
            analytic: vec![false, true, false],
        });
        c.update(9).unwrap();
        assert_eq!(c.n_colours(), 2);
        assert_eq!(c.cost(), 6);
        assert!(c.is_analytic(1) && !c.is_analytic(0));
        for col in 0..c.n_colours() {
            assert!(!c.blocks_of_colour(col).contains(&1));
        }
        assert_eq!(c.n_components(), 1);
        // refresh rebuilds only on a change.
        c.next = c.structure.clone();
        assert!(!c.refresh(9).unwrap());
        c.next.analytic = vec![false, false, false];
        assert!(c.refresh(9).unwrap());
        assert_eq!(c.cost(), 9);
    }

    #[test]
    fn components_partition_the_unknowns() {
        // Blocks 0-1-2 chained, 3 alone, 4-5 coupled; block 3 interleaved in the numbering.
        let block_of = vec![0, 3, 1, 2, 3, 4, 5, 0];
        let c = colouring(block_of, 6, vec![(1, 0), (1, 2), (5, 4)]);
        let comps: Vec<Vec<usize>> = (0..c.n_components())
            .map(|k| c.component(k).to_vec())
            .collect();
        assert_eq!(comps, vec![vec![0, 2, 3, 7], vec![1, 4], vec![5, 6]]);
        assert_valid(&c, 8);
    }

    #[test]
    fn inconsistent_structures_are_errors() {
        let mut c = Colouring::with_structure(BlockStructure {
            block_of: vec![0, 1, 2],
            n_blocks: 2,
            couplings: vec![],
            ..Default::default()
        });
        assert!(c.update(3).unwrap_err().contains("unknown 2 is in block 2"));
        c.structure.n_blocks = 3;
        assert!(c.update(4).unwrap_err().contains("length 3"));
        c.structure.couplings = vec![(0, 7)];
        assert!(c.update(3).unwrap_err().contains("(0, 7)"));
    }
}
