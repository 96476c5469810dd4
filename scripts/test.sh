#!/usr/bin/env bash
# The test suite: unit tests, GPU tests on the real driver (lavapipe on a machine without a
# GPU) with the Khronos validation layer and synchronization validation on, and a one-shot
# smoke run of the GPU benchmarks.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
# Without a GPU the only driver is lavapipe; with one, UNDERLIGHT_DEVICE may pick it.
# Benchmarks first (each runs once), so the run closes on the test summary.
cargo test --benches "$@"
cargo test --lib --bins --tests "$@"
