//! Envelopes over the time history: per node the peak relative displacement in each direction
//! and the peak drift ratio, per cell the largest tensile and compressive damage.
//!
//! The drift ratio of a node is its horizontal displacement relative to the base over its
//! height above the base, `sqrt(u_x² + u_y²) / (z − z_base)` (z_base: the lowest z of the model;
//! nodes at the base have none). Damage never decreases, so its envelope is also its final value;
//! it is tracked anyway at every output step, for any element output named `d_t_max`/`d_c_max`.

/// Envelopes of one rank (owned nodes, owned cells).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Envelopes {
    /// Per owned node: peak |u_x|, |u_y|, |u_z|, drift ratio.
    pub node: Vec<f64>,
    /// Per owned cell: peak d_t, peak d_c (NaN where the element has none).
    pub cell: Vec<f64>,
    /// Height of each owned node above the base (≤ 0 at the base).
    height: Vec<f64>,
}

/// Values per node and per cell.
pub const NODE_VALUES: usize = 4;
/// Values per cell.
pub const CELL_VALUES: usize = 2;

impl Envelopes {
    /// Zero envelopes for nodes at heights `height` and `n_cells` cells.
    pub fn new(height: Vec<f64>, n_cells: usize) -> Envelopes {
        Envelopes { node: vec![0.0; NODE_VALUES * height.len()], cell: vec![f64::NAN; CELL_VALUES * n_cells], height }
    }

    /// Takes in the relative displacement of the owned nodes (6 DOFs per node).
    pub fn update_nodes(&mut self, u: &[f64]) {
        for (i, h) in self.height.iter().enumerate() {
            let e = &mut self.node[NODE_VALUES * i..NODE_VALUES * i + NODE_VALUES];
            for d in 0..3 {
                e[d] = e[d].max(u[6 * i + d].abs());
            }
            if *h > 0.0 {
                e[3] = e[3].max(u[6 * i].hypot(u[6 * i + 1]) / h);
            }
        }
    }

    /// Takes in the cell outputs (names and values per owned cell, field-major).
    pub fn update_cells(&mut self, names: &[String], values: &[Vec<f64>]) {
        for (k, want) in ["d_t_max", "d_c_max"].iter().enumerate() {
            if let Some(f) = names.iter().position(|n| n == want) {
                for (c, v) in values[f].iter().enumerate() {
                    let e = &mut self.cell[CELL_VALUES * c + k];
                    if v.is_finite() && !(e.is_finite() && *e >= *v) {
                        *e = *v;
                    }
                }
            }
        }
    }

    /// One column of the node envelope.
    pub fn node_column(&self, k: usize) -> Vec<f64> {
        self.node.chunks(NODE_VALUES).map(|c| c[k]).collect()
    }

    /// One column of the cell envelope.
    pub fn cell_column(&self, k: usize) -> Vec<f64> {
        self.cell.chunks(CELL_VALUES).map(|c| c[k]).collect()
    }

    /// Largest local value of a node column (0 if none).
    pub fn node_max(&self, k: usize) -> f64 {
        self.node_column(k).into_iter().fold(0.0, f64::max)
    }

    /// Largest local value of a cell column (0 if none is finite).
    pub fn cell_max(&self, k: usize) -> f64 {
        self.cell_column(k).into_iter().filter(|v| v.is_finite()).fold(0.0, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn peaks_and_drift() {
        let mut e = Envelopes::new(vec![0.0, 2.0], 1);
        let mut u = vec![0.0; 12];
        u[6] = 0.03;
        u[7] = -0.04;
        e.update_nodes(&u);
        u[6] = -0.01;
        e.update_nodes(&u);
        assert_eq!(e.node_column(0), vec![0.0, 0.03]);
        assert!((e.node[7] - 0.05 / 2.0).abs() < 1e-15);
        e.update_cells(&["d_t_max".into()], &[vec![0.2]]);
        e.update_cells(&["d_t_max".into()], &[vec![0.1]]);
        assert_eq!(e.cell_column(0), vec![0.2]);
        assert!(e.cell_column(1)[0].is_nan());
    }
}
