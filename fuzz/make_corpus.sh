#!/bin/sh
# Builds the starting corpora for the fuzz targets under $1 (default
# build-fuzz/corpus) from files the repository and the shared corpus already
# have: NQC sources, images nqc compiles from them, the hand-written seeds in
# fuzz/seeds. Nothing generated here is committed.
set -eu
root=$(cd "$(dirname "$0")/.." && pwd)
out=${1:-$root/build-fuzz/corpus}
shared=${RCXC_CORPUS_DIR:-$root/../shared/corpus}
mkdir -p "$out/compile" "$out/image" "$out/packet" "$out/scenario" "$out/test" "$out/link" "$out/srec" "$out/nxt" "$out/lsp" "$out/dap"

# fuzz_lsp's structured mode (first byte 1): JSON bodies separated by 0x1e;
# initialize, the file opened, symbols, a hover and a completion in it.
lsp_session() {
  python3 - "$1" <<'PY'
import json, sys
text = open(sys.argv[1], encoding="utf-8", errors="replace").read()
uri = "file:///nonexistent/rcxc-fuzz/prog.nqc"
doc = {"textDocument": {"uri": uri}}
msgs = [{"jsonrpc": "2.0", "id": 1, "method": "initialize", "params": {"capabilities": {}}},
        {"jsonrpc": "2.0", "method": "textDocument/didOpen",
         "params": {"textDocument": {"uri": uri, "languageId": "nqc", "version": 1, "text": text}}},
        {"jsonrpc": "2.0", "id": 2, "method": "textDocument/documentSymbol", "params": doc},
        {"jsonrpc": "2.0", "id": 3, "method": "textDocument/hover", "params": dict(doc, position={"line": 5, "character": 4})},
        {"jsonrpc": "2.0", "id": 4, "method": "textDocument/completion", "params": dict(doc, position={"line": 8, "character": 2})}]
sys.stdout.buffer.write(b"\x01" + "\x1e".join(json.dumps(m) for m in msgs).encode())
PY
}

sources=$(find "$root/tests/semantic" "$root/examples" "$shared" -name '*.nqc' 2>/dev/null || true)
n=0
for f in $sources; do
  n=$((n + 1))
  cp "$f" "$out/compile/src$n.nqc"
  # Whole test files (directives and program) for the `rcxc test` target.
  cp "$f" "$out/test/test$n.nqc"
  # Semantic-test directives go to the scenario target (first byte 0 = spec).
  { printf '\000'; cat "$f"; } > "$out/scenario/spec$n"
  # The program opened in the language server (structured mode, fuzz_lsp.cpp).
  if command -v python3 > /dev/null; then lsp_session "$f" > "$out/lsp/open$n"; fi
  if command -v nqc > /dev/null; then
    nqc -Trcx -O"$out/image/img$n.rcx" "$f" > /dev/null 2>&1 || rm -f "$out/image/img$n.rcx"
  fi
done
for f in "$root"/fuzz/seeds/scenario/*; do { printf '\001'; cat "$f"; } > "$out/scenario/$(basename "$f")"; done
cp "$root"/fuzz/seeds/packet/* "$out/packet/"
cp "$root"/fuzz/seeds/compile/* "$out/compile/"
for kind in test link srec nxt lsp dap; do cp "$root"/fuzz/seeds/$kind/* "$out/$kind/"; done
echo "corpus in $out: $(ls "$out/compile" | wc -l) sources, $(ls "$out/image" | wc -l) images," \
  "$(ls "$out/packet" | wc -l) packet seeds, $(ls "$out/scenario" | wc -l) text seeds"
