#!/usr/bin/env bash
# Runs every fuzz target for SECONDS (default 60) each with libFuzzer, starting from the seeds in
# seeds/ and the corpus grown by earlier runs (corpus/, not committed). Crashes go to artifacts/;
# each crasher becomes a regression test in tests/fuzz_regressions.rs once fixed.
# Needs cargo-fuzz (`cargo install cargo-fuzz`); on a stable toolchain RUSTC_BOOTSTRAP=1 lets it
# pass its sanitizer flags. Not part of CI (`.ci/run`): fuzzing is open-ended by nature.
set -euo pipefail
cd "$(dirname "$0")"
secs=${1:-60}
for t in toml_scene obj gltf bsdf usd photometry; do
  mkdir -p "corpus/$t" "artifacts/$t"
  echo "== $t ($secs s)"
  RUSTC_BOOTSTRAP=1 cargo fuzz run "$t" "corpus/$t" "seeds/$t" -- \
    -max_total_time="$secs" -rss_limit_mb=4096 -timeout=20 -artifact_prefix="artifacts/$t/" -print_final_stats=1 2>&1 |
    grep -E "stat::number_of_executed_units|stat::peak_rss_mb|Done|ERROR|SUMMARY|crash-|timeout-|oom-" || true
done
