#!/bin/sh
# Builds the starting corpora for the fuzz targets under $1 (default
# build-fuzz/corpus) from files the repository and the shared corpus already
# have: NQC sources, images nqc compiles from them, the hand-written seeds in
# fuzz/seeds. Nothing generated here is committed.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$root/build-fuzz/corpus}
shared=${RCXC_CORPUS_DIR:-$root/../shared/corpus}
mkdir -p "$out/compile" "$out/image" "$out/packet" "$out/scenario" "$out/test" "$out/link" "$out/srec" "$out/nxt"

sources=$(find "$root/tests/semantic" "$root/examples" "$shared" -name '*.nqc' 2>/dev/null || true)
n=0
for f in $sources; do
  n=$((n + 1))
  cp "$f" "$out/compile/src$n.nqc"
  # Whole test files (directives and program) for the `rcxc test` target.
  cp "$f" "$out/test/test$n.nqc"
  # Semantic-test directives go to the scenario target (first byte 0 = spec).
  { printf '\000'; cat "$f"; } > "$out/scenario/spec$n"
  if command -v nqc > /dev/null; then
    nqc -Trcx -O"$out/image/img$n.rcx" "$f" > /dev/null 2>&1 || rm -f "$out/image/img$n.rcx"
  fi
done
for f in "$root"/fuzz/seeds/scenario/*; do { printf '\001'; cat "$f"; } > "$out/scenario/$(basename "$f")"; done
cp "$root"/fuzz/seeds/packet/* "$out/packet/"
cp "$root"/fuzz/seeds/compile/* "$out/compile/"
for kind in test link srec nxt; do cp "$root"/fuzz/seeds/$kind/* "$out/$kind/"; done
echo "corpus in $out: $(ls "$out/compile" | wc -l) sources, $(ls "$out/image" | wc -l) images," \
  "$(ls "$out/packet" | wc -l) packet seeds, $(ls "$out/scenario" | wc -l) text seeds"
