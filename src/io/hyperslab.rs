//! Collective hyperslab writes through MPI-IO.
//!
//! `hdf5-metno` writes with the default transfer property list, which means *independent* MPI-IO.
//! Here every rank writes its own contiguous block of rows of a dataset in one *collective*
//! `H5Dwrite` (`H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE)`), which lets MPI-IO aggregate the
//! pieces into few large file writes. All ranks must call [`write_rows`] for the same dataset in
//! the same order; a rank with no rows selects nothing but still takes part.

use hdf5::{Dataset, H5Type};
use hdf5_sys::h5::{herr_t, hsize_t};
use hdf5_sys::h5d::H5Dwrite;
use hdf5_sys::h5i::hid_t;
use hdf5_sys::h5p::{H5FD_mpio_xfer_t, H5Pclose, H5Pcreate, H5Pset_dxpl_mpio};
use hdf5_sys::h5s::{H5S_seloper_t, H5Sclose, H5Scopy, H5Screate_simple, H5Sselect_hyperslab, H5Sselect_none};

/// Turns a negative HDF5 return value into the library's current error stack.
fn check<T: Copy + Into<i64>>(ret: T) -> hdf5::Result<T> {
    if ret.into() < 0 {
        Err(hdf5::Error::query().unwrap_or_else(|e| e))
    } else {
        Ok(ret)
    }
}

/// An HDF5 id closed by `close` on drop.
struct Owned(hid_t, unsafe extern "C" fn(hid_t) -> herr_t);

impl Drop for Owned {
    fn drop(&mut self) {
        // SAFETY: the id was returned by a successful create/copy call and is closed once.
        unsafe {
            (self.1)(self.0);
        }
    }
}

/// A dataset transfer property list asking for collective MPI-IO.
pub(crate) struct CollectiveXfer(Owned);

impl CollectiveXfer {
    /// Creates the property list.
    pub(crate) fn new() -> hdf5::Result<Self> {
        hdf5::sync::sync(|| {
            // SAFETY: plain HDF5 C calls on ids we own; the library is initialized by `sync`.
            let id = check(unsafe { H5Pcreate(*hdf5::globals::H5P_DATASET_XFER) })?;
            let owned = Owned(id, H5Pclose);
            check(unsafe { H5Pset_dxpl_mpio(id, H5FD_mpio_xfer_t::H5FD_MPIO_COLLECTIVE) })?;
            Ok(Self(owned))
        })
    }
}

/// Collectively writes `data` as rows `[first_row, first_row + data.len() / row_len)` of `ds`,
/// whose shape is `(rows)` when `row_len == 1` and the dataset is 1-D, else `(rows, row_len)`.
pub(crate) fn write_rows<T: H5Type>(
    ds: &Dataset,
    xfer: &CollectiveXfer,
    first_row: usize,
    row_len: usize,
    data: &[T],
) -> hdf5::Result<()> {
    let shape = ds.shape();
    let ndim = shape.len();
    if ndim == 0 || ndim > 2 || (ndim == 2 && shape[1] != row_len) || (ndim == 1 && row_len != 1) {
        return Err(format!("dataset shape {shape:?} does not hold rows of {row_len}").into());
    }
    if row_len == 0 || data.len() % row_len != 0 {
        return Err(format!("{} values are not whole rows of {row_len}", data.len()).into());
    }
    let n_rows = data.len() / row_len;
    if first_row + n_rows > shape[0] {
        return Err(
            format!("rows [{first_row}, {}) outside the dataset's {} rows", first_row + n_rows, shape[0]).into()
        );
    }
    let mem_type = hdf5::Datatype::from_type::<T>()?;
    let start: Vec<hsize_t> = [first_row as hsize_t, 0][..ndim].to_vec();
    let count: Vec<hsize_t> = [n_rows as hsize_t, row_len as hsize_t][..ndim].to_vec();
    hdf5::sync::sync(|| {
        // SAFETY: the spaces are created and closed here; `data` outlives the call and holds
        // exactly the number of elements selected in the memory space (n_rows * row_len).
        unsafe {
            let file_space = Owned(check(hdf5_sys::h5d::H5Dget_space(ds.id()))?, H5Sclose);
            let mem_space = if n_rows == 0 {
                check(H5Sselect_none(file_space.0))?;
                let m = Owned(check(H5Scopy(file_space.0))?, H5Sclose);
                check(H5Sselect_none(m.0))?;
                m
            } else {
                check(H5Sselect_hyperslab(
                    file_space.0,
                    H5S_seloper_t::H5S_SELECT_SET,
                    start.as_ptr(),
                    std::ptr::null(),
                    count.as_ptr(),
                    std::ptr::null(),
                ))?;
                let n = [data.len() as hsize_t];
                Owned(check(H5Screate_simple(1, n.as_ptr(), std::ptr::null()))?, H5Sclose)
            };
            check(H5Dwrite(ds.id(), mem_type.id(), mem_space.0, file_space.0, (xfer.0).0, data.as_ptr().cast()))?;
        }
        Ok(())
    })
}
