//! Build script: generates the raw PETSc/SLEPc binding (`src/petsc/sys.rs` includes it) and the
//! raw CHOLMOD binding of the DEM solver's updatable factor (`src/dem/solver/cholmod_sys.rs`).
//!
//! * Include paths come from pkg-config: `ompi-c` FIRST (PETSc's `petsc.pc` carries no MPI include
//!   path, and a fake sequential `mpi.h` lives in `/usr/include/mumps_seq`, which must never be the
//!   one found), then `petsc` and `slepc`.
//! * MPI types are not generated: they are blocklisted and taken from rsmpi (`mpi::ffi`), so a
//!   communicator from `mpi::raw::AsRaw::as_raw()` passes straight into PETSc.
//! * Links `petsc_real` (pkg-config `petsc`) and `slepc_real` (pkg-config `slepc`).
//! * CHOLMOD: `cholmod.h` from pkg-config `cholmod`, else `SUITESPARSE_DIR`, else
//!   `/usr/include/suitesparse`; only the functions and constants the solver uses are generated
//!   (allowlists: bindgen's time grows with what it emits).

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

    let out_dir = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let out = out_dir.join("petsc_bindings.rs");
    bindings.write_to_file(&out).unwrap_or_else(|e| panic!("cannot write {}: {e}", out.display()));
    cholmod_bindings(&out_dir);
}

/// Header bindgen reads for the CHOLMOD binding (`src/dem/solver/cholmod_sys.rs` includes it).
const CHOLMOD_WRAPPER: &str = "src/dem/solver/cholmod_wrapper.h";

/// The CHOLMOD functions the DEM solver calls; bindgen generates these and the types they reach
/// (`cholmod_common`, `cholmod_sparse`, `cholmod_dense`, `cholmod_factor`), nothing else.
const CHOLMOD_FUNCTIONS: &str =
    "cholmod_(start|finish|allocate_sparse|free_sparse|allocate_dense|free_dense|analyze|factorize|free_factor|solve|updown|rcond)";

/// The CHOLMOD constants it uses.
const CHOLMOD_CONSTANTS: &str = "CHOLMOD_(SIMPLICIAL|REAL|A|Lt|OK|NOT_POSDEF)";

/// Default include directory of SuiteSparse (Debian's `libsuitesparse-dev`).
const SUITESPARSE_INCLUDE: &str = "/usr/include/suitesparse";

/// Generates the CHOLMOD binding: headers from pkg-config `cholmod` (which also emits the link
/// flags), else from `SUITESPARSE_DIR` (`include/suitesparse` or `include`, libraries in `lib`),
/// else from [`SUITESPARSE_INCLUDE`] with the system's library path.
fn cholmod_bindings(out_dir: &std::path::Path) {
    println!("cargo:rerun-if-changed={CHOLMOD_WRAPPER}");
    println!("cargo:rerun-if-env-changed=SUITESPARSE_DIR");
    let include_dirs: Vec<PathBuf> = match pkg_config::Config::new().probe("cholmod") {
        Ok(lib) => lib.include_paths,
        Err(_) => {
            println!("cargo:rustc-link-lib=cholmod");
            match env::var_os("SUITESPARSE_DIR").map(PathBuf::from) {
                Some(dir) => {
                    println!("cargo:rustc-link-search=native={}", dir.join("lib").display());
                    vec![dir.join("include").join("suitesparse"), dir.join("include")]
                }
                None => vec![PathBuf::from(SUITESPARSE_INCLUDE)],
            }
        }
    };
    let bindings = bindgen::Builder::default()
        .header(CHOLMOD_WRAPPER)
        .clang_args(include_dirs.iter().map(|d| format!("-I{}", d.display())))
        .allowlist_function(CHOLMOD_FUNCTIONS)
        .allowlist_var(CHOLMOD_CONSTANTS)
        .layout_tests(false)
        .generate_comments(false)
        .merge_extern_blocks(true)
        .parse_callbacks(Box::new(bindgen::CargoCallbacks::new()))
        .generate()
        .unwrap_or_else(|e| panic!("bindgen failed on {CHOLMOD_WRAPPER} (headers searched in {include_dirs:?}): {e}"));
    let out = out_dir.join("cholmod_bindings.rs");
    bindings.write_to_file(&out).unwrap_or_else(|e| panic!("cannot write {}: {e}", out.display()));
}
