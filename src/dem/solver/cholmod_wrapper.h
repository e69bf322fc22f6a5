/* The CHOLMOD API of the DEM solver's updatable factor (src/dem/solver/cholmod.rs): build.rs runs
 * bindgen on this header, restricted to the functions, types and constants that file uses. */
#include <cholmod.h>
