#!/usr/bin/env bash
# The runtime's layering (docs/architecture.md, "The runtime's rooms"): each
# room of runtime/src includes only its own room, the rooms below it and the
# API (include/ldae); the API includes no room. Read from the #include lines,
# so an arrow running back up fails CI before it becomes a habit.
#
#   scripts/check-runtime-layers.sh [runtime-dir]
set -euo pipefail

runtime=${1:-"$(dirname "$0")/../runtime"}
# Lowest first; the order is the one docs/architecture.md draws.
rooms=(model results init integrators events run sweep cmain)

rank_of() {
  local i
  for i in "${!rooms[@]}"; do
    if [[ ${rooms[$i]} == "$1" ]]; then
      echo $((i + 1))
      return
    fi
  done
  echo -1
}

status=0
complain() {
  echo "$1" >&2
  status=1
}

while IFS= read -r file; do
  rel=${file#"$runtime"/}
  case $rel in
  include/ldae/*) own=api rank=0 ;;
  src/*/*)
    own=${rel#src/}
    own=${own%%/*}
    rank=$(rank_of "$own")
    if ((rank < 0)); then
      complain "$rel: '$own' is not a room of the runtime (add it to $0 and docs/architecture.md)"
      continue
    fi
    ;;
  *)
    complain "$rel: outside every room (runtime/src/<room>/ or include/ldae/)"
    continue
    ;;
  esac
  while IFS=: read -r line header; do
    case $header in
    ldae/*) continue ;; # the API: open to every room
    */*) ;;
    *)
      complain "$rel:$line: #include \"$header\" names no room (write \"<room>/$header\")"
      continue
      ;;
    esac
    room=${header%%/*}
    used=$(rank_of "$room")
    ((used < 0)) && continue # compiler/ (numeric, graph, support): below all
    if [[ $own == api ]]; then
      complain "$rel:$line: the API includes \"$header\" of room '$room'"
    elif ((used > rank)); then
      complain "$rel:$line: room '$own' includes \"$header\" of room '$room' above it"
    fi
  done < <(grep -n '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' "$file" |
    sed -E 's/^([0-9]+):[^"]*"([^"]*)".*/\1:\2/')
done < <(find "$runtime/src" "$runtime/include" -type f \( -name '*.h' -o -name '*.cpp' -o -name '*.c' \) | sort)

if ((status == 0)); then
  echo "runtime layers: ok (${rooms[*]})"
fi
exit $status
