#!/bin/sh
# CTest registers each Catch2 test case under its name (catch_discover_tests);
# a name with '[', ']' or ';' breaks that silently: later cases fold into one
# entry that runs none of them (commas are escaped and work). Fails if a test
# binary has such a name.
set -eu
bad=$("$1" --list-test-names-only | grep -n '[][;]' || true)
if [ -n "$bad" ]; then
  echo "$1: test names CTest cannot register (no '[', ']' or ';' allowed):" >&2
  echo "$bad" >&2
  exit 1
fi
