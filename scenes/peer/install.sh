#!/usr/bin/env bash
# Installs the optional mesh peers Coal and TrueForm, as their PyPI wheels ship them (C++
# headers and libraries inside), into a virtual environment under target/peers/venv, where
# scenes/build.rs finds them; the next build of the reports then measures them beside tridist
# (reports/MESH.md). Needs python3 with venv and a C++17 compiler; about 650 MB. Nothing else
# in the project needs them. FCL, the third mesh peer, comes from Debian:
# `apt-get install libfcl-dev libeigen3-dev`.
#
#   bash scenes/peer/install.sh
#   cargo run --release -p tridist-reports --features all-variants -- report --quick
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
venv="$root/target/peers/venv"
python3 -m venv "$venv"
"$venv/bin/pip" install --quiet --disable-pip-version-check \
    "coal==3.0.3" "cmeel-eigen==3.4.1" "trueform==0.10.7"
# scenes/build.rs watches the shims' sources: touching them rebuilds the peers
touch "$root/scenes/peer/coal_mesh.cpp" "$root/scenes/peer/trueform_mesh.cpp"
echo "Coal and TrueForm installed in $venv; the next build of the reports measures them."
