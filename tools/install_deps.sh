#!/usr/bin/env bash
# Installs what minibot3d needs and is missing: the Debian packages in tools/deps.txt (apt-get,
# through sudo when not root) and xacro from PyPI into the system Python (Debian has no xacro).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export PATH="/usr/local/bin:/usr/bin:/bin:/usr/sbin:/sbin:${PATH}"
export DEBIAN_FRONTEND=noninteractive

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null; then sudo_cmd=(sudo); else
    echo "install_deps: not root and no sudo: cannot install Debian packages" >&2; exit 1; fi
fi

mapfile -t wanted < <(sed -e 's/#.*//' -e 's/[[:space:]]//g' "$here/deps.txt" | grep -v '^$')
missing=()
for pkg in "${wanted[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  [ "$status" = "install ok installed" ] || missing+=("$pkg")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install_deps: installing ${#missing[@]} Debian packages: ${missing[*]}"
  "${sudo_cmd[@]}" apt-get update -qq
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "install_deps: all ${#wanted[@]} Debian packages present"
fi

# xacro: ROS 1's xacro 1.13.3 from PyPI, into the system interpreter (not pyenv's python3).
if ! /usr/bin/python3 -c 'import xacro' 2>/dev/null || ! command -v xacro >/dev/null; then
  echo "install_deps: installing xacro==1.13.3 into /usr/bin/python3"
  "${sudo_cmd[@]}" /usr/bin/python3 -m pip install -q --break-system-packages xacro==1.13.3
fi
