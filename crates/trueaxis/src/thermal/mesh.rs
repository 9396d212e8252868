//! Structured finite-element meshes of 1, 2 or 3 dimensions: a bar or fin (1D, 2-node linear
//! elements), a plate (2D, bilinear quadrilaterals) or a block (3D, trilinear hexahedra), all on a
//! rectangular grid of equal cells. Lengths in m.

use crate::error::Error;

/// A rectangular grid of `cells[d]` equal cells over `size_m[d]` along each dimension d.
/// Nodes are numbered `i0 + n0 (i1 + n1 i2)` with `n_d = cells[d] + 1`.
#[derive(Clone, Debug, PartialEq)]
pub struct StructuredMesh {
    cells: Vec<usize>,
    size_m: Vec<f64>,
}

impl StructuredMesh {
    /// A mesh of 1 to 3 dimensions; every size positive and finite, every cell count at least 1.
    pub fn new(cells: Vec<usize>, size_m: Vec<f64>) -> Result<StructuredMesh, Error> {
        if cells.is_empty() || cells.len() > 3 || cells.len() != size_m.len() {
            return Err(Error::input(format!(
                "a structured mesh needs 1 to 3 dimensions with one size per cell count (got {} cell counts, {} sizes)",
                cells.len(),
                size_m.len()
            )));
        }
        if cells.contains(&0) {
            return Err(Error::input("every cell count must be at least 1"));
        }
        if size_m.iter().any(|s| !(s.is_finite() && *s > 0.0)) {
            return Err(Error::input("every size must be a positive finite length in m"));
        }
        let nodes: usize = cells.iter().map(|c| c + 1).product();
        if nodes > 50_000_000 {
            return Err(Error::input(format!("{nodes} nodes is more than the 50 million this mesher accepts")));
        }
        Ok(StructuredMesh { cells, size_m })
    }

    /// A bar of `length_m` with `elements` equal elements (Zhu 2008 Table 3.1: 22 elements).
    pub fn bar(length_m: f64, elements: usize) -> Result<StructuredMesh, Error> {
        Self::new(vec![elements], vec![length_m])
    }

    pub fn dimensions(&self) -> usize {
        self.cells.len()
    }

    pub fn cells(&self) -> &[usize] {
        &self.cells
    }

    pub fn size_m(&self) -> &[f64] {
        &self.size_m
    }

    /// Cell size along dimension `d` (m).
    pub fn spacing(&self, d: usize) -> f64 {
        self.size_m[d] / self.cells[d] as f64
    }

    /// Nodes along each dimension.
    pub fn node_counts(&self) -> Vec<usize> {
        self.cells.iter().map(|c| c + 1).collect()
    }

    pub fn node_count(&self) -> usize {
        self.cells.iter().map(|c| c + 1).product()
    }

    pub fn cell_count(&self) -> usize {
        self.cells.iter().product()
    }

    /// Node number of grid indices `ijk` (one per dimension).
    pub fn node_index(&self, ijk: &[usize]) -> usize {
        let mut index = 0;
        for d in (0..self.dimensions()).rev() {
            index = index * (self.cells[d] + 1) + ijk[d];
        }
        index
    }

    /// Grid indices of node `node`.
    pub fn node_grid(&self, mut node: usize) -> [usize; 3] {
        let mut ijk = [0; 3];
        for (d, c) in self.cells.iter().enumerate() {
            ijk[d] = node % (c + 1);
            node /= c + 1;
        }
        ijk
    }

    /// Coordinates (m) of node `node`; unused dimensions are 0.
    pub fn node_coordinates(&self, node: usize) -> [f64; 3] {
        let ijk = self.node_grid(node);
        let mut x = [0.0; 3];
        for d in 0..self.dimensions() {
            x[d] = ijk[d] as f64 * self.spacing(d);
        }
        x
    }

    /// The node nearest to point `x` (m).
    pub fn nearest_node(&self, x: &[f64]) -> usize {
        let ijk: Vec<usize> = (0..self.dimensions())
            .map(|d| ((x.get(d).copied().unwrap_or(0.0) / self.spacing(d)).round().max(0.0) as usize).min(self.cells[d]))
            .collect();
        self.node_index(&ijk)
    }

    /// The `2^dim` nodes of cell `cell`, local node `a` having grid offset bit d = `(a >> d) & 1`.
    pub fn cell_nodes(&self, cell: usize, nodes: &mut [usize; 8]) {
        let dim = self.dimensions();
        let base = self.cell_grid(cell);
        for (a, node) in nodes.iter_mut().enumerate().take(1 << dim) {
            let mut ijk = [0usize; 3];
            for d in 0..dim {
                ijk[d] = base[d] + ((a >> d) & 1);
            }
            *node = self.node_index(&ijk[..dim]);
        }
    }

    /// Grid indices of the first node of cell `cell`.
    pub fn cell_grid(&self, mut cell: usize) -> [usize; 3] {
        let mut ijk = [0; 3];
        for (g, c) in ijk.iter_mut().zip(&self.cells) {
            *g = cell % c;
            cell /= c;
        }
        ijk
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbering_round_trips_and_cells_touch_their_nodes() {
        let m = StructuredMesh::new(vec![3, 2, 4], vec![0.3, 0.2, 0.4]).unwrap();
        assert_eq!(m.node_count(), 4 * 3 * 5);
        for node in 0..m.node_count() {
            let g = m.node_grid(node);
            assert_eq!(m.node_index(&g), node);
            let x = m.node_coordinates(node);
            assert_eq!(m.nearest_node(&x), node);
        }
        let mut nodes = [0; 8];
        m.cell_nodes(m.cell_count() - 1, &mut nodes);
        assert_eq!(nodes[7], m.node_count() - 1);
        assert_eq!(nodes[0], m.node_index(&[2, 1, 3]));
        assert!(StructuredMesh::new(vec![0], vec![1.0]).is_err());
        assert!(StructuredMesh::bar(-1.0, 3).is_err());
    }
}
