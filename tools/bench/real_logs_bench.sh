#!/bin/bash
# SLAM on every real log in a list: slam_offline with the defaults, 5 seeds per log, each run's
# wall time and peak memory (/usr/bin/time), its map's consistency between passes
# (map_consistency: the share of endpoints lying where another pass saw free space, and the
# scans placed off the map) and, where the log has relations beside it (LOG with .relations for
# its extension), the relations error (Kuemmerle et al. 2009). The same consistency is given for
# the log's raw odometry and, when the list names one, for a reference trajectory's log (e.g.
# GMapping's corrected .gfs log), so each figure has its log's scale beside it; as a reference log
# may hold only some of the scans (a .gfs log keeps those GMapping processed) and the score depends
# on which scans make the map, each run is also scored on the reference's scans alone
# (map_consistency --scans-of), the like-for-like comparison with the reference.
#
#   tools/bench/real_logs_bench.sh LIST [OUT_DIR]     (default build/bench/real_logs in the repo)
#
# LIST: one log per line, "NAME LOG [REFERENCE_LOG]", paths relative to the repository; '#'
# starts a comment. A log that is not there is reported as skipped. Prints one summary line per
# log (mean ± standard deviation over the seeds) and writes OUT_DIR/NAME_sSEED/ (map,
# trajectory) and OUT_DIR/NAME.png (seed 1's map with its trajectory).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
list="$(realpath -m "${1:?usage: real_logs_bench.sh LIST [OUT_DIR]}")"
out="$(realpath -m "${2:-$root/build/bench/real_logs}")"
cd "$root"
source tools/ros_env.sh  # plot_map.py imports the workspace's Python modules
bin=devel/lib/minibot3d_slam
seeds="${SEEDS:-1 2 3 4 5}"
source tools/bench/log_list.sh
read_log_list real_logs_bench.sh "$list"
mkdir -p "$out"
for entry in "${LOGS[@]}"; do
  read -r name log reference <<< "$entry"
  relations="${log%.*}.relations"
  rm -f "$out/$name.runs"
  for seed in $seeds; do
    dir="$out/${name}_s$seed"
    /usr/bin/time -f "%e %M" -o "$dir.time" "$bin/slam_offline" --log "$log" --out "$dir" --quiet \
      --param seed="$seed" > "$dir.line"
    score=""
    if [ -f "$relations" ]; then
      score=" | $("$bin/evaluate_relations" "$dir/trajectory.txt" "$relations" | head -1)"
    fi
    if [ -n "${reference:-}" ] && [ -f "$reference" ]; then
      score="$score | on the reference's scans: $("$bin/map_consistency" "$log" "$dir/trajectory.txt" \
        --scans-of "$reference" --worst 0)"
    fi
    echo "seed $seed | time $(cat "$dir.time") | $("$bin/map_consistency" "$log" "$dir/trajectory.txt" --worst 0)$score" \
      >> "$out/$name.runs"
  done
  raw="$("$bin/map_consistency" "$log" --worst 0)"
  ref="none"
  if [ -n "${reference:-}" ]; then
    if [ -f "$reference" ]; then
      ref="$("$bin/map_consistency" "$reference" --worst 0)"
    else
      ref="missing: no reference log at '$reference'"
    fi
  fi
  /usr/bin/python3 - "$name" "$out/$name.runs" "$raw" "$ref" <<'PY'
import re, statistics as st, sys
name, runs, raw, ref = sys.argv[1:5]
rows = [l for l in open(runs) if l.startswith('seed')]
def nums(pattern, text=None):
    return [float(m.group(1)) for l in ([text] if text else rows)
            for m in [re.search(pattern, l)] if m]
def ms(v, fmt):
    return (fmt % st.mean(v)) + (' ± ' + fmt % st.stdev(v) if len(v) > 1 else '')
wall = nums(r'time ([0-9.]+) [0-9]+')
peak = [v / 1024 for v in nums(r'time [0-9.]+ ([0-9]+)')]
conf = nums(r'\| consistency conflict_pct ([0-9.]+)')
bad = nums(r'\| consistency conflict_pct [0-9.]+ scans_inconsistent ([0-9]+)')
judged = nums(r'\| consistency conflict_pct [0-9.]+ scans_inconsistent [0-9]+ of ([0-9]+)')
same = r"on the reference's scans: consistency conflict_pct ([0-9.]+) scans_inconsistent ([0-9]+) of ([0-9]+)"
same_rows = [m.groups() for l in rows for m in [re.search(same, l)] if m]
parts = ['%s, %d seeds: conflicts %s %% of revisited endpoints, inconsistent scans %s of %.0f'
         % (name, len(rows), ms(conf, '%.2f'), ms(bad, '%.1f'), st.mean(judged))]
tr = nums(r'translation_m ([0-9.]+)')
rot = nums(r'rotation_deg ([0-9.]+)')
if tr:
    parts.append('relations %s m, %s deg' % (ms(tr, '%.4f'), ms(rot, '%.3f')))
parts.append('wall %s s, peak %.0f MB' % (ms(wall, '%.1f'), max(peak)))
raw_c = re.search(r'conflict_pct ([0-9.]+)', raw)
parts.append('raw odometry: conflicts %s %%' % (raw_c.group(1) if raw_c else '?'))
ref_c = re.search(r'conflict_pct ([0-9.]+) scans_inconsistent ([0-9]+) of ([0-9]+)', ref)
if ref_c:
    parts.append('reference: conflicts %s %%, inconsistent scans %s of %s' % ref_c.groups())
    if same_rows:
        parts.append("%s on the reference's scans: conflicts %s %%, inconsistent scans %s of %.0f"
                     % (name, ms([float(g[0]) for g in same_rows], '%.2f'),
                        ms([float(g[1]) for g in same_rows], '%.1f'), st.mean(float(g[2]) for g in same_rows)))
elif ref != 'none':
    parts.append('reference ' + ref)
print('; '.join(parts))
PY
  /usr/bin/python3 minibot3d_slam/scripts/plot_map.py "$out/${name}_s1/map.yaml" \
    "$out/${name}_s1/trajectory.txt" "$out/$name.png" > /dev/null
done
