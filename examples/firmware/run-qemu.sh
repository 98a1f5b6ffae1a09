#!/usr/bin/env bash
# Builds and runs hfray's firmware scene on every target and compares each
# frame with the host reference render. One line per target and scene:
#
#   target=T frame_checksum=HEX host_checksum=HEX stack_bytes=N text_bytes=N instructions=N
#            frame_instructions=N [extras]
#
# `instructions`: the whole program; `frame_instructions`: the frame alone
# (each program brackets it with marker instructions the plugin counts
# between, tools/qemu-insn-count; README "What the counts include").
#
# Targets (T; the first line of each is the issue-5 frame, scene `base`):
#   thumbv6m-none-eabi/microbit        qemu-system-arm -machine microbit   (Cortex-M0, soft-float)
#   thumbv7em-none-eabihf/mps2-an386   qemu-system-arm -machine mps2-an386 (Cortex-M4F)
#   i586-unknown-linux-gnu/i486        qemu-i386 -cpu 486 (x87), and the same ELF natively
#                                      under `ulimit -v 8192; ulimit -s 64`
# and, for each, the scene variants (T gets a suffix):
#   T:reflect-1, T:reflect-5           height-field-only build, the field as a mirror
#                                      at max_trace_level 1 and 5 (stack vs depth)
#   T+full, T+full:plane-1, T+full:plane-5
#                                      the `full` build (hfray's primitives): its .text,
#                                      and a reflective plane under the field at depth 1, 5
#   T:lcd                              160 × 128 RGB565 (ST7735), Rocky Mountain 152 × 187
#   T:thesis                           the thesis benchmark, 512² plasma at 320 × 200
#                                      (Cortex-M4F and i486; not in the micro:bit's flash)
#   thumbv7em-none-eabihf/mps2-an386:sqrt-check, i586-unknown-linux-gnu/i486:sqrt-check
#                                      vsqrt.f32 / fsqrt against libm's sqrtf over 2^20
#                                      inputs (the 486 at three x87 precisions)
#   thumbv6m-none-eabi/microbit-minimal[:reflect-5]
#                                      the minimal M0 build (no secondary rays): the
#                                      base frame, and reflect-5 refused
#   i586-unknown-linux-gnu/i486sx[:lcd]
#                                      the i486 program built with `fixed-frame`
#                                      (the FPU-less 486SX) under qemu-i386 -cpu 486:
#                                      the fixed-point frame, byte for byte the
#                                      host's; the line adds x87_in_pixels (x87
#                                      instructions the render ran: must be 0) and
#                                      x87_in_setup (the per-frame f64 set-up's)
# The Cortex-M0's height-field-only and minimal builds draw the fixed-point
# frame (hfray::fixed_frame, its default): their base frame must equal the
# host's fixed-point frame (`firmware_host --frame fixed`) byte for byte, the
# line adds `frame=fixed mean_abs=X max_abs=Y px_over_8=N` (per channel,
# 0-255, against the host's f32 frame of the same scene), and the mirror
# scenes are refused (`refused=FixedFrame`). Its `full` build draws in f32.
# `--base` runs the base scene of the height-field-only builds only (and
# the 486SX's).
# `--profile` also prints, under each run's line, the functions that
# executed the most instructions in the frame (`PROFILE_TOP`, default 12), symbolised
# from the run's ELF (tools/qemu-insn-count/by_symbol.py; needs python3
# and nm):
#   profile T:  N  P%  FUNCTION
#
# Exits non-zero if a tool or target is missing (saying which), a build or
# run fails, or any frame differs from the host's (checksum and bytes) or
# any work counter (hits, rays, cells, triangle tests) differs from the
# host's.
# Installs nothing. Needs: cargo, rust targets thumbv6m-none-eabi,
# thumbv7em-none-eabihf, i586-unknown-linux-gnu; qemu-system-arm (Debian
# package qemu-system-arm), qemu-i386 (qemu-user); gcc (builds the QEMU
# instruction-count plugin and links the i486 program); readelf (binutils).
#
# Output files (frames as PPM, instruction dumps, logs) go to $OUT
# (default: <repo>/target/firmware-run).
set -euo pipefail

all=1
profile=0
for arg in "$@"; do
    case "$arg" in
    --base) all=0 ;;
    --profile) profile=1 ;;
    *)
        echo "usage: run-qemu.sh [--base] [--profile]" >&2
        exit 2
        ;;
    esac
done
# Functions listed per run by --profile.
profile_top="${PROFILE_TOP:-12}"

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="$(realpath -m "${OUT:-$root/target/firmware-run}")" # a relative OUT is taken from where the script was started
run_timeout="${RUN_TIMEOUT:-600}"

# --- what is needed, and is it here? -------------------------------------
missing=()
tools=(cargo gcc readelf cmp timeout qemu-system-arm qemu-i386)
((profile)) && tools+=(python3 nm)
for tool in "${tools[@]}"; do
    if ! command -v "$tool" >/dev/null 2>&1; then
        case "$tool" in
        qemu-system-arm) missing+=("qemu-system-arm (apt-get install -y qemu-system-arm)") ;;
        qemu-i386) missing+=("qemu-i386 (apt-get install -y qemu-user)") ;;
        readelf | nm) missing+=("$tool (apt-get install -y binutils)") ;;
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

# Where cargo puts things (honours CARGO_TARGET_DIR and config files).
target_dir() {
    (cd "$1" && cargo metadata --format-version 1 --no-deps) |
        sed -n 's/.*"target_directory":"\([^"]*\)".*/\1/p'
}
host_bin="$(target_dir "$root")/release/examples/firmware_host"
fw_dir="$(target_dir "$here")"
i486_dir="$(target_dir "$here/i486")"
# The `full` builds go to their own target directories, so both binaries
# of each target exist side by side.
fw_full_dir="$fw_dir/full"
# The minimal M0 build (no reflection or transparency: `--no-default-features`).
fw_min_dir="$fw_dir/minimal"
i486_full_dir="$i486_dir/full"
# The 486SX build (`--features fixed-frame`: the fixed-point frame).
i486sx_dir="$i486_dir/fixed"

# --- builds ---------------------------------------------------------------
# Added to .cargo/config.toml's i486 flags for the x87 builds (the i486
# program, plain and `full`): LLVM's PBQP register allocator with its
# coalescing, whose x87 code moves values on the FPU stack less than the
# default (greedy) allocator's, with MachineSink's sinking into loops to
# avoid spills and compares not merged into one branch (see
# .cargo/config.toml for the figures). Not for the 486SX build (integers
# per pixel), which PBQP makes slower.
i486_x87_config='target.i586-unknown-linux-gnu.rustflags=["-C", "llvm-args=-regalloc=pbqp", "-C", "llvm-args=-pbqp-coalescing", "-C", "llvm-args=-sink-insts-to-avoid-spills", "-C", "llvm-args=-x86-br-merging-base-cost=-1"]'
echo "run-qemu.sh: building (log: $log)" >&2
build() {
    local what="$1"
    shift
    "$@" >>"$log" 2>&1 || { echo "run-qemu.sh: $what build failed (see $log)" >&2; tail -20 "$log" >&2; exit 1; }
}
build "host reference" bash -c "cd '$root' && cargo build --release --example firmware_host"
# One target a build: features are unified across the targets of one cargo
# invocation, and only the Cortex-M0 asks for hfray's `compact` walk.
build "Cortex-M0 firmware" bash -c "cd '$here' && cargo build --release --target thumbv6m-none-eabi"
build "Cortex-M4F firmware" bash -c "cd '$here' && cargo build --release --target thumbv7em-none-eabihf"
# The x87 builds (not the 486SX's) with LLVM's PBQP register allocator
# (`i486_x87_config` above).
build "i486" bash -c "cd '$here/i486' && cargo build --release --target i586-unknown-linux-gnu --config '$i486_x87_config'"
build "486SX" bash -c "cd '$here/i486' && cargo build --release --features fixed-frame --target-dir '$i486sx_dir' --target i586-unknown-linux-gnu"
if ((all)); then
    build "Cortex-M0 firmware (full)" bash -c "cd '$here' && cargo build --release --features full --target-dir '$fw_full_dir' --target thumbv6m-none-eabi"
    build "Cortex-M4F firmware (full)" bash -c "cd '$here' && cargo build --release --features full --target-dir '$fw_full_dir' --target thumbv7em-none-eabihf"
    build "i486 (full)" bash -c "cd '$here/i486' && cargo build --release --features full --target-dir '$i486_full_dir' --target i586-unknown-linux-gnu --config '$i486_x87_config'"
    build "Cortex-M0 firmware (minimal)" bash -c "cd '$here' && cargo build --release --no-default-features --target-dir '$fw_min_dir' --target thumbv6m-none-eabi"
fi
plugin="$out/libinsn_count.so"
build "instruction-count plugin" gcc -O2 -shared -fPIC -fvisibility=hidden -o "$plugin" "$here/tools/qemu-insn-count/insn_count.c"

for f in "$host_bin" "$fw_dir/thumbv6m-none-eabi/release/hfray-firmware" \
    "$fw_dir/thumbv7em-none-eabihf/release/hfray-firmware" \
    "$i486_dir/i586-unknown-linux-gnu/release/hfray-i486" \
    "$i486sx_dir/i586-unknown-linux-gnu/release/hfray-i486"; do
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
# image_bytes ELF: bytes the program image occupies (allocated sections with
# contents: vector table, .text, .rodata, .data, ...; not .bss). On the
# Cortex-M boards that is the flash used.
image_bytes() {
    local hex sum=0
    for hex in $(readelf -S -W "$1" | awk '
        /^ *\[ *[0-9]+\]/ {
            sub(/^ *\[ *[0-9]+\] */, "")
            if ($2 != "NOBITS" && $2 != "NULL" && $7 ~ /A/) print $5
        }'); do
        sum=$((sum + 16#$hex))
    done
    echo "$sum"
}
# profile LABEL DUMP ELF: with --profile, the top functions of the run's
# frame by executed instructions.
profile() {
    ((profile)) || return 0
    python3 "$here/tools/qemu-insn-count/by_symbol.py" "$2" "$3" nm "$profile_top" |
        tail -n +2 | sed "s|^|profile $1: |"
}
# frame_instructions LOG: the instructions of the frame (the program brackets
# it with marker instructions, tools/qemu-insn-count), from a QEMU log.
frame_instructions() { sed -n 's/^insn_count: frame=\([0-9]*\).*/\1/p' "$1"; }
# check_marks LOG: fails the run unless the frame's markers ran in pairs (a
# marker the plugin missed would make the frame a part of itself).
check_marks() {
    local marks
    marks="$(sed -n 's/^insn_count: frame=.* marks=\([0-9]*\).*/\1/p' "$1")"
    if [[ -z "$marks" || $((marks % 2)) != 0 ]]; then
        fail "$1: the frame markers ran ${marks:-?} times, not in pairs"
    fi
}
# The work counters every program prints; they must equal the host's.
work_keys=(hits reflected_rays shadow_rays shadow_hits cells triangle_tests dropped_rays)
work() {
    local k w=""
    for k in "${work_keys[@]}"; do w+=" $k=$(field "$k" "$1")"; done
    echo "${w# }"
}

# --- host reference, one frame per scene --------------------------------------
declare -A host_sum host_work
host() {
    local scene="$1" line
    line="$(cd "$out" && "$host_bin" --scene "$scene" "$out/frame-host-$scene.ppm")" ||
        { echo "run-qemu.sh: host reference failed for scene $scene" >&2; exit 1; }
    host_sum[$scene]="$(field host_checksum "$line")"
    host_work[$scene]="$(work "$line")"
    [[ -n "${host_sum[$scene]}" ]] || { echo "run-qemu.sh: no host checksum in: $line" >&2; exit 1; }
}
scenes=(base)
((all)) && scenes+=(reflect-1 reflect-5 plane-1 plane-5 lcd thesis)
for s in "${scenes[@]}"; do host "$s"; done
cp "$out/frame-host-base.ppm" "$out/frame-host.ppm"

# --- host reference of the fixed-point frame (the Cortex-M0's default) -------
# Keyed `fixed:SCENE`, with the frame in frame-host-fixed:SCENE.ppm; fixed_error
# holds its distance from the f32 frame (mean_abs=.. max_abs=.. px_over_8=..).
# The scenes the fixed-point frame draws (the others have mirrors).
declare -A fixed_error
fixed_scenes=(base)
((all)) && fixed_scenes+=(lcd)
for s in "${fixed_scenes[@]}"; do
    line="$(cd "$out" && "$host_bin" --scene "$s" --frame fixed "$out/frame-host-fixed:$s.ppm")" ||
        { echo "run-qemu.sh: host fixed-point reference failed for scene $s" >&2; exit 1; }
    host_sum[fixed:$s]="$(field host_checksum "$line")"
    host_work[fixed:$s]="$(work "$line")"
    fixed_error[$s]="mean_abs=$(field mean_abs "$line") max_abs=$(field max_abs "$line") px_over_8=$(field px_over_8 "$line")"
done
# frame_uses_fixed BOARD BUILD: the build draws the fixed-point frame.
frame_uses_fixed() { [[ "$1" == microbit && "$2" != full ]]; }

# compare WHAT SCENE LINE PPM: checks the checksum, the frame bytes and the
# work counters against the host's (SCENE `fixed:NAME`: its fixed-point frame).
compare() {
    local t="$1" scene="$2" line="$3" ppm="$4" sum
    sum="$(field frame_checksum "$line")"
    if [[ -z "$sum" ]]; then
        fail "$t printed no checksum: $line"
    elif [[ "$sum" != "${host_sum[$scene]}" ]]; then
        fail "$t frame checksum $sum != host ${host_sum[$scene]}"
    elif ! cmp -s "$ppm" "$out/frame-host-$scene.ppm"; then
        fail "$t frame bytes differ from the host frame ($ppm)"
    elif [[ "$(work "$line")" != "${host_work[$scene]}" ]]; then
        fail "$t work counters differ from the host's: $(work "$line") != ${host_work[$scene]}"
    fi
}
# Output name of a run: target, +full for the full build, :scene unless base.
label() {
    local l="$1"
    [[ "$2" == full ]] && l+="+full"
    [[ "$3" != base ]] && l+=":$3"
    echo "$l"
}
# Frames of runs other than the hf-only base keep their scene in the name.
frame_name() {
    local board="$1" build="$2" scene="$3"
    if [[ "$build" == hf && "$scene" == base ]]; then
        echo "frame-$board.ppm"
    else
        echo "frame-$board-$build-$scene.ppm"
    fi
}
# Each run writes its frame into this scratch directory (the programs'
# working directory); the frame is then moved to its name in $out.
scratch="$out/scratch"
# The runs: build (hf = height-field only, full) and scene.
runs=("hf base")
((all)) && runs+=("hf reflect-1" "hf reflect-5" "full base" "full plane-1" "full plane-5" "hf lcd" "hf thesis")

# --- Cortex-M under qemu-system-arm ----------------------------------------
for pair in thumbv6m-none-eabi:microbit thumbv7em-none-eabihf:mps2-an386; do
    triple="${pair%%:*}"
    board="${pair##*:}"
    for r in "${runs[@]}"; do
        read -r build scene <<<"$r"
        # The thesis field (256 KiB) does not fit the micro:bit's flash.
        [[ "$board" == microbit && "$scene" == thesis ]] && continue
        if [[ "$build" == full ]]; then elf="$fw_full_dir/$triple/release/hfray-firmware"; else elf="$fw_dir/$triple/release/hfray-firmware"; fi
        t="$(label "$triple/$board" "$build" "$scene")"
        tag="$board-$build-$scene"
        ppm="$out/$(frame_name "$board" "$build" "$scene")"
        rm -rf "$scratch" && mkdir -p "$scratch"
        if ! line="$(cd "$scratch" && timeout "$run_timeout" qemu-system-arm -machine "$board" -nographic \
            -semihosting-config "enable=on,target=native,arg=hfray-firmware,arg=$scene" \
            -plugin "$plugin,out=$out/insns-$tag.txt,frame_out=$out/frame-insns-$tag.txt" -d plugin -D "$out/qemu-$tag.log" \
            -kernel "$elf")"; then
            # The fixed-point frame draws no mirrors: refused, never drawn otherwise.
            if frame_uses_fixed "$board" "$build" && [[ -z "${fixed_error[$scene]+set}" && "$line" == *"error=render:FixedFrame"* ]]; then
                echo "target=$t refused=FixedFrame scene=$scene build=$build"
            else
                fail "$t: qemu-system-arm exited non-zero: $line"
            fi
            continue
        fi
        mv -f "$scratch/frame-$board.ppm" "$ppm" 2>/dev/null || rm -f "$ppm"
        ref="$scene" extra=""
        if frame_uses_fixed "$board" "$build"; then
            if [[ -z "${fixed_error[$scene]+set}" ]]; then
                fail "$t: expected error=render:FixedFrame, got: $line"
                continue
            fi
            ref="fixed:$scene" extra=" frame=fixed ${fixed_error[$scene]}"
        fi
        compare "$t" "$ref" "$line" "$ppm"
        insns="$(sed -n 's/^insn_count: total=\([0-9]*\).*/\1/p' "$out/qemu-$tag.log")"
        check_marks "$out/qemu-$tag.log"
        frame_insns="$(frame_instructions "$out/qemu-$tag.log")"
        vfp="$(sed -n 's/.*vfp(cp10\/11)=\([0-9]*\).*/\1/p' "$out/qemu-$tag.log")"
        echo "target=$t frame_checksum=$(field frame_checksum "$line") host_checksum=${host_sum[$ref]}" \
            "stack_bytes=$(field stack_bytes "$line") text_bytes=$(section_size "$elf" .text)" \
            "instructions=${insns:-?} frame_instructions=${frame_insns:-?} vfp_instructions=${vfp:-?} rodata_bytes=$(section_size "$elf" .rodata)" \
            "image_bytes=$(image_bytes "$elf") stack_limit_bytes=$(field stack_limit_bytes "$line")" \
            "render_stack_bytes=$(field render_stack_bytes "$line") render_peak_stack_bytes=$(field render_peak_stack_bytes "$line")" \
            "setup_stack_bytes=$(field setup_stack_bytes "$line")" \
            "model_bytes=$(field model_bytes "$line") heightfield_bytes=$(field heightfield_bytes "$line")" \
            "tracer_bytes=$(field tracer_bytes "$line") line_bytes=$(field line_bytes "$line")" \
            "scene=$scene build=$build $(work "$line")$extra"
        profile "$t" "$out/frame-insns-$tag.txt" "$elf"
    done
done

# --- hardware square root: vsqrt.f32 against libm, bit for bit ----------------
# The Cortex-M4F firmware's `sqrt-check` compares hfray::math::sqrtf
# (`vsqrt.f32`) with libm's software sqrtf over 2^20 inputs.
elf="$fw_dir/thumbv7em-none-eabihf/release/hfray-firmware"
t="thumbv7em-none-eabihf/mps2-an386:sqrt-check"
line="$(cd "$out" && timeout "$run_timeout" qemu-system-arm -machine mps2-an386 -nographic \
    -semihosting-config "enable=on,target=native,arg=hfray-firmware,arg=sqrt-check" -kernel "$elf")" || true
if [[ "$(field sqrt_mismatches "$line")" == 0 && -n "$(field sqrt_checked "$line")" ]]; then
    echo "target=$t sqrt_checked=$(field sqrt_checked "$line") sqrt_mismatches=0"
else
    fail "$t: hardware sqrt differs from libm's: $line"
fi

# --- minimal M0 build: the same base frame; a mirror scene is refused -------
# Built without `secondary-rays`, the firmware must draw the base frame
# byte for byte (the fixed-point frame, the M0's default) and refuse the
# reflect-5 scene (`FixedFrame`; `NotBuilt` in f32), never draw a different
# picture.
if ((all)); then
    elf="$fw_min_dir/thumbv6m-none-eabi/release/hfray-firmware"
    for scene in base reflect-5; do
        t="thumbv6m-none-eabi/microbit-minimal"
        [[ "$scene" != base ]] && t+=":$scene"
        tag="microbit-minimal-$scene"
        rm -rf "$scratch" && mkdir -p "$scratch"
        line="$(cd "$scratch" && timeout "$run_timeout" qemu-system-arm -machine microbit -nographic \
            -semihosting-config "enable=on,target=native,arg=hfray-firmware,arg=$scene" \
            -plugin "$plugin,out=$out/insns-$tag.txt,frame_out=$out/frame-insns-$tag.txt" -d plugin -D "$out/qemu-$tag.log" \
            -kernel "$elf")" || true
        insns="$(sed -n 's/^insn_count: total=\([0-9]*\).*/\1/p' "$out/qemu-$tag.log")"
        check_marks "$out/qemu-$tag.log"
        frame_insns="$(frame_instructions "$out/qemu-$tag.log")"
        if [[ "$scene" == base ]]; then
            ppm="$out/frame-microbit-minimal.ppm"
            mv -f "$scratch/frame-microbit.ppm" "$ppm" 2>/dev/null || rm -f "$ppm"
            compare "$t" fixed:base "$line" "$ppm"
            echo "target=$t frame_checksum=$(field frame_checksum "$line") host_checksum=${host_sum[fixed:base]}" \
                "stack_bytes=$(field stack_bytes "$line") text_bytes=$(section_size "$elf" .text)" \
                "instructions=${insns:-?} frame_instructions=${frame_insns:-?} image_bytes=$(image_bytes "$elf") scene=base build=minimal $(work "$line")" \
                "frame=fixed ${fixed_error[base]}"
            profile "$t" "$out/frame-insns-$tag.txt" "$elf"
        elif [[ "$line" == *"error=render:FixedFrame"* || "$line" == *"error=render:NotBuilt"* ]]; then
            echo "target=$t refused=$(sed -n 's/.*error=render:\([A-Za-z]*\).*/\1/p' <<<"$line") scene=$scene build=minimal"
        else
            fail "$t: expected error=render:FixedFrame or NotBuilt, got: $line"
        fi
    done
fi

# --- i486: qemu-i386 -cpu 486 (instruction set, counts) and native (8 MiB) ---
for r in "${runs[@]}"; do
    read -r build scene <<<"$r"
    if [[ "$build" == full ]]; then d="$i486_full_dir"; else d="$i486_dir"; fi
    i486_bin="$d/i586-unknown-linux-gnu/release/hfray-i486"
    t="$(label "i586-unknown-linux-gnu/i486" "$build" "$scene")"
    tag="i486-$build-$scene"
    ppm="$out/$(frame_name i486 "$build" "$scene")"
    rm -rf "$scratch" && mkdir -p "$scratch"
    if ! line="$(cd "$scratch" && timeout "$run_timeout" qemu-i386 -cpu 486 \
        -plugin "$plugin,out=$out/insns-$tag.txt,frame_out=$out/frame-insns-$tag.txt" -d plugin -D "$out/qemu-$tag.log" "$i486_bin" "$scene")"; then
        fail "$t: qemu-i386 -cpu 486 exited non-zero: $line"
        continue
    fi
    mv -f "$scratch/frame-i486.ppm" "$ppm" 2>/dev/null || rm -f "$ppm"
    compare "$t (qemu-i386 -cpu 486)" "$scene" "$line" "$ppm"
    insns="$(sed -n 's/^insn_count: total=\([0-9]*\).*/\1/p' "$out/qemu-$tag.log")"
    check_marks "$out/qemu-$tag.log"
    frame_insns="$(frame_instructions "$out/qemu-$tag.log")"
    x87="$(sed -n 's/.*x87(D8-DF,9B)=\([0-9]*\).*/\1/p' "$out/qemu-$tag.log")"
    # The same ELF run directly by the kernel with an 8 MiB address-space cap
    # and a 64 KiB stack cap (QEMU itself cannot run under such a cap: it maps
    # a 128 MiB code buffer and reserves the guest's 4 GiB space). The program
    # reports its own VmPeak/VmHWM (under QEMU those would be QEMU's).
    if ! native="$(cd "$scratch" && ulimit -v 8192 && ulimit -s 64 && timeout "$run_timeout" "$i486_bin" "$scene" 2>&1)"; then
        fail "$t: native run under ulimit -v 8192 -s 64 failed (does this kernel run i386 ELF files?): $native"
    else
        compare "$t (native, ulimit -v 8192)" "$scene" "$native" "$scratch/frame-i486.ppm"
    fi
    rss="?"
    if [[ -x /usr/bin/time ]]; then
        rss="$(cd "$scratch" && { /usr/bin/time -f 'maxrss_kib=%M' "$i486_bin" "$scene" >/dev/null; } 2>&1 | sed -n 's/^maxrss_kib=//p')"
    fi
    echo "target=$t frame_checksum=$(field frame_checksum "$line") host_checksum=${host_sum[$scene]}" \
        "stack_bytes=$(field stack_bytes "$line") text_bytes=$(section_size "$i486_bin" .text)" \
        "instructions=${insns:-?} frame_instructions=${frame_insns:-?} x87_instructions=${x87:-?} other_instructions=$((${insns:-0} - ${x87:-0}))" \
        "rodata_bytes=$(section_size "$i486_bin" .rodata) image_bytes=$(image_bytes "$i486_bin")" \
        "render_stack_bytes=$(field render_stack_bytes "$line") render_peak_stack_bytes=$(field render_peak_stack_bytes "$line")" \
            "setup_stack_bytes=$(field setup_stack_bytes "$line")" \
        "model_bytes=$(field model_bytes "$line") heightfield_bytes=$(field heightfield_bytes "$line")" \
        "tracer_bytes=$(field tracer_bytes "$line") line_bytes=$(field line_bytes "$line")" \
        "native_8MiB_checksum=$(field frame_checksum "$native") vm_peak_kib=$(field vm_peak_kib "$native")" \
        "vm_hwm_kib=$(field vm_hwm_kib "$native") max_rss_kib=${rss:-?}" \
        "scene=$scene build=$build $(work "$line")"
    profile "$t" "$out/frame-insns-$tag.txt" "$i486_bin"
done

# --- 486SX: the fixed-point frame under qemu-i386 -cpu 486 -------------------
# The frame must be the host's fixed-point frame, and its pixels must run no
# x87 instruction (the plugin's segment_fp: the program's two frame segments
# are the set-up, f64 on the x87, which a 486SX runs through the kernel's FPU
# emulation, and the render).
i486sx_bin="$i486sx_dir/i586-unknown-linux-gnu/release/hfray-i486"
for scene in "${fixed_scenes[@]}"; do
    t="i586-unknown-linux-gnu/i486sx"
    [[ "$scene" != base ]] && t+=":$scene"
    tag="i486sx-$scene"
    ppm="$out/frame-i486sx-$scene.ppm"
    rm -rf "$scratch" && mkdir -p "$scratch"
    if ! line="$(cd "$scratch" && timeout "$run_timeout" qemu-i386 -cpu 486 \
        -plugin "$plugin,out=$out/insns-$tag.txt,frame_out=$out/frame-insns-$tag.txt" -d plugin -D "$out/qemu-$tag.log" "$i486sx_bin" "$scene")"; then
        fail "$t: qemu-i386 -cpu 486 exited non-zero: $line"
        continue
    fi
    mv -f "$scratch/frame-i486.ppm" "$ppm" 2>/dev/null || rm -f "$ppm"
    compare "$t" "fixed:$scene" "$line" "$ppm"
    insns="$(sed -n 's/^insn_count: total=\([0-9]*\).*/\1/p' "$out/qemu-$tag.log")"
    check_marks "$out/qemu-$tag.log"
    frame_insns="$(frame_instructions "$out/qemu-$tag.log")"
    segments="$(sed -n 's/.*segment_fp=\([0-9]*,[0-9]*\)$/\1/p' "$out/qemu-$tag.log")"
    x87_setup="${segments%%,*}" x87_pixels="${segments#*,}"
    if [[ "$x87_pixels" != 0 ]]; then
        fail "$t: the fixed-point frame's render ran ${x87_pixels:-?} x87 instructions (segment_fp=${segments:-?})"
    fi
    echo "target=$t frame_checksum=$(field frame_checksum "$line") host_checksum=${host_sum[fixed:$scene]}" \
        "stack_bytes=$(field stack_bytes "$line") text_bytes=$(section_size "$i486sx_bin" .text)" \
        "instructions=${insns:-?} frame_instructions=${frame_insns:-?} x87_in_pixels=${x87_pixels:-?} x87_in_setup=${x87_setup:-?}" \
        "image_bytes=$(image_bytes "$i486sx_bin") render_stack_bytes=$(field render_stack_bytes "$line")" \
        "scene=$scene build=hf $(work "$line") frame=fixed ${fixed_error[$scene]}"
    profile "$t" "$out/frame-insns-$tag.txt" "$i486sx_bin"
done

# fsqrt against libm on the 486, at the x87 precision of the render, the
# setup and the reset default.
t="i586-unknown-linux-gnu/i486:sqrt-check"
line="$(cd "$out" && timeout "$run_timeout" qemu-i386 -cpu 486 "$i486_dir/i586-unknown-linux-gnu/release/hfray-i486" sqrt-check)" || true
if [[ "$(field sqrt_mismatches "$line")" == 0 && -n "$(field sqrt_checked "$line")" ]]; then
    echo "target=$t sqrt_checked=$(field sqrt_checked "$line") sqrt_mismatches=0"
else
    fail "$t: hardware sqrt differs from libm's: $line"
fi

if ((status)); then
    echo "run-qemu.sh: FAILED (outputs in $out)" >&2
else
    echo "run-qemu.sh: all frames and work counters match the host (outputs in $out)" >&2
fi
exit "$status"
