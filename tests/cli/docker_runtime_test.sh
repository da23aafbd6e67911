#!/usr/bin/env bash
# The Dockerfile's runtime stage installs a package for every shared library the built binary
# needs (readelf NEEDED, resolved by ldd, mapped to its Debian package by dpkg -S), or the
# library comes with every debian:12-slim image (apt is in it: apt's own dependencies). The image
# cannot be built here (no container engine); this is the check that would have caught the
# missing libtomlplusplus3. Usage: docker_runtime_test.sh BINARY DOCKERFILE (exit 77: skipped).
set -euo pipefail
exe="$1"
dockerfile="$2"
fail() { echo "FAIL: $*" >&2; exit 1; }
command -v dpkg >/dev/null && command -v readelf >/dev/null || { echo "skipped: no dpkg or readelf"; exit 77; }

# Packages of the last stage's `apt-get install` (the runtime image), options left out.
runtime=$(awk '/^FROM /{stage=""} {stage = stage $0 "\n"} END {printf "%s", stage}' "$dockerfile" |
  sed -e ':a' -e '/\\$/N; s/\\\n//; ta' | grep 'apt-get install' |
  sed -e 's/.*apt-get install//' -e 's/&&.*//' | tr ' ' '\n' | grep -v '^-' | grep -v '^$' || true)
[ -n "$runtime" ] || fail "no apt-get install in the runtime stage of $dockerfile"
# What every debian:12-slim has: apt and the packages it depends on.
base="apt $(dpkg-query -W -f='${Depends}\n' apt | tr ',|' '\n\n' | sed -e 's/(.*)//' -e 's/ //g')"

package_of() { # the package that installed library file $1 (usrmerge: /lib and /usr/lib are one)
  local path="$1" candidate
  for candidate in "$path" "${path#/usr}" "/usr$path" "$(readlink -f "$path")"; do
    if owner=$(dpkg -S "$candidate" 2>/dev/null); then
      echo "${owner%%:*}" | cut -d, -f1
      return 0
    fi
  done
  return 1
}

checked=0
for lib in $(readelf -d "$exe" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
  path=$(ldd "$exe" | awk -v lib="$lib" '$1 == lib && $3 ~ /^\// { print $3 }')
  [ -n "$path" ] || fail "$lib: not found by ldd"
  package=$(package_of "$path") || fail "$lib ($path): no Debian package installed it"
  if ! grep -qx "$package" <<<"$runtime" && ! grep -qx "$package" <<<"$(tr ' ' '\n' <<<"$base")"; then
    fail "$lib is in package $package, which the runtime stage of $dockerfile does not install (it installs: $(echo $runtime))"
  fi
  checked=$((checked + 1))
done
[ "$checked" -gt 0 ] || fail "no NEEDED libraries read from $exe"
echo "$checked libraries covered by the runtime stage"
