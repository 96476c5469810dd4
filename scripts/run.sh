#!/usr/bin/env bash
# The main job: renders the built-in tank scene headless to out/underlight.png and prints the
# per-pass GPU times. Extra arguments go to `underlight render` (see `--help`).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/setup.sh
cargo run --release --quiet -- render --scene tank --out out/underlight.png "$@"
