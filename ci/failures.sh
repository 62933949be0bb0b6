#!/usr/bin/env bash
# Prints, from a `cargo test --no-fail-fast` log, only what failed: each failing test's header
# and panic message, each target that did not exit successfully and why (a signal, say).
# Used by ci/test.sh, so that the end of a CI log says what failed.
set -euo pipefail
log="$1"
awk '
    /^---- .* stdout ----$/ { print; shown = 8; next }
    /panicked at/ { print; shown = 4; next }
    shown > 0 { print; shown--; next }
    /^error: test failed, to rerun pass/ { print; next }
    /process didn.t exit successfully/ { sub(/`[^`]*`/, "(the test binary)"); print; next }
    /^test result: FAILED/ { print }
' "$log"
