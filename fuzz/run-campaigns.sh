#!/usr/bin/env bash
# Runs every fuzz target for N seconds and prints a summary table.
#
#   fuzz/run-campaigns.sh [-j 1|2] [-t SECONDS] [--cmin] [TARGET...]
#
#   -t SECONDS  time per target (default 1200 = the 20 minutes of issue #14)
#   -j JOBS     targets run at once (default 1; 2 on a two-core machine at most)
#   --cmin      minimise each target's corpus after its run (cargo fuzz cmin;
#               for the readers, inputs over 2 KB are dropped first)
#   TARGET...   a subset (default: all seven)
#
# Each run uses libFuzzer's fork mode with -ignore_crashes=1, so a known
# violation does not end the campaign: every crash, timeout and OOM is saved
# under fuzz/artifacts/<target>/ and counted. Logs go to fuzz/logs/ (ignored
# by git). New corpus entries go to fuzz/corpus/<target>/; run with --cmin
# (or `cargo fuzz cmin <target>`) before committing them.
set -euo pipefail

cd "$(dirname "$0")"
seconds=1200
jobs=1
cmin=0
targets=()
while (($#)); do
    case "$1" in
        -t) seconds="$2"; shift 2 ;;
        -j) jobs="$2"; shift 2 ;;
        --cmin) cmin=1; shift ;;
        -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
        *) targets+=("$1"); shift ;;
    esac
done
((${#targets[@]})) || targets=(obj off ply stl gltf usd from_soup end_to_end evaluate sample project fit)

max_len() {
    case "$1" in
        end_to_end | evaluate | sample | project | fit) echo 4096 ;;
        from_soup) echo 16384 ;;
        *) echo 65536 ;;
    esac
}

# The code under test is safe Rust (unsafe_code = forbid in the workspace), so
# AddressSanitizer adds little but halves the executions: build without it.
# Without a nightly toolchain, RUSTC_BOOTSTRAP=1 lets the stable one take cargo-fuzz's flags.
if rustup toolchain list 2>/dev/null | grep -q '^nightly'; then
    fuzz=(cargo +nightly fuzz)
else
    fuzz=(env RUSTC_BOOTSTRAP=1 cargo fuzz)
fi
"${fuzz[@]}" build -s none
mkdir -p logs

run_one() {
    local target="$1" log="logs/$1.log"
    mkdir -p "artifacts/$target"
    # Crashes found by this campaign only: count artifacts newer than the start.
    touch "logs/$target.start"
    "${fuzz[@]}" run -s none "$target" -- \
        -max_total_time="$seconds" -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
        -rss_limit_mb=2048 -timeout=10 -max_len="$(max_len "$target")" -print_final_stats=1 \
        >"$log" 2>&1 || true
    if ((cmin)); then
        local flags=()
        case "$target" in
            from_soup|end_to_end) ;;
            *)
                # Reader inputs grow to -max_len; for a committed corpus of
                # about 100 KB per reader keep inputs up to 2 KB and merge
                # by edges only (hit counts off): measured, this keeps all
                # but 0.1-2 % of the edges.
                find "corpus/$target" -type f -size +2k -delete
                flags=(-use_counters=0)
                ;;
        esac
        "${fuzz[@]}" cmin -s none "$target" -- -rss_limit_mb=2048 -timeout=10 "${flags[@]}" >>"$log" 2>&1 || true
    fi
}

running=0
for target in "${targets[@]}"; do
    run_one "$target" &
    running=$((running + 1))
    if ((running >= jobs)); then
        wait -n || true
        running=$((running - 1))
    fi
done
wait || true

# Summary: libFuzzer's last status line ("#EXECS: cov: C ft: F ..." in fork
# mode) and the artifacts written since the run started.
printf '%-12s %8s %12s %8s %8s %8s\n' target seconds execs cov ft crashes
for target in "${targets[@]}"; do
    log="logs/$target.log"
    line=$(grep -E '^#[0-9]+.*cov: [0-9]+' "$log" | tail -n 1 || true)
    execs=$(sed -nE 's/^#([0-9]+).*/\1/p' <<<"$line")
    cov=$(sed -nE 's/.*cov: ([0-9]+).*/\1/p' <<<"$line")
    ft=$(sed -nE 's/.*ft: ([0-9]+).*/\1/p' <<<"$line")
    crashes=$(find "artifacts/$target" -type f -newer "logs/$target.start" \( -name 'crash-*' -o -name 'timeout-*' -o -name 'oom-*' \) | wc -l)
    printf '%-12s %8s %12s %8s %8s %8s\n' "$target" "$seconds" "${execs:-?}" "${cov:-?}" "${ft:-?}" "$crashes"
done
