#!/usr/bin/env bash
# Drives a program's window on an X display (run it under xvfb-run) with xdotool and captures the
# window from the X server (xwd, converted to PNG by ImageMagick), for test_demo_windows.
#
#   window_session.sh OUT_DIR WINDOW_NAME STEPS -- PROGRAM [ARGS...]
#
# STEPS, separated by ';':
#   shot NAME            wait until the window's picture is still, save it as OUT_DIR/NAME.png
#   change NAME          wait until the picture differs from the last one saved, then is still; save it
#   click X Y            left click at the window's pixel (X, Y)
#   drag X1 Y1 X2 Y2     left-button drag
#   wheel N              N wheel steps away from the user
#   key KEY...           xdotool key names (s, space, Escape, ...)
# At the end Escape closes the window; the program must then exit with status 0.
# "Still": three captures 0.25 s apart are equal (an animation on a busy machine may pause for a
# frame, not for half a second). Each wait gives up after 20 s.
set -euo pipefail
out=$1 name=$2 steps=$3
shift 3
[[ $1 == -- ]] && shift
mkdir -p "$out"
"$@" &
pid=$!
fail() {
  echo "window_session: $*" >&2
  kill "$pid" 2>/dev/null || true
  exit 1
}
win=$(timeout 20 xdotool search --sync --onlyvisible --name "^$name\$" | head -1) || true
[[ -n $win ]] || fail "no window named $name"
xdotool mousemove --window "$win" 1 1

capture() { xwd -silent -id "$win" > "$1" || fail "xwd cannot capture window $win"; }
still() {  # waits until the picture is still, leaves it in $out/current.xwd
  local deadline=$((SECONDS + 20)) same=0
  capture "$out/current.xwd"
  while ((SECONDS < deadline)); do
    sleep 0.25
    capture "$out/next.xwd"
    if cmp -s "$out/current.xwd" "$out/next.xwd"; then
      ((++same < 2)) || return 0
    else
      same=0
      mv "$out/next.xwd" "$out/current.xwd"
    fi
  done
  fail "the picture does not stay still"
}
save() {
  cp "$out/current.xwd" "$out/last.xwd"
  convert "xwd:$out/current.xwd" "png:$out/$1.png" || fail "cannot convert the capture to PNG"
}

IFS=';' read -ra list <<< "$steps"
for step in "${list[@]}"; do
  read -ra w <<< "$step"
  ((${#w[@]})) || continue
  case ${w[0]} in
    shot) still; save "${w[1]}" ;;
    change)
      deadline=$((SECONDS + 20))
      while capture "$out/current.xwd"; cmp -s "$out/current.xwd" "$out/last.xwd"; do
        ((SECONDS < deadline)) || fail "the picture does not change before ${w[1]}"
        sleep 0.1
      done
      still
      save "${w[1]}" ;;
    click) xdotool mousemove --window "$win" "${w[1]}" "${w[2]}" click 1 ;;
    drag)
      xdotool mousemove --window "$win" "${w[1]}" "${w[2]}" mousedown 1
      for i in 1 2 3 4 5; do
        xdotool mousemove --window "$win" $((w[1] + (w[3] - w[1]) * i / 5)) $((w[2] + (w[4] - w[2]) * i / 5))
        sleep 0.05
      done
      xdotool mouseup 1 ;;
    wheel) xdotool click --repeat "${w[1]}" --delay 50 4 ;;
    key) xdotool key --delay 40 "${w[@]:1}" ;;
    *) fail "unknown step: $step" ;;
  esac
done
xdotool key Escape
status=0
wait "$pid" || status=$?
rm -f "$out"/*.xwd
((status == 0)) || { echo "window_session: the program exited with status $status" >&2; exit 1; }
