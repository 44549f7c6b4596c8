#!/bin/bash
# Packs the built programs for a machine without Debian's packages (the scale measurements of
# docs/performance.md on a 16-core machine): build/app/fibrane (serial), build/bench/bench_newton_breakdown,
# build/bench/bench_linear_solver, build/bench/bench_dense_blas, build/bench/bench_fresh_memory,
# build/bench/bench_assembly_threads and, where it is built,
# build-petsc/app/fibrane (PETSc, as fibrane-mpi), every shared library
# they and Open MPI's launcher load except glibc's, OpenBLAS's OpenMP build in lib-openblas-openmp/ where
# libopenblas0-openmp is installed (chosen per run by LD_LIBRARY_PATH), and Open MPI's run-time files
# (components, help texts, settings), which bench/remote/scale.sh puts back at the paths Debian's Open MPI
# looks for them; xz and its library beside it, for a machine without xz. With STATE=DIR, the checkpoint
# of an unfinished run of examples/bending.yaml in DIR and its history.csv (for scale.sh's part 9) go in as
# state/.
#
#   [STATE=DIR] bash bench/remote/make-bundle.sh [OUTPUT = devbundle/bundle.tar.xz]
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-devbundle/bundle.tar.xz}
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/bundle/bin" "$stage/bundle/lib" "$stage/bundle/system"

cp build/app/fibrane "$stage/bundle/bin/fibrane"
cp build/bench/bench_newton_breakdown build/bench/bench_linear_solver build/bench/bench_dense_blas \
   build/bench/bench_fresh_memory build/bench/bench_assembly_threads "$stage/bundle/bin/"
if [ -x build-petsc/app/fibrane ]; then
  cp build-petsc/app/fibrane "$stage/bundle/bin/fibrane-mpi"
else
  echo "make-bundle: no build-petsc/app/fibrane: the bundle has no fibrane-mpi (scale.sh's parts 1-4 need it)" >&2
fi
cp "$(readlink -f /usr/bin/mpirun)" "$stage/bundle/bin/mpirun"
cp /usr/bin/orted /usr/bin/time "$stage/bundle/bin/"

multiarch=/usr/lib/x86_64-linux-gnu
components=$(find $multiarch/openmpi/lib/openmpi3 $multiarch/pmix2/lib -name '*.so' -type f)
glibc=$(dpkg -L libc6 | grep -o '[^/]*\.so[.0-9]*$' | sort -u)

# The libraries that the programs and the components need, found by ldd, glibc's own left out.
for f in "$stage"/bundle/bin/* $components; do
  ldd "$f" 2>/dev/null | awk '/=> \//{print $3}'
done | sort -u | while read -r lib; do
  name=$(basename "$lib")
  grep -qx "$name" <<<"$glibc" && continue
  cp -L "$lib" "$stage/bundle/lib/$name"
done

openmp_blas=/usr/lib/x86_64-linux-gnu/openblas-openmp
if [ -d "$openmp_blas" ]; then
  mkdir -p "$stage/bundle/lib-openblas-openmp"
  cp -L "$openmp_blas"/libopenblas.so.0 "$openmp_blas"/libblas.so.3 "$openmp_blas"/liblapack.so.3 \
    "$stage/bundle/lib-openblas-openmp/"
fi

# Open MPI's and PMIx's run-time trees, at their absolute paths (headers left out).
tar -C / -cf "$stage/bundle/system/openmpi.tar" --exclude='*/include' \
  "${multiarch#/}/openmpi" "${multiarch#/}/pmix2" usr/share/openmpi etc/openmpi

if [ -n "${STATE:-}" ]; then
  mkdir -p "$stage/bundle/state"
  cp "$STATE/checkpoint.bin" "$STATE/history.csv" "$stage/bundle/state/"
fi

mkdir -p "$(dirname "$out")/xz"
tar -C "$stage" -cJf "$out" bundle
cp /usr/bin/xz "$(readlink -f "$(ldd /usr/bin/xz | awk '/liblzma/{print $3}')")" "$(dirname "$out")/xz/"
mv "$(dirname "$out")"/xz/liblzma.so.5.* "$(dirname "$out")/xz/liblzma.so.5"
echo "$out: $(du -h "$out" | cut -f1), $(ls "$stage/bundle/lib" | wc -l) libraries"
