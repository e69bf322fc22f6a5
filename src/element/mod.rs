//! Structural finite elements and the interface they share.
//!
//! | file               | concept                                                           |
//! |--------------------|-------------------------------------------------------------------|
//! | `mod.rs`           | the [`Element`] trait, DOF layout, [`MassKind`], [`AppliedLoads`] |
//! | `output.rs`        | [`ElementOutput`]: preallocated f_int / K_t scratch               |
//! | `error.rs`         | [`ElementError`]                                                  |
//! | `local_frame.rs`   | [`LocalFrame`]: local axes of a line element, T = diag(R,R,R,R)   |
//! | `frame_section.rs` | [`FrameSection`]: E, G, A, Iy, Iz, J, ρ                           |
//! | `frame.rs`         | [`ElasticFrame3d`]: 2-node Euler–Bernoulli 3D frame               |
//! | `beam_inertia.rs`  | mass matrices and self weight of 2-node beams (frame and fiber)   |
//! | `fiber_section.rs` | [`FiberSection`]: rectangular fiber grid, Gauss points            |
//! | `fiber_beam.rs`    | [`FiberBeam3d`]: displacement-based fiber beam, damage per fiber  |
//! | `tie.rs`           | [`Tie`]: 2-node tie rod, axial only, pretension, tension only     |
//! | `point_states.rs`  | [`PointStates`]: damage histories of the points, IMPL-EX's too    |
//!
//! # DOF layout
//! Every node carries [`DOFS_PER_NODE`] = 6 DOF, in the order ux uy uz rx ry rz (global axes,
//! rotations in radians, right-hand rule). Element vectors are node-major: DOF `6 a + k` is
//! component `k` of local node `a`. The caller maps element nodes to global equation numbers; an
//! element never sees the mesh, only the coordinates it was built from.
//!
//! # State: trial and committed
//! Path-dependent elements (layered damage shells, fiber beams) keep integration-point state inside
//! the element ("state lives with the element that computes it"), in two copies:
//!
//! ```text
//!  Newton iteration k:   evaluate(u_k)  — reads COMMITTED state, writes TRIAL state
//!  step converged:       commit()       — TRIAL → COMMITTED
//!  step abandoned:       revert()       — TRIAL ← COMMITTED (before a step cut-back)
//! ```
//!
//! `u_e` is always the **total** element displacement, so `evaluate` is a pure function of
//! (committed state, u_e): calling it twice with the same `u_e` gives the same result, which
//! line searches and step cut-backs rely on.
//!
//! # Checkpoints
//! The committed state of an element is a flat `[f64]` of [`Element::n_state`] values
//! ([`Element::save_state`] / [`Element::load_state`]). Flat arrays map directly onto one HDF5
//! dataset per element kind with per-rank offsets (collective writes), with no per-element
//! serialization format; the layout of the values is documented by each element.
//!
//! # Why a trait
//! Assembly and the Newmark driver only need this interface; the model may store elements as
//! `Vec<Box<dyn Element>>` or in one `Vec` per concrete kind (faster, and natural with one
//! [`ElementOutput`] per element size). The trait is object safe so both work.

mod beam_inertia;
mod error;
mod fiber_beam;
mod fiber_section;
mod frame;
mod frame_section;
#[cfg(test)]
mod implex_tests;
mod local_frame;
mod output;
mod point_states;
mod shell;
mod tie;

use std::fmt::Debug;

use nalgebra::{DMatrix, DVector};

pub use error::ElementError;
pub use fiber_beam::{FiberBeam3d, CELL_OUTPUT_NAMES as FIBER_CELL_OUTPUT_NAMES};
pub use fiber_section::{
    gauss_points, Fiber, FiberMaterial, FiberSection, DEFAULT_INTEGRATION_POINTS, MAX_FIBERS_PER_SIDE,
};
pub use frame::ElasticFrame3d;
pub use frame_section::FrameSection;
pub use local_frame::{LocalFrame, Mat12, Vec12};
pub use output::{ElementOutput, EvalRequest};
pub use point_states::{PointStates, PointUpdate};
pub use shell::{
    PointResultants, ShellElement, ShellError, ShellMaterial, ShellQuad4, ShellSection, ShellTri3, ThicknessRule,
    DEFAULT_LAYERS, DRILLING_FACTOR, SHEAR_CORRECTION, SHELL_CELL_OUTPUT_NAMES, WARPING_LIMIT,
};
pub use tie::{pretension_load, tie_axis, Tie, TieSection, CELL_OUTPUT_NAMES as TIE_CELL_OUTPUT_NAMES};

/// The largest damage increment from the `committed` to the `trial` states of the same points:
/// `max_i max(d_t,trial − d_t,committed, d_c,trial − d_c,committed)`, at least 0 (none for no
/// point).
pub fn damage_increment(trial: &[crate::material::DamageState], committed: &[crate::material::DamageState]) -> f64 {
    debug_assert_eq!(trial.len(), committed.len());
    trial.iter().zip(committed).fold(0.0, |m: f64, (t, c)| m.max(t.d_t - c.d_t).max(t.d_c - c.d_c))
}

/// Degrees of freedom per node: ux uy uz rx ry rz.
pub const DOFS_PER_NODE: usize = 6;

/// Which mass matrix [`Element::mass`] builds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum MassKind {
    /// Consistent mass M = ∫ ρ Nᵀ N, from the same shape functions as the stiffness.
    Consistent,
    /// Lumped (nodal) mass: no coupling between nodes; rotary inertia kept positive so M is
    /// positive definite and can be factored.
    Lumped,
}

/// The loads currently applied on the element's span, which an element needs to turn nodal
/// displacements into member forces (fixed-end forces of distributed loads).
///
/// `Copy + Default`: the default is "no distributed load".
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AppliedLoads {
    /// Gravitational acceleration vector currently applied (global axes, m/s², already multiplied
    /// by any load factor); zero when self-weight is not applied.
    pub gravity: [f64; 3],
}

/// A material point taking part in the nonlocal averaging of damage-driving strains
/// ([`Element::enable_nonlocal`], `material::nonlocal`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NonlocalPoint {
    /// Global coordinates (m).
    pub x: [f64; 3],
    /// Volume weight V (m³) of the point in the averages.
    pub volume: f64,
    /// Points are averaged only with points of the same `layer` (a through-thickness index).
    pub layer: usize,
}

/// What every structural element provides to assembly, dynamics, checkpoints and output.
///
/// All vectors and matrices are in **global** axes with the node-major layout of the module docs.
/// Methods that write results take the destination buffer and resize it only when its size is
/// wrong, so a caller that reuses buffers never allocates.
pub trait Element: Debug {
    /// Short name of the element kind, for messages and output groups (e.g. `"elastic_frame_3d"`).
    fn kind_name(&self) -> &'static str;

    /// Number of nodes.
    fn n_nodes(&self) -> usize;

    /// Number of DOF: `n_nodes() * DOFS_PER_NODE`.
    fn n_dofs(&self) -> usize {
        self.n_nodes() * DOFS_PER_NODE
    }

    /// Internal force f_int(u_e) and, if requested, the tangent K_t = ∂f_int/∂u_e, at the total
    /// element displacement `u_e` (length `n_dofs()`), starting from the COMMITTED state. The
    /// resulting state is stored as the element's TRIAL state. Writes `out` (sized by the element
    /// with [`ElementOutput::prepare`]) and sets `out.has_tangent`.
    ///
    /// Errors: wrong length of `u_e`, non-finite `u_e`, and for nonlinear elements a failure of the
    /// material update. On error the trial state is unspecified; the committed state is untouched.
    fn evaluate(&mut self, u_e: &[f64], request: EvalRequest, out: &mut ElementOutput) -> Result<(), ElementError>;

    /// Accept the trial state of the last `evaluate` as the committed state (converged step).
    fn commit(&mut self);

    /// Discard the trial state: it becomes a copy of the committed state (abandoned step).
    fn revert(&mut self);

    /// Mass matrix of the chosen kind into `m` (resized to `n_dofs() × n_dofs()` if needed).
    /// Translational and rotary inertia are both included; see each element for what it neglects.
    fn mass(&self, kind: MassKind, m: &mut DMatrix<f64>);

    /// Equivalent nodal loads of the self weight under the acceleration `g` (global, m/s²) into `f`
    /// (resized to `n_dofs()` if needed): the consistent load ∫ Nᵀ ρ g.
    fn gravity_load(&self, g: [f64; 3], f: &mut DVector<f64>);

    /// Names of the scalar cell quantities [`Element::cell_output`] writes, in order.
    fn cell_output_names(&self) -> &'static [&'static str];

    /// Cell quantities (member forces, damage max/mean, stress resultants, …) at the total
    /// displacement `u_e` and the COMMITTED state, under the loads `loads` currently applied, into
    /// `values` (length `cell_output_names().len()`).
    fn cell_output(&self, u_e: &[f64], loads: &AppliedLoads, values: &mut [f64]) -> Result<(), ElementError>;

    /// Energy dissipated by the material up to the committed state (J): the law's own
    /// Σ ∫ (Y_t ḋ_t + Y_c ḋ_c) dV over the element's integration points, never negative and
    /// never decreasing. 0 for elastic elements.
    fn dissipated_energy(&self) -> f64 {
        0.0
    }

    /// The largest damage increment of the trial state over the committed one: over the
    /// element's integration points, `max(d_t,trial − d_t,committed, d_c,trial − d_c,committed)`
    /// ([`damage_increment`]); 0 for elastic elements (the default). The time history's step
    /// control reads it after a converged substep, before the commit.
    fn damage_increment(&self) -> f64 {
        0.0
    }

    /// Number of f64 values of the committed state (0 for elastic elements).
    fn n_state(&self) -> usize;

    /// Write the committed state into `out` (length `n_state()`).
    fn save_state(&self, out: &mut [f64]) -> Result<(), ElementError>;

    /// Restore the committed (and trial) state from `state` (length `n_state()`), as written by
    /// [`Element::save_state`]. A damage element also reads the other layout of
    /// [`PointStates`]: IMPL-EX's switches IMPL-EX on with its history, the implicit one read
    /// under IMPL-EX starts it with no step behind.
    fn load_state(&mut self, state: &[f64]) -> Result<(), ElementError>;

    /// The increment of (pseudo-)time `dt` of the next evaluations and the relaxation time `tau`
    /// of the optional viscous regularization of the damage law (`None`: rate independent).
    /// Elements without that law ignore it (the default).
    fn set_damage_relaxation(&mut self, _dt: f64, _tau: Option<f64>) {}

    /// IMPL-EX (`material::implex`) on, with the split of the steps' stress taken where
    /// `split` says, or off (`None`) for the element's damage law: on, the element keeps its
    /// points' committed histories one step back (the checkpoint layout grows by them,
    /// [`PointStates`]), and the stress of each step is computed from the extrapolated history
    /// once [`Element::set_implex_step`] has set the step. Off (the default of every element)
    /// is the implicit law. Elements without that law ignore it (the default).
    fn set_implex(&mut self, _split: Option<crate::material::implex::SplitAt>) {}

    /// Whether the tangent stays symmetric with IMPL-EX on: at the step's fixed damage the stress
    /// derives from a potential (the spectral split, a uniaxial law, an elastic element), so the
    /// time history may factor `J` by Cholesky. True by default; a damage law whose stress is not
    /// a gradient at fixed damage (the paper's split in plane stress, nonlocal driving strains)
    /// says false.
    fn implex_tangent_symmetric(&self) -> bool {
        true
    }

    /// With IMPL-EX on, the size `h` of the step the next evaluations belong to: the histories
    /// are extrapolated by the ratio of `h` to the last committed step's size. Elements without
    /// the damage law ignore it (the default).
    fn set_implex_step(&mut self, _h: f64) {}

    /// With IMPL-EX on, the trial state of the last evaluation's strains, the implicit update
    /// that evaluations with a frozen split leave for later ([`PointStates::settle`]). `commit`
    /// calls it; the time history calls it before it measures [`Element::damage_increment`].
    /// Nothing otherwise (the default).
    fn settle_implex(&mut self) {}

    /// With IMPL-EX on, the settled trial states ([`Element::settle_implex`]) held as the
    /// histories of the step's next evaluations, in place of the extrapolated ones
    /// ([`PointStates::hold_trial`]); returns the largest change of a point's held damage.
    /// Nothing otherwise (the default: 0).
    fn hold_implex_histories(&mut self) -> f64 {
        0.0
    }

    /// Switch the element's damage law to nonlocal driving strains (`material::nonlocal`), the
    /// softening regularized by `length` instead of the element size; returns the points whose
    /// driving strains are averaged (empty, the default: the element takes no part).
    fn enable_nonlocal(&mut self, _length: f64) -> Result<Vec<NonlocalPoint>, crate::material::MaterialError> {
        Ok(Vec::new())
    }

    /// Append the local driving strains `[ε_t,loc, ε_c,loc]` of each of the points
    /// [`Element::enable_nonlocal`] returned, at the total displacement `u_e`, to `out`.
    fn local_driving_strains(&self, _u_e: &[f64], _out: &mut Vec<f64>) -> Result<(), ElementError> {
        Ok(())
    }

    /// The averaged driving strains (2 per point) and the points' own shares of their averages
    /// (1 per point) that the next evaluations use.
    fn set_nonlocal_strains(&mut self, _averaged: &[f64], _self_share: &[f64]) {}
}
