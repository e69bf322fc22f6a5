//! Process-wide MPI + PETSc/SLEPc environment for unit tests anywhere in the crate.
//!
//! `cargo test` runs tests on several threads of one process, while MPI and PETSc initialize once
//! per process and PETSc is not thread-safe. So:
//! * MPI (singleton init, no `mpirun` needed) and PETSc/SLEPc are initialized on first use, behind
//!   a `OnceLock`, and never finalized (the process exits with them alive, which MPI tolerates for
//!   a singleton; finalizing would forbid any later test);
//! * rsmpi's `Universe` is `!Sync` and finalizes MPI when dropped: it is `std::mem::forget`-ten,
//!   and only the world `SimpleCommunicator` is kept;
//! * a `Mutex` around the environment serializes the tests: only one test talks to PETSc at a time.
//!   A test that panics poisons the mutex; the next test takes the environment anyway (PETSc state
//!   is per object, and the failed test's objects were dropped while unwinding).
//!
//! Usage: `with_petsc(|comm| { let v = Vector::new_mpi(comm, 10, None)?; ... })`.

use std::sync::{Mutex, MutexGuard, OnceLock};

use mpi::topology::SimpleCommunicator;

use super::runtime::Petsc;

/// What a test gets: the world communicator and the PETSc guard (for options).
pub(crate) struct TestEnv {
    /// `MPI_COMM_WORLD` (one rank under `cargo test`).
    pub comm: SimpleCommunicator,
    /// The PETSc/SLEPc guard; never dropped.
    pub petsc: Petsc,
}

/// The environment behind its serializing mutex.
struct Shared(Mutex<TestEnv>);

// SAFETY: `TestEnv` holds raw MPI/PETSc handles, which are `!Send`. It is created once, never
// moved or dropped afterwards (it lives in a static), and only reached through the mutex, so no two
// threads ever use PETSc or MPI at the same time. OpenMPI (initialized at MPI_THREAD_SINGLE by the
// singleton) and PETSc tolerate serialized calls from different threads in practice: they keep no
// thread-local state.
unsafe impl Sync for Shared {}
// SAFETY: as above; the value is only ever accessed under the mutex.
unsafe impl Send for Shared {}

static ENV: OnceLock<Shared> = OnceLock::new();

/// Initializes MPI and PETSc/SLEPc once for the whole test process.
fn init() -> Shared {
    let universe = mpi::initialize().expect("MPI initialized outside the test environment");
    let comm = universe.world();
    // Finalizing MPI at exit would need the universe; the OS reclaims everything instead.
    std::mem::forget(universe);
    let petsc = Petsc::initialize(&["masonry-hpc-unit-tests".to_owned()])
        .unwrap_or_else(|e| panic!("PETSc initialization failed in the test environment: {e}"));
    Shared(Mutex::new(TestEnv { comm, petsc }))
}

/// Locks the environment, initializing it on first use.
fn lock() -> MutexGuard<'static, TestEnv> {
    let shared = ENV.get_or_init(init);
    match shared.0.lock() {
        Ok(g) => g,
        Err(poisoned) => poisoned.into_inner(),
    }
}

/// Runs `f` with the world communicator, PETSc running and no other test using it.
pub(crate) fn with_petsc<R>(f: impl FnOnce(&SimpleCommunicator) -> R) -> R {
    let env = lock();
    f(&env.comm)
}

/// Like [`with_petsc`], with access to the PETSc guard too (options database).
pub(crate) fn with_petsc_env<R>(f: impl FnOnce(&TestEnv) -> R) -> R {
    let env = lock();
    f(&env)
}
