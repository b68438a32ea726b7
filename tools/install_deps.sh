#!/usr/bin/env bash
# Installs what minibot3d needs and is missing: the Debian packages in tools/deps.txt (apt-get)
# and xacro from PyPI into the system Python (Debian has no xacro). When nothing is missing it
# only looks (one dpkg-query, one import) and needs neither root nor sudo; root or sudo is asked
# for only to install something.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export PATH="/usr/local/bin:/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
export DEBIAN_FRONTEND=noninteractive

as_root() {
  if [ "$(id -u)" -eq 0 ]; then "$@"
  elif command -v sudo >/dev/null; then sudo "$@"
  else echo "install_deps: not root and no sudo: cannot run: $*" >&2; exit 1; fi
}

mapfile -t wanted < <(sed -e 's/#.*//' -e 's/[[:space:]]//g' "$here/deps.txt" | grep -v '^$')
# One dpkg-query for all: installed packages print "name ok"; unknown ones print nothing.
mapfile -t present < <(dpkg-query -W -f='${Package} ${db:Status-Status}\n' "${wanted[@]}" \
                         2>/dev/null | awk '$2 == "installed" {print $1}')
missing=()
for pkg in "${wanted[@]}"; do
  [[ " ${present[*]} " == *" $pkg "* ]] || missing+=("$pkg")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install_deps: installing ${#missing[@]} Debian packages: ${missing[*]}"
  as_root apt-get update -qq
  as_root apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install_deps: all ${#wanted[@]} Debian packages present"
fi

# xacro: ROS 1's xacro 1.13.3 from PyPI, into the system interpreter (not pyenv's python3).
if ! command -v xacro >/dev/null || ! /usr/bin/python3 -c 'import xacro' 2>/dev/null; then
  echo "install_deps: installing xacro==1.13.3 into /usr/bin/python3"
  as_root /usr/bin/python3 -m pip install -q --break-system-packages xacro==1.13.3
fi
