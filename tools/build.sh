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

# Anything in the source tree (files or folders, so added and removed files count too) newer than
# the stamp of the last successful build.
changed_since_stamp() {
  find . \( -path ./build -o -path ./devel -o -path ./install -o -path ./out -o -path ./.git \
            -o -name __pycache__ -o -name .pytest_cache \) -prune \
         -o -newer "$stamp" -print -quit | grep -q .
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
if [ $# -eq 0 ]; then mv "$new_stamp" "$stamp"; else rm -f "$new_stamp"; fi
