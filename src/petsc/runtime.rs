//! PETSc/SLEPc lifetime: [`Petsc`], an RAII guard around `SlepcInitialize` / `SlepcFinalize`.
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! use masonry_hpc::petsc::Petsc;
//! let universe = mpi::initialize().ok_or("MPI already initialized")?; // 1. MPI first
//! let args: Vec<String> = std::env::args().collect();
//! let petsc = Petsc::initialize(&args)?;                              // 2. then PETSc/SLEPc
//! // ... solvers, vectors, matrices ...
//! drop(petsc);                                                        // 3. SlepcFinalize
//! drop(universe);                                                     // 4. MPI_Finalize
//! # Ok(()) }
//! ```
//! Declaring `universe` before `petsc` in the same scope gives the same order (locals drop in
//! reverse order of declaration).

use std::ffi::{c_char, c_int, CString};
use std::marker::PhantomData;

use super::error::{check, petsc_call, record_error_handler, PetscError};
use super::options::Options;
use super::sys;

/// PETSc and SLEPc, initialized; finalized when dropped.
///
/// # Ordering
/// MPI must be initialized (by rsmpi: `mpi::initialize()`) **before** [`Petsc::initialize`], and
/// this guard must be dropped **before** rsmpi's `Universe`: `SlepcFinalize` (which also runs
/// `PetscFinalize`) calls MPI, and OpenMPI aborts if that happens after `MPI_Finalize`. PETSc then
/// leaves MPI to rsmpi (it only finalizes MPI when it started it, which this guard never lets it do).
///
/// PETSc objects ([`super::Vector`], [`super::Matrix`], ...) should be dropped before the guard; one
/// dropped afterwards is leaked rather than destroyed (PETSc is gone), never a crash.
///
/// The options PETSc reads at initialization are the command line given to
/// [`initialize`](Petsc::initialize) and the `PETSC_OPTIONS` environment variable (PETSc reads it
/// itself); [`set_default_options`](Petsc::set_default_options) adds job-file defaults under them.
///
/// Collective on `PETSC_COMM_WORLD` (= `MPI_COMM_WORLD`) to create and to drop.
pub struct Petsc {
    /// PETSc keeps pointers into `argv` for its whole life (`PetscGetArgs`): the strings, the
    /// pointer array, the count and the pointer to the array are owned here and never moved
    /// (boxed / heap-allocated), so they outlive PETSc.
    _args: Vec<CString>,
    _argv: Vec<*mut c_char>,
    _argc: Box<c_int>,
    _argv_ptr: Box<*mut *mut c_char>,
    /// Raw pointers already make the guard `!Send + !Sync`; PETSc is not thread-safe.
    _not_send: PhantomData<*mut ()>,
}

impl Petsc {
    /// Initializes SLEPc (and through it PETSc) with the command line `args` (`args[0]` is the
    /// program name, as in `std::env::args()`), then installs the error handler that returns
    /// errors to Rust instead of printing PETSc tracebacks.
    ///
    /// Errors: MPI not initialized yet, PETSc already initialized in this process, an argument
    /// holding a NUL byte, or a failure of `SlepcInitialize`. Collective on `MPI_COMM_WORLD`.
    pub fn initialize(args: &[String]) -> Result<Petsc, PetscError> {
        const CALL: &str = "Petsc::initialize";
        if !mpi::is_initialized() {
            return Err(PetscError::usage(
                sys::PETSC_ERR_ORDER,
                CALL,
                "MPI must be initialized (mpi::initialize()) before PETSc",
            ));
        }
        let mut initialized: sys::PetscBool = sys::PETSC_FALSE;
        petsc_call!(PetscInitialized(&mut initialized))?;
        if initialized == sys::PETSC_TRUE {
            return Err(PetscError::usage(sys::PETSC_ERR_ORDER, CALL, "PETSc is already initialized"));
        }

        let mut c_args = Vec::with_capacity(args.len().max(1));
        if args.is_empty() {
            c_args.push(CString::from(c"masonry-hpc"));
        }
        for a in args {
            let c = CString::new(a.as_str()).map_err(|_| {
                PetscError::usage(
                    sys::PETSC_ERR_ARG_WRONG,
                    CALL,
                    format!("command-line argument {a:?} contains a NUL byte"),
                )
            })?;
            c_args.push(c);
        }
        let mut argv: Vec<*mut c_char> = c_args.iter().map(|c| c.as_ptr().cast_mut()).collect();
        argv.push(std::ptr::null_mut()); // C convention: argv[argc] == NULL
        let mut argc = Box::new(c_int::try_from(c_args.len()).unwrap_or(c_int::MAX));
        let mut argv_ptr = Box::new(argv.as_mut_ptr());

        // SAFETY: argc/argv point at storage owned by the returned guard (see the field comment);
        // null file and help strings are allowed.
        check(
            unsafe { sys::SlepcInitialize(&mut *argc, &mut *argv_ptr, std::ptr::null(), std::ptr::null()) },
            "SlepcInitialize",
        )?;
        let guard = Petsc { _args: c_args, _argv: argv, _argc: argc, _argv_ptr: argv_ptr, _not_send: PhantomData };
        // From here on, errors come back as codes with their message recorded, not as tracebacks.
        petsc_call!(PetscPushErrorHandler(Some(record_error_handler), std::ptr::null_mut()))?;
        Ok(guard)
    }

    /// The global options database (command line, `PETSC_OPTIONS`, job defaults).
    pub fn options(&self) -> Options<'_> {
        Options::global(self)
    }

    /// Value of option `name` (e.g. `"-ksp_type"`): `Some("")` for a flag given without a value,
    /// `None` when absent.
    pub fn option_value(&self, name: &str) -> Result<Option<String>, PetscError> {
        self.options().value(name)
    }

    /// Adds job-file defaults under `prefix`: for each `(key, value)`, sets `-{prefix}{key} value`
    /// unless the command line or `PETSC_OPTIONS` already gave that option, so the command line wins.
    ///
    /// Keys may carry the leading `-` or not (`"ksp_type"` or `"-ksp_type"`); a value of `""` or
    /// `"true"` sets a flag (option without value). Call it before the solvers are configured
    /// (their `set_from_options` reads the database). Not collective, but every rank should give
    /// the same defaults.
    pub fn set_default_options(&self, prefix: &str, opts: &[(String, String)]) -> Result<(), PetscError> {
        let options = self.options();
        for (key, value) in opts {
            let name = option_name(prefix, key);
            if !options.has(&name)? {
                let value = match value.trim() {
                    "" | "true" => None,
                    v => Some(v),
                };
                options.set(&name, value)?;
            }
        }
        Ok(())
    }
}

impl Drop for Petsc {
    /// `SlepcFinalize` (which runs `PetscFinalize`). Collective on `MPI_COMM_WORLD`.
    fn drop(&mut self) {
        // The pushed handler is popped by PetscFinalize itself. An error here cannot be returned;
        // PETSc has already reported it through the recording handler, and nothing is left to free.
        // SAFETY: this guard is the one that initialized SLEPc/PETSc; nothing runs after it.
        let _ = unsafe { sys::SlepcFinalize() };
    }
}

/// Full option name `-{prefix}{key}` from a prefix and a key, each with or without leading `-`.
pub(crate) fn option_name(prefix: &str, key: &str) -> String {
    format!("-{}{}", prefix.trim().trim_start_matches('-'), key.trim().trim_start_matches('-'))
}

/// `Ok` if PETSc is initialized and not finalized, else an ordering error naming `call`.
pub(crate) fn ensure_running(call: &'static str) -> Result<(), PetscError> {
    if is_running() {
        Ok(())
    } else {
        Err(PetscError::usage(
            sys::PETSC_ERR_ORDER,
            call,
            "PETSc is not running (call Petsc::initialize first, and keep the guard alive)",
        ))
    }
}

/// True between `PetscInitialize` and `PetscFinalize`. Used by the `Drop` of PETSc objects so that
/// one outliving the [`Petsc`] guard is leaked instead of destroyed by a finalized library.
pub(crate) fn is_running() -> bool {
    let mut initialized = sys::PETSC_FALSE;
    let mut finalized = sys::PETSC_FALSE;
    // SAFETY: both functions only read PETSc's global flags; valid at any time.
    let ok = unsafe { sys::PetscInitialized(&mut initialized) == 0 && sys::PetscFinalized(&mut finalized) == 0 };
    ok && initialized == sys::PETSC_TRUE && finalized == sys::PETSC_FALSE
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::petsc::testing::with_petsc_env;

    #[test]
    fn option_names_accept_keys_with_or_without_dash() {
        assert_eq!(option_name("struct_", "ksp_type"), "-struct_ksp_type");
        assert_eq!(option_name("struct_", "-ksp_type"), "-struct_ksp_type");
        assert_eq!(option_name("", "-pc_type"), "-pc_type");
        assert_eq!(option_name("-modal_", "eps_nev"), "-modal_eps_nev");
    }

    #[test]
    fn command_line_wins_over_job_defaults() {
        with_petsc_env(|env| {
            let opts = env.petsc.options();
            // What the user typed (same database as argv and PETSC_OPTIONS).
            opts.insert_command_line("-prectest_ksp_type gmres -prectest_ksp_monitor_short").unwrap();
            let job = [
                ("ksp_type".to_owned(), "cg".to_owned()),
                ("-pc_type".to_owned(), "jacobi".to_owned()),
                ("ksp_converged_reason".to_owned(), "true".to_owned()),
                ("ksp_monitor_short".to_owned(), "".to_owned()),
            ];
            env.petsc.set_default_options("prectest_", &job).unwrap();
            let value = |n: &str| env.petsc.option_value(n).unwrap();
            assert_eq!(value("-prectest_ksp_type").as_deref(), Some("gmres"), "command line wins");
            assert_eq!(value("-prectest_pc_type").as_deref(), Some("jacobi"), "default fills gaps");
            assert_eq!(value("-prectest_ksp_converged_reason").as_deref(), Some(""), "flag");
            assert_eq!(value("-prectest_ksp_monitor_short").as_deref(), Some(""));
            assert_eq!(value("-prectest_never_given"), None);
            for n in ["ksp_type", "pc_type", "ksp_converged_reason", "ksp_monitor_short"] {
                opts.clear(&option_name("prectest_", n)).unwrap();
            }
        });
    }

    #[test]
    fn second_initialize_is_refused() {
        with_petsc(|_| {
            let e = Petsc::initialize(&["again".to_owned()]).err().expect("must refuse");
            assert_eq!(e.code, sys::PETSC_ERR_ORDER as i32);
        });
    }
    use crate::petsc::testing::with_petsc;
}
