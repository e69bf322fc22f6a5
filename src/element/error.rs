//! Errors of element construction and evaluation.
//!
//! Every variant carries the values that let a reader find the culprit (coordinates, the quantity
//! and its value, the expected and received lengths). The element does not know its own id in the
//! mesh: the caller (model setup, assembly) wraps an [`ElementError`] with the cell id it was
//! working on.

/// What went wrong while building or evaluating an element.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ElementError {
    /// A section or material quantity out of its range ([`ElementError::positive`],
    /// [`ElementError::non_negative`], or Poisson's ratio's).
    #[error("section quantity `{quantity}`: expected {expected}, got {value}")]
    InvalidSection {
        /// The field name (`e`, `g`, `area`, `iy`, `iz`, `j`, `density`, ...).
        quantity: &'static str,
        /// The offending value.
        value: f64,
        /// The range it must lie in ("> 0", ">= 0", "in (-1, 0.5)").
        expected: &'static str,
    },
    /// A node coordinate is NaN or infinite.
    #[error("node {node} has a non-finite coordinate {coords:?}")]
    NonFiniteCoordinates {
        /// Local node number in the element (0-based).
        node: usize,
        /// Its coordinates.
        coords: [f64; 3],
    },
    /// The two end nodes of a line element coincide (to round-off).
    #[error("zero-length element: node 1 at {node1:?} and node 2 at {node2:?} (length {length:e})")]
    ZeroLength {
        /// Coordinates of the first node.
        node1: [f64; 3],
        /// Coordinates of the second node.
        node2: [f64; 3],
        /// The computed length.
        length: f64,
    },
    /// The orientation vector is zero, non-finite or (nearly) parallel to the element axis, so it does
    /// not define a plane.
    #[error(
        "orientation vector {vecxz:?} is zero or parallel to the element axis {axis:?} \
         (sin of the angle between them = {sin_angle:e})"
    )]
    BadOrientation {
        /// The orientation vector as given.
        vecxz: [f64; 3],
        /// The unit element axis (node 1 → node 2).
        axis: [f64; 3],
        /// |axis × vecxz| / |vecxz| (0 if `vecxz` is zero).
        sin_angle: f64,
    },
    /// A slice passed to the element has the wrong length.
    #[error("{what}: expected {expected} values, got {got}")]
    WrongLength {
        /// Which argument (`u_e`, `state`, `cell output`).
        what: &'static str,
        /// The length the element needs.
        expected: usize,
        /// The length received.
        got: usize,
    },
    /// A count of a section (fibers, integration points) lies outside its admissible range.
    #[error("section quantity `{quantity}` must lie in {min}..={max}, got {value}")]
    InvalidCount {
        /// The field name (`ny`, `nz`, `integration_points`).
        quantity: &'static str,
        /// The value given.
        value: usize,
        /// Smallest admissible value.
        min: usize,
        /// Largest admissible value.
        max: usize,
    },
    /// The damage law cannot be set up for this element (invalid parameters, an element longer
    /// than the `hillerborg_no_elastic` size limit).
    #[error("damage law for an element of characteristic length h = {h} m: {source}")]
    Material {
        /// The element's characteristic length (m).
        h: f64,
        /// What the law reported.
        source: crate::material::MaterialError,
    },
    /// An element displacement component is NaN or infinite (typically a diverged iteration).
    #[error("element displacement component {index} is not finite ({value})")]
    NonFiniteDisplacement {
        /// Position in `u_e` (node-major, 6 per node).
        index: usize,
        /// The value.
        value: f64,
    },
}

impl ElementError {
    /// `value` when it is finite and > 0 ([`crate::bounds::positive`]), else
    /// [`ElementError::InvalidSection`] naming `quantity`.
    pub fn positive(quantity: &'static str, value: f64) -> Result<f64, ElementError> {
        crate::bounds::positive(value).map_err(|b| ElementError::out_of_bounds(quantity, b))
    }

    /// `value` when it is finite and >= 0 (a density, a pretension; [`crate::bounds::non_negative`]),
    /// else [`ElementError::InvalidSection`] naming `quantity`.
    pub fn non_negative(quantity: &'static str, value: f64) -> Result<f64, ElementError> {
        crate::bounds::non_negative(value).map_err(|b| ElementError::out_of_bounds(quantity, b))
    }

    /// The [`ElementError::InvalidSection`] of `quantity` out of its bound `b`.
    fn out_of_bounds(quantity: &'static str, b: crate::bounds::OutOfBounds) -> ElementError {
        ElementError::InvalidSection { quantity, value: b.value, expected: b.expected }
    }
}

/// Check that `got == expected`, else a [`ElementError::WrongLength`] naming `what`.
pub(crate) fn check_len(what: &'static str, expected: usize, got: usize) -> Result<(), ElementError> {
    if expected == got {
        Ok(())
    } else {
        Err(ElementError::WrongLength { what, expected, got })
    }
}

/// Check that every component of `u` is finite.
pub(crate) fn check_finite_displacement(u: &[f64]) -> Result<(), ElementError> {
    match u.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(index) => Err(ElementError::NonFiniteDisplacement { index, value: u[index] }),
    }
}
