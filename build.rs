//! Build script: generates the raw PETSc/SLEPc binding (`src/petsc/sys.rs` includes it).
//!
//! * Include paths come from pkg-config: `ompi-c` FIRST (PETSc's `petsc.pc` carries no MPI include
//!   path, and a fake sequential `mpi.h` lives in `/usr/include/mumps_seq`, which must never be the
//!   one found), then `petsc` and `slepc`.
//! * MPI types are not generated: they are blocklisted and taken from rsmpi (`mpi::ffi`), so a
//!   communicator from `mpi::raw::AsRaw::as_raw()` passes straight into PETSc.
//! * Links `petsc_real` (pkg-config `petsc`) and `slepc_real` (pkg-config `slepc`).

use std::env;
use std::path::PathBuf;

/// Header bindgen reads.
const WRAPPER: &str = "src/petsc/wrapper.h";

/// Name prefixes of the PETSc/SLEPc functions, types and variables the crate may use.
const PREFIXES: &str = "(Petsc|PETSC|Slepc|SLEPC|Vec|VEC|Mat|MAT|KSP|PC|EPS|ST|InsertMode|ScatterMode|NormType)";

/// Include path that must not be searched: it holds a fake, sequential `mpi.h`.
const FAKE_MPI_INCLUDE: &str = "mumps_seq";

fn main() {
    println!("cargo:rerun-if-changed={WRAPPER}");
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");

    // Order matters: the real OpenMPI headers are searched before anything PETSc's flags add.
    let mut include_dirs: Vec<PathBuf> = Vec::new();
    for (name, link) in [("ompi-c", false), ("petsc", true), ("slepc", true)] {
        let lib = pkg_config::Config::new()
            .cargo_metadata(link)
            .probe(name)
            .unwrap_or_else(|e| panic!("pkg-config could not find `{name}`: {e}"));
        for dir in lib.include_paths {
            let is_fake_mpi = dir.to_string_lossy().contains(FAKE_MPI_INCLUDE);
            if !is_fake_mpi && !include_dirs.contains(&dir) {
                include_dirs.push(dir);
            }
        }
    }

    let builder = bindgen::Builder::default()
        .header(WRAPPER)
        .clang_args(include_dirs.iter().map(|d| format!("-I{}", d.display())))
        .allowlist_function(format!("{PREFIXES}.*"))
        .allowlist_type(format!("{PREFIXES}.*"))
        .allowlist_var(format!("{PREFIXES}.*"))
        .blocklist_type("MPI_.*|ompi_.*")
        .blocklist_item("MPI_.*|ompi_.*")
        // C enumerators share one namespace, so the bare PETSc names (INSERT_VALUES, ...) are unique.
        .prepend_enum_name(false)
        .layout_tests(false)
        .generate_comments(false)
        .merge_extern_blocks(true)
        .raw_line("use mpi::ffi::*;")
        .parse_callbacks(Box::new(bindgen::CargoCallbacks::new()));
    let bindings = builder.generate().unwrap_or_else(|e| panic!("bindgen failed on {WRAPPER}: {e}"));

    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR")).join("petsc_bindings.rs");
    bindings.write_to_file(&out).unwrap_or_else(|e| panic!("cannot write {}: {e}", out.display()));
}
