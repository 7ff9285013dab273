#!/usr/bin/env bash
# Installs the Debian packages of deploy/debian-packages.txt that are missing (none: no apt-get),
# then configures and builds lbsolid in Release under ./build. Safe to run again and again.
set -euo pipefail
cd "$(dirname "$0")/.."

mapfile -t packages < <(grep -vE '^\s*(#|$)' deploy/debian-packages.txt)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if ((${#missing[@]})); then
  echo "setup: installing ${#missing[@]} Debian packages: ${missing[*]}"
  sudo_cmd=()
  if [ "$(id -u)" != 0 ]; then sudo_cmd=(sudo); fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -q
  "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "setup: all Debian packages present"
fi

cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DLBSOLID_REQUIRE_ALL_TESTS=ON
cmake --build build --parallel "$(nproc)"
