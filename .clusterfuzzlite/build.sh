#!/usr/bin/env bash
# Builds every fuzz target of fuzz/ into $OUT, each with its seed corpus
# ($OUT/<target>_seed_corpus.zip: the family generators' seeds and the committed findings of
# fuzz/regressions/<target>/) and options ($OUT/<target>.options).
#
# Run by ClusterFuzzLite / OSS-Fuzz in their build image (.clusterfuzzlite/Dockerfile), which
# sets SRC, OUT, SANITIZER and the compiler flags; and locally, or by .ci/run, with the same
# variables:
#
#   OUT=/tmp/fuzz-out SANITIZER=address .clusterfuzzlite/build.sh
#   /tmp/fuzz-out/tri_tri -max_total_time=60 /tmp/corpus   # run one target
#
# SANITIZER: address (the default) or none; any other value the service sets (coverage,
# introspector) builds without a sanitizer, the service's cargo wrapper adding its own
# instrumentation. TRIDIST_SEEDS_BIN: an already built `fuzz_seeds` example to write the seeds
# with (otherwise it is built here).
set -euo pipefail
: "${OUT:?set OUT to the directory the fuzz targets are written to}"
if [ -n "${SRC:-}" ] && [ -d "$SRC/tridist/fuzz" ]; then
  root="$SRC/tridist"
else
  root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
fi
case "${SANITIZER:-address}" in
  address) sanitizer=address ;;
  *) sanitizer=none ;;
esac
# cargo-fuzz needs nightly for the sanitizer; the service's image has it as the default
if cargo --version 2>/dev/null | grep -q nightly; then
  fuzz=(cargo fuzz)
elif cargo +nightly --version >/dev/null 2>&1; then
  fuzz=(cargo +nightly fuzz)
else
  echo "build.sh: no nightly toolchain: building without a sanitizer" >&2
  fuzz=(cargo fuzz)
  sanitizer=none
fi
mkdir -p "$OUT"
out="$(cd "$OUT" && pwd)"

cd "$root/fuzz"
"${fuzz[@]}" build --sanitizer "$sanitizer"
mapfile -t targets < <("${fuzz[@]}" list)
[ "${#targets[@]}" -gt 0 ] || { echo "build.sh: cargo fuzz list gave no target" >&2; exit 1; }
bin_dir="$root/fuzz/target/x86_64-unknown-linux-gnu/release"

seeds="$(mktemp -d)"
trap 'rm -rf "$seeds"' EXIT
seeds_bin="${TRIDIST_SEEDS_BIN:-}"
if [ -z "$seeds_bin" ]; then
  (cd "$root" && cargo build -q -p tridist-scenes --example fuzz_seeds)
  seeds_bin="${CARGO_TARGET_DIR:-$root/target}/debug/examples/fuzz_seeds"
fi
"$seeds_bin" "$seeds/corpus" >/dev/null

for t in "${targets[@]}"; do
  cp "$bin_dir/$t" "$out/$t"
  mkdir -p "$seeds/$t"
  cp "$seeds/corpus/$t"/* "$seeds/$t/" 2>/dev/null || true
  cp "$root/fuzz/regressions/$t"/* "$seeds/$t/" 2>/dev/null || true
  rm -f "$seeds/$t/README.md" "$out/${t}_seed_corpus.zip"
  n=$(find "$seeds/$t" -type f | wc -l)
  [ "$n" -gt 0 ] || { echo "build.sh: no seed for $t" >&2; exit 1; }
  (cd "$seeds/$t" && zip -q -j "$out/${t}_seed_corpus.zip" ./*)
  printf '[libfuzzer]\nmax_len = 4096\n' >"$out/$t.options"
  echo "build.sh: $t ($n seeds)"
done
