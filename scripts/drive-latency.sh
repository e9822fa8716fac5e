#!/bin/sh
# Measures the joystick -> platform command and joystick -> HMD frame latency of a live drive:
# `pwsim drive` on the car, driven by the shipped synthetic R-Net log, with `pwsim platform-sim`
# and `pwsim hmd-peer` on loopback (each accepting the drive's own ports only). Runs N drives
# and prints the latencies of each from its report.json (docs/hardware.md quotes them).
#
# With SCENE=scenes/circuit_course.yaml (a circuit) the chair is driven instead, and each drive's
# training metrics (report.json "training") are printed too; DURATION sets the drive time.
#
# Usage: [JOYSTICK=SPEC] [SCENE=FILE] [DURATION=S] scripts/drive-latency.sh [N=3] [BUILD_DIR=build] [EXTRA drive options, e.g. --rt-priority 50]
# JOYSTICK defaults to rnet-log:assets/rnet/joystick_synthetic.log; sdl-script:assets/joystick/scripted_drive.yaml
# plays the scripted drive on SDL's virtual joystick.
set -eu
n=${1:-3}
build=${2:-build}
shift 2 2>/dev/null || shift $#
pwsim="$build/pwsim"
joystick=${JOYSTICK:-rnet-log:assets/rnet/joystick_synthetic.log}
scene=${SCENE:-scenes/car_launch.yaml}
duration=${DURATION:-4.5}
export SDL_VIDEODRIVER=${SDL_VIDEODRIVER:-dummy}
[ -x "$pwsim" ] || { echo "drive-latency: $pwsim not built" >&2; exit 2; }
work=$(mktemp -d "${TMPDIR:-/tmp}/pwsim_drive_latency.XXXXXX")
pids=""
cleanup() { for p in $pids; do kill "$p" 2>/dev/null || true; done; rm -rf "$work"; }
trap cleanup EXIT INT TERM
free_port() { python3 -c 'import socket; s=socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
echo "drive-latency: $n drives of $scene by $joystick ($duration s), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
i=1
while [ "$i" -le "$n" ]; do
  can_local=$(free_port); hmd_local=$(free_port)
  mkfifo "$work/plat.fifo" "$work/hmd.fifo"
  "$pwsim" platform-sim --listen 127.0.0.1:0 --peer "udp:127.0.0.1:$can_local" --idle-exit 1 >"$work/plat.fifo" 2>&1 &
  pids="$pids $!"
  "$pwsim" hmd-peer --listen 127.0.0.1:0 --peer "udp:127.0.0.1:$hmd_local" >"$work/hmd.fifo" 2>&1 &
  pids="$pids $!"
  # events: each peer's "listening on HOST:PORT" line (then drain the rest in the background)
  exec 3<"$work/plat.fifo" 4<"$work/hmd.fifo"
  while read -r line <&3; do case $line in *"listening on "*) can_at=${line##* }; break ;; esac; done
  while read -r line <&4; do case $line in *"listening on "*) hmd_at=${line##* }; break ;; esac; done
  cat <&3 >/dev/null & cat <&4 >/dev/null &
  "$pwsim" drive "$scene" --joystick "$joystick" --duration "$duration" \
    --can "udp:$can_at" --can-local "127.0.0.1:$can_local" --hmd "udp:$hmd_at" --hmd-local "127.0.0.1:$hmd_local" \
    --drive-wait-ms 1000 --out "$work/out$i" "$@" >"$work/drive$i.log" 2>&1 || { cat "$work/drive$i.log"; exit 1; }
  wait
  exec 3<&- 4<&-
  rm -f "$work/plat.fifo" "$work/hmd.fifo"
  pids=""
  python3 - "$work/out$i/report.json" "$i" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
p, h = r["joystick_to_platform_command_ms"], r["joystick_to_hmd_frame_ms"]
print("  drive %s: joystick -> platform p50 %.3f p99 %.3f max %.3f ms (n %d); joystick -> HMD p50 %.3f p99 %.3f max %.3f ms (n %d); lateness p99 %.0f us, %d slips"
      % (sys.argv[2], p["p50"], p["p99"], p["max"], p["n"], h["p50"], h["p99"], h["max"], h["n"],
         r["cycle_lateness_us"]["p99"], r["schedule_slips"]))
t = r.get("training")
if t:
    print("    training: gates %d/%d, completion %s, route deviation mean %.3f max %.3f m, %d contacts (max %.2f m/s), "
          "clearance min %.3f m, %d commands, %d reversals, head jerk RMS %.1f p95 %.1f m/s^3, %d near-tips, %d lift-offs"
          % (t["gates"]["passed"], t["gates"]["total"], t["completion_time_s"],
             (t["route_deviation_m"] or {}).get("mean", float("nan")), (t["route_deviation_m"] or {}).get("max", float("nan")),
             t["contacts"]["count"], t["contacts"]["approach_speed_max_mps"], t["clearance"]["min_m"],
             t["joystick"]["commands"], t["joystick"]["reversals"], t["head_jerk_mps3"]["rms"], t["head_jerk_mps3"]["p95"],
             t["near_tips"], t["lift_offs"]["episodes"]))
PY
  i=$((i + 1))
done
echo "  load at end: $(cut -d' ' -f1-3 /proc/loadavg)"
