# Sourced by the EMPS scripts: sets `emps` to the folder holding DATA_EMPS.mat
# (PWSIM_EMPS_DIR, else ../shared/data/emps beside the checkout) or exits 1 saying so.
# Needs `root` (the source root) set by the caller.
emps=${PWSIM_EMPS_DIR:-}
if [ -z "$emps" ]; then
  for c in "$root/../shared/data/emps" "$root/../../shared/data/emps"; do
    [ -f "$c/DATA_EMPS.mat" ] && emps=$c && break
  done
fi
[ -n "$emps" ] || { echo "EMPS data absent: set PWSIM_EMPS_DIR" >&2; exit 1; }
