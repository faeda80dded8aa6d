#!/usr/bin/env bash
# Installs the Debian 12 packages octarc needs to build and test, if any is missing.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libcfitsio-dev libcfitsio-bin wcslib-dev libeigen3-dev libboost-program-options-dev
  libgtest-dev googletest
  source-extractor fitsverify python3-astropy python3-numpy python3-sep python3-photutils
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "Installing: ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
"${sudo_cmd[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
