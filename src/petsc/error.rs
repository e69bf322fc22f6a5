//! Typed errors of the PETSc/SLEPc layer.
//!
//! * [`PetscError`]: a PETSc call returned a nonzero `PetscErrorCode` (or the safe layer refused its
//!   arguments before calling PETSc). It names the call and carries PETSc's own message.
//! * [`SolverError`]: a linear solve failed, either because a call failed ([`SolverError::Petsc`]) or
//!   because `KSPSolve` returned normally with a negative `KSPConvergedReason`
//!   ([`SolverError::Diverged`], with the preconditioner's diagnosis when it has one).
//!
//! Every raw call of the layer goes through `check` (or the `petsc_call!` macro over it), so no
//! error code is ever dropped.

use std::ffi::CStr;
use std::os::raw::{c_char, c_int, c_void};
use std::sync::Mutex;

use super::sys;

/// A failed PETSc/SLEPc call.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("PETSc error {code} in {call}: {message}")]
pub struct PetscError {
    /// PETSc's error code (`PETSC_ERR_*`), e.g. 63 for an argument out of range.
    pub code: i32,
    /// The C function (or safe-layer method) that failed, e.g. `"KSPSolve"`.
    pub call: &'static str,
    /// PETSc's generic text for the code, followed by the specific message of the error.
    pub message: String,
}

impl PetscError {
    /// An error raised by the safe layer itself (bad arguments caught before PETSc sees them),
    /// using PETSc's code for the kind of problem (e.g. `PETSC_ERR_ARG_SIZ`).
    pub(crate) fn usage(code: u32, call: &'static str, message: impl Into<String>) -> Self {
        PetscError { code: i32::try_from(code).unwrap_or(i32::MAX), call, message: message.into() }
    }

    /// Builds the error for a nonzero `code` returned by `call`: PETSc's generic text for the code,
    /// then the specific message recorded by [`record_error_handler`] for this error, if any.
    fn from_code(code: sys::PetscErrorCode, call: &'static str) -> Self {
        let mut text: *const c_char = std::ptr::null();
        // SAFETY: PetscErrorMessage only writes `text`, pointing at a static PETSc string (or
        // leaving it null); a null `specific` is allowed. It works before initialization too.
        let rc = unsafe { sys::PetscErrorMessage(code, &mut text, std::ptr::null_mut()) };
        let mut message = String::new();
        if rc == 0 && !text.is_null() {
            // SAFETY: non-null pointers from PetscErrorMessage are NUL-terminated C strings.
            message.push_str(unsafe { CStr::from_ptr(text) }.to_string_lossy().trim());
        }
        if let Some(specific) = take_recorded_message() {
            if !message.is_empty() {
                message.push_str(": ");
            }
            message.push_str(&specific);
        }
        if message.is_empty() {
            message = "unknown PETSc error".to_owned();
        }
        PetscError { code, call, message }
    }
}

/// The specific message of the last error PETSc raised, kept by [`record_error_handler`] until
/// the safe layer turns the error code into a [`PetscError`].
static LAST_MESSAGE: Mutex<Option<String>> = Mutex::new(None);

/// Takes (and clears) the recorded message of the last PETSc error.
fn take_recorded_message() -> Option<String> {
    match LAST_MESSAGE.lock() {
        Ok(mut guard) => guard.take(),
        Err(poisoned) => poisoned.into_inner().take(),
    }
}

/// PETSc error handler installed by [`super::Petsc::initialize`] (`PetscPushErrorHandler`).
///
/// Instead of printing a traceback to stderr (PETSc's default), it records the message of the
/// error where it was first raised (`PETSC_ERROR_INITIAL`, with the C function's name) and returns
/// the code unchanged, so the error travels back to Rust as a return value and is reported once,
/// by [`PetscError`]'s `Display`.
///
/// # Safety
/// Called by PETSc only, with `func` and `mess` null or NUL-terminated strings.
pub(crate) unsafe extern "C" fn record_error_handler(
    _comm: mpi::ffi::MPI_Comm,
    _line: c_int,
    func: *const c_char,
    _file: *const c_char,
    code: sys::PetscErrorCode,
    kind: sys::PetscErrorType,
    mess: *const c_char,
    _ctx: *mut c_void,
) -> sys::PetscErrorCode {
    if kind == sys::PETSC_ERROR_INITIAL {
        let read = |p: *const c_char| {
            if p.is_null() {
                String::new()
            } else {
                // SAFETY: PETSc passes NUL-terminated strings (see the function's contract).
                unsafe { CStr::from_ptr(p) }.to_string_lossy().trim().to_owned()
            }
        };
        let (func, mess) = (read(func), read(mess));
        let text = match (func.is_empty(), mess.is_empty()) {
            (false, false) => format!("{mess} (in {func})"),
            (true, false) => mess,
            (false, true) => format!("in {func}"),
            (true, true) => String::new(),
        };
        let mut guard = match LAST_MESSAGE.lock() {
            Ok(guard) => guard,
            Err(poisoned) => poisoned.into_inner(),
        };
        *guard = (!text.is_empty()).then_some(text);
    }
    code
}

/// Turns a `PetscErrorCode` into a `Result`; `call` names the C function for the message.
#[inline]
pub(crate) fn check(code: sys::PetscErrorCode, call: &'static str) -> Result<(), PetscError> {
    if code == 0 {
        Ok(())
    } else {
        Err(PetscError::from_code(code, call))
    }
}

/// Calls a raw PETSc function and checks its error code, naming the function in the error:
/// `petsc_call!(KSPSolve(ksp, b, x))?`. Expands to an `unsafe` call: the caller's `// SAFETY:`
/// comment must justify the arguments.
macro_rules! petsc_call {
    ($f:ident ( $($arg:expr),* $(,)? )) => {
        $crate::petsc::error::check(
            #[allow(unused_unsafe)]
            unsafe { $crate::petsc::sys::$f($($arg),*) },
            stringify!($f),
        )
    };
}
pub(crate) use petsc_call;

/// A linear solve that did not deliver a solution.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolverError {
    /// A PETSc call failed.
    #[error(transparent)]
    Petsc(#[from] PetscError),
    /// `KSPSolve` returned but `KSPGetConvergedReason` is negative.
    #[error(
        "linear solver diverged: {reason} after {iterations} iterations (residual norm {residual_norm:e}){}",
        pc_diagnosis(*pc_failure, *zero_pivot_row)
    )]
    Diverged {
        /// PETSc's name of the reason, without the `KSP_` prefix, e.g. `"DIVERGED_PC_FAILED"`.
        reason: &'static str,
        /// Iterations done (`KSPGetIterationNumber`).
        iterations: i32,
        /// Last residual norm (`KSPGetResidualNorm`).
        residual_norm: f64,
        /// The preconditioner's failure (`PCGetFailedReason`), without the `PC_` prefix, e.g.
        /// `"FACTOR_NUMERIC_ZEROPIVOT"`; `None` when the preconditioner reports no error.
        pc_failure: Option<&'static str>,
        /// Row of the zero pivot (`MatFactorGetErrorZeroPivot`, in the factor's ordering: the
        /// matrix row with `-pc_factor_mat_ordering_type natural`), when PETSc's own factorization
        /// failed on one; `None` for external packages such as MUMPS, which do not report it.
        zero_pivot_row: Option<i64>,
    },
}

/// The tail of the `Diverged` message: the preconditioner diagnosis, if any.
fn pc_diagnosis(pc_failure: Option<&'static str>, zero_pivot_row: Option<i64>) -> String {
    match (pc_failure, zero_pivot_row) {
        (Some(f), Some(row)) => format!("; preconditioner failed: {f} at row {row}"),
        (Some(f), None) => format!("; preconditioner failed: {f}"),
        (None, Some(row)) => format!("; zero pivot at row {row}"),
        (None, None) => String::new(),
    }
}

/// Name of a `KSPConvergedReason` value, as PETSc spells it in `KSPConvergedReasons` (no `KSP_`
/// prefix). Values PETSc 3.18 does not define give `"UNKNOWN"`.
pub fn ksp_reason_name(reason: sys::KSPConvergedReason) -> &'static str {
    match reason {
        sys::KSP_CONVERGED_RTOL_NORMAL => "CONVERGED_RTOL_NORMAL",
        sys::KSP_CONVERGED_ATOL_NORMAL => "CONVERGED_ATOL_NORMAL",
        sys::KSP_CONVERGED_RTOL => "CONVERGED_RTOL",
        sys::KSP_CONVERGED_ATOL => "CONVERGED_ATOL",
        sys::KSP_CONVERGED_ITS => "CONVERGED_ITS",
        sys::KSP_CONVERGED_CG_NEG_CURVE => "CONVERGED_CG_NEG_CURVE",
        sys::KSP_CONVERGED_CG_CONSTRAINED => "CONVERGED_CG_CONSTRAINED",
        sys::KSP_CONVERGED_STEP_LENGTH => "CONVERGED_STEP_LENGTH",
        sys::KSP_CONVERGED_HAPPY_BREAKDOWN => "CONVERGED_HAPPY_BREAKDOWN",
        sys::KSP_CONVERGED_ITERATING => "CONVERGED_ITERATING",
        sys::KSP_DIVERGED_NULL => "DIVERGED_NULL",
        sys::KSP_DIVERGED_ITS => "DIVERGED_ITS",
        sys::KSP_DIVERGED_DTOL => "DIVERGED_DTOL",
        sys::KSP_DIVERGED_BREAKDOWN => "DIVERGED_BREAKDOWN",
        sys::KSP_DIVERGED_BREAKDOWN_BICG => "DIVERGED_BREAKDOWN_BICG",
        sys::KSP_DIVERGED_NONSYMMETRIC => "DIVERGED_NONSYMMETRIC",
        sys::KSP_DIVERGED_INDEFINITE_PC => "DIVERGED_INDEFINITE_PC",
        sys::KSP_DIVERGED_NANORINF => "DIVERGED_NANORINF",
        sys::KSP_DIVERGED_INDEFINITE_MAT => "DIVERGED_INDEFINITE_MAT",
        // Same value as KSP_DIVERGED_PCSETUP_FAILED (-11); PETSc prints this name.
        sys::KSP_DIVERGED_PC_FAILED => "DIVERGED_PC_FAILED",
        _ => "UNKNOWN",
    }
}

/// Name of a `PCFailedReason` value, as PETSc spells it in `PCFailedReasons` (no `PC_` prefix).
/// Values PETSc 3.18 does not define give `"UNKNOWN"`.
pub fn pc_failure_name(reason: sys::PCFailedReason) -> &'static str {
    match reason {
        sys::PC_SETUP_ERROR => "SETUP_ERROR",
        sys::PC_NOERROR => "FACTOR_NOERROR",
        sys::PC_FACTOR_STRUCT_ZEROPIVOT => "FACTOR_STRUCT_ZEROPIVOT",
        sys::PC_FACTOR_NUMERIC_ZEROPIVOT => "FACTOR_NUMERIC_ZEROPIVOT",
        sys::PC_FACTOR_OUTMEMORY => "FACTOR_OUTMEMORY",
        sys::PC_FACTOR_OTHER => "FACTOR_OTHER",
        sys::PC_INCONSISTENT_RHS => "PC_INCONSISTENT_RHS",
        sys::PC_SUBPC_ERROR => "SUBPC_ERROR",
        _ => "UNKNOWN",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::petsc::testing::with_petsc;

    /// Every KSP reason of PETSc 3.18 (petscksp.h), in the order of the enum.
    const KSP_REASONS: [sys::KSPConvergedReason; 20] = [
        sys::KSP_CONVERGED_RTOL_NORMAL,
        sys::KSP_CONVERGED_ATOL_NORMAL,
        sys::KSP_CONVERGED_RTOL,
        sys::KSP_CONVERGED_ATOL,
        sys::KSP_CONVERGED_ITS,
        sys::KSP_CONVERGED_CG_NEG_CURVE,
        sys::KSP_CONVERGED_CG_CONSTRAINED,
        sys::KSP_CONVERGED_STEP_LENGTH,
        sys::KSP_CONVERGED_HAPPY_BREAKDOWN,
        sys::KSP_DIVERGED_NULL,
        sys::KSP_DIVERGED_ITS,
        sys::KSP_DIVERGED_DTOL,
        sys::KSP_DIVERGED_BREAKDOWN,
        sys::KSP_DIVERGED_BREAKDOWN_BICG,
        sys::KSP_DIVERGED_NONSYMMETRIC,
        sys::KSP_DIVERGED_INDEFINITE_PC,
        sys::KSP_DIVERGED_NANORINF,
        sys::KSP_DIVERGED_INDEFINITE_MAT,
        sys::KSP_DIVERGED_PC_FAILED,
        sys::KSP_CONVERGED_ITERATING,
    ];

    /// Reads entry `i` of one of PETSc's shifted string tables (`KSPConvergedReasons`, ...).
    ///
    /// # Safety
    /// `table` must be a PETSc table valid at index `i`.
    unsafe fn table_entry(table: *const *const c_char, i: i32) -> String {
        let p = unsafe { *table.offset(i as isize) };
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }

    #[test]
    fn ksp_reason_table_matches_petsc_strings() {
        // Source of truth: PETSc's own `KSPConvergedReasons` array (src/ksp/ksp/interface/dlregisksp.c).
        with_petsc(|_| {
            for r in KSP_REASONS {
                // SAFETY: PETSc defines an entry for every enum value listed above.
                let petsc = unsafe { table_entry(sys::KSPConvergedReasons, r) };
                assert_eq!(ksp_reason_name(r), petsc, "reason {r}");
            }
        });
        assert_eq!(ksp_reason_name(-11), "DIVERGED_PC_FAILED");
        assert_eq!(ksp_reason_name(-3), "DIVERGED_ITS");
        assert_eq!(ksp_reason_name(2), "CONVERGED_RTOL");
        assert_eq!(ksp_reason_name(-99), "UNKNOWN");
    }

    #[test]
    fn pc_failure_table_matches_petsc_strings() {
        // Source of truth: PETSc's own `PCFailedReasons` array (src/ksp/pc/interface/pcset.c).
        with_petsc(|_| {
            for r in -1..=6 {
                // SAFETY: PCFailedReasons has entries for -1..=6 in PETSc 3.18.
                let petsc = unsafe { table_entry(sys::PCFailedReasons, r) };
                assert_eq!(pc_failure_name(r), petsc, "reason {r}");
            }
        });
        assert_eq!(pc_failure_name(2), "FACTOR_NUMERIC_ZEROPIVOT");
        assert_eq!(pc_failure_name(42), "UNKNOWN");
    }

    #[test]
    fn error_message_names_call_and_petsc_text() {
        let e = check(sys::PETSC_ERR_ARG_OUTOFRANGE as i32, "VecSetValues").unwrap_err();
        assert_eq!(e.code, 63);
        assert_eq!(e.call, "VecSetValues");
        // PETSc's generic text for code 63 (src/sys/error/err.c): "Argument out of range".
        assert!(e.message.contains("out of range"), "{e}");
        assert!(check(0, "VecSetValues").is_ok());
    }

    #[test]
    fn diverged_message_carries_diagnosis() {
        let e = SolverError::Diverged {
            reason: "DIVERGED_PC_FAILED",
            iterations: 0,
            residual_norm: 0.0,
            pc_failure: Some("FACTOR_NUMERIC_ZEROPIVOT"),
            zero_pivot_row: Some(3),
        };
        let s = e.to_string();
        assert!(s.contains("DIVERGED_PC_FAILED") && s.contains("FACTOR_NUMERIC_ZEROPIVOT at row 3"), "{s}");
    }
}
