//! [`Vector`]: a distributed PETSc `Vec`, optionally with ghost entries.
//!
//! Layout: rank `r` owns the contiguous global range `ownership_range()`. A ghosted vector also
//! stores copies of some entries owned by other ranks (the ghosts); its *local form* is
//! `[owned entries in global order | ghosts in the order given at creation]`, refreshed from the
//! owners by [`Vector::ghost_update`].

use std::ffi::c_void;

use mpi::collective::SystemOperation;
use mpi::traits::CommunicatorCollectives;

use super::error::{petsc_call, PetscError};
use super::runtime::{ensure_running, is_running};
use super::{sys, to_petsc_int, to_usize, type_name, PetscComm};

/// A PETSc vector of `f64`; destroyed (`VecDestroy`) when dropped.
///
/// Indices are checked against the global size before PETSc sees them: the Debian PETSc is built
/// without debugging, and an out-of-range index would silently corrupt memory.
pub struct Vector {
    raw: sys::Vec,
    /// Global size, cached for the index checks.
    n_global: sys::PetscInt,
}

/// Checks that index and value slices pair up.
fn check_pairs(call: &'static str, idx: usize, vals: usize) -> Result<sys::PetscInt, PetscError> {
    if idx != vals {
        return Err(PetscError::usage(sys::PETSC_ERR_ARG_SIZ, call, format!("{idx} indices but {vals} values")));
    }
    to_petsc_int(idx, call, "number of entries")
}

/// Checks that every non-negative index is below `n` (negative ones are ignored by the callers).
pub(crate) fn check_indices(call: &'static str, what: &str, idx: &[i32], n: sys::PetscInt) -> Result<(), PetscError> {
    match idx.iter().find(|&&i| i >= n) {
        None => Ok(()),
        Some(bad) => Err(PetscError::usage(
            sys::PETSC_ERR_ARG_OUTOFRANGE,
            call,
            format!("{what} index {bad} out of range: global size is {n}"),
        )),
    }
}

impl Vector {
    /// Takes ownership of a live raw `Vec` (destroyed on error too), caches its size, and sets
    /// `VEC_IGNORE_NEGATIVE_INDICES` (PETSc's default would write before the array).
    pub(crate) fn adopt(raw: sys::Vec) -> Result<Self, PetscError> {
        let mut v = Vector { raw, n_global: 0 };
        v.configure()?;
        Ok(v)
    }

    /// Sets `VEC_IGNORE_NEGATIVE_INDICES` and caches the global size of a set-up vector.
    fn configure(&mut self) -> Result<(), PetscError> {
        petsc_call!(VecSetOption(self.raw, sys::VEC_IGNORE_NEGATIVE_INDICES, sys::PETSC_TRUE))?;
        petsc_call!(VecGetSize(self.raw, &mut self.n_global))
    }

    /// A vector with `n_local` entries on this rank (`n_global`, if given, must equal the sum
    /// over ranks; PETSc checks it). Entries start at zero. Collective on `comm`.
    pub fn new_mpi(comm: &impl PetscComm, n_local: usize, n_global: Option<usize>) -> Result<Vector, PetscError> {
        const CALL: &str = "Vector::new_mpi";
        ensure_running(CALL)?;
        let n = to_petsc_int(n_local, CALL, "n_local")?;
        let mut raw: sys::Vec = std::ptr::null_mut();
        petsc_call!(VecCreate(comm.as_raw(), &mut raw))?;
        let mut v = Vector { raw, n_global: 0 }; // owns `raw` from here: destroyed on error
                                                 // The global size is always summed by PETSc (a collective check that works without
                                                 // PETSc's debug mode), then compared with the expected one.
        petsc_call!(VecSetSizes(v.raw, n, sys::PETSC_DETERMINE))?;
        petsc_call!(VecSetType(v.raw, type_name(sys::VECSTANDARD)))?;
        v.configure()?;
        if let Some(expected) = n_global {
            if to_usize(v.n_global) != expected {
                return Err(PetscError::usage(
                    sys::PETSC_ERR_ARG_SIZ,
                    CALL,
                    format!("local sizes sum to {} but the global size should be {expected}", v.n_global),
                ));
            }
        }
        v.set_all(0.0)?;
        Ok(v)
    }

    /// A ghosted vector: `n_local` owned entries plus copies of the entries with global indices
    /// `ghosts` (owned by other ranks). Entries start at zero. Collective on `comm`.
    pub fn new_ghosted(comm: &impl PetscComm, n_local: usize, ghosts: &[i32]) -> Result<Vector, PetscError> {
        const CALL: &str = "Vector::new_ghosted";
        ensure_running(CALL)?;
        let n = to_petsc_int(n_local, CALL, "n_local")?;
        let n_ghost = to_petsc_int(ghosts.len(), CALL, "number of ghosts")?;
        // Ghost indices must be valid global indices: sum the local sizes first (collective).
        let mut big_n: i64 = 0;
        comm.all_reduce_into(&i64::from(n), &mut big_n, SystemOperation::sum());
        let big_n = to_petsc_int(usize::try_from(big_n).unwrap_or(usize::MAX), CALL, "global size")?;
        if let Some(bad) = ghosts.iter().find(|&&g| g < 0 || g >= big_n) {
            return Err(PetscError::usage(
                sys::PETSC_ERR_ARG_OUTOFRANGE,
                CALL,
                format!("ghost index {bad} out of range: global size is {big_n}"),
            ));
        }
        let mut raw: sys::Vec = std::ptr::null_mut();
        petsc_call!(VecCreateGhost(comm.as_raw(), n, big_n, n_ghost, ghosts.as_ptr(), &mut raw))?;
        let mut v = Vector::adopt(raw)?;
        v.set_all(0.0)?;
        Ok(v)
    }

    /// The raw PETSc handle (still owned by `self`).
    pub fn as_raw(&self) -> sys::Vec {
        self.raw
    }

    /// Sets entries `vals[k]` at global indices `idx[k]` (`INSERT_VALUES`); negative indices are
    /// ignored. Entries of other ranks are allowed; [`assemble`](Self::assemble) sends them.
    /// Not collective.
    pub fn set_values(&mut self, idx: &[i32], vals: &[f64]) -> Result<(), PetscError> {
        let n = check_pairs("VecSetValues", idx.len(), vals.len())?;
        check_indices("VecSetValues", "vector", idx, self.n_global)?;
        petsc_call!(VecSetValues(self.raw, n, idx.as_ptr(), vals.as_ptr(), sys::INSERT_VALUES))
    }

    /// Adds `vals[k]` to the entries at global indices `idx[k]` (`ADD_VALUES`); negative indices
    /// are ignored. Not collective; call [`assemble`](Self::assemble) afterwards.
    pub fn add_values(&mut self, idx: &[i32], vals: &[f64]) -> Result<(), PetscError> {
        let n = check_pairs("VecSetValues", idx.len(), vals.len())?;
        check_indices("VecSetValues", "vector", idx, self.n_global)?;
        petsc_call!(VecSetValues(self.raw, n, idx.as_ptr(), vals.as_ptr(), sys::ADD_VALUES))
    }

    /// Finishes `set_values`/`add_values` (`VecAssemblyBegin/End`). Collective.
    pub fn assemble(&mut self) -> Result<(), PetscError> {
        petsc_call!(VecAssemblyBegin(self.raw))?;
        petsc_call!(VecAssemblyEnd(self.raw))
    }

    /// Copies the owners' values into the ghost entries (`INSERT_VALUES`, `SCATTER_FORWARD`).
    /// Collective; for a vector created without ghosts PETSc does nothing beyond an assembly.
    pub fn ghost_update(&mut self) -> Result<(), PetscError> {
        petsc_call!(VecGhostUpdateBegin(self.raw, sys::INSERT_VALUES, sys::SCATTER_FORWARD))?;
        petsc_call!(VecGhostUpdateEnd(self.raw, sys::INSERT_VALUES, sys::SCATTER_FORWARD))
    }

    /// Adds the ghost entries into their owners' entries (`ADD_VALUES`, `SCATTER_REVERSE`), e.g.
    /// after assembling element contributions into the local form. Collective.
    pub fn ghost_accumulate(&mut self) -> Result<(), PetscError> {
        petsc_call!(VecGhostUpdateBegin(self.raw, sys::ADD_VALUES, sys::SCATTER_REVERSE))?;
        petsc_call!(VecGhostUpdateEnd(self.raw, sys::ADD_VALUES, sys::SCATTER_REVERSE))
    }

    /// Calls `f` with the local form: owned entries then ghosts (see the module docs); for a
    /// vector without ghosts, just the owned entries. Call [`ghost_update`](Self::ghost_update)
    /// first for current ghost values. Not collective.
    pub fn with_local_form<R>(&self, f: impl FnOnce(&[f64]) -> R) -> Result<R, PetscError> {
        let mut local: sys::Vec = std::ptr::null_mut();
        petsc_call!(VecGhostGetLocalForm(self.raw, &mut local))?;
        if local.is_null() {
            // Not a ghosted vector: the local form is the owned part.
            return self.with_owned_values(f);
        }
        let result = read_array(local, f);
        let restored = petsc_call!(VecGhostRestoreLocalForm(self.raw, &mut local));
        let r = result?;
        restored?;
        Ok(r)
    }

    /// Calls `f` with this rank's owned entries (global indices `ownership_range()`).
    pub fn with_owned_values<R>(&self, f: impl FnOnce(&[f64]) -> R) -> Result<R, PetscError> {
        read_array(self.raw, f)
    }

    /// Overwrites this rank's owned entries with `values` (length: the local size), without the
    /// assembly that [`set_values`](Self::set_values) needs. Not collective.
    pub fn copy_owned_from(&mut self, values: &[f64]) -> Result<(), PetscError> {
        let mut n: sys::PetscInt = 0;
        petsc_call!(VecGetLocalSize(self.raw, &mut n))?;
        check_pairs("VecGetArray", to_usize(n), values.len())?;
        let mut ptr: *mut f64 = std::ptr::null_mut();
        petsc_call!(VecGetArray(self.raw, &mut ptr))?;
        if !ptr.is_null() && !values.is_empty() {
            // SAFETY: PETSc guarantees `n` writable entries at `ptr` until VecRestoreArray, and
            // `values` has exactly `n` entries (checked above).
            unsafe { std::ptr::copy_nonoverlapping(values.as_ptr(), ptr, values.len()) };
        }
        petsc_call!(VecRestoreArray(self.raw, &mut ptr))
    }

    /// A copy of this rank's owned entries.
    pub fn owned_values(&self) -> Result<std::vec::Vec<f64>, PetscError> {
        self.with_owned_values(<[f64]>::to_vec)
    }

    /// Sets every entry (ghosts included) to `value`. Collective.
    pub fn set_all(&mut self, value: f64) -> Result<(), PetscError> {
        petsc_call!(VecSet(self.raw, value))
    }

    /// Multiplies every entry by `alpha`. Collective.
    pub fn scale(&mut self, alpha: f64) -> Result<(), PetscError> {
        petsc_call!(VecScale(self.raw, alpha))
    }

    /// Euclidean norm ‖v‖₂ = (Σᵢ vᵢ²)^½ over all ranks (ghosts not counted). Collective.
    pub fn norm2(&self) -> Result<f64, PetscError> {
        let mut norm = 0.0;
        petsc_call!(VecNorm(self.raw, sys::NORM_2, &mut norm))?;
        Ok(norm)
    }

    /// Maximum norm ‖v‖∞ = maxᵢ |vᵢ| over all ranks. Collective.
    pub fn norm_inf(&self) -> Result<f64, PetscError> {
        let mut norm = 0.0;
        petsc_call!(VecNorm(self.raw, sys::NORM_INFINITY, &mut norm))?;
        Ok(norm)
    }

    /// Dot product Σᵢ selfᵢ·otherᵢ over all ranks. Collective; same layout required.
    pub fn dot(&self, other: &Vector) -> Result<f64, PetscError> {
        let mut d = 0.0;
        petsc_call!(VecDot(self.raw, other.raw, &mut d))?;
        Ok(d)
    }

    /// `self ← self + alpha·x`. Collective; same layout required.
    pub fn axpy(&mut self, alpha: f64, x: &Vector) -> Result<(), PetscError> {
        petsc_call!(VecAXPY(self.raw, alpha, x.raw))
    }

    /// `self ← src` (owned entries). Collective; same layout required.
    pub fn copy_from(&mut self, src: &Vector) -> Result<(), PetscError> {
        petsc_call!(VecCopy(src.raw, self.raw))
    }

    /// A new vector with the same layout (and ghosts); its values are NOT copied (PETSc leaves
    /// them unset: call [`set_all`](Self::set_all) or [`copy_from`](Self::copy_from)). Collective.
    pub fn duplicate(&self) -> Result<Vector, PetscError> {
        let mut raw: sys::Vec = std::ptr::null_mut();
        petsc_call!(VecDuplicate(self.raw, &mut raw))?;
        Vector::adopt(raw)
    }

    /// Global index range `[start, end)` owned by this rank.
    pub fn ownership_range(&self) -> Result<(usize, usize), PetscError> {
        let (mut lo, mut hi) = (0, 0);
        petsc_call!(VecGetOwnershipRange(self.raw, &mut lo, &mut hi))?;
        Ok((to_usize(lo), to_usize(hi)))
    }

    /// Number of entries over all ranks.
    pub fn len_global(&self) -> usize {
        to_usize(self.n_global)
    }

    /// Number of entries owned by this rank (ghosts excluded).
    pub fn len_local(&self) -> Result<usize, PetscError> {
        let mut n = 0;
        petsc_call!(VecGetLocalSize(self.raw, &mut n))?;
        Ok(to_usize(n))
    }
}

/// Calls `f` on the array of a (sequential or parallel) `v`, restoring the array afterwards.
fn read_array<R>(v: sys::Vec, f: impl FnOnce(&[f64]) -> R) -> Result<R, PetscError> {
    let mut n: sys::PetscInt = 0;
    petsc_call!(VecGetLocalSize(v, &mut n))?;
    let mut ptr: *const f64 = std::ptr::null();
    petsc_call!(VecGetArrayRead(v, &mut ptr))?;
    /// Restores the array even if `f` panics.
    struct Restore(sys::Vec, *const f64);
    impl Drop for Restore {
        fn drop(&mut self) {
            // SAFETY: the array was obtained from this Vec by VecGetArrayRead just before.
            let _ = unsafe { sys::VecRestoreArrayRead(self.0, &mut self.1) };
        }
    }
    let restore = Restore(v, ptr);
    let len = to_usize(n);
    let slice: &[f64] = if len == 0 || ptr.is_null() {
        &[]
    } else {
        // SAFETY: PETSc guarantees `len` readable entries at `ptr` until VecRestoreArrayRead,
        // which `restore` runs only after `f` returns; `f` cannot keep the borrow.
        unsafe { std::slice::from_raw_parts(ptr, len) }
    };
    let r = f(slice);
    drop(restore);
    Ok(r)
}

impl Drop for Vector {
    /// `VecDestroy` (collective). A vector outliving PETSc is leaked instead.
    fn drop(&mut self) {
        if !self.raw.is_null() && is_running() {
            // SAFETY: `raw` is a live Vec owned by this value.
            let _ = unsafe { sys::VecDestroy(&mut self.raw) };
        }
    }
}

impl std::fmt::Debug for Vector {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Vector").field("raw", &self.raw.cast::<c_void>()).finish()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::petsc::testing::with_petsc;

    #[test]
    fn values_norms_and_blas() {
        with_petsc(|comm| {
            let mut v = Vector::new_mpi(comm, 4, None).unwrap();
            assert_eq!(v.len_global(), 4);
            assert_eq!(v.ownership_range().unwrap(), (0, 4));
            v.set_values(&[0, 1, 2, 3, -1], &[3.0, 4.0, 0.0, 0.0, 99.0]).unwrap();
            v.assemble().unwrap();
            // ‖(3,4,0,0)‖₂ = 5 exactly (3-4-5 triangle).
            assert_eq!(v.norm2().unwrap(), 5.0);
            let mut w = v.duplicate().unwrap();
            w.set_all(1.0).unwrap();
            assert_eq!(v.dot(&w).unwrap(), 7.0);
            w.axpy(2.0, &v).unwrap(); // (7, 9, 1, 1)
            w.add_values(&[3, -5], &[1.0, 1.0]).unwrap();
            w.assemble().unwrap();
            assert_eq!(w.owned_values().unwrap(), vec![7.0, 9.0, 1.0, 2.0]);
            let mut c = w.duplicate().unwrap();
            c.copy_from(&v).unwrap();
            assert_eq!(c.owned_values().unwrap(), vec![3.0, 4.0, 0.0, 0.0]);
            assert!(v.set_values(&[0, 1], &[1.0]).is_err(), "length mismatch is an Err");
            let e = v.add_values(&[4], &[1.0]).unwrap_err();
            assert_eq!(e.code, sys::PETSC_ERR_ARG_OUTOFRANGE as i32, "{e}");
        });
    }

    #[test]
    fn ghosted_round_trip_on_one_rank() {
        with_petsc(|comm| {
            // On one rank a ghost can only name an owned entry; the local form still has the
            // layout [owned | ghosts] and the update copies the owner's value.
            let ghosts = [4, 0];
            let mut v = Vector::new_ghosted(comm, 5, &ghosts).unwrap();
            let idx: Vec<i32> = (0..5).collect();
            let vals: Vec<f64> = (0..5).map(|i| 10.0 * f64::from(i)).collect();
            v.set_values(&idx, &vals).unwrap();
            v.assemble().unwrap();
            v.ghost_update().unwrap();
            let local = v.with_local_form(<[f64]>::to_vec).unwrap();
            assert_eq!(local, vec![0.0, 10.0, 20.0, 30.0, 40.0, 40.0, 0.0]);
            assert_eq!(v.owned_values().unwrap(), vals);
            // A plain vector's local form is its owned part.
            let plain = Vector::new_mpi(comm, 2, Some(2)).unwrap();
            assert_eq!(plain.with_local_form(<[f64]>::len).unwrap(), 2);
        });
    }

    #[test]
    fn wrong_global_size_is_an_error() {
        with_petsc(|comm| {
            let e = Vector::new_mpi(comm, 3, Some(4)).unwrap_err();
            assert_eq!(e.code, sys::PETSC_ERR_ARG_SIZ as i32, "{e}");
            assert!(e.message.contains('3') && e.message.contains('4'), "{e}");
            let e = Vector::new_ghosted(comm, 3, &[3]).unwrap_err();
            assert_eq!(e.code, sys::PETSC_ERR_ARG_OUTOFRANGE as i32, "{e}");
        });
    }
}
