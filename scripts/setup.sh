#!/usr/bin/env bash
# Installs what is missing (Debian 12 packages) and builds nsmodal in build/.
# (scripts/install.sh then installs the libraries, the CLI and the Python module.)
# Usage: bash scripts/setup.sh [extra cmake options]
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(build-essential cmake pkg-config libeigen3-dev libsundials-dev libgsl-dev
  libtomlplusplus-dev libcli11-dev nlohmann-json3-dev libgtest-dev libbenchmark-dev
  gnuplot-nox python3 python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-matplotlib python3-pandas
  libhdf5-dev python3-h5py mypy
  python3-distributed python3-mpi4py openmpi-bin
  python3-venv python3-setuptools python3-wheel python3-pip
  python3-sphinx python3-myst-parser python3-sphinx-rtd-theme
  python3-nbsphinx python3-nbconvert python3-ipykernel pandoc python3-breathe doxygen)
# (mypy: the Python tests type-check code against the package's stubs;
# Dask distributed, mpi4py and OpenMPI: nsmodal.study's executors; the
# third-to-last line: pip install . into a venv, offline; the last two: the docs,
# scripts/docs.sh: Sphinx and MyST; the tutorials executed by nbsphinx in a python3
# kernel (ipykernel), whose Markdown cells pandoc converts; the C++ reference by
# Doxygen's XML read by Breathe)
missing=()
for p in "${packages[@]}"; do
  dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "installing: ${missing[*]}"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Debian's python3, where apt put NumPy, pytest and matplotlib (a python3
# earlier on PATH, e.g. pyenv's, may have none of them).
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DNSMODAL_WERROR=ON -DPython_EXECUTABLE=/usr/bin/python3 "$@"
cmake --build build -j"$(nproc)"
