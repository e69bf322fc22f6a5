//! The PETSc options database: queries and insertions.
//!
//! Precedence (highest first): the command line given to [`super::Petsc::initialize`] and
//! `PETSC_OPTIONS` (both read by PETSc at initialization, and [`Options::insert_command_line`]),
//! then job-file defaults ([`super::Petsc::set_default_options`], which never overwrite), then the
//! values the code sets programmatically before `*SetFromOptions` (which the database overrides).

use std::ffi::{c_char, CStr, CString};
use std::marker::PhantomData;

use super::error::{petsc_call, PetscError};
use super::runtime::Petsc;
use super::sys;

/// Longest option value read back, in bytes (PETSc's own limit for most strings is 256).
const MAX_VALUE_LEN: usize = 4096;

/// Handle on PETSc's global options database, valid while the [`Petsc`] guard lives.
/// Not collective: each rank has its own copy of the database.
#[derive(Clone, Copy)]
pub struct Options<'a> {
    _petsc: PhantomData<&'a Petsc>,
}

/// `s` as a C string, or an error naming `call` if it holds a NUL byte.
pub(crate) fn c_string(s: &str, call: &'static str) -> Result<CString, PetscError> {
    CString::new(s)
        .map_err(|_| PetscError::usage(sys::PETSC_ERR_ARG_WRONG, call, format!("string {s:?} contains a NUL byte")))
}

impl<'a> Options<'a> {
    /// The global database (`PetscOptions` NULL) of a running PETSc.
    pub(crate) fn global(_petsc: &'a Petsc) -> Self {
        Options { _petsc: PhantomData }
    }

    /// True if option `name` (with its leading `-`, e.g. `"-ksp_type"`) is in the database.
    pub fn has(&self, name: &str) -> Result<bool, PetscError> {
        let c = c_string(name, "PetscOptionsHasName")?;
        let mut set = sys::PETSC_FALSE;
        petsc_call!(PetscOptionsHasName(std::ptr::null_mut(), std::ptr::null(), c.as_ptr(), &mut set))?;
        Ok(set == sys::PETSC_TRUE)
    }

    /// Value of option `name`: `Some("")` for a flag without value, `None` when absent.
    pub fn value(&self, name: &str) -> Result<Option<String>, PetscError> {
        let c = c_string(name, "PetscOptionsGetString")?;
        let mut buf = vec![0 as c_char; MAX_VALUE_LEN];
        let mut set = sys::PETSC_FALSE;
        // SAFETY: `buf` holds MAX_VALUE_LEN bytes and PETSc writes at most that many, NUL included.
        petsc_call!(PetscOptionsGetString(
            std::ptr::null_mut(),
            std::ptr::null(),
            c.as_ptr(),
            buf.as_mut_ptr(),
            MAX_VALUE_LEN,
            &mut set
        ))?;
        if set != sys::PETSC_TRUE {
            return Ok(None);
        }
        // SAFETY: PETSc NUL-terminates the copy (buf was zeroed, so even an empty value is one).
        let s = unsafe { CStr::from_ptr(buf.as_ptr()) };
        Ok(Some(s.to_string_lossy().into_owned()))
    }

    /// Sets option `name` to `value` (`None`: a flag), overwriting any previous value.
    pub fn set(&self, name: &str, value: Option<&str>) -> Result<(), PetscError> {
        let c_name = c_string(name, "PetscOptionsSetValue")?;
        let c_value = value.map(|v| c_string(v, "PetscOptionsSetValue")).transpose()?;
        let value_ptr = c_value.as_ref().map_or(std::ptr::null(), |v| v.as_ptr());
        petsc_call!(PetscOptionsSetValue(std::ptr::null_mut(), c_name.as_ptr(), value_ptr))
    }

    /// Removes option `name` from the database (no error if absent).
    pub fn clear(&self, name: &str) -> Result<(), PetscError> {
        let c = c_string(name, "PetscOptionsClearValue")?;
        petsc_call!(PetscOptionsClearValue(std::ptr::null_mut(), c.as_ptr()))
    }

    /// Inserts options written as on a command line (`"-ksp_type cg -ksp_monitor"`), with the
    /// same precedence as the command line: they overwrite earlier values.
    pub fn insert_command_line(&self, line: &str) -> Result<(), PetscError> {
        let c = c_string(line, "PetscOptionsInsertString")?;
        petsc_call!(PetscOptionsInsertString(std::ptr::null_mut(), c.as_ptr()))
    }
}

#[cfg(test)]
mod tests {
    use crate::petsc::testing::with_petsc_env;

    #[test]
    fn set_query_clear_round_trip() {
        with_petsc_env(|env| {
            let o = env.petsc.options();
            o.set("-optstest_value", Some("1e-8")).unwrap();
            o.set("-optstest_flag", None).unwrap();
            assert!(o.has("-optstest_value").unwrap());
            assert_eq!(o.value("-optstest_value").unwrap().as_deref(), Some("1e-8"));
            assert_eq!(o.value("-optstest_flag").unwrap().as_deref(), Some(""));
            o.clear("-optstest_value").unwrap();
            o.clear("-optstest_flag").unwrap();
            assert_eq!(o.value("-optstest_value").unwrap(), None);
            assert!(o.set("-bad\0name", None).is_err(), "NUL byte is an error, not a panic");
        });
    }
}
