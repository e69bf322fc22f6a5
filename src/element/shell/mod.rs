//! Flat shell elements, 6 DOF per node, layered through the thickness with the plane-stress damage
//! law (paper §4.2).
//!
//! | file          | concept                                                                    |
//! |---------------|----------------------------------------------------------------------------|
//! | `section.rs`  | [`ShellSection`], [`ShellMaterial`]: thickness, layers, material, masses    |
//! | `layers.rs`   | [`ThicknessRule`] (Simpson per layer) and the section update N, M, A B D    |
//! | `geometry.rs` | local frame of a flat element, projection of a warped quad, rigid links    |
//! | `element.rs`  | [`ShellElement`]: force, tangent, state, mass, gravity, outputs, checkpoint|
//! | `mass.rs`     | the mass matrix in the flat local frame, consistent or lumped               |
//! | `products.rs` | the element matrices' products over nonzero columns and node blocks        |
//! | `mitc4.rs`    | [`ShellQuad4`]: bilinear membrane + MITC4 bending/shear + drilling          |
//! | `tri3.rs`     | [`ShellTri3`]: Allman membrane (vertex rotations) + DKT bending + drilling |
//! | `error.rs`    | [`ShellError`]: construction errors                                         |
//! | `tests.rs`    | patch tests, Scordelis–Lo roof, plate frequency, layered/damage checks     |
//!
//! Conventions (local axes, rotation signs, drilling, mass, state layout) are documented in
//! [`geometry`] and [`element`].

pub mod element;
mod error;
pub mod geometry;
pub mod layers;
mod mass;
mod mitc4;
mod products;
mod section;
mod tri3;

#[cfg(test)]
mod tests;

pub use element::{PointResultants, ShellElement, CELL_OUTPUT_NAMES as SHELL_CELL_OUTPUT_NAMES, DRILLING_FACTOR};
pub use error::ShellError;
pub use geometry::WARPING_LIMIT;
pub use layers::ThicknessRule;
pub use mitc4::ShellQuad4;
pub use section::{ShellMaterial, ShellSection, DEFAULT_LAYERS, SHEAR_CORRECTION};
pub use tri3::ShellTri3;
