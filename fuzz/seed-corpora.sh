#!/usr/bin/env bash
# Copies the seed files of every fuzz target (fuzz/seeds.txt) and its regressions
# (fuzz/regressions/<target>/) into fuzz/corpus/<target>/, where cargo-fuzz starts from them and
# keeps what it finds. Run from anywhere; docs/reliability.md.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
while read -r target files; do
    case "$target" in ''|'#'*) continue ;; esac
    mkdir -p "$root/fuzz/corpus/$target"
    for f in $files; do cp "$root/$f" "$root/fuzz/corpus/$target/"; done
    if [ -d "$root/fuzz/regressions/$target" ]; then
        cp "$root/fuzz/regressions/$target/"* "$root/fuzz/corpus/$target/" 2>/dev/null || true
    fi
done < "$root/fuzz/seeds.txt"
