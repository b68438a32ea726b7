#!/usr/bin/env bash
# Builds the catkin workspace whose source space is the repository root (build/, devel/).
#   tools/build.sh            build; a no-op when no file of the source tree changed since the
#                             last successful build (FORCE=1 runs catkin_make anyway)
#   tools/build.sh ARGS...    catkin_make ARGS (e.g. install), always run
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
export PATH="/usr/local/bin:/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
unset PYTHONPATH PYTHONHOME
stamp=build/.minibot3d_source_stamp

# The packages' files (what catkin builds; the top-level maps/, config/ and launch/ are read where
# they are, and a user's files saved beside them change nothing), without Python's caches.
package_files() {
  find CMakeLists.txt minibot3d_* \( -name __pycache__ -o -name .pytest_cache \) -prune \
       -o \( -type f -o -type l \) "$@" -print
}
# A file edited since the stamp of the last successful build, or one added or removed (the stamp
# holds the list's digest).
changed_since_stamp() {
  [ -n "$(package_files -newer "$stamp" | head -n 1)" ] && return 0
  [ "$(package_files | LC_ALL=C sort | sha1sum)" != "$(cat "$stamp")" ]
}

if [ $# -eq 0 ] && [ "${FORCE:-0}" != 1 ] && [ -f "$stamp" ] && [ -f devel/setup.bash ] \
   && ! changed_since_stamp; then
  echo "build: nothing changed since the last build (FORCE=1 rebuilds)"
  exit 0
fi
rm -f "$stamp"
new_stamp="$(mktemp)"  # taken before the build: a file edited during it counts as changed
trap 'rm -f "$new_stamp"' EXIT
catkin_make --source . --build build \
  -DCMAKE_BUILD_TYPE=Release \
  -DPYTHON_EXECUTABLE=/usr/bin/python3 \
  -DCATKIN_ENABLE_TESTING=ON \
  -j"${JOBS:-2}" "$@"
if [ $# -eq 0 ]; then
  # The digest goes in a file dated like new_stamp: the build's start is what -newer compares with.
  digest="$(mktemp)"
  package_files | LC_ALL=C sort | sha1sum > "$digest"
  touch -r "$new_stamp" "$digest"
  mv "$digest" "$stamp"
fi
rm -f "$new_stamp"
