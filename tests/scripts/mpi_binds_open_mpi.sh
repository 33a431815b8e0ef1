#!/bin/bash
# The MPI functions flexsens calls bind to Open MPI, not to the stand-ins that the sequential
# MUMPS libraries define (MPI_Init, MPI_Comm_rank, MPI_Finalize, MPI_Wtime): the link order
# must put libmpi before libdmumps_seq (CMakeLists.txt). Under mpirun a stand-in MPI_Init left
# Open MPI uninitialised and every rank aborted. Binds every symbol at start (LD_BIND_NOW) and
# reads the loader's bindings; needs no mpirun. Skipped (77) for a build without MPI.
#   bash tests/scripts/mpi_binds_open_mpi.sh <build>/flexsens
set -u
FLEXSENS=$1
bindings=$(LD_BIND_NOW=1 LD_DEBUG=bindings "$FLEXSENS" --help 2>&1 >/dev/null | grep "binding file $FLEXSENS ")
echo "$bindings" | grep -q "symbol \`MPI_Init'" || { echo "skip: flexsens calls no MPI_Init (built without MPI)"; exit 77; }
fail=0
for f in MPI_Init MPI_Initialized MPI_Finalize MPI_Comm_rank MPI_Wtime; do
  line=$(echo "$bindings" | grep "symbol \`$f'" | head -1)
  [ -z "$line" ] && continue  # not called by flexsens
  if echo "$line" | grep -q "libmpi\.so"; then
    echo "ok: $f -> $(echo "$line" | sed 's/.* to \([^ ]*\) .*/\1/')"
  else
    echo "FAIL: $f binds to $(echo "$line" | sed 's/.* to \([^ ]*\) .*/\1/'), not Open MPI's libmpi"
    fail=1
  fi
done
exit $fail
