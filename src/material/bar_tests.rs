//! Mesh objectivity of the regularized law on a 1D bar.
