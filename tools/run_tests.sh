#!/usr/bin/env bash
# Runs every test of the workspace — gtest and rostest through catkin's run_tests, then pytest —
# and ends with one line "N passed, N failed[, N skipped]". Exits non-zero on any failure.
# Assumes the workspace is built (make test runs make setup first).
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
export PATH="/usr/local/bin:/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
unset PYTHONPATH PYTHONHOME
# Loopback only (docs/security.md): every master, roslaunch and node of the tests; the closed-loop
# rostests check what listens beyond loopback.
export ROS_IP=127.0.0.1
unset ROS_HOSTNAME
results=build/test_results
rm -rf "$results"
mkdir -p "$results"
status=0

echo "== gtest + rostest (catkin run_tests)"
if ! JOBS="${JOBS:-2}" tools/build.sh run_tests; then
  echo "run_tests: building or running the catkin tests failed" >&2
  status=1
fi

echo "== pytest"
# shellcheck disable=SC1091
set +u; source devel/setup.bash; set -u
mapfile -t pytest_dirs < <(ls -d test minibot3d_*/test 2>/dev/null)
/usr/bin/python3 -m pytest -q -p no:cacheprovider --junitxml="$results/pytest/pytest.xml" \
  "${pytest_dirs[@]}"
rc=$?
# Any non-zero status fails the run, 5 ("no tests collected") too: a test directory that yields
# no test is a broken suite, not an empty one.
if [ $rc -ne 0 ]; then
  [ $rc -eq 5 ] && echo "pytest: no tests collected from ${pytest_dirs[*]}" >&2
  status=1
fi

/usr/bin/python3 tools/summarize_tests.py "$results" || status=1
exit $status
