#!/usr/bin/env bash
# Given a driver and its failed `cargo test --no-fail-fast` log: succeeds only if every target
# that failed there died of a signal (not a failed test) and passes when run once more.
# Says which targets crashed, with what signal, and how the second run went.
set -euo pipefail
device="$1"
log="$2"
# Pairs "<target args>|<why>" from cargo's "to rerun pass `-p x --test y`" and the
# "process didn't exit successfully: ... (why)" line after it (none where a test failed).
mapfile -t failures < <(awk '
    function flush() { if (target != "") print target "|a test failed"; target = "" }
    /^error: (test|doctest) failed, to rerun pass `/ { flush(); split($0, a, "`"); target = a[2]; next }
    /process didn.t exit successfully/ && target != "" {
        why = $0; sub(/.*` \(/, "", why); sub(/\)$/, "", why)
        print target "|" why; target = ""
    }
    END { flush() }
' "$log")
if [ ${#failures[@]} -eq 0 ]; then
    exit 1
fi
# Each verdict goes to the log too, for ci/test.sh's last lines.
say() { echo "== ci: $*" | tee -a "$log"; }
status=0
for failure in "${failures[@]}"; do
    target="${failure%%|*}"
    why="${failure#*|}"
    case "$why" in
    signal:*) ;;
    *)
        say "$target failed on $device ($why): not a crash, not run again"
        status=1
        continue
        ;;
    esac
    say "$target CRASHED on $device ($why); running it once more"
    # With --workspace in place of -p, as the suite ran it: the same features, nothing rebuilt.
    again=$(sed -E 's/-p [^ ]+/--workspace/' <<<"$target")
    # shellcheck disable=SC2086 # cargo's own target arguments, e.g. "--workspace --test name"
    if UMBRA_DEVICE=$device cargo test --locked $again -- --test-threads=2 --show-output 2>&1 | tee -a "$log"; then
        say "$target passed on $device when run again, after a crash ($why)"
    else
        say "$target failed on $device again"
        status=1
    fi
done
exit $status
