#!/usr/bin/env bash
# `cmake --install` into a temporary prefix puts the binary, the man page, the bash completion
# and the licence there; the man page names every subcommand `trisnap --help` lists, and the
# completion completes commands and options. Usage: install_test.sh BUILD_DIR
set -euo pipefail
build_dir="$1"
prefix="$(mktemp -d)"
trap 'rm -rf "$prefix"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

cmake --install "$build_dir" --prefix "$prefix" >/dev/null
exe="$prefix/bin/trisnap"
man_page="$prefix/share/man/man1/trisnap.1"
completion="$prefix/share/bash-completion/completions/trisnap"
for f in "$exe" "$man_page" "$completion" "$prefix/share/doc/trisnap/LICENSE"; do
  [ -f "$f" ] || fail "not installed: ${f#"$prefix"/}"
done
"$exe" --version | grep -q '^trisnap ' || fail "the installed binary does not run"

# Every subcommand of --help has its section in the man page.
commands=$("$exe" --help | sed -n '/^Subcommands:/,/^$/p' | awk 'NR > 1 && NF { print $1 }')
[ -n "$commands" ] || fail "no subcommands in --help"
for c in $commands; do
  escaped=$(printf '%s' "$c" | sed 's/-/\\\\-/g') # roff writes snap-tiles as snap\-tiles
  grep -q "^\.SS \"trisnap $escaped" "$man_page" || fail "man page has no section for '$c'"
done
grep -q '^\.B \\-\\-tolerance FLOAT' "$man_page" || fail "man page lacks snap's --tolerance"
if command -v groff >/dev/null; then
  warnings=$(groff -man -Tutf8 -ww -z "$man_page" 2>&1) || fail "groff failed: $warnings"
  [ -z "$warnings" ] || fail "groff warns: $warnings"
fi

# The completion offers commands, then the options of the command given.
complete_words() {
  bash -c 'source "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _trisnap; echo "${COMPREPLY[*]}"' _ "$completion" "$@"
}
[ "$(complete_words trisnap sn)" = "snap snap-tiles" ] || fail "'trisnap sn<TAB>' gives '$(complete_words trisnap sn)'"
[ "$(complete_words trisnap snap in.gpkg --toler)" = "--tolerance --tolerance-m" ] ||
  fail "'trisnap snap --toler<TAB>' gives '$(complete_words trisnap snap in.gpkg --toler)'"
[ "$(complete_words trisnap assess --fail)" = "--fail-on-defects" ] || fail "assess options not completed"
echo "1 passed, 0 failed"
