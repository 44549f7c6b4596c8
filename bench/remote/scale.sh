#!/bin/bash
# The scale measurements of docs/performance.md on a 16-core machine without Debian's packages, from the
# bundle that bench/remote/make-bundle.sh packs (run from the repository root; results under $OUT):
#   1. the full membrane at 278 k unknowns (bench/cases/bending-full-278k.yaml), one step, on
#      1, 2, 4, 8 and 16 processes of one thread each: wall, CPU and peak memory per process;
#   2. the quarter at the paper mesh (examples/bending.yaml), three steps: serial with 16 and 2 threads,
#      and on 16 processes of one thread;
#   3. the full membrane at the paper's resolution (bench/cases/bending-full-1m.yaml, 1.1 M unknowns), one
#      step on 8 processes of 2 threads, each Newton iteration's residual time-stamped;
#   4. (only when PARTS names it) the quarter's three steps at 4 threads and at 16 with OpenBLAS's own
#      idle spin (OPENBLAS_THREAD_TIMEOUT=28), and the 278 k step on 16 processes with MUMPS's block
#      low-rank factor (PETSc options) preconditioning GMRES;
#   5. (only when PARTS names it) what memory handed back costs to touch again (bench_fresh_memory), the
#      BLAS alone (bench_dense_blas: OpenBLAS's kernel for the processor,
#      dgemm and dpotrf of 3000 x 3000 at 1, 2, 4, 8 and 16 threads), then the quarter's three steps by bench_newton_breakdown
#      (where the time goes, per phase) at 2, 16 and 4 threads (the case's split Cholesky: as many domains
#      as threads), at 16 threads factorised whole (split: false), and at 8 threads;
#   6. (only when PARTS names it) the 1.1 M membrane's first step in one process of 16 threads on the
#      in-memory default path (the case without out_of_core): time per Newton iteration and peak memory.
#   7. (only when PARTS names it) memory over time, for the size estimate of src/case/case_limits.cpp: the
#      47 k example and the 278 k membrane to t = 1 and bench_linear_solver's CHOLMOD factor of the 1.1 M
#      membrane's first tangent, side by side with 2 threads each; each process's resident memory every
#      second beside its time-stamped Newton log.
#   8. (only when PARTS names it) one malloc arena (fibrane's glibc.malloc.arena_max=1) against one per
#      thread at 16 threads: an evaluation of the quarter's model with its tangent (bench_assembly_threads,
#      5 rounds) with each, then the quarter's three steps by bench_newton_breakdown with one per thread
#      (part 5's q3-bd-t16 is the same with one arena).
#   9. (only when PARTS names it, and the bundle has a state: make-bundle.sh's STATE) the quarter's tangent
#      at a late state, where the soft windows' dense blocks have gathered in a few domains: the split
#      Cholesky as the case makes it (bisecting a heavy domain again) and with the plain tree of as many
#      domains as threads (bench_linear_solver, cholmod-split against cholmod-split-L, two rounds each) at
#      16, 8 and 4 threads, and at 2 (where the two are the same).
# PARTS (default "1 2 3") picks the parts. Every run stops at DEADLINE seconds (default 560) from the start,
# so that what was measured comes back when the machine's time runs out; each run's summary line is printed
# as it ends, and the runs' logs are packed into $OUT/runs.tar.gz after each part. SMOKE=1 runs the same
# parts on coarse meshes and leaves the machine's own Open MPI files in place.
#
#   OUT=results/remote bash bench/remote/scale.sh [BUNDLE = devbundle/bundle.tar.xz]
set -u
cd "$(dirname "$0")/../.."
bundle=${1:-devbundle/bundle.tar.xz}
: "${OUT:?OUT names the folder for the results}"
mkdir -p "$OUT"
start=$SECONDS
deadline=${DEADLINE:-560}
work=${WORK:-/tmp/fibrane-scale}
rm -rf "$work" && mkdir -p "$work"
log=$OUT/scale.txt
say() { echo "$*" | tee -a "$log"; }

# The programs, their libraries, and Open MPI's run-time files where Debian's Open MPI looks for them
# (a tree of the machine's own at those paths is moved aside).
# xz from beside the bundle where the machine has none.
xz=xz; command -v xz > /dev/null || xz=$(dirname "$bundle")/xz/xz
LD_LIBRARY_PATH=$(dirname "$bundle")/xz "$xz" -dc "$bundle" | tar -C "$work" -x || exit 1
for d in /usr/lib/x86_64-linux-gnu/openmpi /usr/lib/x86_64-linux-gnu/pmix2 /usr/share/openmpi /etc/openmpi; do
  if [ -e "$d" ] && [ ! -e "$d.machine" ] && [ -z "${SMOKE:-}" ]; then mv "$d" "$d.machine"; fi
done
tar -C / -xf "$work/bundle/system/openmpi.tar" || exit 1
bin=$work/bundle/bin
export PATH=$bin:$PATH
libs=$work/bundle/lib
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl=self,vader OMPI_MCA_pml=ob1

say "machine: $(nproc) cores, $(awk '/MemTotal/{print int($2/1048576)}' /proc/meminfo) GiB,$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2)"
left() { echo $((deadline - (SECONDS - start))); }

# One run: NAME, PROCESSES (0: the serial program), THREADS, TIME LIMIT, CASE, extra arguments.
# Each process writes /usr/bin/time -v to $work/NAME/time.RANK; the summary line gives the run's seconds,
# the CPU time (user + system) and peak resident memory of the largest process and the sum over those that
# wrote theirs, the machine's memory in use at its highest, the Newton residuals, and summary.json's figures.
measure() {
  local name=$1 procs=$2 threads=$3 limit=$4 case=$5; shift 5
  local dir=$work/$name; mkdir -p "$dir"
  [ "$limit" -gt "$(left)" ] && limit=$(left)
  if [ "$limit" -lt 10 ]; then say "$name: skipped (time is up)"; return; fi
  local cmd=(run "$case" -o "$dir/out" --threads "$threads" --quiet --newton-log "$@")
  sample > "$dir/memory" & local sampler=$!
  local t0=$SECONDS
  if [ "$procs" = 0 ]; then
    timeout -k 5 "$limit" env LD_LIBRARY_PATH="$libs" time -v -o "$dir/time.0" fibrane "${cmd[@]}" > "$dir/stdout" 2> >(stamp > "$dir/stderr")
  else
    timeout -k 5 "$limit" env LD_LIBRARY_PATH="$libs" mpirun -n "$procs" --bind-to "$([ "$threads" = 1 ] && echo core || echo none)" \
      bash -c 'exec time -v -o "$0/time.$OMPI_COMM_WORLD_RANK" fibrane-mpi "$@"' "$dir" "${cmd[@]}" \
      > "$dir/stdout" 2> >(stamp > "$dir/stderr")
  fi
  local rc=$? seconds=$((SECONDS - t0))
  sleep 1; kill $sampler 2>/dev/null
  local cpu rss used
  cpu=$(awk -F': ' '/User time|System time/{c[FILENAME]+=$2} END{for(f in c)if(c[f]>m)m=c[f]; printf "%.1f", m}' "$dir"/time.* 2>/dev/null)
  rss=$(awk -F': ' '/Maximum resident/{if($2>m)m=$2; s+=$2} END{printf "%.2f / %.2f", m/1048576, s/1048576}' "$dir"/time.* 2>/dev/null)
  used=$(sort -n "$dir/memory" | tail -n 1)
  say "$name: exit $rc after ${seconds} s; CPU ${cpu} s (largest process); peak ${rss} GiB (largest process / sum); machine's memory in use at most ${used} MiB; $(grep -c '|r|=' "$dir/stderr") Newton residuals"
  grep -h -E '"(end_uz|start_uz|newton_iterations|wall_seconds|linear_solver|linear_solver_statistics|interface_unknowns|imbalance)"' \
    "$dir/out/summary.json" 2>/dev/null | tr -s ' ' | tee -a "$log"
  cp "$dir/out/summary.json" "$dir/summary.json" 2>/dev/null
}
# One bench_newton_breakdown run: NAME, THREADS, TIME LIMIT, CASE, then VAR=VALUE settings of the environment.
# The environment is fibrane's own (run/process_environment.cpp) unless the settings replace it; the summary
# line has /usr/bin/time -v's figures, and the table follows it in scale.txt.
breakdown() {
  local name=$1 threads=$2 limit=$3 case=$4; shift 4
  local dir=$work/$name; mkdir -p "$dir"
  [ "$limit" -gt "$(left)" ] && limit=$(left)
  if [ "$limit" -lt 10 ]; then say "$name: skipped (time is up)"; return; fi
  local t0=$SECONDS
  timeout -k 5 "$limit" env LD_LIBRARY_PATH="$libs" OMP_WAIT_POLICY=passive OMP_THREAD_LIMIT="$threads" \
    GLIBC_TUNABLES=glibc.malloc.mmap_threshold=4294967296:glibc.malloc.trim_threshold=17179869184:glibc.malloc.hugetlb=1:glibc.malloc.arena_max=1 "$@" \
    time -v -o "$dir/time.0" bench_newton_breakdown "$case" --threads "$threads" > "$dir/table.txt" 2>&1
  local rc=$?
  say "$name: exit $rc after $((SECONDS - t0)) s; $(awk -F': ' '/User time/{u=$2} /System time/{s=$2} /Maximum resident/{m=$2} END{printf "user %.1f s, system %.1f s, peak %.2f GiB", u, s, m/1048576}' "$dir/time.0" 2>/dev/null)"
  tee -a "$log" < "$dir/table.txt"
}
# The machine's memory in use (MiB; total less available), every 2 s.
sample() { while :; do awk '/MemTotal/{t=$2} /MemAvailable/{a=$2} END{print int((t-a)/1024)}' /proc/meminfo; sleep 2; done; }
# The resident memory (MiB) of the process PID and its descendants (the program under its launchers,
# whose share is a few MiB), every second.
rss_of() {
  while kill -0 "$1" 2>/dev/null; do
    echo "$EPOCHREALTIME $(ps -e -o pid=,ppid=,rss= | awk -v root="$1" '
      {parent[$1] = $2; rss[$1] = $3}
      END {for (p in parent) {q = p; while (q != root && q in parent && q != parent[q]) q = parent[q];
                             if (q == root) sum += rss[p]}
           print int(sum / 1024)}')"
    sleep 1
  done
}
# One run of COMMAND (fibrane or a bench program) with its resident memory profiled: NAME, TIME LIMIT,
# COMMAND, arguments (the string NAME_DIR in them stands for the run's folder).
profile() {
  local name=$1 limit=$2 command=$3; shift 3
  local dir=$work/$name; mkdir -p "$dir"
  [ "$limit" -gt "$(left)" ] && limit=$(left)
  local args=("${@//NAME_DIR/$dir}")
  local t0=$SECONDS
  timeout -k 5 "$limit" env LD_LIBRARY_PATH="$libs" time -v -o "$dir/time.0" "$command" "${args[@]}" \
    > "$dir/stdout" 2> >(stamp > "$dir/stderr") &
  local pid=$!
  rss_of "$pid" > "$dir/rss" &
  wait "$pid"
  local rc=$?
  say "$name: exit $rc after $((SECONDS - t0)) s; $(awk -F': ' '/Maximum resident/{printf "peak %.2f GiB", $2/1048576}' "$dir/time.0" 2>/dev/null)"
  grep -h -E '"(end_uz|start_uz|newton_iterations|wall_seconds|linear_solver_statistics)"' "$dir/out/summary.json" 2>/dev/null | tr -s ' ' | tee -a "$log"
  tail -n 3 "$dir/stdout" | tee -a "$log"
}
stamp() { while IFS= read -r line; do echo "$EPOCHREALTIME $line"; done; }
pack() { tar -C "$work" --exclude='*/out' -czf "$OUT/runs.tar.gz" $(cd "$work" && ls -d */ | grep -v bundle) 2>/dev/null; }

if [ -n "${SMOKE:-}" ]; then
  full=$work/full.yaml big=$work/full.yaml procs="1 2" big_procs=2 q3_procs=2
  sed -e 's/  t_end: 1.0/  t_end: 0.01/' examples/bending-full.yaml > "$full"
  sed -e 's/elements: \[100, 100\]/elements: [10, 10]/' -e 's/elements: 400/elements: 40/' \
      -e 's/t_end: 1.0/t_end: 0.035/' examples/bending.yaml > "$work/q3.yaml"
  grep -v 'out_of_core' "$full" > "$work/big-in-memory.yaml"
else
  full=bench/cases/bending-full-278k.yaml big=bench/cases/bending-full-1m.yaml procs="1 2 4 8 16" big_procs=8 q3_procs=16
  sed -e 's/t_end: 1.0/t_end: 0.035/' examples/bending.yaml > "$work/q3.yaml"
  # Without local_newton too: the distributed path refuses it (a serial run's local solves).
  grep -v -e 'out_of_core' -e 'local_newton: ' "$big" > "$work/big-in-memory.yaml"
fi

parts=${PARTS:-1 2 3}
part() { [[ " $parts " == *" $1 "* ]]; }

if part 1; then
  say "== 1. full membrane (278 k), one step, P processes of one thread"
  for p in $procs; do
    measure "full-p$p" "$p" 1 "$([ "$p" = 1 ] && echo 150 || echo 100)" "$full" --max-steps 1 --mpi-solver mumps
  done
  pack
fi

if part 2; then
  say "== 2. quarter at the paper mesh, three steps"
  measure q3-t16 0 16 100 "$work/q3.yaml"
  measure "q3-p$q3_procs" "$q3_procs" 1 100 "$work/q3.yaml" --mpi-solver mumps
  measure q3-t2 0 2 130 "$work/q3.yaml"
  pack
fi

if part 3; then
  say "== 3. full membrane at the paper's resolution (1.1 M), one step, $big_procs processes of 2 threads"
  measure "big-p$big_procs" "$big_procs" 2 "$(($(left) - 5))" "$work/big-in-memory.yaml" --max-steps 1 --mpi-solver mumps
  cp "$work/big-p$big_procs/stderr" "$OUT/big-newton.txt" 2>/dev/null
  pack
fi

if part 4; then
  say "== 4. the quarter's three steps at 4 threads, and at 16 with OpenBLAS's own spin; the 278 k step on $q3_procs processes with MUMPS's block low-rank factor (CNTL(7) = 1e-8) preconditioning GMRES"
  measure q3-t4 0 4 90 "$work/q3.yaml"
  # OpenBLAS's own spin before its idle threads sleep, against fibrane's OPENBLAS_THREAD_TIMEOUT=20 (part 2)
  OPENBLAS_THREAD_TIMEOUT=28 measure q3-t16-spin28 0 16 90 "$work/q3.yaml"
  PETSC_OPTIONS="-mat_mumps_icntl_35 1 -mat_mumps_cntl_7 1e-8" \
    measure "full-p$q3_procs-blr" "$q3_procs" 1 "$(($(left) - 5))" "$full" --max-steps 1 --mpi-solver gmres
  pack
fi
if part 5; then
  say "== 5. fresh memory; the BLAS alone; the quarter's three steps, per phase: 2, 4, 16 threads; 16 factorised whole"
  timeout 60 bench_fresh_memory 2048 5 2>&1 | tee -a "$log"
  LD_LIBRARY_PATH="$libs" timeout 60 bench_dense_blas --size 3000 1 2 4 8 16 2>&1 | tee -a "$log"
  # the bench programs do not re-execute themselves as fibrane does: give them fibrane's OpenBLAS kernel
  core=$(LD_LIBRARY_PATH="$libs" bench_dense_blas --upgrade)
  if [ -n "$core" ] && [ -z "${OPENBLAS_CORETYPE:-}" ]; then
    export OPENBLAS_CORETYPE=$core
    say "OPENBLAS_CORETYPE=$core (as fibrane sets it on this machine)"
    LD_LIBRARY_PATH="$libs" timeout 60 bench_dense_blas --size 3000 1 2 4 8 16 2>&1 | tee -a "$log"
  fi
  sed -e 's/split: true/split: false/' "$work/q3.yaml" > "$work/q3-whole.yaml"
  breakdown q3-bd-t2 2 150 "$work/q3.yaml"
  breakdown q3-bd-t16 16 100 "$work/q3.yaml"
  breakdown q3-bd-t4 4 110 "$work/q3.yaml"
  breakdown q3-bd-t16-whole 16 100 "$work/q3-whole.yaml"
  breakdown q3-bd-t8 8 100 "$work/q3.yaml"
  pack
fi

if part 6; then
  say "== 6. the 1.1 M membrane in memory, first step, one process of 16 threads"
  measure big-t16-in-memory 0 16 "$(($(left) - 5))" "$work/big-in-memory.yaml" --max-steps 1
  cp "$work/big-t16-in-memory/stderr" "$OUT/big-in-memory-newton.txt" 2>/dev/null
  pack
fi
if part 7; then
  say "== 7. memory over time: 47 k and 278 k to t = 1, CHOLMOD's factor of the 1.1 M tangent (2 threads each, side by side)"
  small=examples/bending-full.yaml
  [ -n "${SMOKE:-}" ] && small=$full
  profile mem-47k "$(($(left) - 5))" fibrane run "$small" -o NAME_DIR/out --threads 2 --quiet --newton-log &
  profile mem-278k "$(($(left) - 5))" fibrane run "$full" -o NAME_DIR/out --threads 2 --quiet --newton-log &
  profile mem-1m-cholmod "$(($(left) - 5))" bench_linear_solver "$work/big-in-memory.yaml" --threads 2 --solver cholmod &
  wait
  pack
fi
if part 8; then
  say "== 8. one malloc arena against one per thread, 16 threads"
  tunables=glibc.malloc.mmap_threshold=4294967296:glibc.malloc.trim_threshold=17179869184:glibc.malloc.hugetlb=1
  for arenas in ":glibc.malloc.arena_max=1" ""; do
    say "GLIBC_TUNABLES=$tunables$arenas"
    limit=$(( $(left) < 120 ? $(left) : 120 ))
    [ "$limit" -ge 10 ] && env LD_LIBRARY_PATH="$libs" GLIBC_TUNABLES="$tunables$arenas" OMP_WAIT_POLICY=passive \
      timeout -k 5 "$limit" bench_assembly_threads "$work/q3.yaml" --threads 16 --rounds 5 2>&1 | tee -a "$log"
  done
  breakdown q3-bd-t16-arenas 16 100 "$work/q3.yaml" GLIBC_TUNABLES="$tunables"
  pack
fi
if part 9; then
  say "== 9. the quarter's tangent at a late state: the split as the case makes it against the plain tree"
  if [ -f "$work/bundle/state/checkpoint.bin" ]; then
    for tl in 16:4 8:3 4:2 2:1; do
      limit=$(( $(left) < 150 ? $(left) : 150 ))
      [ "$limit" -ge 20 ] && LD_LIBRARY_PATH="$libs" timeout -k 5 "$limit" bench_linear_solver examples/bending.yaml \
        --threads "${tl%:*}" --solver cholmod-split --solver "cholmod-split-${tl#*:}" --rounds 2 \
        --state "$work/bundle/state" 2>&1 | tee -a "$log"
    done
  else
    say "the bundle has no state/ (make-bundle.sh with STATE=DIR)"
  fi
  pack
fi
say "done after $((SECONDS - start)) s"
