#!/usr/bin/env bash
# The lab decides the unilateral split: the calibrated DEM wall's cyclic tests against the
# identified law with each split, at a material point on the same paths.
#
#   scripts/compare_splits.sh            # about a minute on 2 cores after the build
#
# Runs jobs/lab-cyclic-tension-compression.toml and jobs/lab-cyclic-shear.toml (DEM, 4 samples
# each), then material-point jobs (plane stress, h = 1.2 m, the wall's height as in the
# identification) of materials/rubble-identified.toml (split "trace", the paper's) and
# materials/rubble-identified-spectral.toml (split "spectral") along the same protocols:
# uniaxial strain cycles +-a_k, a_k = 0.5, 1, 2, 4e-4, then back to 0; and, under 1 MPa vertical
# compression held, shear strain cycles +-u_k/1.2 m, u_k = 0.5, 1, 2 mm, then back to 0.
# Writes results/compare-splits/: splits.md and splits.csv (the measures of scripts/compare_splits.py:
# stiffness at closure, residual strain, work per shear cycle, peaks, whole-path error) and
# splits.png (the loops). Needs matplotlib for the picture.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
cargo build --release --quiet
bin=target/release/masonry-hpc
out=results/compare-splits
mkdir -p "$out"
mpi=(mpirun -n 2)
for t in tension-compression shear; do
  OMPI_MCA_mpi_yield_when_idle=1 "${mpi[@]}" "$bin" jobs/lab-cyclic-$t.toml > "$out/lab-$t.log"
done
rm -rf "$out/lab-tc" "$out/lab-shear"
cp -r results/lab-cyclic-tension-compression "$out/lab-tc"
cp -r results/lab-cyclic-shear "$out/lab-shear"

# The [law] table of a material file, as the material-point job's [material].
law_table() { sed -n '/^\[law\]/,/^\[/p' "$1" | sed '1d;/^\[/d;/^$/d'; }
paths_tc='type = "uniaxial"
targets = [0.5e-4, -0.5e-4, 1.0e-4, -1.0e-4, 2.0e-4, -2.0e-4, 4.0e-4, -4.0e-4, 0.0]
steps_per_segment = 40'
paths_shear="type = \"shear_under_compression\"
vertical_stress = 1.0e6
targets = [$(python3 -c 'print(", ".join(repr(s * a / 1.2) for a in (0.5e-3, 1.0e-3, 2.0e-3) for s in (1, -1)) + ", 0.0")')]
steps_per_segment = 40"
for split in trace spectral; do
  file=materials/rubble-identified.toml
  [ "$split" = spectral ] && file=materials/rubble-identified-spectral.toml
  for tag in tc shear; do
    path="$paths_tc"
    [ "$tag" = shear ] && path="$paths_shear"
    job="$out/law-$split-$tag.toml"
    {
      printf 'title = "%s law, %s path"\n[analysis]\ntype = "material_point"\nkinematics = "plane_stress"\nelement_size = 1.2\n[material]\n' "$split" "$tag"
      law_table "$file"
      printf '[path]\n%s\n[output]\ndir = "law-%s-%s"\nexisting = "overwrite"\n' "$path" "$split" "$tag"
    } > "$job"
    # A law that cannot follow the path stops with its curve kept: a finding, not a failure here.
    "$bin" "$job" > "$out/law-$split-$tag.log" 2>&1 \
      || echo "compare_splits: the $split law stopped on the $tag path: $(tail -n 1 "$out/law-$split-$tag.log")"
  done
done
py=$(matplotlib_python)   # the picture needs matplotlib; without it, the table alone
"${py:-python3}" scripts/compare_splits.py "$out"
