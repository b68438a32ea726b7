# Sourced by the benchmarks that run over a list of real logs (real_logs_bench.sh,
# real_maps_global_loc.sh). The list has one log per line, "NAME LOG [REFERENCE_LOG]", paths
# relative to the repository; '#' starts a comment.
#
#   read_log_list SCRIPT_NAME LIST
#
# sets LOGS to one "NAME LOG [REFERENCE_LOG]" entry per log that is there, prints
# "NAME: skipped, no log at 'LOG'" for each one that is not, and stops the calling script (exit 2)
# with a message naming the list, and the line, for a missing list or a malformed line.
read_log_list() {
  local script=$1 list=$2 line_no=0 name log reference rest
  LOGS=()
  if [ ! -f "$list" ]; then
    echo "$script: no list of logs at '$list'" >&2
    exit 2
  fi
  while read -r name log reference rest || [ -n "${name:-}" ]; do
    line_no=$((line_no + 1))
    [ -z "${name:-}" ] && continue
    [ "${name:0:1}" = "#" ] && continue
    if [ -z "${log:-}" ] || [ -n "${rest:-}" ]; then
      echo "$script: $list:$line_no: expected 'NAME LOG [REFERENCE_LOG]'" >&2
      exit 2
    fi
    if [ ! -f "$log" ]; then
      echo "$name: skipped, no log at '$log'"
      continue
    fi
    LOGS+=("$name $log${reference:+ $reference}")
  done < "$list"
}
