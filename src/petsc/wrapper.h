/* The C API the crate binds: PETSc's linear solvers (KSP, which pulls in PC, Mat, Vec and the
   system layer) and SLEPc's eigensolvers (EPS, which pulls in ST). Read by build.rs / bindgen. */
#include <petscksp.h>
#include <slepceps.h>
