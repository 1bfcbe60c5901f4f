#!/usr/bin/env bash
# Builds the fastest quasar binary: the `dist` profile (fat LTO, one codegen unit) with
# profile-guided optimisation (PGO). BENCHMARKS.md ("Build profiles and PGO") gives what it
# buys; the images are bit-identical to those of `cargo build --release`.
#
#   scripts/build-pgo.sh            # writes target/pgo/quasar
#
# Steps: an instrumented build, training renders of the shipped scenes with every method family
# (small images, a few seconds each), the merged profile, the optimised build. Needs rustup's
# `llvm-tools` component (for `llvm-profdata` of the compiler's own LLVM); the script adds it
# when rustup can. About 10 minutes on two cores.
set -euo pipefail
cd "$(dirname "$0")/.."

sysroot=$(rustc --print sysroot)
host=$(rustc -vV | sed -n 's/^host: //p')
profdata="$sysroot/lib/rustlib/$host/bin/llvm-profdata"
if [ ! -x "$profdata" ]; then
  rustup component add llvm-tools >/dev/null 2>&1 || true
fi
if [ ! -x "$profdata" ]; then
  echo "build-pgo.sh: $profdata not found: install it with 'rustup component add llvm-tools'" >&2
  exit 1
fi

pgo=target/pgo
data=$pgo/data
merged=$pgo/quasar.profdata
rm -rf "$data"
mkdir -p "$data"

# the flags travel in CARGO_ENCODED_RUSTFLAGS, which keeps a path with spaces in one argument
echo "== instrumented build"
CARGO_ENCODED_RUSTFLAGS="-Cprofile-generate=$PWD/$data" cargo build --profile dist --bin quasar --target-dir "$pgo/gen"

echo "== training renders"
bin=$pgo/gen/dist/quasar
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
train() {
  "$bin" render "$@" --width 96 --height 72 --quiet -o "$out/train.exr"
}
for scene in cornell-box/cornell-box glass-plate/glass-plate glossy-room/glossy-room lightguide/lightguide \
  office/office gltf-showcase/showcase material-library/material-library; do
  train "scenes/$scene.toml" --method pt --spp 16
done
for scene in glass-plate/glass-plate glossy-room/glossy-room lightguide/lightguide; do
  train "scenes/$scene.toml" --method auto --spp 40
  train "scenes/$scene.toml" --method vismap --spp 8
done
train scenes/cornell-box/cornell-box.toml --method direct --spp 16

echo "== merged profile"
"$profdata" merge -o "$merged" "$data"

echo "== optimised build"
CARGO_ENCODED_RUSTFLAGS="-Cprofile-use=$PWD/$merged" cargo build --profile dist --bin quasar \
  --target-dir "$pgo/use"
cp "$pgo/use/dist/quasar" "$pgo/quasar"
echo "$pgo/quasar"
