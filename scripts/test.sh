#!/usr/bin/env bash
# The test suite: unit tests, GPU tests on the real driver (lavapipe on a machine without a
# GPU) with the Khronos validation layer and synchronization validation on, and a one-shot
# smoke run of the GPU benchmarks.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
# Lint first: formatting and clippy, warnings as errors.
for component in rustfmt clippy; do
  if ! cargo "${component/rustfmt/fmt}" --version >/dev/null 2>&1; then
    echo "the tests need cargo's $component. Install it with: rustup component add $component" >&2
    exit 1
  fi
done
cargo fmt --check
cargo clippy --all-targets --quiet -- -D warnings
# Without a GPU the only driver is lavapipe; with one, UNDERLIGHT_DEVICE may pick it.
# Benchmarks first (each runs once), so the run closes on the test summary.
cargo test --benches "$@"
cargo test --lib --bins --tests --examples "$@"
