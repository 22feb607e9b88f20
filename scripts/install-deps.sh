#!/usr/bin/env bash
# Installs the Debian 12 packages flexrod needs, only those that are missing.
# Idempotent; works as root (with or without sudo installed) or as a sudoer.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libsuitesparse-dev libarpack2-dev libsundials-dev libgsl-dev
  libgtest-dev libgmock-dev libbenchmark-dev libcli11-dev libtomlplusplus-dev
  libhdf5-dev hdf5-tools libdeflate-dev libopenmpi-dev openmpi-bin nlohmann-json3-dev
  python3 python3-numpy python3-matplotlib python3-h5py clang libclang-rt-14-dev clang-format
  python3-dev pybind11-dev python3-pybind11 python3-pytest
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "flexrod: installing missing Debian packages: ${missing[*]}"
if [ "$(id -u)" -eq 0 ]; then
  SUDO=()
elif command -v sudo >/dev/null 2>&1; then
  SUDO=(sudo)
else
  echo "flexrod: need root or sudo to install: ${missing[*]}" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
"${SUDO[@]}" apt-get update -qq
"${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
