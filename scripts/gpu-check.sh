#!/usr/bin/env bash
# The project's GPU check in one command: the paper's four configurations, the shipped
# footprint points and the triangles on every photon path, the scaling curves, the three godray methods (lines,
# footprint ribbons, ray march) in one run, issue 16's choice of photons at the port's and the
# storage's own size, and the shipped settings' accuracy on the three built-in scenes against
# the CPU reference. Output: one JSON file and one
# Markdown file (docs/performance.md, "On a GPU", says how to read them).
#
#   Here, before the device is lent:   bash scripts/gpu-check.sh --prepare
#     builds the release binary and puts it, the Vulkan loader (../shared/gpu) and the
#     cached references the accuracy step needs into .gpu/ (git-ignored, carried along).
#   On the device (the run tool, carry [".gpu"]):
#     source .gpu/env.sh; bash scripts/gpu-check.sh --out "$OUT"
#   Anywhere, as a smoke test of this script (tiny configuration, one scene, lavapipe):
#     bash scripts/gpu-check.sh --quick --out out/gpu-check
#   (tests/gpu_check.rs runs that with --bin, the binary cargo built for the tests).
#   --bin PATH runs that binary instead of .gpu/underlight or target/release/underlight.
#
# Sized to finish in under 8 minutes on the H200: the benches run 20 frames after 3 warm-up
# frames; the accuracy step renders 3 scenes at 320×200 and reads the references from the
# cache (tracing them there would take the CPU minutes).
set -euo pipefail
cd "$(dirname "$0")/.."

mode=run
out=out/gpu-check
bin=""
while [ $# -gt 0 ]; do
  case "$1" in
    --prepare) mode=prepare ;;
    --quick) mode=quick ;;
    --out) out="${2:?gpu-check: --out needs a folder}"; shift ;;
    --bin) bin="${2:?gpu-check: --bin needs the path to an underlight binary}"; shift ;;
    *) echo "gpu-check: unknown argument $1 (expected --prepare, --quick, --out DIR or --bin PATH)" >&2; exit 2 ;;
  esac
  shift
done

scenes=(tank port storage)
# The shipped settings (assets/scenes/*.toml [effects]: footprint points, 165² × 3²) as sweep
# axes, and the size the accuracy tables in docs/accuracy.md use; beside them the triangles
# with the same photons, whose mesh is the other geometry-shader estimator.
sweep_axes=(--width 320 --height 200 --grid 165 --subdiv 3 --estimator footprint,triangles --filter on)

if [ "$mode" = prepare ]; then
  cargo build --release
  ../shared/gpu/prepare.sh
  cp target/release/underlight .gpu/underlight
  # The references the accuracy step compares with (two times each: the flicker figure),
  # traced here once by the same sweep on this machine's driver; the device reads them back.
  for scene in "${scenes[@]}"; do
    target/release/underlight sweep --scene "$scene" "${sweep_axes[@]}" --frames 1 --warmup 1 \
      --cache .gpu/reference --out "out/gpu-check-prepare/sweep-$scene"
  done
  du -sh .gpu
  echo "prepared .gpu/: on the device run  source .gpu/env.sh; bash scripts/gpu-check.sh --out \"\$OUT\""
  exit 0
fi

if [ -n "$bin" ]; then
  if [ ! -x "$bin" ]; then echo "gpu-check: --bin $bin is not an executable file" >&2; exit 1; fi
elif [ -x .gpu/underlight ]; then
  bin=.gpu/underlight
elif [ -x target/release/underlight ]; then
  bin=target/release/underlight
else
  echo "gpu-check: no binary; run  bash scripts/gpu-check.sh --prepare  first (or cargo build --release)" >&2
  exit 1
fi
cache_args=()
if [ -d .gpu/reference ]; then cache_args=(--cache .gpu/reference); fi

if [ "$mode" = quick ]; then
  configs=tiny
  godray_configs=""
  footprint_scaling=""
  frames=(--frames 2 --warmup 1)
  own_size_configs=tiny
  own_size_scenes=(port)
  scenes=(tank)
  sweep_axes=(--width 96 --height 60 --grid 24 --subdiv 3 --estimator footprint,triangles --filter on
    --photons 200000 --beams 50000)
else
  configs=paper-800,paper-1440,paper-1m-photons,paper-1440-high,footprint-points-800,receiver-800,triangles-800,refined-800
  godray_configs=triangles-800,footprint-800,marched-800
  # The scaling curves again from the shipped estimator (the ones above start from
  # paper-800): the footprint points' balance of coarse grid against subdivision (3 shipped,
  # 6 cheaper on lavapipe, output per invocation 4x larger) is for a GPU to settle.
  footprint_scaling=footprint-points-800
  # Issue 16's open choice: at 1440×850 the shipped 165² × 3² misses the port's and the
  # storage's caustic RMSE target, 200² × 3² is the fewest photons that meet it, 225² × 3²
  # meets it with room; what each costs against the triangles' pass that the shipped
  # settings were held to, on the scenes themselves.
  own_size_configs=triangles-1440,footprint-points-1440,footprint-points-200-1440,footprint-points-225-1440
  own_size_scenes=(port storage)
  frames=(--frames 20 --warmup 3)
fi

mkdir -p "$out"
start=$(date +%s)
"$bin" devices | tee "$out/devices.txt"
echo "== bench: $configs, every photon path, scaling"
"$bin" bench --config "$configs" "${frames[@]}" --compare-paths --scaling --json "$out/bench.json" | tee "$out/bench.txt"
# The work behind those times, per pass and shader stage (pipeline statistics), in a run of
# its own: on some GPUs the queries serialise the passes, so the timed runs go without.
echo "== bench: $configs, every photon path, each pass's work per stage"
"$bin" bench --config "$configs" --frames 1 --warmup 1 --compare-paths --pipeline-statistics \
  --json "$out/bench-work.json" | tee "$out/bench-work.txt"
if [ -n "$godray_configs" ]; then
  echo "== bench: the godray methods, $godray_configs"
  "$bin" bench --config "$godray_configs" "${frames[@]}" --json "$out/bench-godrays.json" | tee "$out/bench-godrays.txt"
fi
if [ -n "$footprint_scaling" ]; then
  echo "== bench: scaling from $footprint_scaling, the shipped footprint points"
  "$bin" bench --config "$footprint_scaling" "${frames[@]}" --scaling --json "$out/bench-footprint-scaling.json" \
    | tee "$out/bench-footprint-scaling.txt"
fi
for scene in "${own_size_scenes[@]}"; do
  echo "== bench: $scene at its own size, $own_size_configs"
  "$bin" bench --scene "$scene" --config "$own_size_configs" "${frames[@]}" --json "$out/bench-own-size-$scene.json" \
    | tee "$out/bench-own-size-$scene.txt"
done
for scene in "${scenes[@]}"; do
  echo "== accuracy: $scene at the shipped settings"
  "$bin" sweep --scene "$scene" "${sweep_axes[@]}" --frames 5 --warmup 2 "${cache_args[@]}" --out "$out/sweep-$scene" \
    | tee "$out/sweep-$scene.txt"
done
seconds=$(( $(date +%s) - start ))

# One JSON file: the device, the bench's report and each scene's sweep rows.
{
  printf '{\n  "seconds": %d,\n  "devices": %s,\n  "bench": ' "$seconds" \
    "$(sed 's/\\/\\\\/g; s/"/\\"/g' "$out/devices.txt" | awk 'BEGIN{printf "\""} {printf "%s\\n", $0} END{printf "\""}')"
  cat "$out/bench.json"
  printf ',\n  "work": '
  cat "$out/bench-work.json"
  if [ -n "$godray_configs" ]; then
    printf ',\n  "godray_methods": '
    cat "$out/bench-godrays.json"
  fi
  if [ -n "$footprint_scaling" ]; then
    printf ',\n  "footprint_scaling": '
    cat "$out/bench-footprint-scaling.json"
  fi
  printf ',\n  "own_size": {'
  sep=""
  for scene in "${own_size_scenes[@]}"; do
    printf '%s\n    "%s": ' "$sep" "$scene"
    cat "$out/bench-own-size-$scene.json"
    sep=","
  done
  printf '\n  }'
  printf ',\n  "accuracy": {'
  sep=""
  for scene in "${scenes[@]}"; do
    printf '%s\n    "%s": ' "$sep" "$scene"
    cat "$out/sweep-$scene/sweep.json"
    sep=","
  done
  printf '\n  }\n}\n'
} > "$out/gpu-check.json"

# One Markdown file: the bench's tables and each scene's accuracy row.
{
  echo "# GPU check ($(date -u +%Y-%m-%d), ${seconds} s)"
  echo
  echo '```'
  cat "$out/devices.txt"
  echo '```'
  echo
  echo "## Per-pass GPU time"
  echo
  echo '```'
  cat "$out/bench.txt"
  echo '```'
  echo
  echo "## Each pass's work per shader stage"
  echo
  echo '```'
  cat "$out/bench-work.txt"
  echo '```'
  if [ -n "$godray_configs" ]; then
    echo
    echo "## The godray methods"
    echo
    echo '```'
    cat "$out/bench-godrays.txt"
    echo '```'
  fi
  if [ -n "$footprint_scaling" ]; then
    echo
    echo "## Scaling from the shipped footprint points"
    echo
    echo '```'
    cat "$out/bench-footprint-scaling.txt"
    echo '```'
  fi
  for scene in "${own_size_scenes[@]}"; do
    echo
    echo "## Issue 16's photons at the own size: $scene"
    echo
    echo '```'
    cat "$out/bench-own-size-$scene.txt"
    echo '```'
  done
  for scene in "${scenes[@]}"; do
    echo
    echo "## Accuracy: $scene"
    echo
    cat "$out/sweep-$scene/sweep.md"
  done
} > "$out/gpu-check.md"
echo "wrote $out/gpu-check.json and $out/gpu-check.md in ${seconds} s"
