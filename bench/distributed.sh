#!/usr/bin/env bash
# Distributed rendering on this machine (docs/distributed.md): the wall time of one render with 1
# and 2 ranks (mpirun -np N) × 1 and 2 threads, against the same render without mpirun, and the
# parallel efficiency; then the costs that limit scaling to many machines: mpirun's start, the
# overhead per piece, the gather. The figures go into docs/performance.md between the
# BENCH:distributed markers. Reports; never fails on a time.
# usage: bench/distributed.sh [BUILD]   BENCH_RUNS=N keeps the fastest of N runs (default 3).
set -euo pipefail
build=${1:-build}
bin=$build/bouguer
doc=docs/performance.md
runs=${BENCH_RUNS:-3}
cores=$(nproc)
machine="$cores cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'))"
today=$(date -u +%Y-%m-%d)
mkdir -p out/bench
command -v mpirun >/dev/null || { echo "bench/distributed.sh: no mpirun (install openmpi-bin)" >&2; exit 1; }
[ -e "$build/libbouguer_mpi.so" ] || { echo "bench/distributed.sh: $build has no MPI module (configure with libopenmpi-dev)" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpirun=(mpirun --oversubscribe --bind-to none)

scene=scenes/paper/pyramid-red-glass.json
render=(render "$scene" --resolution 384x384 --spp 32 --quiet -o out/bench/distributed.exr)

# Seconds of wall time of a command, the fastest of $runs.
wall() {
  local best="" t0 t1 s
  for ((i = 0; i < runs; i++)); do
    t0=$(date +%s.%N)
    "$@" >/dev/null 2>out/bench/distributed.err
    t1=$(date +%s.%N)
    s=$(echo "$t1 - $t0" | bc -l)
    if [ -z "$best" ] || (($(echo "$s < $best" | bc -l))); then best=$s; fi
  done
  printf '%.2f' "$best"
}

# The line rank 0 prints about the pieces and the gather (without --quiet).
summary() { "${mpirun[@]}" "$@" 2>&1 >/dev/null | grep '^bouguer: .* ranks'; }

# The table's runs, "label ranks threads"; ranks 0: without mpirun.
configs=("without-mpirun 0 1" "without-mpirun 0 2" "mpirun 1 1" "mpirun 1 2" "mpirun 2 1" "mpirun 2 2")
declare -A best_wall best_cpu
# Runs alternate between the configurations (the machine is shared: its load drifts), each keeping
# its fastest wall time and that run's CPU time (user + system, every rank and mpirun together).
for ((run = 0; run < runs; run++)); do
  for c in "${configs[@]}"; do
    read -r label ranks threads <<<"$c"
    cmd=("$bin" "${render[@]}" --threads "$threads")
    [ "$ranks" -gt 0 ] && cmd=("${mpirun[@]}" -np "$ranks" "${cmd[@]}")
    /usr/bin/time -f '%e %U %S' -o out/bench/distributed.time "${cmd[@]}" >/dev/null 2>out/bench/distributed.err
    read -r w u sy <out/bench/distributed.time
    if [ -z "${best_wall[$c]:-}" ] || (($(echo "$w < ${best_wall[$c]}" | bc -l))); then
      best_wall[$c]=$w
      best_cpu[$c]=$(echo "$u + $sy" | bc -l)
    fi
  done
done

{
  echo "Measured on $today, $machine, Release build, on a machine shared with other work (its load"
  echo "drifted during the runs); \`bouguer ${render[*]:0:6}\` (Whitted, full spectra). Wall"
  echo "time of the whole command including MPI's start, the fastest of $runs runs alternating between"
  echo "the rows, and that run's CPU time (every process). Speed-up against one process on one thread;"
  echo "efficiency = speed-up / min(ranks × threads, $cores cores); CPU efficiency = the one-thread CPU"
  echo "time / this row's (the work that overheads add, whatever the load). \`mpirun --oversubscribe --bind-to none -np N\`."
  echo
  echo "| run | ranks | threads per rank | seconds | CPU seconds | speed-up | efficiency | CPU efficiency |"
  echo "|---|---|---|---|---|---|---|---|"
  t1=${best_wall[${configs[0]}]}
  c1=${best_cpu[${configs[0]}]}
  for c in "${configs[@]}"; do
    read -r label ranks threads <<<"$c"
    r=$((ranks > 0 ? ranks : 1))
    p=$((r * threads < cores ? r * threads : cores))
    printf '| %s | %s | %s | %.2f | %.2f | %.2f | %.0f %% | %.0f %% |\n' "${label/-/ }" "$r" "$threads" "${best_wall[$c]}" \
      "${best_cpu[$c]}" "$(echo "$t1 / ${best_wall[$c]}" | bc -l)" "$(echo "100 * $t1 / ($p * ${best_wall[$c]})" | bc -l)" \
      "$(echo "100 * $c1 / ${best_cpu[$c]}" | bc -l)"
  done
  echo
  # What does not shrink with more machines.
  tiny=(render "$scene" --resolution 1x1 --spp 1 --quiet -o out/bench/distributed.exr)
  start_plain=$(wall "$bin" "${tiny[@]}")
  start_mpi=$(wall "${mpirun[@]}" -np 2 "$bin" "${tiny[@]}")
  # Per piece: the same cheap render cut into 16 and into 1024 pieces per rank (rows of one pixel).
  cheap=(render "$scene" --resolution 64x2048 --spp 1 --spectral rgb3 -o out/bench/distributed.exr --threads 1)
  few=$(BOUGUER_PIECES_PER_RANK=16 wall "${mpirun[@]}" -np 2 "$bin" "${cheap[@]}" --quiet)
  many=$(BOUGUER_PIECES_PER_RANK=1024 wall "${mpirun[@]}" -np 2 "$bin" "${cheap[@]}" --quiet)
  few_pieces=$(BOUGUER_PIECES_PER_RANK=16 summary -np 2 "$bin" "${cheap[@]}" | sed -E 's/.* ranks, ([0-9]+) pieces.*/\1/')
  many_pieces=$(BOUGUER_PIECES_PER_RANK=1024 summary -np 2 "$bin" "${cheap[@]}" | sed -E 's/.* ranks, ([0-9]+) pieces.*/\1/')
  per_piece_ms=$(echo "1000 * ($many - $few) / ($many_pieces - $few_pieces)" | bc -l)
  # The gather: one other rank's film, without and with spectra (96 wavelengths).
  gather_rgb=$(summary -np 2 "$bin" render "$scene" --resolution 1024x1024 --spp 1 --spectral rgb3 -o out/bench/distributed.exr)
  gather_spectra=$(summary -np 2 "$bin" render "$scene" --resolution 512x512 --spp 1 -o out/bench/distributed.exr \
    --spectral-exr out/bench/distributed_spectra.exr)
  echo "- mpirun's start: a 1×1 render takes $start_mpi s with \`mpirun -np 2\`, $start_plain s without."
  printf -- '- Per piece: %s pieces took %s s, %s pieces %s s (64×2048, 1 spp, rgb3, 2 ranks × 1 thread): %.2f ms per piece.\n' \
    "$few_pieces" "$few" "$many_pieces" "$many" "$per_piece_ms"
  echo "- The gather, as rank 0 reports it: \`${gather_rgb#bouguer: }\` (1024×1024, no spectra);"
  echo "  \`${gather_spectra#bouguer: }\` (512×512 with spectra)."
} > out/bench/distributed.md

cat out/bench/distributed.md
body=$(cat out/bench/distributed.md)
awk -v body="$body" '
  $0 == "<!-- BENCH:distributed:begin -->" { print; print body; skip = 1; next }
  $0 == "<!-- BENCH:distributed:end -->" { skip = 0 }
  !skip { print }' "$doc" > "$doc.tmp" && mv "$doc.tmp" "$doc"
