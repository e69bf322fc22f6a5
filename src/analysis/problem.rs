//! The FE problem of one structural job, in the manner of deal.II's step-40 class: what it reads
//! (the communicator, the job, the mesh, the model resolved against it) and the one thing it
//! builds from them, the rank's [`Discretization`] (partition, DOF numbering, the owned cells'
//! elements with their integration-point state).
//!
//! Every FE analysis takes the problem; none sets up a discretization of its own, so a chain of
//! analyses on one problem (a seismic assessment: modal, updating, modal, gravity, earthquake)
//! partitions and numbers once, and its stages see each other's element state. [`FeProblem::setup`]
//! is the only caller of [`Discretization::setup`] (`tests/layers.rs` checks it).
//!
//! The inputs are borrowed, not owned: a sweep's members share one mesh, and an analysis reads
//! its settings from `job` while it changes `disc`.
use super::Discretization;
use crate::config::Job;
use crate::error::Error;
use crate::mesh::Mesh;
use crate::model::StructuralModel;
use crate::parallel::{timed, Context};

/// One rank's share of a structural job's FE problem.
pub struct FeProblem<'a> {
    /// The communicator of the ranks that share the problem, and the log.
    pub ctx: &'a Context,
    /// The job as read.
    pub job: &'a Job,
    /// The whole mesh (on every rank).
    pub mesh: &'a Mesh,
    /// The job resolved against the mesh (on every rank).
    pub model: &'a StructuralModel,
    /// This rank's discretization.
    pub disc: Discretization,
    /// Seconds of the setup not yet reported by an analysis ([`FeProblem::take_setup_seconds`]).
    setup_seconds: f64,
}

impl<'a> FeProblem<'a> {
    /// Collective. Partitions the model's cells, numbers the DOFs and builds the owned elements.
    pub fn setup(
        ctx: &'a Context,
        job: &'a Job,
        mesh: &'a Mesh,
        model: &'a StructuralModel,
    ) -> Result<FeProblem<'a>, Error> {
        let (disc, setup_seconds) = timed(|| Discretization::setup(ctx, job, mesh, model));
        Ok(FeProblem { ctx, job, mesh, model, disc: disc?, setup_seconds })
    }

    /// Collective. The owned elements built again, fresh (no damage, no state), with the Young
    /// modulus of each part's material scaled by `scale[part]` (modal updating moves the moduli
    /// of the problem it runs on); the partition and the numbering stay.
    pub fn rebuild_elements(&mut self, scale: &[f64]) -> Result<(), Error> {
        self.disc.rebuild_elements(self.ctx, self.job, self.mesh, self.model, scale)
    }

    /// The setup's seconds the first time (for the first analysis that reports a setup time),
    /// zero after: a chain of analyses counts the setup once.
    pub fn take_setup_seconds(&mut self) -> f64 {
        std::mem::take(&mut self.setup_seconds)
    }
}
