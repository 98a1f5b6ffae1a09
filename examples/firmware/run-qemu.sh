#!/usr/bin/env bash
# Builds and runs hfray's firmware scene on every target and compares each
# frame with the host reference render. One line per target:
#
#   target=T frame_checksum=HEX host_checksum=HEX stack_bytes=N text_bytes=N instructions=N [extras]
#
# Targets:
#   thumbv6m-none-eabi/microbit        qemu-system-arm -machine microbit   (Cortex-M0, soft-float)
#   thumbv7em-none-eabihf/mps2-an386   qemu-system-arm -machine mps2-an386 (Cortex-M4F)
#   i586-unknown-linux-gnu/i486        qemu-i386 -cpu 486 (x87), and the same ELF natively
#                                      under `ulimit -v 8192; ulimit -s 64`
#
# Exits non-zero if a tool or target is missing (saying which), a build or
# run fails, or any frame differs from the host's (checksum and bytes).
# Installs nothing. Needs: cargo, rust targets thumbv6m-none-eabi,
# thumbv7em-none-eabihf, i586-unknown-linux-gnu; qemu-system-arm (Debian
# package qemu-system-arm), qemu-i386 (qemu-user); gcc (builds the QEMU
# instruction-count plugin and links the i486 program); readelf (binutils).
#
# Output files (frames as PPM, instruction dumps, logs) go to $OUT
# (default: <repo>/target/firmware-run).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="${OUT:-$root/target/firmware-run}"
run_timeout="${RUN_TIMEOUT:-600}"

# --- what is needed, and is it here? -------------------------------------
missing=()
for tool in cargo gcc readelf cmp timeout qemu-system-arm qemu-i386; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        case "$tool" in
        qemu-system-arm) missing+=("qemu-system-arm (apt-get install -y qemu-system-arm)") ;;
        qemu-i386) missing+=("qemu-i386 (apt-get install -y qemu-user)") ;;
        readelf) missing+=("readelf (apt-get install -y binutils)") ;;
        *) missing+=("$tool") ;;
        esac
    fi
done
targets=(thumbv6m-none-eabi thumbv7em-none-eabihf i586-unknown-linux-gnu)
if command -v rustup >/dev/null 2>&1; then
    installed="$(rustup target list --installed 2>/dev/null || true)"
    for t in "${targets[@]}"; do
        grep -qx "$t" <<<"$installed" || missing+=("rust target $t (rustup target add $t)")
    done
fi
if ((${#missing[@]})); then
    echo "run-qemu.sh: missing:" >&2
    printf '  - %s\n' "${missing[@]}" >&2
    exit 2
fi

# The host and the firmware builds must compile the same numeric code: the
# crates that do arithmetic must resolve to the same versions in every lock.
lock_versions() {
    awk '/^name = /{n=$3} /^version = /{if (n ~ /^"(libm|glam|heapless)"$/) print n, $3}' "$1" | sort
}
if [[ -f "$root/Cargo.lock" ]]; then
    want="$(lock_versions "$root/Cargo.lock")"
    for lock in "$here/Cargo.lock" "$here/i486/Cargo.lock"; do
        if [[ "$(lock_versions "$lock")" != "$want" ]]; then
            echo "run-qemu.sh: $lock resolves libm/glam/heapless differently from $root/Cargo.lock:" >&2
            diff <(echo "$want") <(lock_versions "$lock") >&2 || true
            exit 1
        fi
    done
fi

mkdir -p "$out"
log="$out/build.log"
: >"$log"

# --- builds ---------------------------------------------------------------
echo "run-qemu.sh: building (log: $log)" >&2
(cd "$root" && cargo build --release --example firmware_host) >>"$log" 2>&1 ||
    { echo "run-qemu.sh: host reference build failed (see $log)" >&2; tail -20 "$log" >&2; exit 1; }
(cd "$here" && cargo build --release --target thumbv6m-none-eabi --target thumbv7em-none-eabihf) >>"$log" 2>&1 ||
    { echo "run-qemu.sh: Cortex-M firmware build failed (see $log)" >&2; tail -20 "$log" >&2; exit 1; }
(cd "$here/i486" && cargo build --release --target i586-unknown-linux-gnu) >>"$log" 2>&1 ||
    { echo "run-qemu.sh: i486 build failed (see $log)" >&2; tail -20 "$log" >&2; exit 1; }
plugin="$out/libinsn_count.so"
gcc -O2 -shared -fPIC -fvisibility=hidden -o "$plugin" "$here/tools/qemu-insn-count/insn_count.c" >>"$log" 2>&1 ||
    { echo "run-qemu.sh: building the instruction-count plugin failed (see $log)" >&2; exit 1; }

# Where cargo put things (honours CARGO_TARGET_DIR and config files).
target_dir() {
    (cd "$1" && cargo metadata --format-version 1 --no-deps) |
        sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p'
}
host_bin="$(target_dir "$root")/release/examples/firmware_host"
fw_dir="$(target_dir "$here")"
i486_bin="$(target_dir "$here/i486")/i586-unknown-linux-gnu/release/hfray-i486"
for f in "$host_bin" "$fw_dir/thumbv6m-none-eabi/release/hfray-firmware" \
    "$fw_dir/thumbv7em-none-eabihf/release/hfray-firmware" "$i486_bin"; do
    [[ -f "$f" ]] || { echo "run-qemu.sh: built file not found: $f" >&2; exit 1; }
done

# --- helpers ----------------------------------------------------------------
status=0
fail() {
    echo "run-qemu.sh: FAIL: $*" >&2
    status=1
}
# field NAME LINE: value of NAME=... in a key=value line.
field() { sed -n "s/.*\b$1=\([^ ]*\).*/\1/p" <<<"$2" | head -1; }
# section_size ELF NAME: size in bytes of an ELF section (readelf works for ARM and x86).
section_size() {
    local hex
    hex="$(readelf -S -W "$1" | awk -v s="$2" '{for (i = 1; i <= NF; i++) if ($i == s) {print $(i + 4); exit}}')"
    if [[ -n "$hex" ]]; then echo $((16#$hex)); else echo "?"; fi
}

# --- host reference ---------------------------------------------------------
host_line="$(cd "$out" && "$host_bin" "$out/frame-host.ppm")" || { echo "run-qemu.sh: host reference failed" >&2; exit 1; }
host_sum="$(field host_checksum "$host_line")"
[[ -n "$host_sum" ]] || { echo "run-qemu.sh: no host checksum in: $host_line" >&2; exit 1; }

# compare TARGET LINE PPM: checks the checksum and the frame bytes.
compare() {
    local t="$1" line="$2" ppm="$3" sum
    sum="$(field frame_checksum "$line")"
    if [[ -z "$sum" ]]; then
        fail "$t printed no checksum: $line"
    elif [[ "$sum" != "$host_sum" ]]; then
        fail "$t frame checksum $sum != host $host_sum"
    elif ! cmp -s "$ppm" "$out/frame-host.ppm"; then
        fail "$t frame bytes differ from the host frame ($ppm)"
    fi
}

# --- Cortex-M under qemu-system-arm ----------------------------------------
for pair in thumbv6m-none-eabi:microbit thumbv7em-none-eabihf:mps2-an386; do
    triple="${pair%%:*}"
    board="${pair##*:}"
    elf="$fw_dir/$triple/release/hfray-firmware"
    rm -f "$out/frame-$board.ppm"
    if ! line="$(cd "$out" && timeout "$run_timeout" qemu-system-arm -machine "$board" -nographic \
        -semihosting-config enable=on,target=native \
        -plugin "$plugin,out=$out/insns-$board.txt" -d plugin -D "$out/qemu-$board.log" \
        -kernel "$elf")"; then
        fail "$board: qemu-system-arm exited non-zero: $line"
        continue
    fi
    compare "$triple/$board" "$line" "$out/frame-$board.ppm"
    insns="$(sed -n 's/^insn_count: total=\([0-9]*\).*/\1/p' "$out/qemu-$board.log")"
    vfp="$(sed -n 's/.*vfp(cp10\/11)=\([0-9]*\).*/\1/p' "$out/qemu-$board.log")"
    echo "target=$triple/$board frame_checksum=$(field frame_checksum "$line") host_checksum=$host_sum" \
        "stack_bytes=$(field stack_bytes "$line") text_bytes=$(section_size "$elf" .text)" \
        "instructions=${insns:-?} vfp_instructions=${vfp:-?} rodata_bytes=$(section_size "$elf" .rodata)" \
        "stack_limit_bytes=$(field stack_limit_bytes "$line") render_stack_bytes=$(field render_stack_bytes "$line")"
done

# --- i486: qemu-i386 -cpu 486 (instruction set, counts) and native (8 MiB) ---
rm -f "$out/frame-i486.ppm"
if ! line="$(cd "$out" && timeout "$run_timeout" qemu-i386 -cpu 486 \
    -plugin "$plugin,out=$out/insns-i486.txt" -d plugin -D "$out/qemu-i486.log" "$i486_bin")"; then
    fail "i486: qemu-i386 -cpu 486 exited non-zero: $line"
else
    compare "i586-unknown-linux-gnu/i486 (qemu-i386 -cpu 486)" "$line" "$out/frame-i486.ppm"
fi
insns="$(sed -n 's/^insn_count: total=\([0-9]*\).*/\1/p' "$out/qemu-i486.log")"
x87="$(sed -n 's/.*x87(D8-DF,9B)=\([0-9]*\).*/\1/p' "$out/qemu-i486.log")"
# The same ELF run directly by the kernel with an 8 MiB address-space cap
# and a 64 KiB stack cap (QEMU itself cannot run under such a cap: it maps a
# 128 MiB code buffer and reserves the guest's 4 GiB space).
rm -f "$out/frame-i486.ppm"
if ! native="$(cd "$out" && ulimit -v 8192 && ulimit -s 64 && timeout "$run_timeout" "$i486_bin" 2>&1)"; then
    fail "i486 native run under ulimit -v 8192 -s 64 failed (does this kernel run i386 ELF files?): $native"
else
    compare "i586-unknown-linux-gnu/i486 (native, ulimit -v 8192)" "$native" "$out/frame-i486.ppm"
fi
rss="?"
if [[ -x /usr/bin/time ]]; then
    rss="$(cd "$out" && { /usr/bin/time -f 'maxrss_kib=%M' "$i486_bin" >/dev/null; } 2>&1 | sed -n 's/^maxrss_kib=//p')"
fi
echo "target=i586-unknown-linux-gnu/i486 frame_checksum=$(field frame_checksum "$line") host_checksum=$host_sum" \
    "stack_bytes=$(field stack_bytes "$line") text_bytes=$(section_size "$i486_bin" .text)" \
    "instructions=${insns:-?} x87_instructions=${x87:-?} other_instructions=$(( ${insns:-0} - ${x87:-0} ))" \
    "rodata_bytes=$(section_size "$i486_bin" .rodata) render_stack_bytes=$(field render_stack_bytes "$line") native_8MiB_checksum=$(field frame_checksum "$native") max_rss_kib=${rss:-?}"

if ((status)); then
    echo "run-qemu.sh: FAILED (outputs in $out)" >&2
else
    echo "run-qemu.sh: all frames match the host (outputs in $out)" >&2
fi
exit "$status"
