#!/usr/bin/env bash
# Installs the Debian 12 packages dacrt needs, only those that are missing. Idempotent; runs as root
# (or through sudo when it is available). Set DACRT_NO_INSTALL=1 to skip entirely.
set -euo pipefail
[ "${DACRT_NO_INSTALL:-0}" = 1 ] && exit 0

packages=(cmake g++ make pkg-config libtinygltf-dev nlohmann-json3-dev libstb-dev libopenexr-dev
          libglm-dev libopencolorio-dev doctest-dev libtbb-dev libembree-dev libpng-dev
          libjpeg62-turbo-dev libwebp-dev libmeshoptimizer-dev libdraco-dev gnuplot-nox
          libopenmpi-dev openmpi-bin pybind11-dev python3-dev python3-numpy python3-pytest
          groff-base man-db  # the man page checked, `dacrt man | man -l -`
          python3-venv python3-setuptools python3-wheel)  # the last three: `pip install .`
packages+=("$@")  # extra packages a target needs (make fuzz: clang and its runtime)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing ${missing[*]}" >&2
sudo=""
if [ "$(id -u)" != 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root to install ${missing[*]}" >&2; exit 1; }
  sudo=sudo
fi
export DEBIAN_FRONTEND=noninteractive
# A fresh machine has empty package lists; refresh them once per install.
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
