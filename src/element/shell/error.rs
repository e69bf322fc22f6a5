//! Errors of shell element construction.
//!
//! Evaluation errors (wrong length or non-finite `u_e`) are [`ElementError`]s like those of every
//! element; construction can also fail on the geometry (degenerate or too warped quadrilateral) and
//! on the damage law's set-up for the element size, which [`ElementError`] does not describe, hence
//! this type. It converts from [`ElementError`] and wraps [`MaterialError`] with the element size.

use crate::element::ElementError;
use crate::material::MaterialError;

/// What went wrong while building a shell element.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShellError {
    /// Bad coordinates or section quantity (non-finite node, non-positive thickness, ...).
    #[error(transparent)]
    Element(#[from] ElementError),
    /// The number of layers through the thickness must be at least 1.
    #[error("shell section: `layers` must be >= 1, got {layers}")]
    NoLayers {
        /// The value given.
        layers: usize,
    },
    /// The damage law cannot be set up for this element (invalid parameters, element larger than
    /// the `hillerborg_no_elastic` size limit).
    #[error("damage law for a shell element of characteristic length h = {h} m: {source}")]
    Material {
        /// The element's characteristic length sqrt(area) (m).
        h: f64,
        /// What the law reported.
        source: MaterialError,
    },
    /// The element has (nearly) zero area, a collapsed edge, or is not convex / its nodes are not
    /// ordered around its normal: the Jacobian at a corner is not positive.
    #[error(
        "degenerate shell element with nodes {coords:?}: the Jacobian at corner {corner} is \
         {ratio:e} of the mean (must be > {min_ratio:e}); check the node order (it must go around \
         the element) and that the element is convex, or split it into triangles"
    )]
    Degenerate {
        /// Node coordinates (global).
        coords: Vec<[f64; 3]>,
        /// Local corner where the test failed (0-based).
        corner: usize,
        /// Jacobian at that corner over the mean Jacobian.
        ratio: f64,
        /// The smallest accepted ratio.
        min_ratio: f64,
    },
    /// The quadrilateral is too warped for a flat element.
    #[error(
        "warped shell quadrilateral with nodes {coords:?}: the nodes lie ±{offset:e} m off the mean \
         plane, warping ratio offset/sqrt(area) = {ratio:e} > limit {limit:e}; refine the mesh or \
         use triangles"
    )]
    Warped {
        /// Node coordinates (global).
        coords: Vec<[f64; 3]>,
        /// Distance of the nodes from the mean plane (m).
        offset: f64,
        /// offset / sqrt(projected area).
        ratio: f64,
        /// The accepted limit ([`WARPING_LIMIT`](super::WARPING_LIMIT)).
        limit: f64,
    },
}
