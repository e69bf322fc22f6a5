//! The 2D discrete-element virtual testing lab (paper §2.1): rigid polygonal stones bonded by
//! brittle Euler–Bernoulli beams, with contact and Coulomb friction once the bonds break.
pub mod error;
pub mod mechanics;
pub mod output;
pub mod polygon;
pub mod sample;
pub mod solver;
