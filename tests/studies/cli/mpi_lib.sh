# What the MPI scripts share (mpi_render_test.sh, mpi_verify_test.sh, mpi_gate_test.sh): `mpirun`
# is set by the script that sources this.
# Loopback only; as root in CI's container; no cross-memory attach (often not permitted there).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none
# mpi NP CMD...: CMD over NP ranks of this machine; a hang ends in a timeout's non-zero exit.
mpi() { local np=$1; shift; timeout 300 "$mpirun" --oversubscribe -np "$np" "$@"; }
# on NP CMD...: CMD as one process (NP 1, no mpirun) or over NP ranks.
on() { local np=$1; shift; if [ "$np" -gt 1 ]; then mpi "$np" "$@"; else "$@"; fi; }
# work_was_dealt NP FILE: VRV_RANK_SHARES's lines in FILE show at least two of the NP ranks
# computing blocks (which ones is the counter's: a rank slowed by the machine's other work may
# find a loop's blocks gone, as dealing by measured cost means).
work_was_dealt() {
  local np=$1 file=$2 r computed=0
  for ((r = 0; r < np; ++r)); do
    if grep -Eq "^vrv: rank $r of $np: [1-9][0-9]* of [0-9]+ blocks$" "$file"; then computed=$((computed + 1)); fi
  done
  [ $computed -ge 2 ] || fail "$file: $computed of $np ranks computed blocks: $(cat "$file")"
}
