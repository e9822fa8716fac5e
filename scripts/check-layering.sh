#!/usr/bin/env bash
# Checks the include direction between pwsim's folders (the CMake link check in
# cmake/PwsimTargets.cmake cannot see a header-only include). Each folder may include only
# the folders listed for it; run from the source root. Exit 1 with every offending line.
#   engine <- plot, sysid, mca <- synth, hardware, render <- report <- app
set -u
cd "$(dirname "$0")/.." || exit 2
declare -A allowed=(
  [engine]="engine"
  [plot]="plot engine"
  [sysid]="sysid engine"
  [synth]="synth sysid engine"
  [mca]="mca engine"
  [render]="render engine"
  [hardware]="hardware mca engine"
  [report]="report plot sysid synth mca render hardware engine"
)
status=0
for folder in "${!allowed[@]}"; do
  [ -d "$folder" ] || continue
  pattern=$(printf '%s|' ${allowed[$folder]})
  pattern=${pattern%|}
  # Every project include ("folder/...") whose first path part is a pwsim folder not allowed.
  while IFS= read -r line; do
    target=$(sed -E 's/.*#include "([a-z_]+)\/.*/\1/' <<<"${line#*:*:}")
    if [ -d "$target" ] && ! grep -qE "^($pattern)$" <<<"$target"; then
      echo "layering: $line  ($folder may include only: ${allowed[$folder]})"
      status=1
    fi
  done < <(grep -rnE '^#include "[a-z_]+/' "$folder" --include='*.h' --include='*.cc')
done
[ $status -eq 0 ] && echo "layering: every include follows the dependency direction"
exit $status
