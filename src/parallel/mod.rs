//! MPI-side building blocks: the run context with rank-aware logging, collective agreement on
//! errors, the METIS partition of the cells, and the numbering of nodes and equations.
//!
//! Conventions (see ARCHITECTURE.md): every rank holds the whole mesh (a church is a few hundred
//! thousand cells); each rank *owns* the cells METIS gives it and computes only those; a node is
//! owned by the lowest rank among the cells that touch it; the nodes a rank's cells touch but it
//! does not own are its *ghosts*. Global node numbers are contiguous per rank in rank order, and
//! equations are `6 * global_node + dof` so that a node's six DOFs form one block.
mod agree;
pub mod batch;
mod context;
mod dof_map;
mod groups;
mod partition;
mod phases;

pub use agree::{agree, Agreed};
pub use batch::{run_batch, BatchError, TaskResult, Unfinished};
pub use context::{all_ranks, global_sum, print_error, Context, Log};
pub use dof_map::{DofMap, Preallocation, DOFS_PER_NODE};
pub use groups::{Answer, Dispatcher, GroupError, Groups, TaskSource};
pub use partition::{partition_cells, PartitionError};
pub use phases::{timed, Phases};
