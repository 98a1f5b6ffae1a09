#!/usr/bin/env bash
# Coverage-guided fuzzing on the stable toolchain: the flags cargo-fuzz
# passes for coverage (SanitizerCoverage's counters and compare tracing),
# without its nightly-only AddressSanitizer, which safe Rust does not
# need. New inputs go to target/stable-fuzz/corpus/TARGET (the committed
# seeds in corpus/TARGET are read, never written); a crash is written to
# target/stable-fuzz/TARGET-crash-*.
#
#   bash fuzz/run.sh TARGET [SECONDS]      (default 600)
#   bash fuzz/run.sh intersect 60
set -euo pipefail
cd "$(dirname "$0")"
target=${1:?usage: run.sh TARGET [SECONDS] (targets: $(ls fuzz_targets | sed 's/\.rs$//' | tr '\n' ' '))}
seconds=${2:-600}
[ -f "fuzz_targets/$target.rs" ] || { echo "no fuzz target '$target' in fuzz/fuzz_targets" >&2; exit 2; }
host=$(rustc -vV | sed -n 's/^host: //p')
# With --target, RUSTFLAGS reach the fuzzed code but not build scripts or
# proc macros, which cannot link without libFuzzer's symbols.
export RUSTFLAGS="-Cpasses=sancov-module -Cllvm-args=-sanitizer-coverage-level=4 \
-Cllvm-args=-sanitizer-coverage-inline-8bit-counters -Cllvm-args=-sanitizer-coverage-pc-table \
-Cllvm-args=-sanitizer-coverage-trace-compares --cfg fuzzing -Cdebug-assertions -Coverflow-checks"
cargo build --release --bin "$target" --target "$host" --target-dir target/stable-fuzz
work="target/stable-fuzz/corpus/$target"
mkdir -p "$work"
exec "target/stable-fuzz/$host/release/$target" "$work" "corpus/$target" \
    -max_total_time="$seconds" -timeout=10 -artifact_prefix="target/stable-fuzz/$target-"
